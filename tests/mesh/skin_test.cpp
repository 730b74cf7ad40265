#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <doctest/doctest.h>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

#include "mesh/gltf_io.hpp"
#include "mesh/skin_arrays.hpp"
#include "mesh/skin_pose.hpp"
#include "mesh/skin_weld.hpp"
#include "support/gltf_builder.hpp"
#include "support/skinned_limb.hpp"

using namespace dfm;

namespace {

struct Loaded {
    mesh::Mesh host;
    mesh::GltfAsset asset;
    mesh::Skin skin;
    mesh::LoadReport report;
    Status status;
};

Loaded read(const std::string& glb) {
    Loaded l;
    l.status = mesh::read_gltf(glb, "limb.glb", nullptr, "", l.host, l.asset, l.skin, l.report);
    return l;
}

// Skinning written out here, apart from the engine's: each vertex's two
// joints of the limb, blended.
glm::dvec3 skin_by_hand(const test::SkinnedLimb& limb, std::size_t v, const glm::dmat4& shoulder,
                        const glm::dmat4& elbow, const glm::dvec3& p) {
    const glm::dmat4 s0 = shoulder * limb.inverse_bind[0];
    const glm::dmat4 s1 = elbow * limb.inverse_bind[1];
    const glm::dvec4 q(p, 1.0);
    return glm::dvec3(limb.weights[v][0] * (s0 * q) + limb.weights[v][1] * (s1 * q));
}

double largest_distance(const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b) {
    double d = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, glm::length(a[i] - b[i]));
    return d;
}

}  // namespace

TEST_CASE("skin: a skinned glTF gives its joints, weights, node graph, animations and targets") {
    const test::SkinnedLimb limb = test::make_skinned_limb(12, 10);
    const Loaded l = read(limb.glb);
    INFO(l.status.message());
    REQUIRE(l.status);
    const mesh::Skin& skin = l.skin;
    REQUIRE(skin.joint_count() == 2);
    CHECK(skin.joint_names[0] == "Shoulder");
    CHECK(skin.joint_names[1] == "Elbow");
    CHECK(skin.joint_nodes[1] == 2);
    CHECK(skin.nodes[2].parent == 1);
    REQUIRE(skin.vertex_count() == limb.mesh.vertex_count());
    CHECK(skin.max_influences == 2);
    for (std::size_t v = 0; v < skin.vertex_count(); ++v) {
        double sum = 0.0;
        for (std::uint32_t k = skin.influence_offsets[v]; k < skin.influence_offsets[v + 1]; ++k) {
            CHECK(skin.influence_weights[k] > 0.0);
            CHECK(skin.influence_weights[k] ==
                  doctest::Approx(limb.weights[v][skin.influence_joints[k]]).epsilon(1e-7));
            sum += skin.influence_weights[k];
        }
        CHECK(sum == doctest::Approx(1.0).epsilon(1e-15));
    }
    REQUIRE(skin.animations.size() == 2);
    CHECK(skin.animations[0].name == "Bend");
    CHECK(skin.animations[0].channels.size() == 3);
    CHECK(skin.animations[0].end == 1.0);
    CHECK(skin.animations[1].channels[0].interpolation == mesh::Interpolation::cubic_spline);
    REQUIRE(skin.morph_targets.size() == 1);
    CHECK(skin.morph_targets[0].name == "Flex");
    CHECK(skin.morph_targets[0].default_weight == 0.25);
    CHECK(skin.morph_targets[0].node == 0);
    REQUIRE(l.asset.weight_samplers.size() == 1);
    CHECK(l.asset.weight_samplers[0].node == 0);
}

TEST_CASE("skin: the rest pose skins to the bind positions plus the default morphs") {
    const test::SkinnedLimb limb = test::make_skinned_limb(12, 10);
    const Loaded l = read(limb.glb);
    INFO(l.status.message());
    REQUIRE(l.status);
    mesh::SkinPose pose;
    REQUIRE(mesh::rest_pose(l.skin, pose));
    std::vector<glm::dvec3> posed(l.host.vertex_count());
    mesh::pose_positions(l.skin, pose, l.host.positions, posed);
    for (std::size_t v = 0; v < posed.size(); ++v) {
        const glm::dvec3 expected = limb.mesh.positions[v] + 0.25 * limb.flex[v];
        CHECK(glm::length(posed[v] - expected) < 1e-12);
    }
}

