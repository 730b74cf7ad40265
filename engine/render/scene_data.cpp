#include "render/scene_data.hpp"

#include <cmath>
#include <cstring>
#include <string>

#include <glm/common.hpp>

#include "mesh/normals.hpp"

namespace dfm::render {

namespace {

bool finite(const glm::dvec3& p) {
    return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

Status check_positions(const StridedPositions& p) {
    if (p.count > 0 && p.data == nullptr) {
        return Status(Errc::invalid_argument, "positions: data is NULL");
    }
    const std::size_t triple = p.is_double ? 3 * sizeof(double) : 3 * sizeof(float);
    if (p.stride != 0 && p.stride < triple) {
        return Status(Errc::invalid_argument, "positions: stride " + std::to_string(p.stride) +
                                                  " is smaller than one xyz triple (" +
                                                  std::to_string(triple) + " bytes)");
    }
    return Status::ok();
}

}  // namespace

glm::dvec3 StridedPositions::at(std::size_t i) const {
    const std::size_t triple = is_double ? 3 * sizeof(double) : 3 * sizeof(float);
    const auto* base = static_cast<const unsigned char*>(data) + i * (stride ? stride : triple);
    if (is_double) {
        double v[3];
        std::memcpy(v, base, sizeof v);
        return {v[0], v[1], v[2]};
    }
    float v[3];
    std::memcpy(v, base, sizeof v);
    return {v[0], v[1], v[2]};
}

Status SceneData::read_positions(const StridedPositions& positions) {
    if (Status s = check_positions(positions); !s) return s;
    std::vector<glm::dvec3> read(positions.count);
    for (std::size_t i = 0; i < positions.count; ++i) {
        read[i] = positions.at(i);
        if (!finite(read[i])) {
            return Status(Errc::invalid_argument,
                          "positions: vertex " + std::to_string(i) + " is not finite");
        }
    }
    mesh_.positions = std::move(read);
    return Status::ok();
}

Status SceneData::set_mesh(const StridedPositions& positions,
                           std::span<const std::uint32_t> triangle_indices) {
    if (positions.count == 0 || triangle_indices.empty()) {
        return Status(Errc::invalid_argument, "mesh: no vertices or no triangles");
    }
    if (triangle_indices.size() % 3 != 0) {
        return Status(Errc::invalid_argument, "mesh: the index count is not a multiple of 3");
    }
    if (positions.count > UINT32_MAX || triangle_indices.size() > UINT32_MAX) {
        return Status(Errc::invalid_argument, "mesh: more than 2^32 vertices or indices");
    }
    for (std::size_t i = 0; i < triangle_indices.size(); ++i) {
        if (triangle_indices[i] >= positions.count) {
            return Status(Errc::invalid_argument,
                          "mesh: index " + std::to_string(i) + " names vertex " +
                              std::to_string(triangle_indices[i]) + ", past the " +
                              std::to_string(positions.count) + " vertices");
        }
    }
    mesh::Mesh previous = std::move(mesh_);
    if (Status s = read_positions(positions); !s) {
        mesh_ = std::move(previous);
        return s;
    }
    mesh_.triangles.resize(triangle_indices.size() / 3);
    std::memcpy(mesh_.triangles.data(), triangle_indices.data(),
                triangle_indices.size() * sizeof(std::uint32_t));
    marks_.assign(positions.count, 0);
    mesh::compute_vertex_normals(mesh_, mesh_.positions, normals_);
    update_bounds();
    return Status::ok();
}

Status SceneData::set_positions(const StridedPositions& positions) {
    if (!has_mesh()) return Status(Errc::invalid_argument, "positions: no mesh set");
    if (positions.count != mesh_.positions.size()) {
        return Status(Errc::invalid_argument, "positions: " + std::to_string(positions.count) +
                                                  " vertices given, the mesh has " +
                                                  std::to_string(mesh_.positions.size()));
    }
    if (Status s = read_positions(positions); !s) return s;
    mesh::compute_vertex_normals(mesh_, mesh_.positions, normals_);
    update_bounds();
    return Status::ok();
}

Status SceneData::set_marks(std::span<const std::uint8_t> marks) {
    if (marks.empty()) {
        marks_.assign(mesh_.positions.size(), 0);
        return Status::ok();
    }
    if (marks.size() != mesh_.positions.size()) {
        return Status(Errc::invalid_argument,
                      "marks: " + std::to_string(marks.size()) + " given, the mesh has " +
                          std::to_string(mesh_.positions.size()) + " vertices");
    }
    for (std::size_t i = 0; i < marks.size(); ++i) {
        if (marks[i] > static_cast<std::uint8_t>(Mark::fixed)) {
            return Status(Errc::invalid_argument, "marks: vertex " + std::to_string(i) +
                                                      " has mark " + std::to_string(marks[i]) +
                                                      " (0 to 3 allowed)");
        }
    }
    marks_.assign(marks.begin(), marks.end());
    return Status::ok();
}

Status SceneData::set_lines(std::span<const Polyline> lines) {
    std::vector<LineVertex> vertices;
    for (std::size_t l = 0; l < lines.size(); ++l) {
        const Polyline& line = lines[l];
        for (const glm::dvec3& p : line.points) {
            if (!finite(p)) {
                return Status(Errc::invalid_argument,
                              "lines: polyline " + std::to_string(l) + " has a non-finite point");
            }
        }
        const std::size_t n = line.points.size();
        const std::size_t segments = n < 2 ? 0 : (line.closed && n > 2 ? n : n - 1);
        for (std::size_t s = 0; s < segments; ++s) {
            for (const glm::dvec3& p : {line.points[s], line.points[(s + 1) % n]}) {
                LineVertex v{};
                v.position[0] = static_cast<float>(p.x);
                v.position[1] = static_cast<float>(p.y);
                v.position[2] = static_cast<float>(p.z);
                for (int c = 0; c < 4; ++c) v.color[c] = line.color[c];
                vertices.push_back(v);
            }
        }
    }
    line_vertices_ = std::move(vertices);
    update_bounds();
    return Status::ok();
}

std::span<const std::uint32_t> SceneData::indices() const {
    return {mesh_.triangles.empty() ? nullptr : mesh_.triangles.front().data(),
            mesh_.triangles.size() * 3};
}

void SceneData::update_bounds() {
    bounds_ = mesh::compute_bounds(mesh_.positions);
    for (const LineVertex& v : line_vertices_) {
        const glm::dvec3 p(v.position[0], v.position[1], v.position[2]);
        if (bounds_.empty) {
            bounds_.min = bounds_.max = p;
            bounds_.empty = false;
        }
        bounds_.min = glm::min(bounds_.min, p);
        bounds_.max = glm::max(bounds_.max, p);
    }
}

void SceneData::pack_vertices(MeshVertex* out) const {
    for (std::size_t i = 0; i < mesh_.positions.size(); ++i) {
        const glm::dvec3& p = mesh_.positions[i];
        const glm::dvec3& n = normals_[i];
        out[i] =
            MeshVertex{{static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)},
                       {static_cast<float>(n.x), static_cast<float>(n.y), static_cast<float>(n.z)},
                       marks_[i]};
    }
}

}  // namespace dfm::render
