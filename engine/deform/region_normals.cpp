#include "deform/region_normals.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace dfm::deform {

namespace {

glm::dvec3 face_cross(std::span<const glm::dvec3> p, const mesh::Triangle& t) {
    return glm::cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]]);
}

}  // namespace

void RegionNormals::build(const MeshModel& model, std::span<const std::uint32_t> moving) {
    model_ = &model;
    const std::size_t n = model.mesh.vertex_count();
    std::vector<std::uint8_t> face_moves(model.mesh.face_count(), 0);
    for (std::uint32_t v : moving) {
        for (std::uint32_t f : model.faces_of(v)) face_moves[f] = 1;
    }
    faces_.clear();
    // Per mesh vertex: its index in vertices_, or `unaffected`; a direct
    // look-up, where a binary search per face corner took most of the build.
    constexpr std::uint32_t unaffected = ~std::uint32_t{0};
    std::vector<std::uint32_t> slot(n, unaffected);
    for (std::uint32_t f = 0; f < face_moves.size(); ++f) {
        if (face_moves[f] == 0) continue;
        faces_.push_back(f);
        for (std::uint32_t v : model.mesh.triangles[f]) slot[v] = 0;
    }
    vertices_.clear();
    for (std::uint32_t v = 0; v < n; ++v) {
        if (slot[v] == unaffected) continue;
        slot[v] = static_cast<std::uint32_t>(vertices_.size());
        vertices_.push_back(v);
    }
    slot_of_vertex_.resize(3 * faces_.size());
    for (std::size_t i = 0; i < faces_.size(); ++i) {
        const mesh::Triangle& t = model.mesh.triangles[faces_[i]];
        for (int c = 0; c < 3; ++c) slot_of_vertex_[3 * i + c] = slot[t[c]];
    }
    const std::span<const glm::dvec3> rest = model.mesh.positions;
    rest_sum_.assign(vertices_.size(), glm::dvec3(0.0));
    for (std::size_t k = 0; k < vertices_.size(); ++k) {
        for (std::uint32_t f : model.faces_of(vertices_[k])) {
            if (face_moves[f] == 0) rest_sum_[k] += face_cross(rest, model.mesh.triangles[f]);
        }
    }
}

void RegionNormals::compute(std::span<const glm::dvec3> positions,
                            std::span<glm::dvec3> normals) const {
    std::copy(rest_sum_.begin(), rest_sum_.end(), normals.begin());
    for (std::size_t i = 0; i < faces_.size(); ++i) {
        const glm::dvec3 n = face_cross(positions, model_->mesh.triangles[faces_[i]]);
        for (int c = 0; c < 3; ++c) normals[slot_of_vertex_[3 * i + c]] += n;
    }
    for (std::size_t k = 0; k < vertices_.size(); ++k) {
        const double len = glm::length(normals[k]);
        normals[k] = len > 0.0 && std::isfinite(len) ? normals[k] / len : glm::dvec3(0.0);
    }
}

}  // namespace dfm::deform
