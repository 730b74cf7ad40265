#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/status.hpp"
#include "mesh/load.hpp"
#include "mesh/mesh.hpp"
#include "mesh/where.hpp"

namespace dfm::mesh {

// Collects what a reader parses and enforces what every format shares:
// finite coordinates, indices in range, polygons of a sane size, fan
// triangulation, and faces that repeat a vertex dropped with a warning.
// Vertices must come before the faces that use them.
class MeshBuilder {
public:
    explicit MeshBuilder(LoadReport& report) : report_(report) {}

    // Readers check declared counts against the bytes left before they call
    // this, so a header with absurd counts never causes a giant allocation.
    void reserve(std::uint64_t vertices, std::uint64_t polygons);

    Status add_vertex(const glm::dvec3& p, const Where& where);

    // Rejects a polygon size before its corners are read.
    Status check_polygon_size(std::uint64_t corners, const Where& where) const;

    // `corners` are 0-based vertex indices as the file gives them.
    Status add_polygon(std::span<const std::int64_t> corners, const Where& where);

    void warn(const Where& where, const std::string& what);

    std::size_t vertex_count() const { return mesh_.positions.size(); }
    std::size_t polygon_count() const { return polygons_; }

    Mesh take() { return std::move(mesh_); }

private:
    Mesh mesh_;
    LoadReport& report_;
    std::size_t polygons_ = 0;
    std::vector<std::uint32_t> ring_;
};

}  // namespace dfm::mesh
