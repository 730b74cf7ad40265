#pragma once

#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "core/status.hpp"
#include "mesh/fbx_asset.hpp"
#include "mesh/load.hpp"
#include "mesh/mesh.hpp"
#include "mesh/seam_weld.hpp"
#include "mesh/skin.hpp"

namespace dfm::mesh {

// Reads a binary or ASCII FBX 7.x file: the node tree is parsed and checked
// first (fbx_scene.hpp), then Assimp reads the scene, and its mesh corners
// are joined back onto the file's control points (their positions, skin
// weights and morph positions must agree). `host` receives every instanced
// mesh's control points in metres, +Y up (glTF's axes), in the file's order,
// and its polygons fanned into triangles; `skin` what poses them (clusters
// as joints with their bind poses, the model hierarchy, animation stacks,
// blend shape channels as morph targets), empty when nothing does; `asset`
// what a save writes back. docs/fbx.md says what is read, what is restored
// of what Assimp loses, and what is refused. Never throws but for
// std::bad_alloc.
Status read_fbx(std::string bytes, std::string_view source, Mesh& host, FbxAsset& asset, Skin& skin,
                LoadReport& report);

// The asset's file with `host_positions` (Dualform's space, host order) as
// its meshes' control points: only the Vertices of geometries whose points
// moved, and their normals (LayerElementNormal, mapped by polygon vertex or
// by control point) where a polygon around them moved, are new; every other
// node is copied as read. A non-empty `morph_target` leaves the
// control points and adds the edit as a blend shape channel of that name
// (weight 0) on each geometry it moves: a Shape geometry, a
// BlendShapeChannel deformer (and a BlendShape deformer where the geometry
// has none), their connections and the Definitions' counts; `pose_record`
// (a JSON object's text, or empty) is kept in the channel's properties.
// The file is written in its own version (7.5 and later with 64-bit node
// headers); ASCII files are not written back (Errc::unsupported).
Status write_fbx(const FbxAsset& asset, std::span<const glm::dvec3> host_positions,
                 const std::string& morph_target, const std::string& pose_record, std::string& out);

}  // namespace dfm::mesh
