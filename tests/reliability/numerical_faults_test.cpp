// Numerical faults met through the C API: each gives a clear status, the
// session keeps its last good result (nothing lost), and the host can keep
// going. The plain cases (an iteration cap of 1, a NaN target, an infinite
// transform element) are in tests/sdk/session_api_test.cpp; these are the
// ones a host meets with real data.

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <doctest/doctest.h>

#include "sdk/sdk_fixture.hpp"
#include "support/procedural_meshes.hpp"

namespace dfm::test {

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();
constexpr double nan = std::numeric_limits<double>::quiet_NaN();

// The newest frame's ROI positions, x y z per vertex.
std::vector<double> roi_positions(dfm_session* session, const dfm_roi* roi, dfm_frame_info& info) {
    std::size_t count = 0;
    REQUIRE(dfm_roi_count(roi, &count) == DFM_OK);
    std::vector<double> xyz(3 * count);
    const dfm_vec3_output out = {xyz.data(), count, 0, DFM_SCALAR_FLOAT64};
    REQUIRE_MESSAGE(dfm_session_read_roi_positions(session, &out, &info) == DFM_OK, last_error());
    return xyz;
}

bool all_finite(const std::vector<double>& values) {
    for (double v : values) {
        if (!std::isfinite(v)) return false;
    }
    return true;
}

double largest_difference(const std::vector<double>& a, const std::vector<double>& b) {
    REQUIRE(a.size() == b.size());
    double largest = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) largest = std::max(largest, std::abs(a[i] - b[i]));
    return largest;
}

// Submits the staged targets and waits for their finished frame.
dfm_frame_info submit_and_wait(dfm_session* session) {
    std::uint64_t g = 0;
    REQUIRE(dfm_session_submit(session, &g) == DFM_OK);
    dfm_frame_info info = {};
    REQUIRE(dfm_session_wait(session, g, -1, &info) == DFM_OK);
    CHECK(info.generation == g);
    return info;
}

void stage_translation(dfm_session* session, double x, double y, double z) {
    double m[16];
    translation(x, y, z, m);
    REQUIRE_MESSAGE(dfm_session_set_group_transform(session, 0, m) == DFM_OK, last_error());
}

}  // namespace

TEST_CASE(
    "numerical fault: refused non-finite targets leave the staged targets and frame as they were") {
    LimbEdit limb;
    stage_translation(limb.session, 0.4, 0.0, 0.0);
    const dfm_frame_info good = submit_and_wait(limb.session);
    REQUIRE(good.converged);
    dfm_frame_info info = {};
    const std::vector<double> good_positions = roi_positions(limb.session, limb.roi, info);

    double m[16];
    translation(0.0, 0.0, 0.0, m);
    m[0] = nan;
    CHECK(dfm_session_set_group_transform(limb.session, 0, m) == DFM_ERROR_NUMERICAL);
    std::vector<double> targets(3 * limb.tip.size(), 1.0);
    targets[3 * limb.tip.size() - 1] = -inf;
    const dfm_vec3_input in = {targets.data(), limb.tip.size(), 0, DFM_SCALAR_FLOAT64};
    CHECK(dfm_session_set_targets(limb.session, &in) == DFM_ERROR_NUMERICAL);
    CHECK(std::string(dfm_last_error_message()).find("not finite") != std::string::npos);

    // Nothing was staged: solving again lands where the good frame is, to
    // within the solver's stopping tolerance.
    const dfm_frame_info again = submit_and_wait(limb.session);
    CHECK(again.status == DFM_OK);
    CHECK(again.converged);
    CHECK(largest_difference(roi_positions(limb.session, limb.roi, info), good_positions) < 1e-4);
}

TEST_CASE("numerical fault: an iteration-capped solve is finite and a later cap finishes it") {
    dfm_solver_settings capped = {};
    capped.max_iterations = 1;
    capped.tolerance = 1e-14;
    LimbEdit limb(16, 20, capped);
    stage_translation(limb.session, 0.5, 0.0, 0.0);
    dfm_frame_info first = {};
    REQUIRE(dfm_session_solve(limb.session, nullptr) == DFM_OK);
    const std::vector<double> after_one = roi_positions(limb.session, limb.roi, first);
    CHECK_FALSE(first.converged);
    CHECK(first.status == DFM_OK);
    CHECK(all_finite(after_one));

    dfm_solver_settings finish = {};
    finish.max_iterations = 200;
    finish.tolerance = 1e-6;
    REQUIRE(dfm_session_set_solver(limb.session, &finish) == DFM_OK);
    const dfm_frame_info done = submit_and_wait(limb.session);
    CHECK(done.converged);
    CHECK(done.status == DFM_OK);
    dfm_frame_info info = {};
    const std::vector<double> finished = roi_positions(limb.session, limb.roi, info);
    CHECK(all_finite(finished));
    CHECK(largest_difference(finished, after_one) > 0.0);
}

