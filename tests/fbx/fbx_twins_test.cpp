#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <numeric>
#include <set>
#include <sstream>
#include <utility>

#include "fbx_assets.hpp"
#include "mesh/skin_pose.hpp"
#include "support/test_files.hpp"

// Blender exports one scene as glb and as FBX (tests/skin/make_rigged_assets.py):
// the two must load to the same surface, skin and morph targets, and the
// same edit must give the same result from either.
namespace {

using namespace dfm;
using test::fbx::asset;
using test::fbx::load;
using test::fbx::Loaded;

double diagonal(const mesh::Mesh& m) {
    return mesh::compute_bounds(m.positions).diagonal();
}

// A triangle as its matched corners, rotated to start at the smallest.
std::array<std::uint32_t, 3> canonical(const mesh::Triangle& t,
                                       const std::vector<std::uint32_t>& map) {
    std::array<std::uint32_t, 3> c{map[t[0]], map[t[1]], map[t[2]]};
    std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
    return c;
}

}  // namespace

TEST_CASE("the FBX and glb exports of one Blender scene load to the same surface") {
    for (const char* name : {"prop", "shapekey", "arm", "arm-morph", "humanoid", "humanoid-20k"}) {
        CAPTURE(std::string(name));
        const Loaded fbx = load(asset(std::string(name) + ".fbx"));
        const Loaded glb = load(asset(std::string(name) + ".glb"));
        REQUIRE(fbx.surface.vertex_count() == glb.surface.vertex_count());
        REQUIRE(fbx.surface.face_count() == glb.surface.face_count());
        const double diag = diagonal(glb.surface);
        double worst = 0.0;
        const std::vector<std::uint32_t> map = test::fbx::match_points(
            fbx.surface.positions, glb.surface.positions, 1e-6 * diag, worst);
        MESSAGE(std::string(name) << ": " << fbx.surface.vertex_count()
                                  << " surface vertices, positions within " << worst / diag
                                  << " of the diagonal");
        // The same triangles, each turning the same way; coincident
        // vertices (which the match may pair either way) by their position.
        std::vector<std::uint32_t> at_position(glb.surface.vertex_count());
        {
            // The lowest vertex within the match's tolerance of each.
            std::vector<std::uint32_t> order(at_position.size());
            std::iota(order.begin(), order.end(), 0u);
            const auto& p = glb.surface.positions;
            std::sort(order.begin(), order.end(),
                      [&](std::uint32_t i, std::uint32_t j) { return p[i].x < p[j].x; });
            for (std::size_t k = 0; k < order.size(); ++k) {
                const std::uint32_t v = order[k];
                at_position[v] = v;
                for (std::size_t j = k; j-- > 0 && p[order[j]].x >= p[v].x - 1e-6 * diag;) {
                    if (glm::length(p[order[j]] - p[v]) <= 1e-6 * diag) {
                        at_position[v] = std::min(at_position[v], at_position[order[j]]);
                    }
                }
            }
        }
        std::vector<std::uint32_t> fbx_at_position(map.size());
        for (std::size_t v = 0; v < map.size(); ++v) fbx_at_position[v] = at_position[map[v]];
        std::set<std::array<std::uint32_t, 3>> from_glb;
        for (const mesh::Triangle& t : glb.surface.triangles) {
            from_glb.insert(canonical(t, at_position));
        }
        std::size_t same = 0;
        for (const mesh::Triangle& t : fbx.surface.triangles) {
            same += from_glb.count(canonical(t, fbx_at_position));
        }
        CHECK(same == fbx.surface.face_count());

        REQUIRE(static_cast<bool>(fbx.host.skin) == static_cast<bool>(glb.host.skin));
        if (!fbx.host.skin) continue;
        const mesh::Skin& a = *fbx.host.skin;
        const mesh::Skin& b = *glb.host.skin;
        std::vector<std::string> joints_a = a.joint_names, joints_b = b.joint_names;
        std::sort(joints_a.begin(), joints_a.end());
        std::sort(joints_b.begin(), joints_b.end());
        CHECK(joints_a == joints_b);
        CHECK(a.max_influences == b.max_influences);
        REQUIRE(a.morph_targets.size() == b.morph_targets.size());
        for (std::size_t t = 0; t < a.morph_targets.size(); ++t) {
            const mesh::MorphTarget& ta = a.morph_targets[t];
            const mesh::MorphTarget& tb = b.morph_targets[t];
            CAPTURE(ta.name);
            CHECK(ta.name == tb.name);
            CHECK(ta.default_weight == doctest::Approx(tb.default_weight).epsilon(1e-6));
            std::vector<glm::dvec3> db(glb.surface.vertex_count(), glm::dvec3(0.0));
            for (std::size_t i = 0; i < tb.vertices.size(); ++i) db[tb.vertices[i]] = tb.deltas[i];
            std::vector<glm::dvec3> da(fbx.surface.vertex_count(), glm::dvec3(0.0));
            for (std::size_t i = 0; i < ta.vertices.size(); ++i) da[ta.vertices[i]] = ta.deltas[i];
            double delta_error = 0.0;
            for (std::size_t v = 0; v < da.size(); ++v) {
                delta_error = std::max(delta_error, glm::length(da[v] - db[map[v]]));
            }
            CHECK(delta_error <= 1e-6 * diag);
        }
    }
}

