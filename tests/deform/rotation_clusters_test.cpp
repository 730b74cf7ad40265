// The coarse rotation field's clusters (rotation_clusters.hpp): seeds spread
// over the rows, every reached row's weights a partition of unity, the same
// clusters every time.
#include <doctest/doctest.h>

#include <cmath>

#include "deform/mesh_model.hpp"
#include "deform/rotation_clusters.hpp"
#include "support/procedural_meshes.hpp"

using namespace dfm;

namespace {

// Every face of a grid as a row, its neighbours across its edges.
std::vector<std::array<std::uint32_t, 3>> grid_rows(int nx, int ny) {
    const deform::MeshModel model = deform::build_mesh_model(test::make_grid(nx, ny));
    return model.topology.face_neighbors;
}

double weight_sum(const deform::RotationClusters& c, std::size_t row) {
    double sum = 0.0;
    for (const auto& m : c.of(row)) sum += m.weight;
    return sum;
}

}  // namespace

TEST_CASE("rotation clusters: every row blends a few clusters, weights summing to one") {
    const auto ring = grid_rows(40, 20);
    deform::RotationClusters clusters;
    clusters.build(ring, 16);
    CHECK(clusters.size() == 16);
    std::vector<std::size_t> rows_of(clusters.size(), 0);
    for (std::size_t r = 0; r < ring.size(); ++r) {
        CAPTURE(r);
        REQUIRE(!clusters.of(r).empty());
        CHECK(clusters.of(r).size() < clusters.size());
        CHECK(std::abs(weight_sum(clusters, r) - 1.0) < 1e-12);
        for (const auto& m : clusters.of(r)) {
            CHECK(m.weight > 0.0);
            ++rows_of[m.cluster];
        }
    }
    // Spread out: every cluster holds rows, none holds them all.
    for (const std::size_t n : rows_of) {
        CHECK(n > 0);
        CHECK(n < ring.size());
    }
}

TEST_CASE("rotation clusters: the same rows give the same clusters") {
    const auto ring = grid_rows(30, 30);
    deform::RotationClusters a;
    deform::RotationClusters b;
    a.build(ring, 16);
    b.build(ring, 16);
    for (std::size_t r = 0; r < ring.size(); ++r) {
        REQUIRE(a.of(r).size() == b.of(r).size());
        for (std::size_t k = 0; k < a.of(r).size(); ++k) {
            CHECK(a.of(r)[k].cluster == b.of(r)[k].cluster);
            CHECK(a.of(r)[k].weight == b.of(r)[k].weight);
        }
    }
}

TEST_CASE("rotation clusters: fewer rows than clusters, and parts no seed reaches") {
    const auto small = grid_rows(2, 1);  // four rows
    deform::RotationClusters c;
    c.build(small, 16);
    CHECK(c.size() == small.size());
    for (std::size_t r = 0; r < small.size(); ++r) CHECK(std::abs(weight_sum(c, r) - 1.0) < 1e-12);

    // Two grids side by side, no row joining them: two seeds reach both,
    // one seed leaves the second grid's rows to their own rotations.
    auto ring = grid_rows(6, 6);
    const std::size_t half = ring.size();
    for (std::size_t r = 0; r < half; ++r) {
        std::array<std::uint32_t, 3> shifted = ring[r];
        for (std::uint32_t& j : shifted) {
            if (j != mesh::no_index) j += static_cast<std::uint32_t>(half);
        }
        ring.push_back(shifted);
    }
    c.build(ring, 2);
    for (std::size_t r = 0; r < ring.size(); ++r) CHECK(!c.of(r).empty());
    c.build(ring, 1);
    for (std::size_t r = 0; r < half; ++r) CHECK(!c.of(r).empty());
    for (std::size_t r = half; r < ring.size(); ++r) CHECK(c.of(r).empty());
}
