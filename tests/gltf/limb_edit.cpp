#include "limb_edit.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <iterator>
#include <string>

namespace dfm::test::gltf {

namespace {

std::string failure() {
    return std::string(dfm_result_name(dfm_last_error_code())) + ": " + dfm_last_error_message();
}

std::vector<std::uint32_t> read_roi(const dfm_roi* roi) {
    std::size_t n = 0;
    REQUIRE(dfm_roi_count(roi, &n) == DFM_OK);
    std::vector<std::uint32_t> out(n);
    REQUIRE(dfm_roi_read(roi, out.data(), n) == DFM_OK);
    return out;
}

struct RoiPtr {
    dfm_roi* roi = nullptr;
    ~RoiPtr() { dfm_roi_destroy(roi); }
};

}  // namespace

ContextPtr make_context() {
    dfm_context* c = nullptr;
    REQUIRE_MESSAGE(dfm_context_create(nullptr, &c) == DFM_OK, failure());
    return ContextPtr(c);
}

MeshPtr load_mesh(dfm_context* context, const std::filesystem::path& path) {
    dfm_mesh* m = nullptr;
    REQUIRE_MESSAGE(dfm_mesh_load(context, path.c_str(), &m) == DFM_OK, failure());
    return MeshPtr(m);
}

std::vector<double> rest_positions(const dfm_mesh* mesh) {
    dfm_mesh_info info{};
    REQUIRE(dfm_mesh_get_info(mesh, &info) == DFM_OK);
    std::vector<double> out(3 * info.vertex_count);
    const dfm_vec3_output o{out.data(), info.vertex_count, 0, DFM_SCALAR_FLOAT64};
    REQUIRE_MESSAGE(dfm_mesh_read_positions(mesh, &o) == DFM_OK, failure());
    return out;
}

double diagonal(const dfm_mesh* mesh) {
    dfm_mesh_info info{};
    REQUIRE(dfm_mesh_get_info(mesh, &info) == DFM_OK);
    return info.diagonal;
}

EditOutcome edit_limb(dfm_mesh* mesh, const LimbEdit& edit, bool bake) {
    EditOutcome out;
    RoiPtr fill, ball;
    dfm_water_fill_diagnosis diagnosis{};
    REQUIRE_MESSAGE(
        dfm_roi_water_fill(mesh, edit.first, edit.last, &fill.roi, &diagnosis) == DFM_OK,
        failure());
    CHECK_FALSE(diagnosis.suspect);
    REQUIRE_MESSAGE(dfm_roi_ball(mesh, edit.handle, edit.handle_radius, &ball.roi) == DFM_OK,
                    failure());
    out.roi = read_roi(fill.roi);
    const std::vector<std::uint32_t> near = read_roi(ball.roi);
    std::set_intersection(out.roi.begin(), out.roi.end(), near.begin(), near.end(),
                          std::back_inserter(out.handles));
    REQUIRE(!out.handles.empty());

    const dfm_handle_group group{out.handles.data(), out.handles.size()};
    dfm_session_desc desc{};
    desc.struct_size = sizeof desc;
    desc.roi = fill.roi;
    desc.groups = &group;
    desc.group_count = 1;
    // Tight enough that meshes of one surface in other vertex orders agree
    // far below 1e-9 diagonals; 1e-10 is past what the iteration reaches on
    // Suzanne's ear in 1,000 steps.
    desc.solver.tolerance = 1e-9;
    desc.solver.max_iterations = 1000;
    dfm_session* session = nullptr;
    REQUIRE_MESSAGE(dfm_session_create(mesh, &desc, &session) == DFM_OK, failure());
    double m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    std::copy(edit.translate, edit.translate + 3, m + 12);
    CHECK_MESSAGE(dfm_session_set_group_transform(session, 0, m) == DFM_OK, failure());
    uint64_t generation = 0;
    CHECK_MESSAGE(dfm_session_solve(session, &generation) == DFM_OK, failure());
    out.positions.resize(rest_positions(mesh).size());
    const dfm_vec3_output o{out.positions.data(), out.positions.size() / 3, 0, DFM_SCALAR_FLOAT64};
    dfm_frame_info info{};
    CHECK_MESSAGE(dfm_session_read_positions(session, &o, &info) == DFM_OK, failure());
    CHECK(info.converged);
    if (bake) CHECK_MESSAGE(dfm_session_bake(session) == DFM_OK, failure());
    dfm_session_destroy(session);
    return out;
}

}  // namespace dfm::test::gltf
