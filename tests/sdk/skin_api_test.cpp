#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/matrix.hpp>

#include "dualform/dualform.h"
#include "sdk/sdk_fixture.hpp"
#include "support/skinned_limb.hpp"
#include "support/test_files.hpp"

using namespace dfm;
using namespace dfm::test;

namespace {

struct Context {
    dfm_context* context = nullptr;
    Context() { REQUIRE(dfm_context_create(nullptr, &context) == DFM_OK); }
    ~Context() { dfm_context_destroy(context); }
};

std::vector<glm::dvec3> read_positions(const dfm_mesh* mesh, bool bind = false) {
    dfm_mesh_info info = {};
    REQUIRE(dfm_mesh_get_info(mesh, &info) == DFM_OK);
    std::vector<glm::dvec3> out(info.vertex_count);
    dfm_vec3_output o = {out.data(), out.size(), 0, DFM_SCALAR_FLOAT64};
    REQUIRE(bind ? dfm_mesh_read_bind_positions(mesh, &o) == DFM_OK
                 : dfm_mesh_read_positions(mesh, &o) == DFM_OK);
    return out;
}

// `name` is the test case's own: CTest runs the cases side by side, and a
// scratch folder is made anew by each that asks for it.
dfm_mesh* load_limb(dfm_context* context, const SkinnedLimb& limb, const char* name) {
    const auto dir = scratch_dir(std::string("skin_api_") + name);
    write_text(dir / name, limb.glb);
    dfm_mesh* mesh = nullptr;
    REQUIRE_MESSAGE(dfm_mesh_load(context, (dir / name).string().c_str(), &mesh) == DFM_OK,
                    last_error());
    return mesh;
}

// Linear blend skinning written out here, apart from the engine's.
glm::dvec3 skin_by_hand(const SkinnedLimb& limb, std::size_t v, const glm::dmat4& shoulder,
                        const glm::dmat4& elbow, const glm::dvec3& p) {
    const glm::dvec4 q(p, 1.0);
    return glm::dvec3(limb.weights[v][0] * (shoulder * limb.inverse_bind[0] * q) +
                      limb.weights[v][1] * (elbow * limb.inverse_bind[1] * q));
}

double largest_distance(const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b) {
    double d = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, glm::length(a[i] - b[i]));
    return d;
}

// The limb's hand (y >= 1.7 at rest) lifted by a session on the ROI above
// y = 1.0 at rest; the session solved and baked. The vertex lists are the
// same for every mesh made from the limb.
struct HandLift {
    std::vector<std::uint32_t> roi, hand;
};

HandLift hand_lift(const SkinnedLimb& limb) {
    HandLift h;
    for (std::uint32_t v = 0; v < limb.mesh.vertex_count(); ++v) {
        if (limb.mesh.positions[v].y > 1.0) h.roi.push_back(v);
        if (limb.mesh.positions[v].y >= 1.7) h.hand.push_back(v);
    }
    return h;
}

void lift_and_bake(dfm_mesh* mesh, const HandLift& lift, double dx, double dy) {
    dfm_roi* roi = nullptr;
    REQUIRE(dfm_roi_from_vertices(mesh, lift.roi.data(), lift.roi.size(), &roi) == DFM_OK);
    dfm_handle_group group = {lift.hand.data(), lift.hand.size()};
    dfm_session_desc desc = {};
    desc.roi = roi;
    desc.groups = &group;
    desc.group_count = 1;
    dfm_session* session = nullptr;
    REQUIRE_MESSAGE(dfm_session_create(mesh, &desc, &session) == DFM_OK, last_error());
    double m[16];
    translation(dx, dy, 0.0, m);
    REQUIRE(dfm_session_set_group_transform(session, 0, m) == DFM_OK);
    REQUIRE_MESSAGE(dfm_session_solve(session, nullptr) == DFM_OK, last_error());
    REQUIRE_MESSAGE(dfm_session_bake(session) == DFM_OK, last_error());
    dfm_session_destroy(session);
    dfm_roi_destroy(roi);
}

}  // namespace

