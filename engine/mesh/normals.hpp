#pragma once

#include <span>
#include <vector>

#include "mesh/mesh.hpp"

namespace dfm::mesh {

// Area-weighted vertex normals of the triangles over `positions` (which may
// be a deformed copy of mesh.positions). A vertex in no triangle, or only in
// degenerate ones, gets (0, 0, 0).
void compute_vertex_normals(const Mesh& mesh, std::span<const glm::dvec3> positions,
                            std::vector<glm::dvec3>& normals);

}  // namespace dfm::mesh
