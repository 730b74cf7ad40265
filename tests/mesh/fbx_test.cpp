#include <doctest/doctest.h>

#include <algorithm>
#include <string>

#include "mesh/fbx_binary_writer.hpp"
#include "mesh/fbx_io.hpp"
#include "mesh/host_mesh.hpp"
#include "mesh/load.hpp"
#include "mesh/write.hpp"
#include "support/fbx_trees.hpp"
#include "support/test_files.hpp"

// The FBX reader and writer on the small Blender exports of tests/data/fbx
// (tests/fbx/make_small_fbx.py) and their ASCII and 7.5 rewrites
// (tests/fbx/fbx_convert.py). The rigged assets' tests are tests/fbx/.
namespace {

using namespace dfm;

std::filesystem::path small(std::string_view name) {
    return test::data_dir() / "fbx" / std::string(name);
}

struct Loaded {
    mesh::Mesh surface;
    mesh::HostMesh host;
    mesh::LoadReport report;
};

Loaded load(const std::filesystem::path& path) {
    Loaded l;
    const Status s = mesh::load_host_mesh(path, l.surface, l.host, &l.report);
    REQUIRE_MESSAGE(s.is_ok(), s.message());
    return l;
}

}  // namespace

TEST_CASE("fbx: a Blender cube with a shape key loads by control point, in metres, +Y up") {
    const Loaded l = load(small("cube.fbx"));
    CHECK(l.surface.vertex_count() == 26);
    CHECK(l.surface.face_count() == 48);
    CHECK(l.report.polygons == 24);
    CHECK(l.report.triangulated_polygons == 24);
    REQUIRE(l.host.weld);
    CHECK(l.host.weld->host_vertex_count() == 26);
    const mesh::Bounds b = mesh::compute_bounds(l.surface.positions);
    CHECK(b.min.x == doctest::Approx(-0.5));
    CHECK(b.max.y == doctest::Approx(0.5));
    REQUIRE(l.host.skin);
    REQUIRE(l.host.skin->morph_targets.size() == 1);
    const mesh::MorphTarget& dent = l.host.skin->morph_targets[0];
    CHECK(dent.name == "Dent");
    CHECK(dent.default_weight == 0.5);
    CHECK(dent.vertices.size() == 9);
    // Blender's +Z is glTF's +Y: the dent goes down.
    for (const glm::dvec3& d : dent.deltas) CHECK(d.y < 0.0);
    CHECK(l.host.skin->joint_count() == 0);
}

TEST_CASE("fbx: binary 7.4, binary 7.5 and ASCII of one file load to the same mesh and skin") {
    const Loaded bin = load(small("strip.fbx"));
    CHECK(bin.surface.vertex_count() == 21);
    CHECK(bin.surface.face_count() == 24);
    REQUIRE(bin.host.skin);
    const mesh::Skin& skin = *bin.host.skin;
    CHECK(skin.joint_names == std::vector<std::string>{"Root", "Tip"});
    REQUIRE(skin.animations.size() == 1);
    CHECK(skin.animations[0].name == "Rig|Bend");
    CHECK(skin.animations[0].end == doctest::Approx(0.5));
    CHECK(skin.skinned_vertex_count() == 21);
    for (const char* other : {"strip-7500.fbx", "strip-ascii.fbx"}) {
        CAPTURE(other);
        const Loaded o = load(small(other));
        CHECK(o.host.fbx->document.version ==
              (std::string(other) == "strip-7500.fbx" ? 7500 : 7400));
        CHECK(o.surface.positions == bin.surface.positions);
        CHECK(o.surface.triangles == bin.surface.triangles);
        REQUIRE(o.host.skin);
        CHECK(o.host.skin->inverse_bind == skin.inverse_bind);
        CHECK(o.host.skin->influence_joints == skin.influence_joints);
        CHECK(o.host.skin->animations[0].channels.size() == skin.animations[0].channels.size());
    }
}

TEST_CASE("fbx: a tree written back unchanged is the file's own bytes") {
    for (const char* name : {"cube.fbx", "strip.fbx", "strip-7500.fbx"}) {
        CAPTURE(name);
        const mesh::FbxDocument doc = test::parse_fbx_file(small(name).string());
        CHECK(mesh::encode_fbx(doc, mesh::fbx_out_tree(doc), doc.version) == doc.bytes);
    }
}