// Blender's FBX exporter bakes every action over the pose the active one
// left on the bones it does not key: only the action active at export (the
// first: Wave, Walk) describes in the FBX what Blender evaluated with the
// others reset (make_rigged_assets.py), so only its frames are compared.
TEST_CASE("posed by its animation stack, an FBX skin matches Blender's evaluated meshes") {
    for (const auto& [name, action] : {std::pair<std::string, std::string>{"arm", "Wave"},
                                       {"arm-morph", "Wave"},
                                       {"humanoid", "Walk"}}) {
        CAPTURE(std::string(name));
        const Loaded fbx = load(asset(std::string(name) + ".fbx"));
        REQUIRE(fbx.host.skin);
        const mesh::Skin& skin = *fbx.host.skin;
        int fps = 0;
        const std::vector<test::fbx::Frame> frames = test::fbx::blender_frames(name, fps);
        const double diag = diagonal(fbx.surface);
        double worst = 0.0;
        std::size_t compared = 0;
        for (const test::fbx::Frame& f : frames) {
            if (f.animation != action) continue;
            ++compared;
            CAPTURE(f.animation);
            CAPTURE(f.frame);
            // Blender's exporter names a stack "OBJECT|ACTION" and starts
            // its time at the action's first frame (frame 1 in these).
            std::size_t a = skin.animations.size();
            for (std::size_t i = 0; i < skin.animations.size(); ++i) {
                if (skin.animations[i].name.ends_with("|" + f.animation)) a = i;
            }
            REQUIRE(a < skin.animations.size());
            mesh::SkinPose pose;
            REQUIRE(mesh::sample_pose(skin, a, (f.frame - 1.0) / fps, pose));
            std::vector<glm::dvec3> posed(fbx.surface.vertex_count());
            mesh::pose_positions(skin, pose, fbx.surface.positions, posed);
            REQUIRE(f.positions.size() == fbx.host.weld->host_vertex_count());
            double error = 0.0;
            for (std::size_t v = 0; v < f.positions.size(); ++v) {
                error = std::max(error,
                                 glm::length(posed[fbx.host.weld->surface_of[v]] - f.positions[v]));
            }
            worst = std::max(worst, error);
            CHECK(error <= 1e-4 * diag);
        }
        CHECK(compared >= 3);
        MESSAGE(name << ": posed by " << action << " within " << worst / diag
                     << " of the diagonal of Blender's " << compared << " evaluated frames");
    }
}