TEST_CASE("skin: LINEAR, STEP and CUBICSPLINE channels sample as glTF says") {
    const test::SkinnedLimb limb = test::make_skinned_limb(8, 6);
    const Loaded l = read(limb.glb);
    INFO(l.status.message());
    REQUIRE(l.status);
    const auto same = [](const glm::dmat4& a, const glm::dmat4& b) {
        double d = 0.0;
        for (int c = 0; c < 4; ++c) {
            for (int r = 0; r < 4; ++r) d = std::max(d, std::abs(a[c][r] - b[c][r]));
        }
        return d < 1e-6;  // the keys are floats
    };
    mesh::SkinPose pose;
    REQUIRE(mesh::sample_pose(l.skin, 0, 0.5, pose));
    // Slerp halfway: 45 degrees; the shoulder has stepped; Flex halfway.
    const glm::dmat4 shoulder = glm::translate(glm::dmat4(1.0), glm::dvec3(0.1, 0.0, 0.0));
    CHECK(same(pose.joint_world[0], shoulder));
    CHECK(same(pose.joint_world[1], shoulder * test::elbow_world(limb, 45.0)));
    CHECK(pose.morph_weights[0] == doctest::Approx(0.625));
    CHECK(pose.time == 0.5);
    REQUIRE(mesh::sample_pose(l.skin, 0, 0.49, pose));
    CHECK(same(pose.joint_world[0], glm::dmat4(1.0)));
    // Clamped to the animation's range.
    REQUIRE(mesh::sample_pose(l.skin, 0, -3.0, pose));
    CHECK(pose.time == 0.0);
    CHECK(same(pose.joint_world[1], test::elbow_world(limb, 0.0)));
    REQUIRE(mesh::sample_pose(l.skin, 0, 7.0, pose));
    CHECK(pose.time == 1.0);
    CHECK(same(pose.joint_world[1], shoulder * test::elbow_world(limb, 90.0)));
    // The Hermite spline with zero tangents is the smoothstep of the
    // quaternions' components, normalised.
    REQUIRE(mesh::sample_pose(l.skin, 1, 0.5, pose));
    const double s = 0.25, h = 3 * s * s - 2 * s * s * s;
    const double half = std::sqrt(0.5);
    const double degrees = glm::degrees(2.0 * std::atan2(h * half, (1.0 - h) + h * half));
    CHECK(same(pose.joint_world[1], test::elbow_world(limb, degrees)));

    CHECK(mesh::sample_pose(l.skin, 0, NAN, pose).code() == Errc::numerical);
    CHECK(mesh::sample_pose(l.skin, 2, 0.0, pose).code() == Errc::out_of_range);
}

