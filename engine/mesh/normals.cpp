#include "mesh/normals.hpp"

#include <cmath>

#include <glm/geometric.hpp>

namespace dfm::mesh {

void compute_vertex_normals(const Mesh& mesh, std::span<const glm::dvec3> positions,
                            std::vector<glm::dvec3>& normals) {
    normals.assign(positions.size(), glm::dvec3(0.0));
    for (const Triangle& t : mesh.triangles) {
        const glm::dvec3& a = positions[t[0]];
        // The cross product's length is twice the area: the weighting comes free.
        const glm::dvec3 n = glm::cross(positions[t[1]] - a, positions[t[2]] - a);
        for (std::uint32_t v : t) normals[v] += n;
    }
    for (glm::dvec3& n : normals) {
        const double len = glm::length(n);
        n = len > 0.0 && std::isfinite(len) ? n / len : glm::dvec3(0.0);
    }
}

}  // namespace dfm::mesh
