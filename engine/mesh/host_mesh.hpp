#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "core/status.hpp"
#include "mesh/fbx_asset.hpp"
#include "mesh/gltf_asset.hpp"
#include "mesh/load.hpp"
#include "mesh/seam_weld.hpp"
#include "mesh/skin.hpp"
#include "mesh/write.hpp"

namespace dfm::mesh {

// What a mesh carries besides its surface: the host's own numbering (the
// split copies a glTF file or a host's buffers have, an FBX file's control
// points), for a mesh from glTF or FBX the asset a save writes back, and what
// poses it (skin.hpp). All null for OFF, OBJ and PLY.
struct HostMesh {
    std::shared_ptr<const SeamWeld> weld;   // null: host vertices are the surface's
    std::shared_ptr<const GltfAsset> gltf;  // null: not from glTF
    std::shared_ptr<const FbxAsset> fbx;    // null: not from FBX
    std::shared_ptr<const Skin> skin;       // per surface vertex; null: nothing poses the mesh
};

// load_mesh that also keeps the host's numbering and the glTF or FBX asset.
// A glTF spec may end in "#mesh=NAME" (or an index); its split copies (an
// FBX file's coincident control points) are welded with `weld` (exact by
// default). A glTF document's external buffers are
// read only inside its own folder and, when not empty, `reference_folder`
// (ExternalFiles, gltf_io.hpp). Copies join only where their skin agrees
// (skin_weld.hpp); a warning counts the positions where it did not.
Status load_host_mesh(const std::filesystem::path& spec, Mesh& surface, HostMesh& host,
                      LoadReport* report = nullptr,
                      const std::filesystem::path& reference_folder = {},
                      const WeldOptions& weld = {});

// The host's vertex positions: each copy at its surface vertex's position.
std::vector<glm::dvec3> host_positions(const Mesh& surface, const HostMesh& host);

// save_mesh for a mesh with a host numbering: glTF (.gltf, .glb) writes the
// host's vertices, back into the asset it came from when there is one, in
// the asset's own (bind) space, `bind`; FBX (.fbx) likewise, only back into
// the FBX file the mesh came from; OFF, OBJ, PLY and a fresh glTF write the
// surface as shown, `shown` (posed, on a posed mesh; else the same as
// `bind`). A morph target (WriteOptions) is written only back into a glTF
// or FBX asset of the same format.
Status save_host_mesh(const std::filesystem::path& path, const Mesh& bind, const Mesh& shown,
                      const HostMesh& host, const WriteOptions& options = {});

}  // namespace dfm::mesh