TEST_CASE("skin api: a skinned glTF lists its joints, animations and morph targets") {
    Context c;
    const SkinnedLimb limb = make_skinned_limb(12, 10);
    dfm_mesh* mesh = load_limb(c.context, limb, "listed.glb");
    dfm_skin_info info = {};
    REQUIRE(dfm_mesh_get_skin_info(mesh, &info) == DFM_OK);
    CHECK(info.joint_count == 2);
    CHECK(info.max_influences == 2);
    CHECK(info.skinned_vertex_count == limb.mesh.vertex_count());
    CHECK(info.animation_count == 2);
    CHECK(info.morph_target_count == 1);
    CHECK_FALSE(info.posed);
    CHECK(info.pose_animation == -1);
    dfm_joint_info joint = {};
    REQUIRE(dfm_mesh_get_joint_info(mesh, 1, &joint) == DFM_OK);
    CHECK(std::string(joint.name) == "Elbow");
    CHECK(joint.parent == 0);
    REQUIRE(dfm_mesh_get_joint_info(mesh, 0, &joint) == DFM_OK);
    CHECK(joint.parent == UINT32_MAX);
    CHECK(dfm_mesh_get_joint_info(mesh, 2, &joint) == DFM_ERROR_OUT_OF_RANGE);
    dfm_animation_info animation = {};
    REQUIRE(dfm_mesh_get_animation_info(mesh, 0, &animation) == DFM_OK);
    CHECK(std::string(animation.name) == "Bend");
    CHECK(animation.rotation_channels == 1);
    CHECK(animation.translation_channels == 1);
    CHECK(animation.weight_channels == 1);
    std::uint32_t index = 9;
    REQUIRE(dfm_mesh_find_animation(mesh, "Spline", &index) == DFM_OK);
    CHECK(index == 1);
    CHECK(dfm_mesh_find_animation(mesh, "Run", &index) == DFM_ERROR_NOT_FOUND);
    CHECK(message_has("'Bend', 'Spline'"));
    dfm_morph_target_info target = {};
    REQUIRE(dfm_mesh_get_morph_target_info(mesh, 0, &target) == DFM_OK);
    CHECK(std::string(target.name) == "Flex");
    CHECK(target.default_weight == 0.25);
    dfm_mesh_destroy(mesh);
}

TEST_CASE("skin api: posing by animation or by joint matrices shows the skinned shape") {
    Context c;
    const SkinnedLimb limb = make_skinned_limb(12, 10);
    dfm_mesh* mesh = load_limb(c.context, limb, "posing.glb");
    // Without a pose the mesh is its bind pose, as it always was.
    const std::vector<glm::dvec3> bind = read_positions(mesh);
    CHECK(largest_distance(bind, limb.mesh.positions) == 0.0);

    REQUIRE(dfm_mesh_set_pose_animation(mesh, 0, 1.0) == DFM_OK);
    const glm::dmat4 shoulder = glm::translate(glm::dmat4(1.0), glm::dvec3(0.1, 0.0, 0.0));
    const glm::dmat4 elbow = shoulder * elbow_world(limb, 90.0);
    std::vector<glm::dvec3> expected(bind.size());
    for (std::size_t v = 0; v < bind.size(); ++v) {
        expected[v] = skin_by_hand(limb, v, shoulder, elbow, bind[v] + limb.flex[v]);
    }
    CHECK(largest_distance(read_positions(mesh), expected) < 1e-6);  // float keys
    CHECK(read_positions(mesh, true) == bind);
    dfm_skin_info info = {};
    REQUIRE(dfm_mesh_get_skin_info(mesh, &info) == DFM_OK);
    CHECK(info.posed);
    CHECK(info.pose_animation == 0);
    CHECK(info.pose_time == 1.0);
    std::vector<double> joints(32);
    REQUIRE(dfm_mesh_read_joint_matrices(mesh, joints.data(), joints.size()) == DFM_OK);
    const glm::dmat4 read_elbow = glm::make_mat4(joints.data() + 16);
    CHECK(glm::length(read_elbow[3] - elbow[3]) < 1e-6);

    // The same pose from the host's joint matrices, Flex at 1: the same shape.
    const glm::dmat4 world[2] = {shoulder, elbow};
    const double flex = 1.0;
    REQUIRE(dfm_mesh_set_pose_joints(mesh, glm::value_ptr(world[0]), 2, &flex, 1) == DFM_OK);
    // The file's float weights, normalised to sum 1, differ from the
    // limb's by their float rounding.
    CHECK(largest_distance(read_positions(mesh), expected) < 1e-6);

    REQUIRE(dfm_mesh_clear_pose(mesh) == DFM_OK);
    CHECK(read_positions(mesh) == bind);
    dfm_mesh_destroy(mesh);
}

