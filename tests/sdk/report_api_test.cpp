// The report calls: quality figures, solver figures and their details of a
// frame, the solver settings a benchmark varies, and Loop subdivision, as the
// dualform tool uses them.

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <filesystem>
#include <vector>

#include "dualform/dualform.h"
#include "sdk_fixture.hpp"
#include "support/test_files.hpp"

using namespace dfm::test;

TEST_CASE("reports: quality and solver figures of a solved limb edit") {
    LimbEdit limb;
    dfm_quality quality = {};
    dfm_frame_info info = {};
    // The start state: every vertex at rest, the handles on their targets.
    REQUIRE(dfm_session_measure_quality(limb.session, &quality, &info) == DFM_OK);
    CHECK(info.generation == 0);
    CHECK(quality.max_handle_error == 0.0);
    CHECK(quality.mean_abs_log_edge == 0.0);
    CHECK(quality.flipped_faces == 0);

    double m[16];
    translation(0.3, 0.0, 0.0, m);
    REQUIRE(dfm_session_set_group_transform(limb.session, 0, m) == DFM_OK);
    std::uint64_t generation = 0;
    REQUIRE_MESSAGE(dfm_session_solve(limb.session, &generation) == DFM_OK, last_error());
    REQUIRE(dfm_session_measure_quality(limb.session, &quality, &info) == DFM_OK);
    CHECK(info.generation == generation);
    CHECK(info.converged);
    CHECK(quality.max_fixed_move == 0.0);
    CHECK(quality.max_handle_error > 0.0);  // soft handles miss by a little
    CHECK(quality.max_handle_error < 0.01);
    CHECK(quality.mean_abs_log_edge > 0.0);
    CHECK(quality.max_abs_log_edge >= quality.mean_abs_log_edge);
    CHECK(quality.mean_normal_change_deg > 0.0);
    CHECK(quality.flipped_faces == 0);
    CHECK(quality.creased_edges == 0);

    dfm_solve_report report = {};
    REQUIRE(dfm_session_get_solve_report(limb.session, &report, &info) == DFM_OK);
    CHECK(info.generation == generation);
    CHECK(report.unknowns > limb.tip.size());
    CHECK(report.rows > 0);
    CHECK(report.normal_nonzeros >= report.unknowns);
    CHECK(report.setup_ms > 0.0);
    CHECK(report.linear_converged);
    CHECK(report.linear_residual < 1e-8);

    CHECK(dfm_session_measure_quality(limb.session, nullptr, nullptr) ==
          DFM_ERROR_INVALID_ARGUMENT);
    CHECK(dfm_session_get_solve_report(limb.session, nullptr, nullptr) ==
          DFM_ERROR_INVALID_ARGUMENT);
    CHECK(dfm_session_measure_quality(nullptr, &quality, nullptr) == DFM_ERROR_INVALID_HANDLE);
    CHECK(dfm_session_get_solve_report(nullptr, &report, nullptr) == DFM_ERROR_INVALID_HANDLE);
}

namespace {

// Moves the limb's tip along x in `frames` equal steps, solving each frame,
// and returns the details of the last.
dfm_solve_details drag_tip(LimbEdit& limb, int frames) {
    dfm_solve_details details = {};
    details.struct_size = sizeof details;
    for (int f = 1; f <= frames; ++f) {
        double m[16];
        translation(0.05 * f, 0.0, 0.0, m);
        REQUIRE(dfm_session_set_group_transform(limb.session, 0, m) == DFM_OK);
        REQUIRE_MESSAGE(dfm_session_solve(limb.session, nullptr) == DFM_OK, last_error());
        REQUIRE(dfm_session_get_solve_details(limb.session, &details, nullptr) == DFM_OK);
    }
    return details;
}

std::vector<double> positions(const LimbEdit& limb) {
    const std::size_t n = limb.shape.vertex_count();
    std::vector<double> xyz(3 * n);
    const dfm_vec3_output out = {xyz.data(), n, 0, DFM_SCALAR_FLOAT64};
    REQUIRE(dfm_session_read_positions(limb.session, &out, nullptr) == DFM_OK);
    return xyz;
}

}  // namespace

