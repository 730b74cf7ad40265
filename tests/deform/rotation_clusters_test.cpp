// The coarse rotation field's clusters (rotation_clusters.hpp): rows in
// patches of neighbours, seeds spread over the patches, every reached
// patch's weights a partition of unity, the same clusters every time.
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

double weight_sum(const deform::RotationClusters& c, std::size_t patch) {
    double sum = 0.0;
    for (const auto& m : c.of(patch)) sum += m.weight;
    return sum;
}

}  // namespace

TEST_CASE("rotation clusters: rows in patches of neighbours, each patch blending a few clusters") {
    const auto ring = grid_rows(40, 20);  // 1,600 rows
    deform::RotationClusters clusters;
    clusters.build(ring, 16, 100);
    CHECK(clusters.size() == 16);
    // Patches of 16 rows where they could grow so far, never larger.
    std::vector<std::size_t> rows_in(clusters.patch_count(), 0);
    for (std::size_t r = 0; r < ring.size(); ++r) ++rows_in[clusters.patch_of(r)];
    CHECK(clusters.patch_count() >= 100);
    CHECK(clusters.patch_count() < 200);
    for (const std::size_t n : rows_in) CHECK((n >= 1 && n <= 16));
    // A patch's rows are connected: each but the first has a neighbour in
    // the patch.
    for (std::size_t r = 0; r < ring.size(); ++r) {
        bool alone = true;
        for (const std::uint32_t j : ring[r]) {
            if (j != mesh::no_index && clusters.patch_of(j) == clusters.patch_of(r)) alone = false;
        }
        if (rows_in[clusters.patch_of(r)] > 1) CHECK(!alone);
    }
    std::vector<std::size_t> patches_of(clusters.size(), 0);
    for (std::size_t p = 0; p < clusters.patch_count(); ++p) {
        CAPTURE(p);
        REQUIRE(!clusters.of(p).empty());
        CHECK(clusters.of(p).size() < clusters.size());
        CHECK(std::abs(weight_sum(clusters, p) - 1.0) < 1e-12);
        for (const auto& m : clusters.of(p)) {
            CHECK(m.weight > 0.0);
            ++patches_of[m.cluster];
        }
    }
    // Spread out: every cluster holds patches, none holds them all.
    for (const std::size_t n : patches_of) {
        CHECK(n > 0);
        CHECK(n < clusters.patch_count());
    }
}

TEST_CASE("rotation clusters: the same rows give the same clusters") {
    const auto ring = grid_rows(30, 30);
    deform::RotationClusters a;
    deform::RotationClusters b;
    a.build(ring, 16, 256);
    b.build(ring, 16, 256);
    REQUIRE(a.patch_count() == b.patch_count());
    for (std::size_t r = 0; r < ring.size(); ++r) CHECK(a.patch_of(r) == b.patch_of(r));
    for (std::size_t p = 0; p < a.patch_count(); ++p) {
        REQUIRE(a.of(p).size() == b.of(p).size());
        for (std::size_t k = 0; k < a.of(p).size(); ++k) {
            CHECK(a.of(p)[k].cluster == b.of(p)[k].cluster);
            CHECK(a.of(p)[k].weight == b.of(p)[k].weight);
        }
    }
}

TEST_CASE("rotation clusters: fewer rows than patches and clusters, and parts no seed reaches") {
    const auto small = grid_rows(2, 1);  // four rows: a patch each, a cluster each
    deform::RotationClusters c;
    c.build(small, 16, 256);
    CHECK(c.patch_count() == small.size());
    CHECK(c.size() == small.size());
    for (std::size_t p = 0; p < c.patch_count(); ++p)
        CHECK(std::abs(weight_sum(c, p) - 1.0) < 1e-12);

    // Two grids side by side, no row joining them: two seeds reach both,
    // one seed leaves the second grid's patches to their rows' own rotations.
    auto ring = grid_rows(6, 6);
    const std::size_t half = ring.size();
    for (std::size_t r = 0; r < half; ++r) {
        std::array<std::uint32_t, 3> shifted = ring[r];
        for (std::uint32_t& j : shifted) {
            if (j != mesh::no_index) j += static_cast<std::uint32_t>(half);
        }
        ring.push_back(shifted);
    }
    c.build(ring, 2, 8);
    for (std::size_t r = 0; r < ring.size(); ++r) CHECK(!c.of(c.patch_of(r)).empty());
    c.build(ring, 1, 8);
    for (std::size_t r = 0; r < half; ++r) CHECK(!c.of(c.patch_of(r)).empty());
    for (std::size_t r = half; r < ring.size(); ++r) CHECK(c.of(c.patch_of(r)).empty());
}
