// The default method (docs/method.md) on real models: rigid motions are met
// exactly, large bends converge without folding, and the energy never rises
// from one iterate to the next. The paper's method stays selectable.
#include <doctest/doctest.h>

#include <cmath>
#include <numeric>
#include <string>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "deform/deform_session.hpp"
#include "deform/quality.hpp"
#include "dualform/api_edit.hpp"
#include "dualform/edit_chain.hpp"
#include "dualform/scenario.hpp"
#include "environment/host_environment.hpp"
#include "mesh/load.hpp"
#include "mesh/model_cache.hpp"
#include "support/real_models.hpp"

using namespace dfm;

namespace {

// A scenario resolved as the dualform tool resolves it (through the C API),
// and the engine's model of the same mesh.
struct ScenarioEdit {
    deform::MeshModel model;
    std::vector<std::uint32_t> roi;
    std::vector<std::uint8_t> in_roi;
    std::vector<std::vector<std::uint32_t>> handle_groups;
    std::vector<glm::dvec3> targets;  // one per handle vertex, in group order
};

void load_edit(const std::string& name, ScenarioEdit& out) {
    cli::Scenario scenario;
    REQUIRE(cli::load_scenario(std::filesystem::path(DUALFORM_SCENARIO_DIR) / (name + ".json"),
                               scenario)
                .is_ok());
    cli::ScenarioMesh mesh;
    REQUIRE(cli::open_scenario_mesh(scenario, mesh).is_ok());
    cli::ScenarioEdit edit;
    REQUIRE(cli::resolve_scenario_edit(scenario, mesh, edit).is_ok());
    std::vector<std::uint32_t> indices;
    REQUIRE(cli::read_mesh_indices(mesh, indices).is_ok());
    mesh::Mesh m;
    m.positions = mesh.rest;
    for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
        m.triangles.push_back({indices[t], indices[t + 1], indices[t + 2]});
    }
    out.model = deform::build_mesh_model(std::move(m));
    out.roi = edit.roi.vertices;
    out.in_roi.assign(out.model.mesh.vertex_count(), 0);
    for (const std::uint32_t v : out.roi) out.in_roi[v] = 1;
    out.handle_groups = edit.groups;
    out.targets = edit.targets;
}

struct Solved {
    deform::SolveReport report;
    deform::QualityReport quality;
    std::vector<double> energies;  // of every iterate, in order
};

Solved solve(const ScenarioEdit& e, const deform::DeformSettings& settings) {
    std::unique_ptr<deform::DeformSession> s;
    REQUIRE(deform::DeformSession::create(e.model, e.roi, e.handle_groups, settings, s).is_ok());
    REQUIRE(s->set_targets(e.targets).is_ok());
    Solved out;
    deform::DeformSession::Control control;
    control.on_iteration = [&out](const deform::SolveReport& r) {
        out.energies.push_back(r.energy);
    };
    REQUIRE(s->solve(out.report, &control).is_ok());
    out.quality = deform::measure_quality(e.model, s->positions(), e.in_roi, s->handle_vertices(),
                                          s->targets());
    return out;
}

// Whole mesh as ROI, three handle groups at its extremes moved by one rigid
// motion: the rigid motion is the exact answer.
void check_rigid_motion(const std::string& name, double degrees) {
    const deform::MeshModel model = test::load_real_model(name);
    std::uint32_t lo = 0;
    std::uint32_t hi = 0;
    std::uint32_t top = 0;
    for (std::uint32_t v = 0; v < model.mesh.vertex_count(); ++v) {
        const glm::dvec3& p = model.mesh.positions[v];
        if (p.x < model.mesh.positions[lo].x) lo = v;
        if (p.x > model.mesh.positions[hi].x) hi = v;
        if (p.y > model.mesh.positions[top].y) top = v;
    }
    const std::vector<std::vector<std::uint32_t>> groups = {test::ball_around(model, lo, 0.04),
                                                            test::ball_around(model, hi, 0.04),
                                                            test::ball_around(model, top, 0.04)};
    glm::dmat4 motion = glm::translate(glm::dmat4(1.0), 0.1 * model.diagonal * glm::dvec3(1, 0, 1));
    motion = glm::rotate(motion, glm::radians(degrees), glm::normalize(glm::dvec3(0.3, 1.0, 0.2)));
    auto moved = [&](const glm::dvec3& p) { return glm::dvec3(motion * glm::dvec4(p, 1.0)); };
    std::vector<std::uint32_t> everything(model.mesh.vertex_count());
    std::iota(everything.begin(), everything.end(), 0u);
    std::unique_ptr<deform::DeformSession> s;
    REQUIRE(deform::DeformSession::create(model, everything, groups, deform::DeformSettings{}, s)
                .is_ok());
    std::vector<glm::dvec3> targets;
    for (std::uint32_t v : s->handle_vertices()) targets.push_back(moved(model.mesh.positions[v]));
    REQUIRE(s->set_targets(targets).is_ok());
    deform::SolveReport r;
    REQUIRE(s->solve(r).is_ok());
    double worst = 0.0;
    for (std::size_t v = 0; v < model.mesh.vertex_count(); ++v) {
        worst = std::max(worst, glm::length(s->positions()[v] - moved(model.mesh.positions[v])));
    }
    CAPTURE(name);
    CAPTURE(degrees);
    CAPTURE(r.iterations);
    CHECK(r.converged);
    CHECK(worst < 1e-4 * model.diagonal);
}

}  // namespace