TEST_CASE("ASCII and 7.5 rewrites of an FBX export load to the same surface and skin") {
    const auto dir = test::scratch_dir("fbx_rewrites");
    const Loaded binary = load(asset("humanoid.fbx"));
    for (const char* mode : {"--ascii", "--7500"}) {
        CAPTURE(mode);
        const auto path = dir / (std::string("humanoid") + mode + ".fbx");
        test::fbx::convert(mode, asset("humanoid.fbx"), path);
        const Loaded other = load(path);
        CHECK(other.surface.positions == binary.surface.positions);
        CHECK(other.surface.triangles == binary.surface.triangles);
        REQUIRE(other.host.skin);
        CHECK(other.host.skin->influence_joints == binary.host.skin->influence_joints);
        CHECK(other.host.skin->inverse_bind == binary.host.skin->inverse_bind);
        CHECK(other.host.skin->animations.size() == binary.host.skin->animations.size());
    }
}

TEST_CASE("an edit of the FBX and of the glb Water-Fills the same region and deforms alike") {
    const auto dir = test::scratch_dir("fbx_twin_edit");
    for (const char* name : {"arm", "humanoid"}) {
        CAPTURE(std::string(name));
        const Loaded fbx = load(asset(std::string(name) + ".fbx"));
        const Loaded glb = load(asset(std::string(name) + ".glb"));
        const double diag = diagonal(glb.surface);
        const std::vector<glm::dvec3> fbx_host = mesh::host_positions(fbx.surface, fbx.host);
        const std::vector<glm::dvec3> glb_host = mesh::host_positions(glb.surface, glb.host);
        const test::fbx::EditVertices e = test::fbx::edit_vertices(fbx_host);
        const auto twin = [&](std::uint32_t v) {
            std::uint32_t best = 0;
            for (std::uint32_t w = 0; w < glb_host.size(); ++w) {
                if (glm::length(glb_host[w] - fbx_host[v]) <
                    glm::length(glb_host[best] - fbx_host[v]))
                    best = w;
            }
            return best;
        };
        const std::string base = std::string(name);
        test::fbx::run_cli({"deform",
                            test::fbx::edit_scenario(dir, asset(base + ".fbx"), e.first, e.last),
                            "--out", (dir / (base + "-fbx.obj")).string(), "--roi-out",
                            (dir / (base + "-fbx.roi")).string()});
        test::fbx::run_cli(
            {"deform",
             test::fbx::edit_scenario(dir, asset(base + ".glb"), twin(e.first), twin(e.last)),
             "--out", (dir / (base + "-glb.obj")).string(), "--roi-out",
             (dir / (base + "-glb.roi")).string()});
        const auto roi = [&](const std::string& file, const std::vector<glm::dvec3>& host) {
            std::vector<glm::dvec3> out;
            std::istringstream lines(test::read_text(dir / file));
            for (std::uint32_t v; lines >> v;) out.push_back(host[v]);
            return out;
        };
        const std::vector<glm::dvec3> roi_fbx = roi(base + "-fbx.roi", fbx_host);
        const std::vector<glm::dvec3> roi_glb = roi(base + "-glb.roi", glb_host);
        CHECK(roi_fbx.size() > 100);
        REQUIRE(roi_fbx.size() == roi_glb.size());
        double worst = 0.0;
        test::fbx::match_points(roi_fbx, roi_glb, 1e-6 * diag, worst);
        // The deformed surfaces, matched by their rest positions.
        const std::vector<std::uint32_t> map = test::fbx::match_points(
            fbx.surface.positions, glb.surface.positions, 1e-6 * diag, worst);
        mesh::Mesh out_fbx, out_glb;
        REQUIRE(mesh::load_mesh(dir / (base + "-fbx.obj"), out_fbx));
        REQUIRE(mesh::load_mesh(dir / (base + "-glb.obj"), out_glb));
        REQUIRE(out_fbx.vertex_count() == map.size());
        double error = 0.0, moved = 0.0;
        for (std::size_t v = 0; v < map.size(); ++v) {
            error = std::max(error, glm::length(out_fbx.positions[v] - out_glb.positions[map[v]]));
            moved = std::max(moved, glm::length(out_fbx.positions[v] - fbx.surface.positions[v]));
        }
        MESSAGE(std::string(name) << ": " << roi_fbx.size()
                                  << " ROI vertices from both; the edit moves up to "
                                  << moved / diag << " of the diagonal, the two results differ by "
                                  << error / diag);
        CHECK(moved > 0.01 * diag);
        CHECK(error <= 1e-6 * diag);
    }
}
