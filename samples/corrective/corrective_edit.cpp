#include "corrective_edit.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace corrective {

namespace {

// The edit's region: every vertex within this distance of the elbow along
// the arm (in the bind pose), past the weights' blend zone, so that its
// fixed border is skinned rigidly.
constexpr double region_half_length = 0.3;
// Its handles: the edge loops at these distances from the elbow (the tube
// has one every 1/48 along the arm).
constexpr double loop_offsets[] = {-0.1875, -0.125, -0.0625, 0.0, 0.0625, 0.125, 0.1875};

bool ok(dfm_result result, const char* call) {
    if (result == DFM_OK) return true;
    std::fprintf(stderr, "corrective: %s: %s: %s\n", call, dfm_result_name(result),
                 dfm_last_error_message());
    return false;
}

// Owns what one edit creates.
struct Edit {
    dfm_roi* region = nullptr;
    dfm_session* session = nullptr;
    ~Edit() {
        dfm_session_destroy(session);
        dfm_roi_destroy(region);
    }
};

}  // namespace

bool make(dfm_mesh* mesh, const arm::Arm& arm, double degrees, Corrective& out) {
    out = Corrective{};
    out.degrees = degrees;
    const std::size_t n = arm.vertex_count();
    const std::array<arm::Matrix, arm::joint_count> joints = arm::joint_matrices(arm, degrees);
    std::vector<double>& posed = out.unedited;
    posed.resize(3 * n);
    const dfm_vec3_output posed_out = {posed.data(), n, 0, DFM_SCALAR_FLOAT64};
    if (!ok(dfm_mesh_set_pose_joints(mesh, joints[0].data(), arm::joint_count, nullptr, 0),
            "dfm_mesh_set_pose_joints") ||
        !ok(dfm_mesh_read_positions(mesh, &posed_out), "dfm_mesh_read_positions")) {
        return false;
    }

    // The region and the handles, chosen on the bind pose as a rigger picks
    // edge loops; each handle's target is where its elbow weight's share of
    // the bend turns it rigidly.
    std::vector<std::uint32_t> region, handles;
    std::vector<double> targets;
    for (std::size_t v = 0; v < n; ++v) {
        const double along = arm.positions[3 * v] - arm.upper_length;
        if (std::abs(along) > region_half_length) continue;
        const auto vertex = static_cast<std::uint32_t>(v);
        region.push_back(vertex);
        for (double offset : loop_offsets) {
            if (std::abs(along - offset) > 1e-4) continue;
            handles.push_back(vertex);
            const double share = arm.weights[arm::influences * v + 1];
            double target[3];
            arm::turn_about_elbow(arm, share * degrees, &arm.positions[3 * v], target);
            targets.insert(targets.end(), target, target + 3);
            out.largest_drag = std::max(
                out.largest_drag, std::hypot(target[0] - posed[3 * v], target[1] - posed[3 * v + 1],
                                             target[2] - posed[3 * v + 2]));
        }
    }
    out.region_count = region.size();
    out.handle_count = handles.size();

    Edit edit;
    const dfm_handle_group group = {handles.data(), handles.size()};
    dfm_session_desc desc = {};
    desc.struct_size = sizeof desc;
    desc.groups = &group;
    desc.group_count = 1;
    const dfm_vec3_input target_input = {targets.data(), handles.size(), 0, DFM_SCALAR_FLOAT64};
    std::uint64_t generation = 0;
    dfm_frame_info solved = {};
    if (!ok(dfm_roi_from_vertices(mesh, region.data(), region.size(), &edit.region),
            "dfm_roi_from_vertices")) {
        return false;
    }
    desc.roi = edit.region;
    if (!ok(dfm_session_create(mesh, &desc, &edit.session), "dfm_session_create") ||
        !ok(dfm_session_set_targets(edit.session, &target_input), "dfm_session_set_targets") ||
        !ok(dfm_session_submit(edit.session, &generation), "dfm_session_submit") ||
        !ok(dfm_session_wait(edit.session, generation, -1, &solved), "dfm_session_wait") ||
        !ok(solved.status, "the solve")) {
        return false;
    }
    out.iterations = solved.iterations;
    // The bake in the pose: the mesh's bind positions move by the corrective.
    if (!ok(dfm_session_bake(edit.session), "dfm_session_bake") ||
        !ok(dfm_mesh_get_skin_info(mesh, &out.skin), "dfm_mesh_get_skin_info")) {
        return false;
    }
    std::vector<double> bind(3 * n);
    const dfm_vec3_output bind_out = {bind.data(), n, 0, DFM_SCALAR_FLOAT64};
    out.edited.resize(3 * n);
    const dfm_vec3_output edited_out = {out.edited.data(), n, 0, DFM_SCALAR_FLOAT64};
    if (!ok(dfm_mesh_read_bind_positions(mesh, &bind_out), "dfm_mesh_read_bind_positions") ||
        !ok(dfm_mesh_read_positions(mesh, &edited_out), "dfm_mesh_read_positions")) {
        return false;
    }
    // Kept in float, as an engine keeps a morph target.
    out.delta.resize(3 * n);
    for (std::size_t i = 0; i < 3 * n; ++i) {
        out.delta[i] = static_cast<float>(bind[i] - static_cast<double>(arm.positions[i]));
    }
    return true;
}

}  // namespace corrective
