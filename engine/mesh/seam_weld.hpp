#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/status.hpp"
#include "mesh/mesh.hpp"

namespace dfm::mesh {

// How split copies of a vertex (for UVs, normals, materials) are found.
enum class WeldMode {
    none,       // every host vertex is its own surface vertex
    exact,      // copies have bit-identical positions
    tolerance,  // copies lie within WeldOptions::tolerance of each other
};

struct WeldOptions {
    WeldMode mode = WeldMode::exact;
    double tolerance = 0.0;  // absolute, in the mesh's units; tolerance mode only
};

// The host's vertices (split copies and all) against the surface vertices
// the engine works on. Surface vertex s has the copies
// copies[copy_offsets[s] .. copy_offsets[s + 1]), ascending; surface vertices
// are numbered in the order of their lowest copy, so "the lowest copy" keeps
// the surface's order.
struct SeamWeld {
    std::vector<std::uint32_t> surface_of;    // host vertex -> surface vertex
    std::vector<std::uint32_t> copy_offsets;  // surface count + 1 entries
    std::vector<std::uint32_t> copies;        // host vertices grouped by surface vertex
    std::vector<Triangle> host_triangles;     // the host's triangles, in its numbering
    std::vector<std::uint32_t> host_face_of;  // surface triangle -> host triangle
    // Positions where faces connect copies (the two sides of a surface edge)
    // whose attribute classes differ (weld_seams' `classes`): seams the
    // attributes keep open.
    std::size_t kept_apart = 0;

    std::size_t host_vertex_count() const { return surface_of.size(); }
    std::size_t surface_vertex_count() const {
        return copy_offsets.empty() ? 0 : copy_offsets.size() - 1;
    }
    std::uint32_t lowest_copy(std::uint32_t surface) const { return copies[copy_offsets[surface]]; }
    std::span<const std::uint32_t> copies_of(std::uint32_t surface) const {
        return {copies.data() + copy_offsets[surface], copies.data() + copy_offsets[surface + 1]};
    }
    // True when some surface vertex has more than one copy.
    bool splits() const { return host_vertex_count() != surface_vertex_count(); }
};

// Joins the copies of each surface vertex. Candidates are host vertices at
// the same position (within the tolerance); two of them are joined only when
// faces around that position connect them, i.e. two faces using them share a
// geometric edge (both endpoints at the same positions) that no third face
// uses. So two sheets that merely touch at a point stay two surface vertices
// and the surface stays manifold. Triangles the weld collapses (two corners
// joined) are left out of `surface`. `host_triangles` must index
// `host_positions`. `classes`, when not empty, gives each host vertex an
// attribute class (its skin, skin_weld.hpp): copies join only within one.
// Never throws but for std::bad_alloc.
void weld_seams(std::span<const glm::dvec3> host_positions,
                std::span<const Triangle> host_triangles, const WeldOptions& options, Mesh& surface,
                SeamWeld& weld, std::span<const std::uint32_t> classes = {});

}  // namespace dfm::mesh
