#include "mesh/mesh.hpp"

#include <glm/geometric.hpp>

namespace dfm::mesh {

double Bounds::diagonal() const {
    return empty ? 0.0 : glm::length(max - min);
}

Bounds compute_bounds(std::span<const glm::dvec3> points) {
    Bounds b;
    for (const glm::dvec3& p : points) {
        if (b.empty) {
            b.min = b.max = p;
            b.empty = false;
        } else {
            b.min = glm::min(b.min, p);
            b.max = glm::max(b.max, p);
        }
    }
    return b;
}

double triangle_area(const Mesh& mesh, std::size_t face) {
    return triangle_area(mesh, mesh.positions, face);
}

double triangle_area(const Mesh& mesh, std::span<const glm::dvec3> positions, std::size_t face) {
    const Triangle& t = mesh.triangles[face];
    const glm::dvec3& a = positions[t[0]];
    return 0.5 * glm::length(glm::cross(positions[t[1]] - a, positions[t[2]] - a));
}

}  // namespace dfm::mesh
