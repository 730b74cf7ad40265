#include <doctest/doctest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numeric>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "deform/deform_session.hpp"
#include "deform/quality.hpp"
#include "support/procedural_meshes.hpp"

using namespace dfm;

namespace {

std::vector<std::uint32_t> all_vertices(const mesh::Mesh& m) {
    std::vector<std::uint32_t> v(m.vertex_count());
    std::iota(v.begin(), v.end(), 0u);
    return v;
}

bool all_finite(std::span<const glm::dvec3> p) {
    for (const glm::dvec3& q : p) {
        if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z)) return false;
    }
    return true;
}

// Vertices of a limb within `length` of its base or its tip.
std::vector<std::uint32_t> near_y(const mesh::Mesh& m, double lo, double hi) {
    std::vector<std::uint32_t> out;
    for (std::uint32_t v = 0; v < m.vertex_count(); ++v) {
        if (m.positions[v].y >= lo && m.positions[v].y <= hi) out.push_back(v);
    }
    return out;
}

std::vector<std::uint32_t> tip_of(const mesh::Mesh& m) {
    return near_y(m, 0.95, 1.0);
}

}  // namespace

TEST_CASE("deform: zero handle motion returns the rest mesh") {
    const deform::MeshModel model = deform::build_mesh_model(test::make_limb(16, 12, 0.2, 2.0));
    const std::vector<std::vector<std::uint32_t>> groups = {near_y(model.mesh, 1.9, 2.0)};
    std::unique_ptr<deform::DeformSession> s;
    REQUIRE(
        deform::DeformSession::create(model, near_y(model.mesh, 0.3, 2.0), groups, {}, s).is_ok());
    deform::SolveReport r;
    REQUIRE(s->solve(r).is_ok());
    CHECK(r.converged);
    for (std::size_t v = 0; v < model.mesh.vertex_count(); ++v) {
        CHECK(glm::length(s->positions()[v] - model.mesh.positions[v]) < 1e-9 * model.diagonal);
    }
}

TEST_CASE("deform: bending a limb moves the handle, keeps the outside bit-identical") {
    const deform::MeshModel model = deform::build_mesh_model(test::make_limb(16, 24, 0.2, 2.0));
    const std::vector<std::uint32_t> roi = near_y(model.mesh, 0.5, 2.0);
    const std::vector<std::vector<std::uint32_t>> groups = {near_y(model.mesh, 1.95, 2.0)};
    std::vector<std::uint8_t> in_roi(model.mesh.vertex_count(), 0);
    for (std::uint32_t v : roi) in_roi[v] = 1;
    std::unique_ptr<deform::DeformSession> s;
    REQUIRE(deform::DeformSession::create(model, roi, groups, {}, s).is_ok());
    std::vector<glm::dvec3> targets(s->targets().begin(), s->targets().end());
    for (glm::dvec3& t : targets) t += glm::dvec3(0.5, -0.2, 0.0);
    REQUIRE(s->set_targets(targets).is_ok());
    deform::SolveReport r;
    REQUIRE(s->solve(r).is_ok());
    CHECK(r.converged);
    CHECK(r.iterations > 1);
    for (std::size_t v = 0; v < model.mesh.vertex_count(); ++v) {
        if (!in_roi[v]) CHECK(s->positions()[v] == model.mesh.positions[v]);
    }
    const deform::QualityReport q =
        deform::measure_quality(model, s->positions(), in_roi, s->handle_vertices(), s->targets());
    CHECK(q.max_fixed_move == 0.0);
    CHECK(q.flipped_faces == 0);
    CHECK(q.max_handle_error < 1e-3);
    CHECK(q.dual_magnitude_error < 0.1);
    CHECK(q.mean_abs_log_edge < 0.1);
}

