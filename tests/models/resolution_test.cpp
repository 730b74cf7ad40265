// The default method at every level of detail (docs/method.md): the same
// edit of the armadillo's leg, Loop-subdivided 0, 1 and 2 times, converges
// in about as many iterations and takes about the same shape, and a jump of
// the handles on the whole armadillo converges in a few iterations.
#include <doctest/doctest.h>

#include <numeric>

#include <glm/geometric.hpp>

#include "deform/deform_session.hpp"
#include "deform/quality.hpp"
#include "mesh/subdivide.hpp"
#include "support/real_models.hpp"

using namespace dfm;

namespace {

// The armadillo's lowest vertex, where the scale scenarios grab its leg.
constexpr std::uint32_t foot = 17208;
constexpr std::size_t base_vertices = 26002;

struct LegEdit {
    int iterations = 0;
    bool converged = false;
    deform::QualityReport quality;
    std::vector<glm::dvec3> displacement;  // of the base vertices, in base diagonals
};

// scale-armadillo-leg at `level`: ROI ball 0.2 and handle ball 0.04 around
// the foot, the handle moved by 0.1 of the diagonal along x.
LegEdit edit_leg(const mesh::Mesh& base, int level, double base_diagonal) {
    mesh::Mesh m = base;
    for (int k = 0; k < level; ++k) m = mesh::subdivide_loop(m);
    const deform::MeshModel model = deform::build_mesh_model(std::move(m));
    const std::vector<std::uint32_t> roi = test::ball_around(model, foot, 0.2);
    const std::vector<std::vector<std::uint32_t>> groups = {test::ball_around(model, foot, 0.04)};
    std::unique_ptr<deform::DeformSession> s;
    REQUIRE(deform::DeformSession::create(model, roi, groups, {}, s).is_ok());
    std::vector<glm::dvec3> targets(s->targets().begin(), s->targets().end());
    for (glm::dvec3& t : targets) t.x += 0.1 * model.diagonal;
    REQUIRE(s->set_targets(targets).is_ok());
    deform::SolveReport r;
    REQUIRE(s->solve(r).is_ok());
    std::vector<std::uint8_t> in_roi(model.mesh.vertex_count(), 0);
    for (const std::uint32_t v : roi) in_roi[v] = 1;
    LegEdit out;
    out.iterations = r.iterations;
    out.converged = r.converged;
    out.quality =
        deform::measure_quality(model, s->positions(), in_roi, s->handle_vertices(), s->targets());
    for (std::size_t v = 0; v < base_vertices; ++v) {
        out.displacement.push_back((s->positions()[v] - model.mesh.positions[v]) / base_diagonal);
    }
    return out;
}

}  // namespace

TEST_CASE("resolution: the armadillo's leg at 26k, 104k and 416k vertices, one edit, one shape") {
    const deform::MeshModel armadillo = test::load_real_model("armadillo");
    REQUIRE(armadillo.mesh.vertex_count() == base_vertices);
    std::vector<LegEdit> levels;
    for (int level = 0; level <= 2; ++level) {
        levels.push_back(edit_leg(armadillo.mesh, level, armadillo.diagonal));
        const LegEdit& e = levels.back();
        CAPTURE(level);
        CAPTURE(e.iterations);
        CHECK(e.converged);
        CHECK(e.iterations <= 30);
        CHECK(e.quality.flipped_faces == 0);
        CHECK(e.quality.creased_edges == 0);
    }
    CHECK(levels[2].iterations <= 1.5 * levels[0].iterations);
    // The base vertices keep their indices through Loop subdivision: where
    // the 26k edit moved them, the finer edits move them alike. (The
    // paper's method differs by 0.0014 and 0.0018 on average, 0.0041 and
    // 0.0049 at most; the default by 0.0018 and 0.0022, 0.0043 and 0.0049,
    // where before the balance it differed by 0.0044 and 0.0095.)
    for (int level = 1; level <= 2; ++level) {
        double sum = 0.0;
        double largest = 0.0;
        std::size_t moved = 0;
        for (std::size_t v = 0; v < base_vertices; ++v) {
            if (levels[0].displacement[v] == glm::dvec3(0.0)) continue;
            const double d = glm::length(levels[level].displacement[v] - levels[0].displacement[v]);
            sum += d;
            largest = std::max(largest, d);
            ++moved;
        }
        CAPTURE(level);
        CAPTURE(sum / moved);
        CAPTURE(largest);
        CHECK(sum / moved < 0.0025);
        CHECK(largest < 0.006);
    }
}

TEST_CASE(
    "resolution: a jump of 0.1 of the diagonal on the whole armadillo takes a few iterations") {
    const deform::MeshModel model = test::load_real_model("armadillo");
    std::vector<std::uint32_t> everything(model.mesh.vertex_count());
    std::iota(everything.begin(), everything.end(), 0u);
    constexpr std::uint32_t ear = 4530;
    const std::vector<std::vector<std::uint32_t>> groups = {test::ball_around(model, ear, 0.04),
                                                            test::ball_around(model, foot, 0.04)};
    std::unique_ptr<deform::DeformSession> s;
    REQUIRE(deform::DeformSession::create(model, everything, groups, {}, s).is_ok());
    const std::vector<glm::dvec3> rest(s->targets().begin(), s->targets().end());
    const std::size_t ear_vertices = groups[0].size();
    // The ear pulled out, then, from that converged pose, up.
    for (const glm::dvec3 move : {glm::dvec3(0.1, 0.0, 0.0), glm::dvec3(0.1, 0.1, 0.0)}) {
        std::vector<glm::dvec3> targets = rest;
        for (std::size_t h = 0; h < ear_vertices; ++h) targets[h] += move * model.diagonal;
        REQUIRE(s->set_targets(targets).is_ok());
        deform::SolveReport r;
        REQUIRE(s->solve(r).is_ok());
        CAPTURE(move.y);
        CAPTURE(r.iterations);
        CHECK(r.converged);
        CHECK(r.iterations <= 20);
    }
}
