#include <doctest/doctest.h>

#include <algorithm>
#include <iterator>
#include <vector>

#include "mesh/adjacency.hpp"
#include "roi/boundary.hpp"
#include "roi/rings.hpp"
#include "roi/set_ops.hpp"
#include "roi/vertex_list.hpp"
#include "support/procedural_meshes.hpp"

using namespace dfm;

namespace {

using Roi = std::vector<std::uint32_t>;

// Vertices within `k` edges of `center`, by breadth-first hop counts.
Roi hop_ball(const mesh::VertexAdjacency& a, std::uint32_t center, int k) {
    std::vector<int> hop(a.offsets.size() - 1, -1);
    Roi queue{center};
    hop[center] = 0;
    for (std::size_t h = 0; h < queue.size(); ++h) {
        for (std::uint32_t w : a.of(queue[h])) {
            if (hop[w] >= 0) continue;
            hop[w] = hop[queue[h]] + 1;
            queue.push_back(w);
        }
    }
    Roi out;
    for (std::uint32_t v = 0; v < hop.size(); ++v) {
        if (hop[v] >= 0 && hop[v] <= k) out.push_back(v);
    }
    return out;
}

struct Grid {
    mesh::Mesh mesh = test::make_grid(20, 20);
    mesh::VertexAdjacency adjacency = mesh::build_vertex_adjacency(mesh);
    std::uint32_t center = 10 * 21 + 10;
};

}  // namespace

TEST_CASE("roi: an explicit list is sorted, deduplicated and checked") {
    Roi out;
    const Roi list{7, 3, 7, 0};
    REQUIRE(roi::select_vertices(list, 8, out).is_ok());
    CHECK(out == Roi{0, 3, 7});
    const Status s = roi::select_vertices(list, 7, out);
    CHECK(s.code() == Errc::out_of_range);
    CHECK(s.message() == "vertices[0]: vertex 7 is out of range (the mesh has 7 vertices)");
    CHECK(out.empty());
}

TEST_CASE("roi: grow by k rings matches breadth-first hops") {
    const Grid g;
    Roi out;
    for (std::uint32_t k : {0u, 1u, 3u}) {
        REQUIRE(roi::grow_rings(g.adjacency, Roi{g.center}, k, out).is_ok());
        CHECK(out == hop_ball(g.adjacency, g.center, static_cast<int>(k)));
    }
    REQUIRE(roi::grow_rings(g.adjacency, Roi{0}, 1000, out).is_ok());
    CHECK(out.size() == g.mesh.vertex_count());
}

TEST_CASE("roi: shrink undoes grow away from the mesh border") {
    const Grid g;
    const Roi ball3 = hop_ball(g.adjacency, g.center, 3);
    Roi out;
    REQUIRE(roi::shrink_rings(g.adjacency, ball3, 1, out).is_ok());
    CHECK(out == hop_ball(g.adjacency, g.center, 2));
    REQUIRE(roi::shrink_rings(g.adjacency, ball3, 3, out).is_ok());
    CHECK(out == Roi{g.center});
    REQUIRE(roi::shrink_rings(g.adjacency, ball3, 4, out).is_ok());
    CHECK(out.empty());
    // A closed mesh taken whole has no border to shrink from.
    const mesh::Mesh sphere = test::make_icosphere(1);
    const auto sa = mesh::build_vertex_adjacency(sphere);
    Roi all(sphere.vertex_count());
    for (std::uint32_t v = 0; v < all.size(); ++v) all[v] = v;
    REQUIRE(roi::shrink_rings(sa, all, 2, out).is_ok());
    CHECK(out == all);
}

TEST_CASE("roi: boundary vertices are the ROI's outer ring") {
    const Grid g;
    Roi out;
    REQUIRE(roi::boundary_vertices(g.adjacency, hop_ball(g.adjacency, g.center, 3), out).is_ok());
    Roi ring3;
    const Roi b3 = hop_ball(g.adjacency, g.center, 3);
    const Roi b2 = hop_ball(g.adjacency, g.center, 2);
    std::set_difference(b3.begin(), b3.end(), b2.begin(), b2.end(), std::back_inserter(ring3));
    CHECK(out == ring3);
    REQUIRE(roi::boundary_vertices(g.adjacency, Roi{}, out).is_ok());
    CHECK(out.empty());
}

TEST_CASE("roi: union and difference") {
    Roi out;
    REQUIRE(roi::roi_union(Roi{1, 4, 6}, Roi{2, 4, 9}, 10, out).is_ok());
    CHECK(out == Roi{1, 2, 4, 6, 9});
    REQUIRE(roi::roi_difference(Roi{1, 4, 6}, Roi{2, 4, 9}, 10, out).is_ok());
    CHECK(out == Roi{1, 6});
    REQUIRE(roi::roi_difference(Roi{1, 4}, Roi{}, 10, out).is_ok());
    CHECK(out == Roi{1, 4});
}

TEST_CASE("roi: the tools reject a ROI that is not ascending or in range") {
    const Grid g;
    Roi out;
    Status s = roi::roi_union(Roi{1, 4}, Roi{5, 3}, 10, out);
    CHECK(s.code() == Errc::invalid_argument);
    CHECK(s.message() == "union.b[1]: the ROI must be strictly ascending, but 3 follows 5");
    s = roi::roi_difference(Roi{1, 10}, Roi{}, 10, out);
    CHECK(s.message() == "difference.a[1]: vertex 10 is out of range (the mesh has 10 vertices)");
    CHECK(roi::grow_rings(g.adjacency, Roi{2, 2}, 1, out).message().starts_with("grow[1]"));
    CHECK(roi::shrink_rings(g.adjacency, Roi{100000}, 1, out).message().starts_with("shrink[0]"));
    CHECK(roi::boundary_vertices(g.adjacency, Roi{3, 1}, out).message().starts_with("boundary[1]"));
}
