#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace dfm::mesh {

// Where an accessor's elements lie in a buffer, for writing them in place:
// only when the accessor is dense, float and no other accessor, image or
// unclaimed buffer view reads those bytes. Otherwise the writer gives the
// accessor a new buffer view.
struct GltfSlot {
    int accessor = -1;  // -1: the attribute is absent
    bool in_place = false;
    int buffer = -1;
    std::size_t offset = 0;  // of element 0 in the buffer
    std::size_t stride = 0;
};

// The vertices of one POSITION accessor as loaded: host vertices
// [first_vertex, first_vertex + count), in the space of the first node that
// reached it (`world`; identity for a mesh chosen by #mesh= or a skinned
// one). NORMAL and TANGENT are those of the first primitive using it.
struct GltfVertexRange {
    int mesh = -1;
    int node = -1;  // the node that instances the mesh; -1 for a mesh chosen by #mesh=
    int skin = -1;  // that node's skin, -1 without one
    std::uint32_t first_vertex = 0;
    std::uint32_t count = 0;
    glm::dmat4 world{1.0};
    GltfSlot position, normal, tangent;
};

// One triangle primitive as loaded: host triangles
// [first_triangle, first_triangle + triangle_count).
struct GltfPrimitive {
    int mesh = -1;
    int primitive = -1;
    std::uint32_t range = 0;  // index into GltfAsset::ranges
    std::uint32_t first_triangle = 0;
    std::uint32_t triangle_count = 0;
};

// An animation sampler that drives morph weights, as loaded: a morph
// target added by a save widens its output by a zero column per key.
struct GltfWeightSampler {
    int animation = -1;
    int sampler = -1;
    int node = -1;            // the node whose weights its channel animates
    std::uint32_t width = 0;  // targets per key
    bool cubic_spline = false;
    std::vector<double> values;  // keys * width (* 3 for a cubic spline)
};

// What saving a glTF back needs: the document as it was (JSON text and
// buffer bytes, untouched), and where the loaded vertices came from, with
// their original local positions, normals and tangents in host order.
struct GltfAsset {
    std::string source;
    std::string json;
    std::vector<std::string> buffers;  // each buffer's bytes, as loaded
    std::vector<GltfVertexRange> ranges;
    std::vector<GltfPrimitive> primitives;
    std::vector<glm::dvec3> local_positions;
    std::vector<glm::dvec3> normals;   // zero where the range has no NORMAL
    std::vector<glm::dvec4> tangents;  // zero where the range has no TANGENT
    std::vector<GltfWeightSampler> weight_samplers;
};

}  // namespace dfm::mesh