TEST_CASE("skin api: a posed edit is the static copy's edit, and its bake an exact corrective") {
    Context c;
    const SkinnedLimb limb = make_skinned_limb(16, 24);
    const HandLift lift = hand_lift(limb);
    dfm_mesh* posed = load_limb(c.context, limb, "posed-edit.glb");
    REQUIRE(dfm_mesh_set_pose_animation(posed, 0, 1.0) == DFM_OK);
    const std::vector<glm::dvec3> shown = read_positions(posed);

    // The static copy: the posed positions as a plain host mesh.
    std::vector<std::uint32_t> indices;
    for (const mesh::Triangle& t : limb.mesh.triangles)
        indices.insert(indices.end(), t.begin(), t.end());
    dfm_mesh_desc desc = {};
    desc.positions = {shown.data(), shown.size(), 0, DFM_SCALAR_FLOAT64};
    desc.indices = indices.data();
    desc.triangle_count = limb.mesh.face_count();
    dfm_mesh* copy = nullptr;
    REQUIRE(dfm_mesh_create(c.context, &desc, &copy) == DFM_OK);

    lift_and_bake(posed, lift, -0.3, 0.2);
    lift_and_bake(copy, lift, -0.3, 0.2);
    const std::vector<glm::dvec3> edited = read_positions(copy);
    const double diagonal = 2.0;
    CHECK(largest_distance(read_positions(posed), edited) < 1e-12 * diagonal);
    CHECK(largest_distance(edited, shown) > 0.1);

    // The bind-space corrective, skinned at the pose by hand, is the edit.
    const std::vector<glm::dvec3> bind = read_positions(posed, true);
    const glm::dmat4 shoulder = glm::translate(glm::dmat4(1.0), glm::dvec3(0.1, 0.0, 0.0));
    std::vector<glm::dvec3> replayed(bind.size());
    for (std::size_t v = 0; v < bind.size(); ++v) {
        replayed[v] = skin_by_hand(limb, v, shoulder, shoulder * elbow_world(limb, 90.0),
                                   bind[v] + limb.flex[v]);
    }
    CHECK(largest_distance(replayed, edited) < 1e-6 * diagonal);  // the file's float keys
    dfm_skin_info info = {};
    REQUIRE(dfm_mesh_get_skin_info(posed, &info) == DFM_OK);
    CHECK(info.corrective_vertex_count > 0);
    CHECK(info.corrective_damped_count == 0);
    // Where the elbow blends two joints at 90 degrees, L_v is no rotation.
    CHECK(info.corrective_worst_condition > 1.0);
    CHECK(info.corrective_worst_condition < 2.0);

    // Back in bind pose the corrective shows unposed; undo takes it back.
    REQUIRE(dfm_mesh_clear_pose(posed) == DFM_OK);
    CHECK(read_positions(posed) == bind);
    REQUIRE(dfm_mesh_undo_bake(posed) == DFM_OK);
    CHECK(largest_distance(read_positions(posed), limb.mesh.positions) == 0.0);
    dfm_mesh_destroy(copy);
    dfm_mesh_destroy(posed);
}

