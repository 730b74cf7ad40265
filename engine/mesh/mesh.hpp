#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace dfm::mesh {

using Triangle = std::array<std::uint32_t, 3>;

// Marks "no vertex / no face" in index arrays (a boundary edge's missing
// neighbour, for instance).
inline constexpr std::uint32_t no_index = std::numeric_limits<std::uint32_t>::max();

// An indexed triangle mesh in flat arrays. Vertex order is the file's order:
// scenarios and hosts address vertices by these indices, so nothing reorders
// them. Positions are double so that the solver never loses the input's
// precision.
struct Mesh {
    std::vector<glm::dvec3> positions;
    std::vector<Triangle> triangles;

    std::size_t vertex_count() const { return positions.size(); }
    std::size_t face_count() const { return triangles.size(); }
};

struct Bounds {
    glm::dvec3 min{0.0};
    glm::dvec3 max{0.0};
    bool empty = true;

    double diagonal() const;
};

Bounds compute_bounds(std::span<const glm::dvec3> points);

double triangle_area(const Mesh& mesh, std::size_t face);
// The same triangle's area with its corners at `positions` (one per vertex).
double triangle_area(const Mesh& mesh, std::span<const glm::dvec3> positions, std::size_t face);

}  // namespace dfm::mesh
