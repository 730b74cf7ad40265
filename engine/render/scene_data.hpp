#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "mesh/mesh.hpp"
#include "render/vulkan_result.hpp"

namespace dfm::render {

// Positions as a host holds them: xyz triples of float or double, `stride`
// bytes apart (at least the triple's size).
struct StridedPositions {
    const void* data = nullptr;
    std::size_t count = 0;
    std::size_t stride = 0;
    bool is_double = false;

    glm::dvec3 at(std::size_t i) const;
};

// Per-vertex highlight, as the shaders colour it.
enum class Mark : std::uint8_t { surface = 0, roi = 1, handle = 2, fixed = 3 };

// The vertex the surface pipelines read (28 bytes, matches mesh.vert).
struct MeshVertex {
    float position[3];
    float normal[3];
    std::uint32_t mark;
};

// The vertex of the host's lines (matches line.vert).
struct LineVertex {
    float position[3];
    float color[4];
};

struct Polyline {
    std::vector<glm::dvec3> points;
    bool closed = false;
    glm::vec4 color{1.0f, 0.85f, 0.1f, 1.0f};
};

// What is drawn, on the CPU side: the mesh, its current positions and smooth
// normals (recomputed whenever the positions change), the marks, and the
// host's lines as a line list. No Vulkan here.
class SceneData {
public:
    // Replaces the mesh; marks reset to surface, lines are kept.
    Status set_mesh(const StridedPositions& positions,
                    std::span<const std::uint32_t> triangle_indices);
    // New positions for the same vertices (count must match).
    Status set_positions(const StridedPositions& positions);
    // One mark per vertex (values 0..3), or empty to clear them.
    Status set_marks(std::span<const std::uint8_t> marks);
    Status set_lines(std::span<const Polyline> lines);

    bool has_mesh() const { return !mesh_.triangles.empty(); }
    std::size_t vertex_count() const { return mesh_.positions.size(); }
    std::uint32_t index_count() const {
        return static_cast<std::uint32_t>(mesh_.triangles.size() * 3);
    }
    std::span<const std::uint32_t> indices() const;
    std::span<const LineVertex> line_vertices() const { return line_vertices_; }
    // Bounds of the current positions and the lines.
    const mesh::Bounds& bounds() const { return bounds_; }

    // Writes vertex_count() MeshVertex values.
    void pack_vertices(MeshVertex* out) const;

private:
    Status read_positions(const StridedPositions& positions);
    void update_bounds();

    mesh::Mesh mesh_;
    std::vector<glm::dvec3> normals_;
    std::vector<std::uint8_t> marks_;
    std::vector<LineVertex> line_vertices_;
    mesh::Bounds bounds_;
};

}  // namespace dfm::render
