#include "mesh/mesh_builder.hpp"

#include <cmath>

namespace dfm::mesh {

void MeshBuilder::reserve(std::uint64_t vertices, std::uint64_t polygons) {
    mesh_.positions.reserve(vertices);
    mesh_.triangles.reserve(polygons);
}

Status MeshBuilder::add_vertex(const glm::dvec3& p, const Where& where) {
    const std::size_t index = mesh_.positions.size();
    for (int axis = 0; axis < 3; ++axis) {
        if (!std::isfinite(p[axis])) {
            return where.parse_error("vertex " + std::to_string(index) + ": " +
                                     static_cast<char>('x' + axis) +
                                     " coordinate is not a finite number");
        }
    }
    if (index >= no_index) {
        return where.error(Errc::out_of_range, "vertex " + std::to_string(index) +
                                                   ": more vertices than 32-bit indices address");
    }
    mesh_.positions.push_back(p);
    return Status::ok();
}

Status MeshBuilder::check_polygon_size(std::uint64_t corners, const Where& where) const {
    if (corners >= 3 && corners <= mesh_.positions.size()) return Status::ok();
    const std::string face = "face " + std::to_string(polygons_) + ": ";
    if (corners < 3) {
        return where.parse_error(face + "has " + std::to_string(corners) +
                                 " vertices; a face needs at least 3");
    }
    if (corners > mesh_.positions.size()) {
        return where.error(Errc::out_of_range,
                           face + "has " + std::to_string(corners) + " vertices, more than the " +
                               std::to_string(mesh_.positions.size()) + " the mesh has");
    }
    return Status::ok();
}

Status MeshBuilder::add_polygon(std::span<const std::int64_t> corners, const Where& where) {
    if (Status s = check_polygon_size(corners.size(), where); !s) return s;
    const std::size_t index = polygons_;
    const auto face = [index] { return "face " + std::to_string(index); };
    const auto n = static_cast<std::int64_t>(mesh_.positions.size());
    ring_.clear();
    for (std::size_t k = 0; k < corners.size(); ++k) {
        const std::int64_t i = corners[k];
        if (i < 0 || i >= n) {
            return where.error(Errc::out_of_range, face() + ": vertex index " + std::to_string(i) +
                                                       " is out of range (the mesh has " +
                                                       std::to_string(n) +
                                                       " vertices, indexed from 0)");
        }
        const auto v = static_cast<std::uint32_t>(i);
        if (ring_.empty() || ring_.back() != v) ring_.push_back(v);
    }
    while (ring_.size() > 1 && ring_.front() == ring_.back()) ring_.pop_back();
    ++polygons_;
    ++report_.polygons;
    if (corners.size() > 3) ++report_.triangulated_polygons;

    std::size_t dropped = 0;
    if (ring_.size() < 3) {
        dropped = corners.size() - 2;
    } else {
        for (std::size_t k = 1; k + 1 < ring_.size(); ++k) {
            const Triangle t{ring_[0], ring_[k], ring_[k + 1]};
            if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
                ++dropped;
            } else {
                mesh_.triangles.push_back(t);
            }
        }
    }
    if (dropped > 0) {
        report_.dropped_faces += dropped;
        warn(where, face() + ": repeats a vertex; " + std::to_string(dropped) +
                        (dropped == 1 ? " triangle" : " triangles") + " dropped");
    }
    return Status::ok();
}

void MeshBuilder::warn(const Where& where, const std::string& what) {
    report_.warn(where.prefix() + what);
}

}  // namespace dfm::mesh
