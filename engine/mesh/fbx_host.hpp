#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "core/status.hpp"
#include "mesh/host_mesh.hpp"
#include "mesh/load.hpp"
#include "mesh/write.hpp"

// FBX for host_mesh.hpp: a file read into the surface and the host's
// numbering (the file's control points), and an edit written back into it.
// A build without Assimp (DUALFORM_FBX off) refuses both with
// Errc::unsupported.
namespace dfm::mesh {

// read_fbx (fbx_io.hpp), then the control points welded (weld_skinned, by skin and morphs);
// `host` receives the weld, the asset and the skin.
Status load_fbx_host(std::string bytes, std::string_view source, const WeldOptions& weld,
                     Mesh& surface, HostMesh& host, LoadReport& report);

// write_fbx of the host's bind-space positions into the asset `host`
// came from, written atomically to `path`.
Status save_fbx_host(const std::filesystem::path& path, const Mesh& bind, const HostMesh& host,
                     const WriteOptions& options);

}  // namespace dfm::mesh