TEST_CASE("skin api: a corrective saved as a morph target replays the edit in float32") {
    Context c;
    const SkinnedLimb limb = make_skinned_limb(16, 24);
    const auto dir = scratch_dir("skin_api_save");
    dfm_mesh* mesh = load_limb(c.context, limb, "saved.glb");
    REQUIRE(dfm_mesh_set_pose_animation(mesh, 0, 1.0) == DFM_OK);
    lift_and_bake(mesh, hand_lift(limb), 0.0, 0.3);
    const std::vector<glm::dvec3> edited = read_positions(mesh);
    dfm_save_options options = {};
    options.struct_size = sizeof options;
    options.morph_target_name = "Lift";
    const std::string out = (dir / "corrective.glb").string();
    REQUIRE_MESSAGE(dfm_mesh_save_with_options(mesh, out.c_str(), &options) == DFM_OK,
                    last_error());

    // Read back: its base is the asset's, the new target the corrective.
    dfm_mesh* saved = nullptr;
    REQUIRE(dfm_mesh_load(c.context, out.c_str(), &saved) == DFM_OK);
    dfm_skin_info info = {};
    REQUIRE(dfm_mesh_get_skin_info(saved, &info) == DFM_OK);
    REQUIRE(info.morph_target_count == 2);
    dfm_morph_target_info target = {};
    REQUIRE(dfm_mesh_get_morph_target_info(saved, 1, &target) == DFM_OK);
    CHECK(std::string(target.name) == "Lift");
    CHECK(target.default_weight == 0.0);
    CHECK(read_positions(saved) == limb.mesh.positions);
    // Played at the pose with the new target at 1, its shape is the edit.
    std::vector<double> joints(32);
    REQUIRE(dfm_mesh_read_joint_matrices(mesh, joints.data(), joints.size()) == DFM_OK);
    const double weights[2] = {1.0, 1.0};
    REQUIRE(dfm_mesh_set_pose_joints(saved, joints.data(), 2, weights, 2) == DFM_OK);
    CHECK(largest_distance(read_positions(saved), edited) < 1e-5 * 2.0);
    // The animation's weights channel drives two targets now: still valid.
    REQUIRE(dfm_mesh_set_pose_animation(saved, 0, 0.5) == DFM_OK);
    dfm_mesh_destroy(saved);
    dfm_mesh_destroy(mesh);
}

TEST_CASE("skin api: the posed positions read the same before and after the posed model is built") {
    Context c;
    const SkinnedLimb limb = make_skinned_limb(16, 24);
    dfm_mesh* mesh = load_limb(c.context, limb, "reads.glb");
    REQUIRE(dfm_mesh_set_pose_animation(mesh, 0, 1.0) == DFM_OK);
    const std::vector<glm::dvec3> posed = read_positions(mesh);  // no model built yet
    dfm_roi* all = nullptr;
    REQUIRE(dfm_roi_all(mesh, &all) == DFM_OK);  // builds it
    dfm_roi_destroy(all);
    CHECK(read_positions(mesh) == posed);
    // Through bakes, undo and redo the reads follow the shown shape.
    lift_and_bake(mesh, hand_lift(limb), 0.0, 0.2);
    const std::vector<glm::dvec3> edited = read_positions(mesh);
    CHECK(largest_distance(edited, posed) > 0.1);
    REQUIRE(dfm_mesh_undo_bake(mesh) == DFM_OK);
    CHECK(largest_distance(read_positions(mesh), posed) == 0.0);
    REQUIRE(dfm_mesh_redo_bake(mesh) == DFM_OK);
    // Redo skins the corrected bind pose again: the edit to rounding.
    CHECK(largest_distance(read_positions(mesh), edited) < 1e-12);
    REQUIRE(dfm_mesh_set_pose_animation(mesh, 0, 0.5) == DFM_OK);
    const std::vector<glm::dvec3> half = read_positions(mesh);
    REQUIRE(dfm_roi_all(mesh, &all) == DFM_OK);
    dfm_roi_destroy(all);
    CHECK(read_positions(mesh) == half);
    dfm_mesh_destroy(mesh);
}