TEST_CASE("reports: the details of the set-up and of a frame's solve") {
    LimbEdit limb;
    double m[16];
    translation(0.3, 0.0, 0.0, m);
    REQUIRE(dfm_session_set_group_transform(limb.session, 0, m) == DFM_OK);
    std::uint64_t generation = 0;
    REQUIRE_MESSAGE(dfm_session_solve(limb.session, &generation) == DFM_OK, last_error());

    dfm_solve_details details = {};
    details.struct_size = sizeof details;
    dfm_frame_info info = {};
    REQUIRE_MESSAGE(dfm_session_get_solve_details(limb.session, &details, &info) == DFM_OK,
                    last_error());
    CHECK(details.struct_size == sizeof details);
    CHECK(info.generation == generation);
    // The parts are parts of the totals the other reports give.
    dfm_solve_report report = {};
    REQUIRE(dfm_session_get_solve_report(limb.session, &report, nullptr) == DFM_OK);
    const double setup_parts = details.setup_rows_ms + details.setup_assembly_ms +
                               details.setup_ordering_ms + details.setup_symbolic_ms +
                               details.setup_numeric_ms;
    CHECK(details.setup_numeric_ms >= 0.0);
    CHECK(setup_parts > 0.0);
    CHECK(setup_parts <= report.setup_ms * 1.001);
    const double solve_parts = details.linear_solve_ms + details.right_hand_side_ms +
                               details.normals_ms + details.anderson_ms;
    CHECK(details.linear_solve_ms > 0.0);
    CHECK(solve_parts <= info.solve_ms * 1.001);
    CHECK_FALSE(details.predicted);  // the first frame has no frames before it

    // struct_size 0 is the whole struct as it first appeared.
    dfm_solve_details zero_size = {};
    REQUIRE(dfm_session_get_solve_details(limb.session, &zero_size, nullptr) == DFM_OK);
    CHECK(zero_size.struct_size == 0);
    CHECK(zero_size.linear_solve_ms == details.linear_solve_ms);
    CHECK(zero_size.setup_numeric_ms == details.setup_numeric_ms);

    CHECK(dfm_session_get_solve_details(limb.session, nullptr, nullptr) ==
          DFM_ERROR_INVALID_ARGUMENT);
    CHECK(dfm_session_get_solve_details(nullptr, &details, nullptr) == DFM_ERROR_INVALID_HANDLE);
}

TEST_CASE("reports: the solve details write only the bytes of the caller's struct") {
    LimbEdit limb;
    REQUIRE_MESSAGE(dfm_session_solve(limb.session, nullptr) == DFM_OK, last_error());

    // An older caller whose struct ended before the frame's parts.
    dfm_solve_details old = {};
    old.struct_size = static_cast<std::uint32_t>(offsetof(dfm_solve_details, linear_solve_ms));
    old.linear_solve_ms = -1.0;
    old.predicted = true;
    REQUIRE_MESSAGE(dfm_session_get_solve_details(limb.session, &old, nullptr) == DFM_OK,
                    last_error());
    CHECK(old.setup_numeric_ms > 0.0);
    CHECK(old.linear_solve_ms == -1.0);
    CHECK(old.predicted);

    // A newer caller: its zero tail is accepted and stays zero, a set byte is refused.
    struct Newer {
        dfm_solve_details known;
        double later;
    } newer = {};
    newer.known.struct_size = sizeof newer;
    REQUIRE(dfm_session_get_solve_details(limb.session, &newer.known, nullptr) == DFM_OK);
    CHECK(newer.known.setup_numeric_ms > 0.0);
    CHECK(newer.later == 0.0);
    newer.later = 1.0;
    CHECK(dfm_session_get_solve_details(limb.session, &newer.known, nullptr) ==
          DFM_ERROR_UNSUPPORTED);
    CHECK(newer.later == 1.0);

    dfm_solve_details tiny = {};
    tiny.struct_size = 2;
    CHECK(dfm_session_get_solve_details(limb.session, &tiny, nullptr) ==
          DFM_ERROR_INVALID_ARGUMENT);
}

