#include "dual/dual_laplacian.hpp"

#include <glm/geometric.hpp>

namespace dfm::dual {

void compute_centroids(const mesh::Mesh& mesh, std::span<const glm::dvec3> positions,
                       std::span<glm::dvec3> centroids) {
    for (std::size_t f = 0; f < mesh.face_count(); ++f)
        centroids[f] = centroid(mesh, positions, static_cast<std::uint32_t>(f));
}

namespace {

bool has_three(const std::array<std::uint32_t, 3>& n) {
    return n[0] != mesh::no_index && n[1] != mesh::no_index && n[2] != mesh::no_index;
}

// The plane's normal, unnormalised, and whether the ring spans a plane.
glm::dvec3 ring_cross(const std::array<std::uint32_t, 3>& n, std::span<const glm::dvec3> c,
                      bool& spans_plane) {
    const glm::dvec3 e1 = c[n[1]] - c[n[0]];
    const glm::dvec3 e2 = c[n[2]] - c[n[0]];
    const glm::dvec3 cross = glm::cross(e1, e2);
    const double scale = glm::dot(e1, e1) + glm::dot(e2, e2);
    spans_plane = glm::length(cross) > degenerate_ring_ratio * scale && scale > 0.0;
    return cross;
}

}  // namespace

DualLaplacian build_dual_laplacian(const mesh::Mesh& mesh, const mesh::EdgeTopology& topology) {
    const std::size_t m = mesh.face_count();
    DualLaplacian dual;
    dual.neighbors = topology.face_neighbors;
    dual.weights.assign(m, glm::dvec3(0.0));
    dual.heights.assign(m, 0.0);
    dual.has_row.assign(m, 0);
    std::vector<glm::dvec3> c(m);
    compute_centroids(mesh, mesh.positions, c);
    for (std::size_t f = 0; f < m; ++f) {
        const auto& n = dual.neighbors[f];
        if (!has_three(n)) {
            ++dual.boundary_faces;
            continue;
        }
        bool spans_plane = false;
        const glm::dvec3 cross = ring_cross(n, c, spans_plane);
        if (!spans_plane) {
            ++dual.degenerate_rings;
            continue;
        }
        const glm::dvec3 normal = glm::normalize(cross);
        const double h = glm::dot(c[f] - c[n[0]], normal);
        const glm::dvec3 foot = c[f] - h * normal;
        // Barycentric coordinates of the foot from sub-triangle areas, signed
        // along the normal so that a foot outside the ring gets negative
        // weights.
        const double area2 = glm::dot(cross, normal);
        const double w0 = glm::dot(glm::cross(c[n[1]] - foot, c[n[2]] - foot), normal) / area2;
        const double w1 = glm::dot(glm::cross(c[n[2]] - foot, c[n[0]] - foot), normal) / area2;
        dual.weights[f] = {w0, w1, 1.0 - w0 - w1};
        dual.heights[f] = h;
        dual.has_row[f] = 1;
    }
    return dual;
}

DualRow dual_row(const mesh::Mesh& mesh, const DualLaplacian& dual, std::uint32_t face) {
    DualRow row;
    auto add = [&row](std::uint32_t v, double c) {
        for (std::uint32_t k = 0; k < row.size; ++k) {
            if (row.vertices[k] == v) {
                row.coefficients[k] += c;
                return;
            }
        }
        row.vertices[row.size] = v;
        row.coefficients[row.size] = c;
        ++row.size;
    };
    for (std::uint32_t v : mesh.triangles[face]) add(v, -1.0 / 3.0);
    for (int j = 0; j < 3; ++j) {
        const double w = dual.weights[face][j] / 3.0;
        for (std::uint32_t v : mesh.triangles[dual.neighbors[face][j]]) add(v, w);
    }
    return row;
}

glm::dvec3 ring_normal(const DualLaplacian& dual, std::span<const glm::dvec3> centroids,
                       std::uint32_t face) {
    bool spans_plane = false;
    const glm::dvec3 cross = ring_cross(dual.neighbors[face], centroids, spans_plane);
    return spans_plane ? glm::normalize(cross) : glm::dvec3(0.0);
}

glm::dvec3 dual_coordinate(const DualLaplacian& dual, std::span<const glm::dvec3> centroids,
                           std::uint32_t face) {
    const auto& n = dual.neighbors[face];
    const glm::dvec3& w = dual.weights[face];
    return w[0] * centroids[n[0]] + w[1] * centroids[n[1]] + w[2] * centroids[n[2]] -
           centroids[face];
}

glm::dvec3 dual_coordinate_at(const mesh::Mesh& mesh, const DualLaplacian& dual,
                              std::span<const glm::dvec3> positions, std::uint32_t face) {
    const auto& n = dual.neighbors[face];
    const glm::dvec3& w = dual.weights[face];
    return w[0] * centroid(mesh, positions, n[0]) + w[1] * centroid(mesh, positions, n[1]) +
           w[2] * centroid(mesh, positions, n[2]) - centroid(mesh, positions, face);
}

}  // namespace dfm::dual