TEST_CASE("deform: rotation invariance: both ends rotated give the rotated rest mesh") {
    const deform::MeshModel model = deform::build_mesh_model(test::make_limb(12, 16, 0.25, 2.0));
    const std::vector<std::vector<std::uint32_t>> groups = {near_y(model.mesh, 0.0, 0.1),
                                                            near_y(model.mesh, 1.9, 2.0)};
    const glm::dmat4 rot = glm::rotate(glm::dmat4(1.0), glm::radians(45.0), glm::dvec3(0, 0, 1));
    auto rotated = [&](const glm::dvec3& p) { return glm::dvec3(rot * glm::dvec4(p, 1.0)); };

    for (auto [method, iterations] :
         {std::pair{deform::DeformMethod::paper, 1}, std::pair{deform::DeformMethod::paper, 400},
          std::pair{deform::DeformMethod::fitted_rotations, 1}}) {
        CAPTURE(deform::method_name(method));
        CAPTURE(iterations);
        deform::DeformSettings settings;
        settings.method = method;
        settings.max_iterations = iterations;
        settings.tolerance = 1e-9;
        std::unique_ptr<deform::DeformSession> s;
        REQUIRE(deform::DeformSession::create(model, all_vertices(model.mesh), groups, settings, s)
                    .is_ok());
        std::vector<glm::dvec3> targets;
        for (std::uint32_t v : s->handle_vertices())
            targets.push_back(rotated(model.mesh.positions[v]));
        REQUIRE(s->set_targets(targets).is_ok());
        deform::SolveReport r;
        REQUIRE(s->solve(r).is_ok());
        double worst = 0.0;
        for (std::size_t v = 0; v < model.mesh.vertex_count(); ++v) {
            worst =
                std::max(worst, glm::length(s->positions()[v] - rotated(model.mesh.positions[v])));
        }
        if (method == deform::DeformMethod::paper && iterations == 1) {
            CHECK(worst > 1e-2 * model.diagonal);  // a linear Laplacian alone fails this
        } else {
            // The fitted rotations start a floating ROI from the handles'
            // rigid motion: one iteration is enough.
            CHECK(worst < 1e-4 * model.diagonal);
        }
    }
}

TEST_CASE("deform: a three-colourable grid, whole ROI, one handle: no NaN") {
    mesh::Mesh grid = test::make_grid(12, 12);
    // Every interior vertex of this grid has valence 6: three-colourable, so
    // D has a null space that one handle does not remove.
    for (glm::dvec3& p : grid.positions) p.z = 0.05 * std::sin(p.x) * std::cos(p.y);
    const deform::MeshModel model = deform::build_mesh_model(grid);
    const std::vector<std::vector<std::uint32_t>> groups = {{84}};
    std::unique_ptr<deform::DeformSession> s;
    REQUIRE(deform::DeformSession::create(model, all_vertices(model.mesh), groups, {}, s).is_ok());
    const glm::dvec3 target = model.mesh.positions[84] + glm::dvec3(0.0, 0.0, 0.5);
    REQUIRE(s->set_targets(std::span(&target, 1)).is_ok());
    deform::SolveReport r;
    REQUIRE(s->solve(r).is_ok());
    CHECK(all_finite(s->positions()));
    CHECK(glm::length(s->positions()[84] - target) < 0.05);
}

TEST_CASE("deform: open grid with a ROI and a handle: finite, handle met") {
    mesh::Mesh grid = test::make_grid(16, 10);
    for (glm::dvec3& p : grid.positions) p.z = 0.1 * std::sin(0.7 * p.x) * std::cos(0.9 * p.y);
    const deform::MeshModel model = deform::build_mesh_model(grid);
    std::vector<std::uint32_t> roi;
    for (std::uint32_t v = 0; v < model.mesh.vertex_count(); ++v) {
        if (model.mesh.positions[v].x >= 6.0) roi.push_back(v);
    }
    std::vector<std::vector<std::uint32_t>> groups(1);
    for (std::uint32_t v : roi) {
        if (model.mesh.positions[v].x >= 15.0) groups[0].push_back(v);
    }
    for (bool hard : {false, true}) {
        CAPTURE(hard);
        deform::DeformSettings settings;
        settings.hard_handles = hard;
        std::unique_ptr<deform::DeformSession> s;
        REQUIRE(deform::DeformSession::create(model, roi, groups, settings, s).is_ok());
        std::vector<glm::dvec3> targets(s->targets().begin(), s->targets().end());
        for (glm::dvec3& t : targets) t.z += 2.0;
        REQUIRE(s->set_targets(targets).is_ok());
        deform::SolveReport r;
        REQUIRE(s->solve(r).is_ok());
        CHECK(all_finite(s->positions()));
        double worst = 0.0;
        for (std::size_t h = 0; h < targets.size(); ++h) {
            worst =
                std::max(worst, glm::length(s->positions()[s->handle_vertices()[h]] - targets[h]));
        }
        CHECK(worst < (hard ? 1e-12 : 0.05) * model.diagonal);
    }
}