TEST_CASE("reports: frame prediction is on by default and disable_prediction turns it off") {
    LimbEdit predicting;
    CHECK(drag_tip(predicting, 4).predicted);

    dfm_solver_settings settings = {};
    settings.disable_prediction = true;
    LimbEdit plain(16, 20, settings);
    CHECK_FALSE(drag_tip(plain, 4).predicted);

    // Both solve the same drag to the tolerance.
    const std::vector<double> a = positions(predicting);
    const std::vector<double> b = positions(plain);
    double worst = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(a[i] - b[i]));
    CHECK(worst < 1e-3);

    // Fixed when the session is created.
    dfm_solver_settings change = {};
    change.disable_prediction = true;
    CHECK(dfm_session_set_solver(predicting.session, &change) == DFM_ERROR_UNSUPPORTED);
    CHECK(dfm_session_set_solver(plain.session, &change) == DFM_OK);
}

TEST_CASE("reports: the preconditioner is a setting, and the settings keep their size") {
    // Two words of `reserved` became the preconditioner and the prediction switch.
    CHECK(sizeof(dfm_solver_settings) == 64);
    CHECK(offsetof(dfm_solver_settings, reserved) + sizeof(dfm_solver_settings{}.reserved) <= 64);

    LimbEdit cholesky;
    dfm_solver_settings settings = {};
    settings.preconditioner = DFM_PRECONDITIONER_JACOBI;
    LimbEdit jacobi(16, 20, settings);
    double m[16];
    translation(0.3, 0.0, 0.0, m);
    dfm_frame_info info = {};
    for (LimbEdit* limb : {&cholesky, &jacobi}) {
        REQUIRE(dfm_session_set_group_transform(limb->session, 0, m) == DFM_OK);
        REQUIRE_MESSAGE(dfm_session_solve(limb->session, nullptr) == DFM_OK, last_error());
    }
    dfm_solve_report exact = {}, diagonal = {};
    REQUIRE(dfm_session_get_solve_report(cholesky.session, &exact, &info) == DFM_OK);
    CHECK(info.converged);
    REQUIRE(dfm_session_get_solve_report(jacobi.session, &diagonal, &info) == DFM_OK);
    CHECK(info.converged);
    CHECK(diagonal.linear_converged);
    // The diagonal alone takes more conjugate gradient steps than the factor.
    CHECK(diagonal.krylov_iterations > exact.krylov_iterations);
    const std::vector<double> a = positions(cholesky);
    const std::vector<double> b = positions(jacobi);
    double worst = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(a[i] - b[i]));
    CHECK(worst < 1e-3);

    // Fixed when the session is created; the same value may be passed again.
    CHECK(dfm_session_set_solver(jacobi.session, &settings) == DFM_OK);
    dfm_solver_settings other = {};
    other.preconditioner = DFM_PRECONDITIONER_INCOMPLETE_CHOLESKY;
    CHECK(dfm_session_set_solver(jacobi.session, &other) == DFM_ERROR_UNSUPPORTED);

    // An unknown value is refused, read as an integer.
    const std::uint32_t unknown = 7;
    dfm_solver_settings bad = {};
    std::memcpy(&bad.preconditioner, &unknown, sizeof unknown);
    const dfm_handle_group group = {cholesky.tip.data(), cholesky.tip.size()};
    dfm_session_desc desc = {};
    desc.roi = cholesky.roi;
    desc.groups = &group;
    desc.group_count = 1;
    desc.solver = bad;
    dfm_session* session = nullptr;
    CHECK(dfm_session_create(cholesky.mesh, &desc, &session) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(session == nullptr);
    CHECK(message_has("preconditioner"));
}