TEST_CASE("skin api: a pose change stops earlier sessions' bakes") {
    Context c;
    const SkinnedLimb limb = make_skinned_limb(12, 12);
    const HandLift lift = hand_lift(limb);
    dfm_mesh* mesh = load_limb(c.context, limb, "pose-change.glb");
    dfm_roi* roi = nullptr;
    REQUIRE(dfm_roi_from_vertices(mesh, lift.roi.data(), lift.roi.size(), &roi) == DFM_OK);
    dfm_handle_group group = {lift.hand.data(), lift.hand.size()};
    dfm_session_desc desc = {};
    desc.roi = roi;
    desc.groups = &group;
    desc.group_count = 1;
    dfm_session* session = nullptr;
    REQUIRE(dfm_session_create(mesh, &desc, &session) == DFM_OK);
    REQUIRE(dfm_session_solve(session, nullptr) == DFM_OK);
    REQUIRE(dfm_mesh_set_pose_animation(mesh, 0, 0.5) == DFM_OK);
    CHECK(dfm_session_bake(session) == DFM_ERROR_BUSY);
    dfm_session_destroy(session);
    dfm_roi_destroy(roi);
    dfm_mesh_destroy(mesh);
}

TEST_CASE("skin api: bad poses and skins are refused, naming what is wrong") {
    Context c;
    const SkinnedLimb limb = make_skinned_limb(8, 6);
    dfm_mesh* mesh = load_limb(c.context, limb, "refusals.glb");
    const std::vector<glm::dvec3> bind = read_positions(mesh);
    CHECK(dfm_mesh_set_pose_animation(mesh, 0, NAN) == DFM_ERROR_NUMERICAL);
    CHECK(dfm_mesh_set_pose_animation(mesh, 5, 0.0) == DFM_ERROR_OUT_OF_RANGE);
    glm::dmat4 world[2] = {glm::dmat4(1.0), glm::dmat4(1.0)};
    CHECK(dfm_mesh_set_pose_joints(mesh, glm::value_ptr(world[0]), 1, nullptr, 0) ==
          DFM_ERROR_INVALID_ARGUMENT);
    CHECK(message_has("joint_count is 1, the skin has 2 joints"));
    world[1][2][3] = 0.5;
    CHECK(dfm_mesh_set_pose_joints(mesh, glm::value_ptr(world[0]), 2, nullptr, 0) ==
          DFM_ERROR_NUMERICAL);
    CHECK(message_has("joint 1's matrix is not affine"));
    world[1] = glm::dmat4(1.0);
    world[0][3][0] = INFINITY;
    CHECK(dfm_mesh_set_pose_joints(mesh, glm::value_ptr(world[0]), 2, nullptr, 0) ==
          DFM_ERROR_NUMERICAL);
    const double weight = NAN;
    world[0] = glm::dmat4(1.0);
    CHECK(dfm_mesh_set_pose_joints(mesh, glm::value_ptr(world[0]), 2, &weight, 1) ==
          DFM_ERROR_NUMERICAL);
    CHECK(dfm_mesh_set_pose_joints(mesh, nullptr, 2, nullptr, 0) == DFM_ERROR_INVALID_ARGUMENT);
    // Nothing changed.
    dfm_skin_info info = {};
    REQUIRE(dfm_mesh_get_skin_info(mesh, &info) == DFM_OK);
    CHECK_FALSE(info.posed);
    CHECK(read_positions(mesh) == bind);
    dfm_mesh_destroy(mesh);

    // A mesh without a skin has nothing to pose.
    dfm_mesh* plain = make_c_mesh(c.context, limb.mesh);
    CHECK(dfm_mesh_set_pose_animation(plain, 0, 0.0) == DFM_ERROR_UNSUPPORTED);
    REQUIRE(dfm_mesh_get_skin_info(plain, &info) == DFM_OK);
    CHECK(info.joint_count == 0);
    dfm_mesh_destroy(plain);
}

