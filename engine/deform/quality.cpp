#include "deform/quality.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

namespace dfm::deform {

namespace {

glm::dvec3 face_normal(const mesh::Triangle& t, std::span<const glm::dvec3> p) {
    const glm::dvec3 n = glm::cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]]);
    const double len = glm::length(n);
    return len > 0.0 ? n / len : glm::dvec3(0.0);
}

// The signed angle between the normals of the faces on either side of edge
// a → b, about that edge: 0 where they are flat, ±180° where folded shut.
// (cos, sin) of it, both scaled by the same positive factor.
glm::dvec2 dihedral(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& left,
                    const glm::dvec3& right) {
    const glm::dvec3 edge = b - a;
    const glm::dvec3 n1 = glm::cross(edge, left - a);
    const glm::dvec3 n2 = glm::cross(right - a, edge);
    return {glm::dot(n1, n2) * glm::length(edge), glm::dot(glm::cross(n1, n2), edge)};
}

}  // namespace

QualityReport measure_quality(const MeshModel& model, std::span<const glm::dvec3> deformed,
                              std::span<const std::uint8_t> in_roi,
                              std::span<const std::uint32_t> handle_vertices,
                              std::span<const glm::dvec3> targets) {
    const mesh::Mesh& mesh = model.mesh;
    const std::span<const glm::dvec3> rest = mesh.positions;
    const double diag = model.diagonal > 0.0 ? model.diagonal : 1.0;
    QualityReport q;

    for (std::size_t h = 0; h < handle_vertices.size(); ++h) {
        q.max_handle_error = std::max(
            q.max_handle_error, glm::length(deformed[handle_vertices[h]] - targets[h]) / diag);
    }

    double log_sum = 0.0;
    std::size_t edges = 0;
    for (const auto& e : model.topology.edges) {
        if (!in_roi[e[0]] && !in_roi[e[1]]) continue;
        const double before = glm::length(rest[e[0]] - rest[e[1]]);
        const double after = glm::length(deformed[e[0]] - deformed[e[1]]);
        if (before <= 0.0) continue;
        const double l = after > 0.0 ? std::abs(std::log(after / before))
                                     : std::numeric_limits<double>::infinity();
        log_sum += l;
        q.max_abs_log_edge = std::max(q.max_abs_log_edge, l);
        ++edges;
    }
    q.mean_abs_log_edge = edges > 0 ? log_sum / static_cast<double>(edges) : 0.0;

    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        if (!in_roi[v])
            q.max_fixed_move =
                std::max(q.max_fixed_move, glm::length(deformed[v] - rest[v]) / diag);
    }

    std::vector<glm::dvec3> new_c(mesh.face_count());
    dual::compute_centroids(mesh, deformed, new_c);
    double angle_sum = 0.0;
    std::size_t faces = 0;
    double magnitude_error = 0.0;
    double magnitude_sum = 0.0;
    std::size_t dual_faces = 0;
    for (std::uint32_t f = 0; f < mesh.face_count(); ++f) {
        const mesh::Triangle& t = mesh.triangles[f];
        if (!in_roi[t[0]] && !in_roi[t[1]] && !in_roi[t[2]]) continue;
        const double cosine =
            std::clamp(glm::dot(face_normal(t, rest), face_normal(t, deformed)), -1.0, 1.0);
        const double degrees = std::acos(cosine) * 180.0 / std::numbers::pi;
        angle_sum += degrees;
        if (degrees > 90.0) ++q.flipped_faces;
        ++faces;
        if (!model.dual.has_row[f]) continue;
        const double h = std::abs(model.dual.heights[f]);
        magnitude_error += std::abs(glm::length(dual::dual_coordinate(model.dual, new_c, f)) - h);
        magnitude_sum += h;
        ++dual_faces;
    }
    // A fold turns the dihedral angle at its crease by about 180°; a rigid
    // motion or a smooth bend turns none by 90°.
    for (std::uint32_t f = 0; f < mesh.face_count(); ++f) {
        const mesh::Triangle& t = mesh.triangles[f];
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t g = model.topology.face_neighbors[f][k];
            const std::uint32_t a = t[k];
            const std::uint32_t b = t[(k + 1) % 3];
            if (g == mesh::no_index || g < f || !in_roi[a] || !in_roi[b]) continue;
            const std::uint32_t c = t[(k + 2) % 3];
            const mesh::Triangle& u = mesh.triangles[g];
            const std::uint32_t d = u[0] != a && u[0] != b   ? u[0]
                                    : u[1] != a && u[1] != b ? u[1]
                                                             : u[2];
            // The turn's cosine, cos(new − rest), up to a positive factor.
            const glm::dvec2 now = dihedral(deformed[a], deformed[b], deformed[c], deformed[d]);
            const glm::dvec2 before = dihedral(rest[a], rest[b], rest[c], rest[d]);
            if (glm::dot(now, before) < 0.0) ++q.creased_edges;
        }
    }
    q.mean_normal_change_deg = faces > 0 ? angle_sum / static_cast<double>(faces) : 0.0;
    q.dual_magnitude_error = magnitude_sum > 0.0 ? magnitude_error / magnitude_sum : 0.0;
    return q;
}

}  // namespace dfm::deform