TEST_CASE("skin: the corrective reproduces a posed edit exactly, the bind-space copy does not") {
    const test::SkinnedLimb limb = test::make_skinned_limb(16, 20);
    const Loaded l = read(limb.glb);
    INFO(l.status.message());
    REQUIRE(l.status);
    mesh::SkinPose pose;
    REQUIRE(mesh::sample_pose(l.skin, 0, 1.0, pose));
    std::vector<glm::dvec3> before(l.host.vertex_count());
    mesh::pose_positions(l.skin, pose, l.host.positions, before);
    // An independent check of the pose itself, with Flex at 1.
    const glm::dmat4 shoulder = glm::translate(glm::dmat4(1.0), glm::dvec3(0.1, 0.0, 0.0));
    for (std::size_t v = 0; v < before.size(); ++v) {
        const glm::dvec3 by_hand =
            skin_by_hand(limb, v, shoulder, shoulder * test::elbow_world(limb, 90.0),
                         limb.mesh.positions[v] + limb.flex[v]);
        REQUIRE(glm::length(before[v] - by_hand) < 1e-6);  // the keys are floats
    }
    // Lift the forearm's end in world space (the artist's drag).
    std::vector<glm::dvec3> after = before;
    const glm::dvec3 lift(0.0, 0.3, 0.05);
    for (std::size_t v = 0; v < after.size(); ++v) {
        if (limb.mesh.positions[v].y > 1.4) after[v] += lift;
    }
    std::vector<glm::dvec3> bind_after;
    mesh::CorrectiveReport report;
    mesh::corrective_positions(l.skin, pose, l.host.positions, before, after, bind_after, report);
    CHECK(report.moved > 0);
    CHECK(report.damped.empty());
    CHECK(report.worst_condition == doctest::Approx(1.0).epsilon(1e-9));
    for (std::size_t v = 0; v < after.size(); ++v) {
        if (after[v] == before[v]) CHECK(bind_after[v] == l.host.positions[v]);
    }
    std::vector<glm::dvec3> replayed(after.size());
    mesh::pose_positions(l.skin, pose, bind_after, replayed);
    CHECK(largest_distance(replayed, after) < 1e-12);
    // The naive corrective, the posed displacement copied into bind space,
    // lands the forearm elsewhere: the elbow turned it by 90 degrees.
    std::vector<glm::dvec3> naive = l.host.positions;
    for (std::size_t v = 0; v < naive.size(); ++v) naive[v] += after[v] - before[v];
    mesh::pose_positions(l.skin, pose, naive, replayed);
    CHECK(largest_distance(replayed, after) > 0.3);
}

TEST_CASE("skin: cancelling weights take the damped inverse and are reported") {
    // One triangle, two joints; vertex 0 half on each. Posed with the joints
    // turned +90 and -90 degrees about x, its L_v is singular in y and z.
    const std::vector<std::uint32_t> joints = {0, 1, 0, 1, 0, 1};
    const std::vector<double> weights = {0.5, 0.5, 1.0, 0.0, 0.0, 1.0};
    const std::vector<glm::dmat4> ibm = {glm::dmat4(1.0), glm::dmat4(1.0)};
    mesh::Skin skin;
    REQUIRE(mesh::skin_from_arrays(3, 2, joints, weights, ibm, skin));
    const std::vector<glm::dmat4> world = {
        glm::rotate(glm::dmat4(1.0), glm::radians(90.0), glm::dvec3(1, 0, 0)),
        glm::rotate(glm::dmat4(1.0), glm::radians(-90.0), glm::dvec3(1, 0, 0))};
    mesh::SkinPose pose;
    REQUIRE(mesh::pose_from_joints(skin, world, {}, pose));
    const std::vector<glm::dvec3> bind = {{0, 1, 0}, {1, 0, 0}, {0, 0, 1}};
    std::vector<glm::dvec3> before(3), bind_after;
    mesh::pose_positions(skin, pose, bind, before);
    std::vector<glm::dvec3> after = before;
    after[0] += glm::dvec3(0.1, 0.1, 0.1);
    after[1] += glm::dvec3(0.0, 0.2, 0.0);
    mesh::CorrectiveReport report;
    mesh::corrective_positions(skin, pose, bind, before, after, bind_after, report);
    CHECK(report.moved == 2);
    REQUIRE(report.damped.size() == 1);
    CHECK(report.damped[0] == 0);
    CHECK(report.worst_vertex == 0);
    CHECK(report.worst_condition > 1e12);
    // The damped corrective stays bounded and meets the direction L_v
    // keeps (x); vertex 1, well conditioned, is exact.
    CHECK(glm::length(bind_after[0] - bind[0]) < 1.0);
    std::vector<glm::dvec3> replayed(3);
    mesh::pose_positions(skin, pose, bind_after, replayed);
    CHECK(replayed[0].x == doctest::Approx(after[0].x).epsilon(1e-5));
    CHECK(glm::length(replayed[1] - after[1]) < 1e-12);
}