TEST_CASE("numerical fault: a handle a million diagonals away, then a sane drag") {
    LimbEdit limb;
    stage_translation(limb.session, 0.3, 0.0, 0.0);
    const dfm_frame_info good = submit_and_wait(limb.session);
    REQUIRE(good.converged);
    dfm_frame_info info = {};
    const std::vector<double> good_positions = roi_positions(limb.session, limb.roi, info);

    dfm_mesh_info mesh_info = {};
    REQUIRE(dfm_mesh_get_info(limb.mesh, &mesh_info) == DFM_OK);
    const double far = 1e6 * mesh_info.diagonal;
    stage_translation(limb.session, far, far, far);
    const dfm_frame_info wild = submit_and_wait(limb.session);
    const std::vector<double> wild_positions = roi_positions(limb.session, limb.roi, info);
    const std::string outcome = std::string(dfm_result_name(wild.status)) +
                                (wild.converged ? ", converged" : ", not converged");
    MESSAGE("a handle 1e6 diagonals away: " << outcome);
    CHECK(all_finite(wild_positions));
    CHECK((wild.status == DFM_OK || wild.status == DFM_ERROR_NUMERICAL));
    if (wild.status == DFM_ERROR_NUMERICAL) CHECK(wild_positions == good_positions);

    // The host drags back: the session recovers the sane shape.
    stage_translation(limb.session, 0.3, 0.0, 0.0);
    const dfm_frame_info back = submit_and_wait(limb.session);
    CHECK(back.status == DFM_OK);
    CHECK(back.converged);
    CHECK(largest_difference(roi_positions(limb.session, limb.roi, info), good_positions) < 1e-3);
}

namespace {

// The limb with every vertex above y = 0.5 (the ROI) moved by `collapse`:
// a region of zero-area triangles.
template <class Collapse>
void check_degenerate_region(Collapse&& collapse) {
    mesh::Mesh shape = make_limb(16, 20, 0.2, 2.0);
    std::vector<std::uint32_t> region;
    std::vector<std::uint32_t> tip;
    for (std::uint32_t v = 0; v < shape.vertex_count(); ++v) {
        if (shape.positions[v].y > 0.5) region.push_back(v);
        if (shape.positions[v].y >= 1.8) tip.push_back(v);
    }
    for (std::uint32_t v : region) collapse(shape.positions[v]);

    dfm_context* context = nullptr;
    REQUIRE(dfm_context_create(nullptr, &context) == DFM_OK);
    dfm_mesh* mesh = make_c_mesh(context, shape);
    dfm_roi* roi = nullptr;
    REQUIRE(dfm_roi_from_vertices(mesh, region.data(), region.size(), &roi) == DFM_OK);
    const dfm_handle_group group = {tip.data(), tip.size()};
    dfm_session_desc desc = {};
    desc.roi = roi;
    desc.groups = &group;
    desc.group_count = 1;
    dfm_session* session = nullptr;
    const dfm_result created = dfm_session_create(mesh, &desc, &session);
    MESSAGE("dfm_session_create: " << (created == DFM_OK ? "DFM_OK" : last_error()));
    CHECK_MESSAGE((created == DFM_OK || created == DFM_ERROR_NUMERICAL), last_error());
    if (created != DFM_OK) {
        CHECK(session == nullptr);
        CHECK(std::string(dfm_last_error_message()).size() >
              std::string("dfm_session_create: ").size());
    } else {
        dfm_frame_info info = {};
        const std::vector<double> start = roi_positions(session, roi, info);
        stage_translation(session, 0.3, 0.0, 0.0);
        const dfm_result solved = dfm_session_solve(session, nullptr);
        MESSAGE("dfm_session_solve: " << std::string(dfm_result_name(solved)));
        CHECK_MESSAGE((solved == DFM_OK || solved == DFM_ERROR_NUMERICAL), last_error());
        const std::vector<double> after = roi_positions(session, roi, info);
        CHECK(all_finite(after));
        CHECK(info.status == solved);
        if (solved != DFM_OK) CHECK(after == start);
        // The host keeps going.
        stage_translation(session, 0.1, 0.0, 0.0);
        std::uint64_t g = 0;
        REQUIRE(dfm_session_submit(session, &g) == DFM_OK);
        REQUIRE(dfm_session_wait(session, g, -1, &info) == DFM_OK);
        CHECK(all_finite(roi_positions(session, roi, info)));
    }
    dfm_session_destroy(session);
    dfm_roi_destroy(roi);
    dfm_mesh_destroy(mesh);
    dfm_context_destroy(context);
}

}  // namespace

TEST_CASE("numerical fault: a region collapsed to a point") {
    check_degenerate_region([](glm::dvec3& p) { p = glm::dvec3(0.0, 1.0, 0.0); });
}

TEST_CASE("numerical fault: a region collapsed to a line") {
    check_degenerate_region([](glm::dvec3& p) { p.x = p.z = 0.0; });
}

}  // namespace dfm::test