TEST_CASE("fbx: an edit saved back changes the Vertices and normals only") {
    const Loaded in = load(small("cube.fbx"));
    mesh::Mesh edited = in.surface;
    std::size_t moved = 0;
    for (glm::dvec3& p : edited.positions) {
        if (p.y > 0.4) {
            p.y += 0.25;
            ++moved;
        }
    }
    REQUIRE(moved == 9);
    const auto dir = test::scratch_dir("fbx_save");
    REQUIRE(mesh::save_host_mesh(dir / "edited.fbx", edited, edited, in.host));
    const Loaded back = load(dir / "edited.fbx");
    for (std::size_t v = 0; v < edited.vertex_count(); ++v) {
        CHECK(glm::length(back.surface.positions[v] - edited.positions[v]) < 1e-12);
    }
    const test::TreeDifference d = test::compare_trees(
        in.host.fbx->document, test::parse_fbx_file((dir / "edited.fbx").string()));
    CHECK(d.added.empty());
    CHECK(d.missing.empty());
    CHECK(d.changed == std::vector<std::string>{"Objects/Geometry/Vertices",
                                                "Objects/Geometry/LayerElementNormal/Normals"});
}

TEST_CASE("fbx: a morph target saved back is a new blend shape channel, the rest as it was") {
    const Loaded in = load(small("strip.fbx"));
    mesh::Mesh edited = in.surface;
    for (glm::dvec3& p : edited.positions) {
        if (p.x > 1.0) p.y += 0.1;
    }
    const auto dir = test::scratch_dir("fbx_morph");
    mesh::WriteOptions options;
    options.morph_target = "Lift";
    options.morph_target_extras = R"({"dualform_pose": {"animation": "Rig|Bend", "time": 0.25}})";
    REQUIRE(mesh::save_host_mesh(dir / "lift.fbx", edited, edited, in.host, options));
    const Loaded back = load(dir / "lift.fbx");
    CHECK(back.surface.positions == in.surface.positions);
    REQUIRE(back.host.skin);
    REQUIRE(back.host.skin->morph_targets.size() == 1);
    const mesh::MorphTarget& lift = back.host.skin->morph_targets[0];
    CHECK(lift.name == "Lift");
    CHECK(lift.default_weight == 0.0);
    REQUIRE(lift.vertices.size() == 3);
    for (std::size_t i = 0; i < lift.vertices.size(); ++i) {
        CHECK(glm::length(lift.deltas[i] - glm::dvec3(0.0, 0.1, 0.0)) < 1e-12);
    }
    const test::TreeDifference d = test::compare_trees(
        in.host.fbx->document, test::parse_fbx_file((dir / "lift.fbx").string()));
    CHECK(d.missing.empty());
    // The Definitions' counts of geometries and deformers, and the new
    // shape, channel, blend shape and their connections.
    for (const std::string& c : d.changed) {
        CAPTURE(c);
        CHECK((c == "Definitions/Count" || c == "Definitions/ObjectType/Count"));
    }
    CHECK(std::count(d.added.begin(), d.added.end(), "Objects/Geometry") == 1);
    CHECK(std::count(d.added.begin(), d.added.end(), "Objects/Deformer") == 2);
    CHECK(std::count(d.added.begin(), d.added.end(), "Connections/C") == 3);
    const std::string& bytes = back.host.fbx->document.bytes;
    CHECK(bytes.find("dualform_pose") != std::string::npos);
}

TEST_CASE("fbx: what is not written back as FBX is refused, naming the file") {
    const auto dir = test::scratch_dir("fbx_refused");
    const Loaded ascii = load(small("strip-ascii.fbx"));
    Status s = mesh::save_host_mesh(dir / "out.fbx", ascii.surface, ascii.surface, ascii.host);
    CHECK(s.code() == Errc::unsupported);
    CHECK(s.message().find("ASCII FBX is read but not written back") != std::string::npos);
    mesh::Mesh cube;
    REQUIRE(mesh::load_mesh(test::data_dir() / "fbx" / "cube.fbx", cube));
    s = mesh::save_mesh(dir / "plain.fbx", cube);
    CHECK(s.code() == Errc::unsupported);
    CHECK(s.message().rfind((dir / "plain.fbx").string() + ": FBX is written only back", 0) == 0);
    CHECK_FALSE(std::filesystem::exists(dir / "plain.fbx"));
    const Loaded strip = load(small("strip.fbx"));
    mesh::WriteOptions morph;
    morph.morph_target = "Lift";
    s = mesh::save_host_mesh(dir / "out.glb", strip.surface, strip.surface, strip.host, morph);
    CHECK(s.code() == Errc::unsupported);
}
