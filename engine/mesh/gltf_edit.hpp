#pragma once

#include <functional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "mesh/gltf_asset.hpp"
#include "mesh/mesh.hpp"

namespace dfm::mesh {

// What an edit changed, per host vertex, in each range's local space.
struct EditedVertices {
    std::vector<bool> moved;  // the position differs from the asset's
    std::vector<bool> dirty;  // moved, or a face using it has a moved corner
    std::vector<glm::dvec3> local_positions;
    // The asset's normal and tangent where not dirty; where dirty the normal
    // is recomputed from the faces using that very copy (area-weighted, so
    // copies on the two sides of a hard edge keep their own) and the tangent
    // turned with it, its w kept.
    std::vector<glm::dvec3> normals;
    std::vector<glm::dvec4> tangents;
};

EditedVertices edited_vertices(const GltfAsset& asset, std::span<const glm::dvec3> host_positions,
                               std::span<const Triangle> host_triangles);

// Appends a dense float accessor (components 1, 3 or 4, with bounds when
// asked) and returns its index.
using AppendAccessor = std::function<int(const std::vector<float>&, int, bool)>;

// Adds the edit as a morph target named `name` to every primitive of each
// mesh the edit touches (POSITION and, where the primitive has normals,
// NORMAL deltas; zero deltas on the mesh's other primitives, since all of a
// mesh's primitives must have the same targets), extending mesh and node
// weights with 0 and mesh.extras.targetNames with the name, and giving
// every animation sampler that drives those meshes' weights a new output
// with a zero column for it (the old output accessor is left as it was).
// `extras`, a JSON object's text or empty, becomes the extras of the new
// POSITION deltas' accessor (what a posed edit records of its pose). The
// base positions stay as they were.
void add_morph_target(const GltfAsset& asset, const EditedVertices& edit, const std::string& name,
                      const std::string& extras, nlohmann::json& doc, const AppendAccessor& append);

}  // namespace dfm::mesh