TEST_CASE("skin: a collapsed joint takes the damped inverse, whatever its condition number") {
    // Vertex 0 wholly on a joint scaled to a millionth: L_v = 1e-6 I, a
    // condition number of 1, and an exact inverse that would throw the bind
    // shape a million times the edit away.
    const std::vector<glm::dmat4> ibm = {glm::dmat4(1.0), glm::dmat4(1.0)};
    mesh::Skin skin;
    REQUIRE(mesh::skin_from_arrays(3, 1, std::vector<std::uint32_t>{1, 0, 0},
                                   std::vector<double>{1.0, 1.0, 1.0}, ibm, skin));
    const std::vector<glm::dmat4> world = {glm::dmat4(1.0),
                                           glm::scale(glm::dmat4(1.0), glm::dvec3(1e-6))};
    mesh::SkinPose pose;
    REQUIRE(mesh::pose_from_joints(skin, world, {}, pose));
    const std::vector<glm::dvec3> bind = {{0, 1, 0}, {1, 0, 0}, {0, 0, 1}};
    std::vector<glm::dvec3> before(3), bind_after;
    mesh::pose_positions(skin, pose, bind, before);
    std::vector<glm::dvec3> after = before;
    after[0] += glm::dvec3(0.1, 0.0, 0.0);
    mesh::CorrectiveReport report;
    mesh::corrective_positions(skin, pose, bind, before, after, bind_after, report);
    REQUIRE(report.damped == std::vector<std::uint32_t>{0});
    CHECK(report.worst_condition == doctest::Approx(1.0));
    // Damped at a thousandth, the bind shape moves no farther than the edit
    // (sigma / (sigma^2 + 1e-6) < 1), not a million times as far.
    CHECK(glm::length(bind_after[0] - bind[0]) <= 0.1);
}

TEST_CASE("skin: host arrays are checked, weights normalised, zero weights dropped") {
    const std::vector<glm::dmat4> ibm = {glm::dmat4(1.0), glm::dmat4(1.0)};
    mesh::Skin skin;
    REQUIRE(mesh::skin_from_arrays(1, 3, std::vector<std::uint32_t>{1, 0, 1},
                                   std::vector<double>{2.0, 1.0, 1.0}, ibm, skin));
    REQUIRE(skin.influence_offsets == std::vector<std::uint32_t>{0, 2});
    CHECK(skin.influence_joints == std::vector<std::uint32_t>{0, 1});
    CHECK(skin.influence_weights[0] == 0.25);
    CHECK(skin.influence_weights[1] == 0.75);

    const auto fails = [&](std::vector<std::uint32_t> j, std::vector<double> w,
                           std::vector<glm::dmat4> m, Errc code, const char* text) {
        const Status s = mesh::skin_from_arrays(1, 2, j, w, m, skin);
        CHECK(s.code() == code);
        CHECK(s.message().find(text) != std::string::npos);
    };
    fails({0, 2}, {1.0, 0.0}, ibm, Errc::out_of_range, "vertex 0 influence 1: joint 2");
    fails({0, 1}, {1.0, -0.5}, ibm, Errc::numerical, "negative or not finite");
    fails({0, 1}, {NAN, 1.0}, ibm, Errc::numerical, "vertex 0 influence 0");
    fails({0, 1}, {0.0, 0.0}, ibm, Errc::numerical, "sum to 0");
    fails({0, 1}, {1.0, 0.0}, {glm::dmat4(1.0), glm::dmat4(0.0)}, Errc::invalid_argument,
          "joint 1's inverse bind matrix is not affine");
    glm::dmat4 flat(1.0);
    flat[2][2] = 0.0;
    fails({0, 1}, {1.0, 0.0}, {glm::dmat4(1.0), flat}, Errc::numerical, "not invertible");
}

