#include <doctest/doctest.h>

#include <algorithm>
#include <string>

#include <assimp/config.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include "fbx_assets.hpp"
#include "support/fbx_trees.hpp"
#include "support/test_files.hpp"

// `dualform deform SCENARIO --out EDITED.fbx [--morph-target NAME]` on the
// FBX that Blender exported: the edit goes back into the artist's file, every
// node it does not touch unchanged (a walk of both trees), and the result
// reads back in Blender's importer and in Assimp.
namespace {

using namespace dfm;
using test::fbx::asset;
using test::fbx::load;
using test::fbx::Loaded;

struct Case {
    std::string name;      // the asset
    std::string object;    // its mesh object in Blender
    std::string armature;  // its armature object, or ""
};

const Case cases[] = {{"arm", "Arm", "ArmRig"},
                      {"humanoid", "Body", "HumanRig"},
                      {"prop", "Prop", ""},
                      {"shapekey", "Block", ""}};

double diagonal(const mesh::Mesh& m) {
    return mesh::compute_bounds(m.positions).diagonal();
}

// The corners Assimp reads of the file's one mesh, in Dualform's space
// (the reload's transform of that geometry), with morph mesh `morph`
// (empty: the base positions).
std::vector<glm::dvec3> assimp_corners(const std::filesystem::path& file, const Loaded& reload,
                                       const std::string& morph) {
    Assimp::Importer importer;
    importer.SetPropertyBool(AI_CONFIG_IMPORT_FBX_READ_MATERIALS, false);
    const aiScene* scene = importer.ReadFile(file.string(), 0);
    REQUIRE_MESSAGE(scene != nullptr, importer.GetErrorString());
    REQUIRE(scene->mNumMeshes == 1);
    const aiMesh& mesh = *scene->mMeshes[0];
    const aiVector3D* source = mesh.mVertices;
    if (!morph.empty()) {
        source = nullptr;
        for (unsigned k = 0; k < mesh.mNumAnimMeshes; ++k) {
            if (std::string(mesh.mAnimMeshes[k]->mName.C_Str()) == morph) {
                source = mesh.mAnimMeshes[k]->mVertices;
            }
        }
        REQUIRE_MESSAGE(source != nullptr, "Assimp read no morph mesh " << morph);
    }
    REQUIRE(reload.host.fbx->ranges.size() == 1);
    const glm::dmat4& world = reload.host.fbx->ranges[0].world;
    std::vector<glm::dvec3> out(mesh.mNumVertices);
    for (unsigned c = 0; c < mesh.mNumVertices; ++c) {
        out[c] = glm::dvec3(world * glm::dvec4(source[c].x, source[c].y, source[c].z, 1.0));
    }
    return out;
}

// The largest distance from each corner to the surface position of its
// control point.
double corner_error(const std::vector<glm::dvec3>& corners, const Loaded& reload,
                    const std::vector<glm::dvec3>& surface) {
    const mesh::FbxGeometry& g = reload.host.fbx->scene.geometries[0];
    REQUIRE(corners.size() == g.corners.size());
    double error = 0.0;
    for (std::size_t c = 0; c < corners.size(); ++c) {
        const std::uint32_t s = reload.host.weld->surface_of[g.corners[c]];
        error = std::max(error, glm::length(corners[c] - surface[s]));
    }
    return error;
}

// The largest distance from Blender's vertices (control point order) to
// the surface position of each.
double blender_error(const std::vector<glm::dvec3>& vertices, const Loaded& reload,
                     const std::vector<glm::dvec3>& surface) {
    REQUIRE(vertices.size() == reload.host.weld->host_vertex_count());
    double error = 0.0;
    for (std::size_t v = 0; v < vertices.size(); ++v) {
        error =
            std::max(error, glm::length(vertices[v] - surface[reload.host.weld->surface_of[v]]));
    }
    return error;
}

}  // namespace

