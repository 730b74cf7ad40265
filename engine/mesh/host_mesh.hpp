#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "core/status.hpp"
#include "mesh/gltf_asset.hpp"
#include "mesh/load.hpp"
#include "mesh/seam_weld.hpp"
#include "mesh/write.hpp"

namespace dfm::mesh {

// What a mesh carries besides its surface: the host's own numbering (the
// split copies a glTF file or a host's buffers have) and, for a mesh from
// glTF, the asset a save writes back. Both null for OFF, OBJ and PLY.
struct HostMesh {
    std::shared_ptr<const SeamWeld> weld;   // null: host vertices are the surface's
    std::shared_ptr<const GltfAsset> gltf;  // null: not from glTF
};

// load_mesh that also keeps the host's numbering and the glTF asset. A glTF
// spec may end in "#mesh=NAME" (or an index); its split copies are welded
// with `weld` (exact by default). A glTF document's external buffers are
// read only inside its own folder and, when not empty, `reference_folder`
// (ExternalFiles, gltf_io.hpp).
Status load_host_mesh(const std::filesystem::path& spec, Mesh& surface, HostMesh& host,
                      LoadReport* report = nullptr,
                      const std::filesystem::path& reference_folder = {},
                      const WeldOptions& weld = {});

// The host's vertex positions: each copy at its surface vertex's position.
std::vector<glm::dvec3> host_positions(const Mesh& surface, const HostMesh& host);

// save_mesh for a mesh with a host numbering: glTF (.gltf, .glb) writes the
// host's vertices, back into the asset it came from when there is one; OFF,
// OBJ and PLY write the welded surface.
Status save_host_mesh(const std::filesystem::path& path, const Mesh& surface, const HostMesh& host,
                      const WriteOptions& options = {});

}  // namespace dfm::mesh