TEST_CASE("skin api: a host's skin through strided 16-bit joints and float weights") {
    Context c;
    const SkinnedLimb limb = make_skinned_limb(12, 10);
    struct Vertex {
        float position[3];
        std::uint16_t joints[2];
        float weights[2];
    };
    std::vector<Vertex> vertices(limb.mesh.vertex_count());
    for (std::size_t v = 0; v < vertices.size(); ++v) {
        for (int k = 0; k < 3; ++k)
            vertices[v].position[k] = static_cast<float>(limb.mesh.positions[v][k]);
        vertices[v].joints[0] = 0;
        vertices[v].joints[1] = 1;
        vertices[v].weights[0] = static_cast<float>(limb.weights[v][0]);
        vertices[v].weights[1] = static_cast<float>(limb.weights[v][1]);
    }
    std::vector<std::uint32_t> indices;
    for (const mesh::Triangle& t : limb.mesh.triangles)
        indices.insert(indices.end(), t.begin(), t.end());
    double ibm[32];
    std::memcpy(ibm, glm::value_ptr(limb.inverse_bind[0]), sizeof(double) * 16);
    std::memcpy(ibm + 16, glm::value_ptr(limb.inverse_bind[1]), sizeof(double) * 16);
    dfm_mesh_desc desc = {};
    desc.struct_size = sizeof desc;
    desc.positions = {vertices[0].position, vertices.size(), sizeof(Vertex), DFM_SCALAR_FLOAT32};
    desc.indices = indices.data();
    desc.triangle_count = limb.mesh.face_count();
    desc.skin.joint_count = 2;
    desc.skin.inverse_bind_matrices = ibm;
    desc.skin.influence_count = 2;
    desc.skin.joints = vertices[0].joints;
    desc.skin.joint_stride = sizeof(Vertex);
    desc.skin.joint_type = DFM_INDEX_UINT16;
    desc.skin.weights = vertices[0].weights;
    desc.skin.weight_stride = sizeof(Vertex);
    dfm_mesh* mesh = nullptr;
    REQUIRE_MESSAGE(dfm_mesh_create(c.context, &desc, &mesh) == DFM_OK, last_error());
    // At rest the host's joints stand where they were bound.
    std::vector<double> joints(32);
    REQUIRE(dfm_mesh_read_joint_matrices(mesh, joints.data(), joints.size()) == DFM_OK);
    CHECK(glm::make_mat4(joints.data() + 16)[3].y == doctest::Approx(1.0));
    const glm::dmat4 world[2] = {glm::dmat4(1.0), elbow_world(limb, 60.0)};
    REQUIRE(dfm_mesh_set_pose_joints(mesh, glm::value_ptr(world[0]), 2, nullptr, 0) == DFM_OK);
    std::vector<glm::dvec3> expected(vertices.size());
    for (std::size_t v = 0; v < expected.size(); ++v) {
        expected[v] = skin_by_hand(limb, v, world[0], world[1], limb.mesh.positions[v]);
    }
    CHECK(largest_distance(read_positions(mesh), expected) < 1e-6);  // float weights, normalised
    dfm_mesh_destroy(mesh);

    // Bad skins, each named.
    const auto refused = [&](dfm_result code, const char* text) {
        dfm_mesh* m = nullptr;
        CHECK(dfm_mesh_create(c.context, &desc, &m) == code);
        CHECK_MESSAGE(message_has(text), last_error());
        CHECK(m == nullptr);
    };
    vertices[3].joints[1] = 7;
    refused(DFM_ERROR_OUT_OF_RANGE, "desc->skin: vertex 3 influence 1: joint 7 is beyond");
    vertices[3].joints[1] = 1;
    vertices[4].weights[0] = -1.0f;
    refused(DFM_ERROR_NUMERICAL, "vertex 4 influence 0: weight -1");
    vertices[4].weights[0] = 0.0f;
    vertices[4].weights[1] = 0.0f;
    refused(DFM_ERROR_NUMERICAL, "vertex 4: its weights sum to 0");
    vertices[4].weights[0] = 1.0f;
    desc.skin.influence_count = 0;
    refused(DFM_ERROR_INVALID_ARGUMENT, "influence_count 0");
    desc.skin.influence_count = 2;
    desc.skin.joint_stride = 2;
    refused(DFM_ERROR_INVALID_ARGUMENT, "joint_stride 2 is smaller than one vertex's joints");
    desc.skin.joint_stride = sizeof(Vertex);
    ibm[16 + 10] = 0.0;
    ibm[16 + 5] = 0.0;
    ibm[16 + 0] = 0.0;
    refused(DFM_ERROR_NUMERICAL, "joint 1's inverse bind matrix is not invertible");
}
