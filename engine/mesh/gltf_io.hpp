#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "core/status.hpp"
#include "mesh/gltf_asset.hpp"
#include "mesh/load.hpp"
#include "mesh/mesh.hpp"
#include "mesh/skin.hpp"

namespace dfm::mesh {

// "FILE.glb#mesh=NAME" into the file and NAME; a spec without the fragment
// leaves `selector` empty.
void split_gltf_spec(std::string_view spec, std::string& file, std::string& selector);

// Where a document's external files (buffers given by a relative URI) may
// be read: inside `folder`, the document's own, and inside `wider_folder`
// when the host names one. A URI that is absolute, carries a scheme (file:,
// http:, ...) or leads out of both folders through ".." is refused, and the
// load fails naming it (Errc::unsupported). Only the folders' names are
// compared (after resolving "." and ".."): links inside them are followed.
struct ExternalFiles {
    std::filesystem::path folder;
    std::filesystem::path wider_folder;  // empty: none
};

// Reads a glTF 2.0 document (JSON or binary, told apart by the GLB magic)
// into the host's vertices and triangles, unwelded, in world space, and the
// asset a save writes back. `selector` names one mesh (by name, else by
// index; its own space); empty: the default scene's meshes with their node
// transforms. `files` says where external buffers may be read from; null
// refuses them all (a document given as bytes). `skin` receives what poses
// the host vertices (gltf_skin_reader.hpp), empty when nothing does. Never
// throws but for std::bad_alloc.
Status read_gltf(std::string_view bytes, std::string_view source, const ExternalFiles* files,
                 const std::string& selector, Mesh& host, GltfAsset& asset, Skin& skin,
                 LoadReport& report);

// The asset written back with `host_positions` (world space, host order):
// see docs/gltf.md for what is kept. A non-empty `morph_target` keeps the
// base positions and adds the edit as a morph target of that name, with
// `morph_target_extras` (a JSON object's text, or empty) as its POSITION
// accessor's extras. `binary` writes GLB, else JSON with embedded buffers.
Status write_gltf(const GltfAsset& asset, std::span<const glm::dvec3> host_positions,
                  std::span<const Triangle> host_triangles, const std::string& morph_target,
                  const std::string& morph_target_extras, bool binary, std::string& out);

// A fresh, minimal asset for a mesh that did not come from glTF: one node
// and one mesh, both called `name`, POSITION and NORMAL and 32-bit indices.
void write_fresh_gltf(std::span<const glm::dvec3> positions, std::span<const Triangle> triangles,
                      const std::string& name, bool binary, std::string& out);

}  // namespace dfm::mesh