TEST_CASE("an edit written back into the FBX: only its nodes change, Blender and Assimp read it") {
    const auto dir = test::scratch_dir("fbx_write_back");
    std::vector<std::filesystem::path> imports;
    struct Done {
        const Case* c;
        Loaded original, edited, lifted;
        std::vector<glm::dvec3> expected;  // the edited surface
    };
    std::vector<Done> done;
    for (const Case& c : cases) {
        CAPTURE(c.name);
        const auto in = asset(c.name + ".fbx");
        Loaded original = load(in);
        const double diag = diagonal(original.surface);
        const test::fbx::EditVertices e =
            test::fbx::edit_vertices(mesh::host_positions(original.surface, original.host));
        const std::string scenario = test::fbx::edit_scenario(dir, in, e.first, e.last);
        const auto edited_path = dir / (c.name + "-edited.fbx");
        const auto lifted_path = dir / (c.name + "-lift.fbx");
        const auto shown_path = dir / (c.name + "-edited.obj");
        test::fbx::run_cli({"deform", scenario, "--out", edited_path.string()});
        test::fbx::run_cli(
            {"deform", scenario, "--out", lifted_path.string(), "--morph-target", "Lift"});
        test::fbx::run_cli({"deform", scenario, "--out", shown_path.string()});
        mesh::Mesh shown;
        REQUIRE(mesh::load_mesh(shown_path, shown));

        // Only the geometry's Vertices and normals changed.
        const mesh::FbxDocument& before = original.host.fbx->document;
        test::TreeDifference d =
            test::compare_trees(before, test::parse_fbx_file(edited_path.string()));
        CHECK(d.added.empty());
        CHECK(d.missing.empty());
        CHECK(std::find(d.changed.begin(), d.changed.end(), "Objects/Geometry/Vertices") !=
              d.changed.end());
        for (const std::string& path : d.changed) {
            CAPTURE(path);
            CHECK((path == "Objects/Geometry/Vertices" ||
                   path == "Objects/Geometry/LayerElementNormal/Normals"));
        }
        // A new blend shape channel, the Definitions' counts; nothing else.
        d = test::compare_trees(before, test::parse_fbx_file(lifted_path.string()));
        CHECK(d.missing.empty());
        for (const std::string& path : d.changed) {
            CAPTURE(path);
            CHECK((path == "Definitions/Count" || path == "Definitions/ObjectType/Count"));
        }
        for (const std::string& path : d.added) {
            CAPTURE(path);
            CHECK((path == "Objects/Geometry" || path == "Objects/Deformer" ||
                   path == "Connections/C" || path == "Definitions/ObjectType"));
        }
        CHECK(std::count(d.added.begin(), d.added.end(), "Objects/Geometry") == 1);

        Loaded edited = load(edited_path);
        Loaded lifted = load(lifted_path);
        double error = 0.0;
        for (std::size_t v = 0; v < shown.vertex_count(); ++v) {
            error = std::max(error, glm::length(edited.surface.positions[v] - shown.positions[v]));
        }
        CHECK(error <= 1e-12 * diag);
        CHECK(lifted.surface.positions == original.surface.positions);
        REQUIRE(lifted.host.skin);
        const mesh::MorphTarget& lift = lifted.host.skin->morph_targets.back();
        CHECK(lift.name == "Lift");
        CHECK(lift.default_weight == 0.0);
        std::vector<glm::dvec3> morphed = lifted.surface.positions;
        for (std::size_t i = 0; i < lift.vertices.size(); ++i) {
            morphed[lift.vertices[i]] += lift.deltas[i];
        }
        error = 0.0;
        for (std::size_t v = 0; v < shown.vertex_count(); ++v) {
            error = std::max(error, glm::length(morphed[v] - shown.positions[v]));
        }
        CHECK(error <= 1e-12 * diag);

        // Assimp reads the new control points, and the channel's shape.
        const double base_error =
            corner_error(assimp_corners(edited_path, edited, ""), edited, shown.positions);
        const double morph_error =
            corner_error(assimp_corners(lifted_path, lifted, "Lift"), lifted, shown.positions);
        MESSAGE(c.name << ": Assimp reads the edit within " << base_error / diag
                       << " of the diagonal, the morph target within " << morph_error / diag);
        CHECK(base_error <= 1e-6 * diag);
        CHECK(morph_error <= 1e-6 * diag);

        imports.push_back(edited_path);
        imports.push_back(lifted_path);
        done.push_back(
            {&c, std::move(original), std::move(edited), std::move(lifted), shown.positions});
    }

    // Blender's importer: the edit, the shape key, the armature and the
    // actions.
    const std::vector<test::fbx::BlenderFile> blender = test::fbx::blender_import(imports, dir);
    REQUIRE(blender.size() == 2 * done.size());
    for (std::size_t i = 0; i < done.size(); ++i) {
        const Done& d = done[i];
        CAPTURE(d.c->name);
        const double diag = diagonal(d.original.surface);
        const test::fbx::BlenderFile& edited = blender[2 * i];
        const test::fbx::BlenderFile& lifted = blender[2 * i + 1];
        const test::fbx::BlenderObject& mesh_edited = edited.object(d.c->object);
        const test::fbx::BlenderObject& mesh_lifted = lifted.object(d.c->object);
        const double edit_error = blender_error(mesh_edited.vertices, d.edited, d.expected);
        CHECK(edit_error <= 1e-6 * diag);
        CHECK(blender_error(mesh_lifted.vertices, d.lifted, d.lifted.surface.positions) <=
              1e-6 * diag);
        REQUIRE_FALSE(mesh_lifted.shape_keys.empty());
        const auto& key = mesh_lifted.shape_keys.back();
        CHECK(key.name == "Lift");
        CHECK(key.value == 0.0);
        const double key_error = blender_error(key.positions, d.lifted, d.expected);
        CHECK(key_error <= 1e-6 * diag);
        MESSAGE(d.c->name << ": Blender imports the edit within " << edit_error / diag
                          << " of the diagonal, its shape key 'Lift' within " << key_error / diag);
        // Every shape key the file had is still there, before the new one.
        if (d.original.host.skin) {
            for (const mesh::MorphTarget& t : d.original.host.skin->morph_targets) {
                CHECK(std::any_of(mesh_lifted.shape_keys.begin(), mesh_lifted.shape_keys.end(),
                                  [&](const auto& k) { return k.name == t.name; }));
            }
        }
        if (d.c->armature.empty()) continue;
        for (const test::fbx::BlenderFile* f : {&edited, &lifted}) {
            CHECK(f->object(d.c->object).armature == d.c->armature);
            const test::fbx::BlenderObject& rig = f->object(d.c->armature);
            for (const std::string& joint : d.original.host.skin->joint_names) {
                CHECK(std::find(rig.bones.begin(), rig.bones.end(), joint) != rig.bones.end());
            }
            for (const mesh::Animation& a : d.original.host.skin->animations) {
                CAPTURE(a.name);
                CHECK(std::any_of(f->actions.begin(), f->actions.end(),
                                  [&](const std::string& n) { return n.ends_with(a.name); }));
            }
        }
    }
}