TEST_CASE("skin: split copies whose skins differ are not welded, and the load says so") {
    // Two triangles sharing an edge, its two ends split; one copy of vertex
    // 1 bound to another joint.
    mesh::Mesh split;
    split.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
    split.triangles = {{0, 1, 2}, {3, 5, 4}};
    const std::vector<glm::dmat4> ibm = {glm::dmat4(1.0), glm::dmat4(1.0)};
    const auto weld = [&](std::vector<std::uint32_t> joints, std::size_t& kept_apart,
                          std::size_t& surfaces, std::size_t& warnings) {
        mesh::Skin skin;
        REQUIRE(mesh::skin_from_arrays(6, 1, joints, std::vector<double>(6, 1.0), ibm, skin));
        mesh::Mesh surface;
        mesh::SeamWeld w;
        std::shared_ptr<const mesh::Skin> on_surface;
        mesh::LoadReport report;
        mesh::weld_skinned(split, skin, mesh::WeldBy::skin, {}, "split", surface, w, on_surface,
                           report);
        kept_apart = w.kept_apart;
        surfaces = surface.vertex_count();
        warnings = report.warnings.size();
        REQUIRE(on_surface);
        CHECK(on_surface->vertex_count() == surfaces);
    };
    std::size_t kept_apart = 0, surfaces = 0, warnings = 0;
    weld({0, 0, 0, 0, 0, 0}, kept_apart, surfaces, warnings);
    CHECK(kept_apart == 0);
    CHECK(surfaces == 4);
    CHECK(warnings == 0);
    // Vertex 1's copies stay apart, so the edge's two sides are no longer
    // one edge, and vertex 2's copies stay apart too.
    weld({0, 0, 0, 1, 0, 0}, kept_apart, surfaces, warnings);
    CHECK(kept_apart == 1);
    CHECK(surfaces == 6);
    CHECK(warnings == 1);
}

TEST_CASE("skin: bad skins and animations in a glTF are located errors or warnings") {
    const test::SkinnedLimb limb = test::make_skinned_limb(6, 4);
    const auto edited = [&](const std::string& from, const std::string& to) {
        std::string glb = limb.glb;
        const std::size_t at = glb.find(from);
        REQUIRE(at != std::string::npos);
        // The same length keeps the GLB's chunk sizes right.
        REQUIRE(from.size() == to.size());
        glb.replace(at, from.size(), to);
        return read(glb);
    };
    Loaded l = edited("\"joints\":[1,2]", "\"joints\":[1,9]");
    CHECK(l.status.code() == Errc::out_of_range);
    CHECK(l.status.message().find("skin 0 joint 1: node 9 does not exist") != std::string::npos);
    l = edited("\"skin\":0", "\"skin\":7");
    CHECK(l.status.code() == Errc::out_of_range);
    CHECK(l.status.message().find("skin 7 does not exist") != std::string::npos);
    l = edited("{\"node\":1,\"path\":\"translation\"}", "{\"path\":\"translation\"         }");
    INFO(l.status.message());
    REQUIRE(l.status);
    CHECK(l.skin.animations[0].channels.size() == 2);
    bool warned = false;
    for (const std::string& w : l.report.warnings) {
        warned = warned || w.find("`node` field is missing in animation.channels.target") !=
                               std::string::npos;
    }
    CHECK(warned);
    l = edited("\"children\":[2]", "\"children\":[1]");
    CHECK(l.status.code() == Errc::parse_error);

    // A joint index past the skin, in the JOINTS_0 bytes.
    std::string glb = limb.glb;
    const std::size_t json_length = [&] {
        std::uint32_t n = 0;
        std::memcpy(&n, glb.data() + 12, 4);
        return n;
    }();
    mesh::Mesh host;
    mesh::GltfAsset asset;
    mesh::Skin skin;
    mesh::LoadReport report;
    REQUIRE(mesh::read_gltf(glb, "limb.glb", nullptr, "", host, asset, skin, report));
    // JOINTS_0 is the third view: find its offset in the JSON.
    const std::string json = glb.substr(20, json_length);
    const std::size_t views = json.find("\"bufferViews\":[");
    std::size_t at = views;
    for (int i = 0; i < 3; ++i) at = json.find("\"byteOffset\":", at + 1);
    const std::size_t joints_offset = std::stoul(json.substr(at + 13));
    glb[20 + json_length + 8 + joints_offset + 1] = 5;
    const Status s = mesh::read_gltf(glb, "limb.glb", nullptr, "", host, asset, skin, report);
    CHECK(s.code() == Errc::out_of_range);
    CHECK(s.message().find("JOINTS_0 element 0 component 1: joint 5 is beyond the skin's 2 "
                           "joints") != std::string::npos);
}
