// The solver's method through the C API (docs/method.md): the default is the
// fitted rotations, DFM_METHOD_PAPER selects the paper's iteration, and an
// unknown method is refused at creation.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "dualform/dualform.h"
#include "sdk/sdk_fixture.hpp"

using namespace dfm::test;

namespace {

// The limb's tip pushed sideways by half its length, solved at once.
std::vector<double> bend(dfm_method method, dfm_frame_info& info) {
    dfm_solver_settings solver = {};
    solver.method = method;
    LimbEdit limb(16, 20, solver);
    double m[16];
    translation(0.6, -0.2, 0.0, m);
    REQUIRE(dfm_session_set_group_transform(limb.session, 0, m) == DFM_OK);
    REQUIRE_MESSAGE(dfm_session_solve(limb.session, nullptr) == DFM_OK, last_error());
    const std::size_t n = limb.shape.vertex_count();
    std::vector<double> xyz(3 * n);
    const dfm_vec3_output out = {xyz.data(), n, 0, DFM_SCALAR_FLOAT64};
    REQUIRE_MESSAGE(dfm_session_read_positions(limb.session, &out, &info) == DFM_OK, last_error());
    return xyz;
}

}  // namespace

TEST_CASE("session: the default method is the fitted rotations, DFM_METHOD_PAPER the paper's") {
    dfm_frame_info by_default = {}, fitted = {}, paper = {};
    const std::vector<double> a = bend(DFM_METHOD_DEFAULT, by_default);
    const std::vector<double> b = bend(DFM_METHOD_FITTED_ROTATIONS, fitted);
    const std::vector<double> c = bend(DFM_METHOD_PAPER, paper);
    CHECK(by_default.converged);
    CHECK(paper.status == DFM_OK);
    CHECK(a == b);
    double apart = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) apart = std::max(apart, std::abs(a[i] - c[i]));
    CHECK(apart > 1e-3);
}

TEST_CASE("session: an unknown method is refused, naming the field") {
    LimbEdit limb;
    dfm_session_desc desc = {};
    desc.roi = limb.roi;
    const dfm_handle_group group = {limb.tip.data(), limb.tip.size()};
    desc.groups = &group;
    desc.group_count = 1;
    const unsigned int unknown = 7;  // a host's value outside the enum
    static_assert(sizeof unknown == sizeof desc.solver.method);
    std::memcpy(&desc.solver.method, &unknown, sizeof unknown);
    dfm_session* s = nullptr;
    CHECK(dfm_session_create(limb.mesh, &desc, &s) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(message_has("solver.method"));
    CHECK(s == nullptr);
}
