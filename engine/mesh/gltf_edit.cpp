#include "mesh/gltf_edit.hpp"

#include <cmath>

#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

namespace dfm::mesh {

namespace {

// The smallest rotation taking unit `from` to unit `to`, applied to `v`
// (Rodrigues with the unnormalised axis from x to, |axis| = sin).
glm::dvec3 rotate_between(const glm::dvec3& from, const glm::dvec3& to, const glm::dvec3& v) {
    const glm::dvec3 axis = glm::cross(from, to);
    const double c = glm::dot(from, to);
    if (c < -1.0 + 1e-12) return -v;
    return v * c + glm::cross(axis, v) + axis * (glm::dot(axis, v) / (1.0 + c));
}

}  // namespace

EditedVertices edited_vertices(const GltfAsset& asset, std::span<const glm::dvec3> host_positions,
                               std::span<const Triangle> host_triangles) {
    const std::size_t n = asset.local_positions.size();
    EditedVertices e;
    e.moved.assign(n, false);
    e.dirty.assign(n, false);
    e.local_positions = asset.local_positions;
    e.normals = asset.normals;
    e.tangents = asset.tangents;
    std::vector<const GltfVertexRange*> range_of(n, nullptr);
    for (const GltfVertexRange& r : asset.ranges) {
        // An identity transform is skipped, not inverted: the inverse's
        // rounding would move positions that a reader expects exact.
        const bool identity = r.world == glm::dmat4(1.0);
        const glm::dmat4 inverse = identity ? r.world : glm::inverse(r.world);
        for (std::uint32_t v = r.first_vertex; v < r.first_vertex + r.count; ++v) {
            range_of[v] = &r;
            const glm::dvec3 rest = glm::dvec3(r.world * glm::dvec4(asset.local_positions[v], 1.0));
            if (rest == host_positions[v]) continue;
            e.moved[v] = true;
            e.dirty[v] = true;
            e.local_positions[v] = identity
                                       ? host_positions[v]
                                       : glm::dvec3(inverse * glm::dvec4(host_positions[v], 1.0));
        }
    }
    std::vector<glm::dvec3> sum(n, glm::dvec3(0.0));
    for (const Triangle& t : host_triangles) {
        const bool touched = e.moved[t[0]] || e.moved[t[1]] || e.moved[t[2]];
        if (!touched) continue;
        const glm::dvec3 f = glm::cross(host_positions[t[1]] - host_positions[t[0]],
                                        host_positions[t[2]] - host_positions[t[0]]);
        for (std::uint32_t v : t) {
            e.dirty[v] = true;
            sum[v] += f;
        }
    }
    for (std::size_t v = 0; v < n; ++v) {
        if (!e.dirty[v] || range_of[v] == nullptr || range_of[v]->normal.accessor < 0) continue;
        // World normals go back to local space by the transpose of the
        // linear part (the inverse of the normal matrix).
        const glm::dvec3 local = glm::transpose(glm::dmat3(range_of[v]->world)) * sum[v];
        const double len = glm::length(local);
        if (!(len > 0.0) || !std::isfinite(len)) continue;
        const glm::dvec3 old_normal = e.normals[v];
        const glm::dvec3 new_normal = local / len;
        e.normals[v] = new_normal;
        if (range_of[v]->tangent.accessor < 0) continue;
        const double old_len = glm::length(old_normal);
        if (!(old_len > 0.0)) continue;
        const glm::dvec3 turned =
            rotate_between(old_normal / old_len, new_normal, glm::dvec3(e.tangents[v]));
        e.tangents[v] = glm::dvec4(turned, e.tangents[v].w);
    }
    return e;
}

}  // namespace dfm::mesh
