// The report calls: quality figures and solver figures of a frame, and Loop
// subdivision, as the dualform tool uses them.

#include <doctest/doctest.h>

#include <cmath>
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
