// The report calls: quality figures and solver figures of a frame, and Loop
// subdivision, as the dualform tool uses them.

#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "dualform/dualform.h"
#include "sdk_fixture.hpp"

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
