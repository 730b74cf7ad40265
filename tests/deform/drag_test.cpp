#include <doctest/doctest.h>

#include <algorithm>
#include <memory>
#include <vector>

#include <glm/geometric.hpp>

#include "deform/deform_session.hpp"
#include "jobs/scheduler.hpp"
#include "support/procedural_meshes.hpp"

// A drag as a host makes it: the handle's targets moved in equal steps,
// each frame solved from the last.
using namespace dfm;

namespace {

std::vector<std::uint32_t> near_y(const mesh::Mesh& m, double lo, double hi) {
    std::vector<std::uint32_t> out;
    for (std::uint32_t v = 0; v < m.vertex_count(); ++v) {
        if (m.positions[v].y >= lo && m.positions[v].y <= hi) out.push_back(v);
    }
    return out;
}

struct Frame {
    std::vector<glm::dvec3> positions;
    deform::SolveReport report;
};

// `frames` frames moving the tip by `move` in all.
std::vector<Frame> drag(const deform::MeshModel& model, const deform::DeformSettings& settings,
                        int frames, glm::dvec3 move) {
    const std::vector<std::vector<std::uint32_t>> groups = {near_y(model.mesh, 1.95, 2.0)};
    std::unique_ptr<deform::DeformSession> s;
    REQUIRE(deform::DeformSession::create(model, near_y(model.mesh, 0.4, 2.0), groups, settings, s)
                .is_ok());
    const std::vector<glm::dvec3> start(s->targets().begin(), s->targets().end());
    std::vector<glm::dvec3> targets(start.size());
    std::vector<Frame> out;
    for (int f = 1; f <= frames; ++f) {
        const double t = static_cast<double>(f) / frames;
        for (std::size_t h = 0; h < start.size(); ++h) targets[h] = start[h] + t * move;
        REQUIRE(s->set_targets(targets).is_ok());
        Frame frame;
        REQUIRE(s->solve(frame.report).is_ok());
        frame.positions.assign(s->positions().begin(), s->positions().end());
        out.push_back(std::move(frame));
    }
    return out;
}

double largest_difference(std::span<const glm::dvec3> a, std::span<const glm::dvec3> b) {
    double worst = 0.0;
    for (std::size_t v = 0; v < a.size(); ++v) worst = std::max(worst, glm::length(a[v] - b[v]));
    return worst;
}

}  // namespace

TEST_CASE("deform: a predicted drag frame converges to the same answer, in fewer iterations") {
    const deform::MeshModel model = deform::build_mesh_model(test::make_limb(24, 40, 0.2, 2.0));
    for (const deform::DeformMethod method :
         {deform::DeformMethod::paper, deform::DeformMethod::fitted_rotations}) {
        CAPTURE(static_cast<int>(method));
        deform::DeformSettings settings;
        settings.method = method;
        settings.predict_frames = false;
        settings.tolerance = 1e-11;
        const std::vector<Frame> exact = drag(model, settings, 12, {0.6, -0.3, 0.1});
        settings.tolerance = 1e-7;
        const std::vector<Frame> plain = drag(model, settings, 12, {0.6, -0.3, 0.1});
        settings.predict_frames = true;
        const std::vector<Frame> predicted = drag(model, settings, 12, {0.6, -0.3, 0.1});
        // The stopping rule bounds the last step, not the distance to the
        // answer: the fitted iteration, slower to contract, stops up to about
        // ten tolerances from it. A predicted start must not end further
        // from the answer than the plain drag's frames do.
        double plain_worst = 0.0;
        for (std::size_t f = 0; f < plain.size(); ++f) {
            plain_worst =
                std::max(plain_worst, largest_difference(plain[f].positions, exact[f].positions));
        }
        int plain_iterations = 0;
        int predicted_iterations = 0;
        for (std::size_t f = 0; f < plain.size(); ++f) {
            CAPTURE(f);
            REQUIRE(plain[f].report.converged);
            REQUIRE(predicted[f].report.converged);
            CHECK(!plain[f].report.predicted);
            // From the rest pose on, every frame has two converged frames before it.
            CHECK(predicted[f].report.predicted == (f > 0));
            CHECK(largest_difference(predicted[f].positions, exact[f].positions) <
                  std::max(1.5 * plain_worst, settings.tolerance * model.diagonal));
            if (method == deform::DeformMethod::paper) {
                CHECK(largest_difference(plain[f].positions, predicted[f].positions) <
                      10.0 * settings.tolerance * model.diagonal);
            }
            plain_iterations += plain[f].report.iterations;
            predicted_iterations += predicted[f].report.iterations;
        }
        CHECK(predicted_iterations < plain_iterations);
    }
}