TEST_CASE("fitted rotations: whole cow, handles moved rigidly, the rigid motion comes back") {
    for (double degrees : {30.0, 60.0, 90.0}) check_rigid_motion("cow", degrees);
}

TEST_CASE("fitted rotations: whole armadillo, handles moved rigidly, the rigid motion comes back") {
    for (double degrees : {45.0, 90.0}) check_rigid_motion("armadillo", degrees);
}

TEST_CASE("fitted rotations: the camel's neck bends within 30 iterations and folds no face") {
    ScenarioEdit e;
    load_edit("figure-camel-neck", e);
    const Solved s = solve(e, deform::DeformSettings{});
    CAPTURE(s.report.iterations);
    CHECK(s.report.converged);
    CHECK(s.report.iterations <= 30);
    CHECK(s.quality.flipped_faces == 0);
    // CGAL's SRE-ARAP, 10 iterations, on the same sets: 0.0807
    // (dualform_cgal_peer, docs/benchmarks.md).
    CHECK(s.quality.mean_abs_log_edge < 0.0807);
    CHECK(s.quality.max_handle_error < 1e-3);
    CHECK(s.quality.max_fixed_move == 0.0);
}

TEST_CASE("fitted rotations: the energy never rises from one iterate to the next") {
    for (const char* name : {"paper-cow-front-leg", "paper-cow-tail", "paper-dino-tail",
                             "paper-triceratops-horn", "figure-camel-neck"}) {
        ScenarioEdit e;
        load_edit(name, e);
        const Solved s = solve(e, deform::DeformSettings{});
        CAPTURE(name);
        CHECK(s.report.converged);
        REQUIRE(s.energies.size() >= 2);
        for (std::size_t k = 1; k < s.energies.size(); ++k) {
            CAPTURE(k);
            CHECK(s.energies[k] <= s.energies[k - 1]);
        }
        CHECK(s.energies.back() > 0.0);
    }
}

TEST_CASE("paper's method: selectable, and it folds the camel's neck where the default does not") {
    ScenarioEdit e;
    load_edit("figure-camel-neck", e);
    deform::DeformSettings paper;
    paper.method = deform::DeformMethod::paper;
    const Solved s = solve(e, paper);
    // docs/method.md: the fold is the paper energy's minimiser (measured: 100
    // iterations without converging, about ten flipped faces).
    CHECK(s.quality.flipped_faces > 0);
    CHECK(s.quality.mean_abs_log_edge > 0.1);
    CHECK(s.report.energy == 0.0);
}

TEST_CASE("fitted rotations: every edit of the paper's figures converges (tools/figures)") {
    const std::filesystem::path dir(DUALFORM_SCENARIO_DIR);
    const std::vector<std::vector<std::string>> figures = {
        {"cow-front-leg-step", "cow-tail-swing"},
        {"figure-cow-run-1", "figure-cow-run-2", "figure-cow-run-3", "figure-cow-run-4",
         "figure-cow-run-5"},
        {"figure-camel-neck", "figure-camel-front-leg-left", "figure-camel-front-leg-right",
         "figure-camel-hind-leg"},
        {"figure-dino-head", "figure-dino-tail"},
        {"triceratops-horn-rotate", "figure-triceratops-horn-far"}};
    for (const auto& names : figures) {
        std::vector<std::string> paths;
        for (const std::string& name : names) paths.push_back((dir / (name + ".json")).string());
        cli::EditChain chain;
        CAPTURE(names.front());
        REQUIRE(cli::run_edit_chain(paths, chain).is_ok());
        CHECK(chain.unconverged == 0);
    }
}

TEST_CASE("fitted rotations: compressive pushes fold no face where CGAL's SRE-ARAP folds none") {
    // Flipped faces / creased edges of CGAL's SRE-ARAP (200 iterations) on
    // the same sets, by tools/peers/quality-table: 0 / 0 on the cow's and
    // the camel's hooves, the dino's tail and the camel's hind leg; 1 / 3 on
    // the armadillo's foot and 1 / 2 on the cow's fourth running step, where
    // the default measured 1 / 0 and 4 / 1 (docs/method.md).
    struct Push {
        const char* name;
        std::size_t flipped;
        std::size_t creased;
    };
    for (const Push& p : {Push{"push-cow-hoof", 0, 0}, Push{"push-camel-hoof", 0, 0},
                          Push{"push-dino-tail", 0, 0}, Push{"figure-camel-hind-leg", 0, 0},
                          Push{"push-armadillo-foot", 1, 3}, Push{"figure-cow-run-4", 4, 2}}) {
        ScenarioEdit e;
        load_edit(p.name, e);
        const Solved s = solve(e, deform::DeformSettings{});
        CAPTURE(p.name);
        CAPTURE(s.quality.flipped_faces);
        CAPTURE(s.quality.creased_edges);
        CHECK(s.report.converged);
        CHECK(s.quality.flipped_faces <= p.flipped);
        CHECK(s.quality.creased_edges <= p.creased);
    }
}