TEST_CASE("reports: Loop subdivision keeps the coarse vertices and their indices") {
    LimbEdit limb;
    dfm_mesh_info coarse = {};
    REQUIRE(dfm_mesh_get_info(limb.mesh, &coarse) == DFM_OK);
    dfm_mesh* fine = nullptr;
    REQUIRE_MESSAGE(dfm_mesh_subdivide(limb.mesh, 1, &fine) == DFM_OK, last_error());
    dfm_mesh_info info = {};
    REQUIRE(dfm_mesh_get_info(fine, &info) == DFM_OK);
    CHECK(info.triangle_count == 4 * coarse.triangle_count);
    CHECK(info.vertex_count > coarse.vertex_count);
    // Coarse vertex indices keep their meaning: the tip is still at the top.
    std::vector<double> positions(3 * info.vertex_count);
    dfm_vec3_output out = {};
    out.data = positions.data();
    out.count = info.vertex_count;
    out.type = DFM_SCALAR_FLOAT64;
    REQUIRE(dfm_mesh_read_positions(fine, &out) == DFM_OK);
    for (const std::uint32_t v : limb.tip) CHECK(positions[3 * v + 1] > 1.7);
    dfm_mesh_destroy(fine);

    dfm_mesh* none = nullptr;
    CHECK(dfm_mesh_subdivide(limb.mesh, 0, &none) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(dfm_mesh_subdivide(limb.mesh, 4, &none) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(message_has("steps 4"));
    CHECK(none == nullptr);
    CHECK(dfm_mesh_subdivide(nullptr, 1, &none) == DFM_ERROR_INVALID_HANDLE);
    CHECK(dfm_mesh_subdivide(limb.mesh, 1, nullptr) == DFM_ERROR_INVALID_ARGUMENT);
}

TEST_CASE("reports: a load's figures, the summary, and saving with options") {
    dfm_context* context = nullptr;
    REQUIRE(dfm_context_create(nullptr, &context) == DFM_OK);
    const std::filesystem::path dir = scratch_dir("sdk_reports");
    // A tetrahedron and a triangle that repeats a vertex (dropped).
    write_text(dir / "shape.off",
               "OFF\n4 5 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
               "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 3\n3 0 0 1\n");
    // A square written as one quad, fanned into two triangles.
    write_text(dir / "square.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n");
    dfm_load_report loaded = {};
    dfm_mesh* square = nullptr;
    REQUIRE_MESSAGE(dfm_mesh_load_with_report(context, (dir / "square.off").string().c_str(),
                                              &loaded, &square) == DFM_OK,
                    last_error());
    CHECK(loaded.polygons == 1);
    CHECK(loaded.triangulated_polygons == 1);
    CHECK(loaded.dropped_faces == 0);
    dfm_mesh_summary flat = {};
    REQUIRE(dfm_mesh_get_summary(square, &flat) == DFM_OK);
    CHECK(flat.boundary_edges == 4);
    CHECK_FALSE(flat.closed);
    dfm_mesh_destroy(square);

    dfm_mesh* mesh = nullptr;
    REQUIRE_MESSAGE(dfm_mesh_load_with_report(context, (dir / "shape.off").string().c_str(),
                                              &loaded, &mesh) == DFM_OK,
                    last_error());
    CHECK(loaded.polygons == 5);
    CHECK(loaded.triangulated_polygons == 0);
    CHECK(loaded.dropped_faces == 1);

    dfm_mesh_summary summary = {};
    REQUIRE(dfm_mesh_get_summary(mesh, &summary) == DFM_OK);
    CHECK(summary.edges == 6);
    CHECK(summary.boundary_edges == 0);
    CHECK(summary.non_manifold_edges == 0);
    CHECK(summary.components == 1);
    CHECK(summary.isolated_vertices == 0);
    CHECK(summary.closed);

    dfm_save_options options = {};
    options.ply_encoding = DFM_PLY_ASCII;
    const std::filesystem::path ply = dir / "shape.ply";
    REQUIRE(dfm_mesh_save_with_options(mesh, ply.string().c_str(), &options) == DFM_OK);
    CHECK(read_text(ply).starts_with("ply\nformat ascii 1.0\n"));
    const int unknown = 7;
    std::memcpy(&options.ply_encoding, &unknown, sizeof unknown);
    CHECK(dfm_mesh_save_with_options(mesh, ply.string().c_str(), &options) ==
          DFM_ERROR_INVALID_ARGUMENT);
    CHECK(message_has("ply_encoding 7"));

    dfm_mesh* none = nullptr;
    CHECK(dfm_mesh_load_with_report(context, (dir / "missing.off").string().c_str(), &loaded,
                                    &none) == DFM_ERROR_NOT_FOUND);
    CHECK(none == nullptr);
    CHECK(loaded.polygons == 0);
    CHECK(dfm_mesh_load_with_report(context, "x.off", nullptr, &none) ==
          DFM_ERROR_INVALID_ARGUMENT);
    CHECK(dfm_mesh_get_summary(nullptr, &summary) == DFM_ERROR_INVALID_HANDLE);
    dfm_mesh_destroy(mesh);
    dfm_context_destroy(context);
}