TEST_CASE("an FBX 7.5 file is edited and written back as 7.5, and Blender imports it") {
    const auto dir = test::scratch_dir("fbx_write_7500");
    const auto in = dir / "arm-morph-7500.fbx";
    test::fbx::convert("--7500", asset("arm-morph.fbx"), in);
    const Loaded original = load(in);
    CHECK(original.host.fbx->document.version == 7500);
    const test::fbx::EditVertices e =
        test::fbx::edit_vertices(mesh::host_positions(original.surface, original.host));
    const std::string scenario = test::fbx::edit_scenario(dir, in, e.first, e.last);
    const auto out = dir / "edited.fbx";
    test::fbx::run_cli({"deform", scenario, "--out", out.string(), "--morph-target", "Lift"});
    const mesh::FbxDocument written = test::parse_fbx_file(out.string());
    CHECK(written.version == 7500);
    const test::TreeDifference d = test::compare_trees(original.host.fbx->document, written);
    CHECK(d.missing.empty());
    CHECK(std::count(d.added.begin(), d.added.end(), "Objects/Geometry") == 1);
    const std::vector<test::fbx::BlenderFile> blender = test::fbx::blender_import({out}, dir);
    REQUIRE(blender.size() == 1);
    const test::fbx::BlenderObject& arm = blender[0].object("Arm");
    CHECK(arm.armature == "ArmRig");
    REQUIRE(arm.shape_keys.size() == 3);
    CHECK(arm.shape_keys[1].name == "Flex");
    CHECK(arm.shape_keys[1].value == doctest::Approx(0.25));
    CHECK(arm.shape_keys[2].name == "Lift");
}

TEST_CASE("a posed edit saved into the FBX as a corrective plays in Blender as Dualform shows it") {
    const auto dir = test::scratch_dir("fbx_corrective");
    const auto in = asset("arm.fbx");
    const Loaded original = load(in);
    const double diag = diagonal(original.surface);
    const test::fbx::EditVertices e =
        test::fbx::edit_vertices(mesh::host_positions(original.surface, original.host));
    // FBX time 0.5 s of Blender's stack is its frame 13 (the importer puts
    // time 0 at frame 1, 24 frames a second).
    const std::string scenario = test::fbx::edit_scenario(
        dir, in, e.first, e.last, R"({"animation": "ArmRig|Wave", "time": 0.5})");
    const auto corrective = dir / "corrective.fbx";
    const auto shown = dir / "posed.obj";
    test::fbx::run_cli({"deform", scenario, "--out", corrective.string(), "--morph-target", "Fix"});
    test::fbx::run_cli({"deform", scenario, "--out", shown.string()});
    mesh::Mesh posed_edit;
    REQUIRE(mesh::load_mesh(shown, posed_edit));
    const std::vector<test::fbx::BlenderFile> blender =
        test::fbx::blender_import({corrective, in}, dir, 13, "Fix");
    REQUIRE(blender.size() == 2);
    const test::fbx::BlenderObject& arm = blender[0].object("Arm");
    CHECK(arm.shape_keys.back().name == "Fix");
    CHECK(test::parse_fbx_file(corrective.string()).bytes.find("dualform_pose") !=
          std::string::npos);
    const double error = blender_error(arm.posed, original, posed_edit.positions);
    // The file without the key, posed alike: where the edit started.
    const double edit =
        blender_error(blender[1].object("Arm").posed, original, posed_edit.positions);
    MESSAGE("Blender plays the corrective at frame 13 within "
            << error / diag << " of the diagonal of Dualform's posed edit (the edit moves "
            << edit / diag << ")");
    CHECK(edit > 0.01 * diag);
    CHECK(error <= 1e-4 * diag);
}