TEST_CASE("deform: bad set-ups and targets are refused with a reason") {
    const deform::MeshModel model = deform::build_mesh_model(test::make_limb(8, 6, 0.2, 1.0));
    std::unique_ptr<deform::DeformSession> s;
    const std::vector<std::uint32_t> roi = near_y(model.mesh, 0.3, 1.0);
    const std::vector<std::vector<std::uint32_t>> outside = {{0}};
    CHECK(deform::DeformSession::create(model, roi, outside, {}, s)
              .message()
              .find("outside the ROI") != std::string::npos);
    const std::vector<std::vector<std::uint32_t>> far = {{100000}};
    CHECK(deform::DeformSession::create(model, roi, far, {}, s).code() == Errc::out_of_range);
    const std::vector<std::vector<std::uint32_t>> none;
    CHECK(deform::DeformSession::create(model, all_vertices(model.mesh), none, {}, s)
              .message()
              .find("nothing pins the ROI") != std::string::npos);
    deform::DeformSettings bad;
    bad.tolerance = -1.0;
    CHECK(deform::DeformSession::create(model, roi, none, bad, s).code() == Errc::invalid_argument);

    // A handle on the ROI's boundary follows its target, as in the CGAL peer.
    const std::vector<std::vector<std::uint32_t>> edge = {near_y(model.mesh, 0.3, 0.35)};
    REQUIRE_FALSE(edge[0].empty());
    REQUIRE(deform::DeformSession::create(model, roi, edge, {}, s).is_ok());
    CHECK(s->unknowns().unknown_of_vertex[edge[0][0]] != mesh::no_index);
    const std::vector<std::vector<std::uint32_t>> twice = {tip_of(model.mesh), tip_of(model.mesh)};
    CHECK(deform::DeformSession::create(model, roi, twice, {}, s).message().find("earlier group") !=
          std::string::npos);

    const std::vector<std::vector<std::uint32_t>> tip = {near_y(model.mesh, 0.95, 1.0)};
    REQUIRE(deform::DeformSession::create(model, roi, tip, {}, s).is_ok());
    std::vector<glm::dvec3> targets(s->targets().begin(), s->targets().end());
    targets[0].x = std::nan("");
    CHECK(s->set_targets(targets).code() == Errc::invalid_argument);
    CHECK(s->set_targets(std::span(targets).first(1)).code() == Errc::invalid_argument);
}

TEST_CASE("deform: baking makes the edit the new rest pose") {
    const deform::MeshModel model = deform::build_mesh_model(test::make_limb(16, 24, 0.2, 2.0));
    const std::vector<std::uint32_t> roi = near_y(model.mesh, 0.5, 2.0);
    const std::vector<std::vector<std::uint32_t>> groups = {near_y(model.mesh, 1.95, 2.0)};
    std::unique_ptr<deform::DeformSession> s;
    REQUIRE(deform::DeformSession::create(model, roi, groups, {}, s).is_ok());
    std::vector<glm::dvec3> targets(s->targets().begin(), s->targets().end());
    for (glm::dvec3& t : targets) t += glm::dvec3(0.3, 0.0, 0.1);
    REQUIRE(s->set_targets(targets).is_ok());
    deform::SolveReport r;
    REQUIRE(s->solve(r).is_ok());

    deform::MeshModel baked;
    REQUIRE(deform::bake_positions(model, s->positions(), baked).is_ok());
    CHECK(baked.mesh.positions ==
          std::vector<glm::dvec3>(s->positions().begin(), s->positions().end()));
    // A second edit with no motion keeps the baked shape: the detail is now
    // measured on it.
    std::unique_ptr<deform::DeformSession> second;
    REQUIRE(deform::DeformSession::create(baked, roi, groups, {}, second).is_ok());
    REQUIRE(second->solve(r).is_ok());
    for (std::size_t v = 0; v < baked.mesh.vertex_count(); ++v) {
        CHECK(glm::length(second->positions()[v] - baked.mesh.positions[v]) <
              1e-9 * baked.diagonal);
    }
    std::vector<glm::dvec3> bad(s->positions().begin(), s->positions().end());
    bad[3].y = std::numeric_limits<double>::infinity();
    CHECK(deform::bake_positions(model, bad, baked).code() == Errc::invalid_argument);
    CHECK(deform::bake_positions(model, std::span(bad).first(3), baked).code() ==
          Errc::invalid_argument);
}

