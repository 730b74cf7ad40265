#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "mesh/adjacency.hpp"
#include "mesh/mesh.hpp"

// The dual Laplacian of Au et al. (docs/design.md, "The dual
// Laplacian"). The dual vertex of face f is its centroid; its dual 1-ring
// is the centroids of the faces across its edges v0v1, v1v2, v2v0, in that
// order. Projecting the centroid onto the plane of its 1-ring gives the
// weights w_f (barycentric coordinates of the foot, summing to 1) and the
// signed height h_f along the plane's unit normal n_f, so that
//   l_f = sum_j w_fj c_fj - c_f = -h_f n_f.
namespace dfm::dual {

// Rest-pose quantities, fixed for a whole edit.
struct DualLaplacian {
    // Per face, the faces across its three edges (edge order); no_index where
    // an edge has no single neighbour (boundary, non-manifold).
    std::vector<std::array<std::uint32_t, 3>> neighbors;
    std::vector<glm::dvec3> weights;
    std::vector<double> heights;
    // A face has a row only with three neighbours whose centroids span a
    // plane; the others (open boundaries, degenerate 1-rings) have none.
    std::vector<std::uint8_t> has_row;
    std::size_t boundary_faces = 0;    // fewer than three neighbours
    std::size_t degenerate_rings = 0;  // three neighbours, collinear centroids
};

// A 1-ring counts as degenerate when the area of its centroid triangle is
// below this fraction of the squared distance scale of the ring.
inline constexpr double degenerate_ring_ratio = 1e-12;

DualLaplacian build_dual_laplacian(const mesh::Mesh& mesh, const mesh::EdgeTopology& topology);

// The dual vertex of `face`: its centroid for the given positions.
inline glm::dvec3 centroid(const mesh::Mesh& mesh, std::span<const glm::dvec3> positions,
                           std::uint32_t face) {
    const mesh::Triangle& t = mesh.triangles[face];
    return (positions[t[0]] + positions[t[1]] + positions[t[2]]) / 3.0;
}

void compute_centroids(const mesh::Mesh& mesh, std::span<const glm::dvec3> positions,
                       std::span<glm::dvec3> centroids);

// Row f of A = L~ D over the vertices: at most six distinct vertices.
struct DualRow {
    std::array<std::uint32_t, 6> vertices{};
    std::array<double, 6> coefficients{};
    std::uint32_t size = 0;
};

DualRow dual_row(const mesh::Mesh& mesh, const DualLaplacian& dual, std::uint32_t face);

// The unit normal of the plane through the centroids of f's 1-ring, or
// (0, 0, 0) when they are collinear.
glm::dvec3 ring_normal(const DualLaplacian& dual, std::span<const glm::dvec3> centroids,
                       std::uint32_t face);

// The dual Laplacian coordinate of f for the given centroids:
// sum_j w_fj c_fj - c_f.
glm::dvec3 dual_coordinate(const DualLaplacian& dual, std::span<const glm::dvec3> centroids,
                           std::uint32_t face);

// The same from the vertices' positions, with only the four centroids it
// needs (the same bits as dual_coordinate over compute_centroids): an edit
// of a few faces then costs nothing per face of the whole mesh.
glm::dvec3 dual_coordinate_at(const mesh::Mesh& mesh, const DualLaplacian& dual,
                              std::span<const glm::dvec3> positions, std::uint32_t face);

}  // namespace dfm::dual