TEST_CASE("deform: a predicted drag of a whole closed mesh ends where the plain one does") {
    // No boundary: what the dual Laplacian cannot see is tied only to the
    // previous iterate, the case where a bad start could linger.
    const deform::MeshModel model = deform::build_mesh_model(test::make_icosphere(3));
    const std::vector<std::uint32_t> roi = [&] {
        std::vector<std::uint32_t> all(model.mesh.vertex_count());
        for (std::uint32_t v = 0; v < all.size(); ++v) all[v] = v;
        return all;
    }();
    std::vector<std::vector<std::uint32_t>> groups(2);
    for (std::uint32_t v = 0; v < model.mesh.vertex_count(); ++v) {
        if (model.mesh.positions[v].y > 0.9) groups[0].push_back(v);
        if (model.mesh.positions[v].y < -0.9) groups[1].push_back(v);
    }
    const auto run = [&](bool predict) {
        deform::DeformSettings settings;
        settings.tolerance = 1e-7;
        settings.predict_frames = predict;
        std::unique_ptr<deform::DeformSession> s;
        REQUIRE(deform::DeformSession::create(model, roi, groups, settings, s).is_ok());
        std::vector<glm::dvec3> targets(s->targets().begin(), s->targets().end());
        const std::size_t top = groups[0].size();
        for (int f = 0; f < 10; ++f) {
            for (std::size_t h = 0; h < top; ++h) targets[h] += glm::dvec3(0.03, 0.02, 0.0);
            REQUIRE(s->set_targets(targets).is_ok());
            deform::SolveReport r;
            REQUIRE(s->solve(r).is_ok());
            REQUIRE(r.converged);
        }
        return std::vector<glm::dvec3>(s->positions().begin(), s->positions().end());
    };
    CHECK(largest_difference(run(false), run(true)) < 10.0 * 1e-7 * model.diagonal);
}

TEST_CASE("deform: replacing the positions stops the prediction until two frames converge") {
    const deform::MeshModel model = deform::build_mesh_model(test::make_limb(12, 16, 0.2, 2.0));
    const std::vector<std::vector<std::uint32_t>> groups = {near_y(model.mesh, 1.95, 2.0)};
    std::unique_ptr<deform::DeformSession> s;
    REQUIRE(
        deform::DeformSession::create(model, near_y(model.mesh, 0.4, 2.0), groups, {}, s).is_ok());
    std::vector<glm::dvec3> targets(s->targets().begin(), s->targets().end());
    const auto step = [&](bool expect_prediction) {
        for (glm::dvec3& t : targets) t += glm::dvec3(0.05, 0.0, 0.0);
        REQUIRE(s->set_targets(targets).is_ok());
        deform::SolveReport r;
        REQUIRE(s->solve(r).is_ok());
        CHECK(r.converged);
        CHECK(r.predicted == expect_prediction);
    };
    step(false);  // the rest pose is the only converged frame before it
    step(true);
    REQUIRE(s->set_positions(model.mesh.positions).is_ok());
    step(false);
    step(false);
    step(true);
}

TEST_CASE("deform: a drag gives the same bits with one and two workers") {
    // The ROI (y from 0.4 to 2.0 of the limb) holds over 8192 unknowns, so
    // that two workers also split the rotation fit and the factor's solves.
    const deform::MeshModel model = deform::build_mesh_model(test::make_limb(96, 120, 0.2, 2.0));
    REQUIRE(0.75 * static_cast<double>(model.mesh.vertex_count()) > 8192.0);
    deform::DeformSettings settings;
    const std::vector<Frame> alone = drag(model, settings, 4, {0.4, -0.2, 0.0});
    jobs::Scheduler pool(jobs::SchedulerConfig::threads(2));
    settings.pool = &pool;
    const std::vector<Frame> shared = drag(model, settings, 4, {0.4, -0.2, 0.0});
    for (std::size_t f = 0; f < alone.size(); ++f) {
        CAPTURE(f);
        CHECK(alone[f].report.iterations == shared[f].report.iterations);
        CHECK(alone[f].positions == shared[f].positions);
    }
}