TEST_CASE("deform: a raised stop flag ends the set-up, a lowered one changes no bit") {
    const deform::MeshModel model = deform::build_mesh_model(test::make_limb(24, 30, 0.2, 2.0));
    const std::vector<std::vector<std::uint32_t>> groups = {near_y(model.mesh, 1.9, 2.0)};
    const std::vector<std::uint32_t> roi = near_y(model.mesh, 0.3, 2.0);
    std::vector<glm::dvec3> targets;
    for (std::uint32_t v : groups[0])
        targets.push_back(model.mesh.positions[v] + glm::dvec3(0.4, 0, 0));

    std::unique_ptr<deform::DeformSession> plain, watched, stopped;
    REQUIRE(deform::DeformSession::create(model, roi, groups, {}, plain).is_ok());
    std::atomic<bool> stop{false};
    REQUIRE(deform::DeformSession::create(model, roi, groups, {}, watched, &stop).is_ok());
    deform::SolveReport r1, r2;
    REQUIRE(plain->set_targets(targets).is_ok());
    REQUIRE(watched->set_targets(targets).is_ok());
    REQUIRE(plain->solve(r1).is_ok());
    REQUIRE(watched->solve(r2).is_ok());
    CHECK(r1.iterations == r2.iterations);
    CHECK(std::equal(plain->positions().begin(), plain->positions().end(),
                     watched->positions().begin()));

    stop = true;
    const Status s = deform::DeformSession::create(model, roi, groups, {}, stopped, &stop);
    CHECK(s.code() == Errc::cancelled);
    CHECK(stopped == nullptr);
}

TEST_CASE("deform: a session's memory: a larger ROI holds a larger factor") {
    const deform::MeshModel model = deform::build_mesh_model(test::make_limb(24, 40, 0.2, 2.0));
    const std::vector<std::vector<std::uint32_t>> groups = {near_y(model.mesh, 1.9, 2.0)};
    std::unique_ptr<deform::DeformSession> small, large;
    REQUIRE(deform::DeformSession::create(model, near_y(model.mesh, 1.5, 2.0), groups, {}, small)
                .is_ok());
    REQUIRE(deform::DeformSession::create(model, near_y(model.mesh, 0.2, 2.0), groups, {}, large)
                .is_ok());
    const deform::SessionMemory a = small->memory(), b = large->memory();
    CHECK(a.factor > 0);
    CHECK(a.system > 0);
    CHECK(a.iteration >= 3 * sizeof(double) * small->unknowns().count());
    CHECK(b.factor > 2 * a.factor);
    CHECK(b.system > a.system);
    CHECK(b.iteration > a.iteration);
    CHECK(a.frames == 0);  // AsyncSession's
    CHECK(a.staging == 0);
}

TEST_CASE("deform: a solve stopped before each iteration resumes to the same bits") {
    const deform::MeshModel model = deform::build_mesh_model(test::make_limb(16, 30, 0.2, 2.0));
    const std::vector<std::vector<std::uint32_t>> groups = {near_y(model.mesh, 1.9, 2.0)};
    for (const deform::DeformMethod method :
         {deform::DeformMethod::fitted_rotations, deform::DeformMethod::paper}) {
        CAPTURE(deform::method_name(method));
        deform::DeformSettings settings;
        settings.method = method;
        std::unique_ptr<deform::DeformSession> whole, stepped;
        REQUIRE(deform::DeformSession::create(model, near_y(model.mesh, 0.3, 2.0), groups, settings,
                                              whole)
                    .is_ok());
        REQUIRE(deform::DeformSession::create(model, near_y(model.mesh, 0.3, 2.0), groups, settings,
                                              stepped)
                    .is_ok());
        // Two solves each, so that the second starts from a prediction.
        for (const double x : {0.3, 0.5}) {
            std::vector<glm::dvec3> targets;
            for (std::uint32_t v : groups[0])
                targets.push_back(model.mesh.positions[v] + glm::dvec3(x, 0, 0));
            REQUIRE(whole->set_targets(targets).is_ok());
            REQUIRE(stepped->set_targets(targets).is_ok());
            deform::SolveReport expected;
            REQUIRE(whole->solve(expected).is_ok());
            // A deadline already past: every call runs one iteration.
            deform::DeformSession::Control control;
            control.pause_after = std::chrono::steady_clock::now();
            deform::SolveReport report;
            REQUIRE(stepped->solve(report, &control).is_ok());
            int calls = 1;
            while (report.paused) {
                CHECK(stepped->paused());
                REQUIRE(stepped->resume(report, &control).is_ok());
                ++calls;
            }
            CHECK_FALSE(stepped->paused());
            CHECK(calls == expected.iterations);
            CHECK(report.iterations == expected.iterations);
            CHECK(report.converged == expected.converged);
            CHECK(report.krylov_iterations == expected.krylov_iterations);
            CHECK(std::equal(whole->positions().begin(), whole->positions().end(),
                             stepped->positions().begin()));
        }
        deform::SolveReport none;
        CHECK(stepped->resume(none).code() == Errc::invalid_argument);
    }
}
