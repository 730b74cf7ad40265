// Issue 15, "done when" 2 and 3: glTF written back by the C API, checked
// with the Khronos validator, this test's own reading of the file, and
// headless Blender. A round trip keeps every accessor but POSITION, NORMAL
// and TANGENT byte for byte; an edit reaches Blender; a morph target keeps
// the base and the existing target and reproduces the edit at weight 1.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "gltf_file.hpp"
#include "limb_edit.hpp"
#include "support/run_process.hpp"
#include "support/test_files.hpp"
#include "surface_match.hpp"
#include "third_party.hpp"

using namespace dfm::test;
using namespace dfm::test::gltf;
using dfm::json::JsonType;
using dfm::json::JsonValue;

namespace {

std::string failure() {
    return std::string(dfm_result_name(dfm_last_error_code())) + ": " + dfm_last_error_message();
}

bool same_json(const JsonValue& a, const JsonValue& b) {
    if (a.type != b.type) return false;
    switch (a.type) {
        case JsonType::null: return true;
        case JsonType::boolean: return a.boolean == b.boolean;
        case JsonType::number: return a.number == b.number;
        case JsonType::string: return a.text == b.text;
        case JsonType::array:
            return std::equal(a.items.begin(), a.items.end(), b.items.begin(), b.items.end(),
                              same_json);
        case JsonType::object:
            if (a.members.size() != b.members.size()) return false;
            for (const auto& m : a.members) {
                const dfm::json::JsonMember* o = b.find(m.key);
                if (!o || !same_json(m.value, o->value)) return false;
            }
            return true;
    }
    return false;
}

// The accessors the base primitives use as POSITION, NORMAL or TANGENT:
// the ones a save may rewrite.
std::set<std::size_t> geometry_accessors(const Asset& a) {
    std::set<std::size_t> out;
    for (const JsonValue& mesh : member(a.doc, "meshes").items)
        for (const JsonValue& prim : member(mesh, "primitives").items)
            for (const char* name : {"POSITION", "NORMAL", "TANGENT"})
                if (const auto* m = member(prim, "attributes").find(name))
                    out.insert(static_cast<std::size_t>(m->value.number));
    return out;
}

const JsonValue& cow_primitive(const Asset& a) {
    const auto& prims =
        member(member(a.doc, "meshes").items.at(mesh_index(a, "Cow")), "primitives");
    REQUIRE(prims.items.size() == 1);
    return prims.items[0];
}

std::size_t target_accessor(const JsonValue& prim, std::size_t target, const char* name) {
    return static_cast<std::size_t>(member(member(prim, "targets").items.at(target), name).number);
}

double max_distance(const std::vector<double>& a, const std::vector<double>& b) {
    REQUIRE(a.size() == b.size());
    double d = 0.0;
    for (std::size_t i = 0; i + 2 < a.size(); i += 3)
        d = std::max(d, std::hypot(a[i] - b[i], a[i + 1] - b[i + 1], a[i + 2] - b[i + 2]));
    return d;
}

std::vector<double> plus(const std::vector<double>& a, const std::vector<double>& b) {
    REQUIRE(a.size() == b.size());
    std::vector<double> out(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) out[i] = a[i] + b[i];
    return out;
}

void check_valid(const std::filesystem::path& file) {
    CAPTURE(file);
    const Validation v = validate(file);
    INFO(v.report);
    CHECK(v.exit_code == 0);
    CHECK(validation_errors(v) == 0);
}

void save(const dfm_mesh* mesh, const std::filesystem::path& path, const char* morph_target) {
    dfm_save_options options{};
    options.struct_size = sizeof options;
    options.morph_target_name = morph_target;
    REQUIRE_MESSAGE(dfm_mesh_save_with_options(mesh, path.c_str(), &options) == DFM_OK, failure());
}

// The cow's edits in the OFF's numbering (tests/scenarios): the front leg
// stepped, the tail swung.
const LimbEdit leg_step{771, 681, 771, 0.03, {0.08, 0.03, 0.0}};
const LimbEdit tail_swing{2334, 964, 2334, 0.02, {-0.05, 0.08, 0.06}};

// `edit` on the cow of `mesh`, whose vertices are the file's Cow mesh in
// its own space: the copies at the OFF vertices' positions.
LimbEdit on_cow(const dfm_mesh* mesh, const LimbEdit& edit) {
    const ContextPtr context = make_context();
    const std::vector<double> off =
        rest_positions(load_mesh(context.get(), asset_path("cow.off")).get());
    const std::vector<double> rest = rest_positions(mesh);
    LimbEdit out = edit;
    out.first = vertex_at(rest, off.data() + 3 * edit.first);
    out.last = vertex_at(rest, off.data() + 3 * edit.last);
    out.handle = vertex_at(rest, off.data() + 3 * edit.handle);
    return out;
}

}  // namespace

TEST_CASE("round trip: a save without an edit keeps every other accessor byte for byte") {
    const std::filesystem::path dir = scratch_dir("blender_round_trip");
    struct Case {
        const char* in;
        const char* asset;
        const char* out;
    };
    for (const Case& c :
         {Case{"suzanne.glb", "suzanne.glb", "suzanne.glb"}, Case{"cow.glb", "cow.glb", "cow.glb"},
          Case{"cow.gltf", "cow.gltf", "cow.gltf"},
          Case{"cow-embedded.gltf", "cow-embedded.gltf", "cow-embedded.gltf"},
          Case{"scene.glb", "scene.glb", "scene.glb"},
          Case{"scene.glb#mesh=Cow", "scene.glb", "scene-cow.glb"}}) {
        CAPTURE(c.in);
        const ContextPtr context = make_context();
        const MeshPtr mesh = load_mesh(context.get(), asset_path(c.in));
        REQUIRE_MESSAGE(dfm_mesh_save(mesh.get(), (dir / c.out).c_str()) == DFM_OK, failure());
        check_valid(dir / c.out);

        const Asset before = read_asset(asset_path(c.asset));
        const Asset after = read_asset(dir / c.out);
        const std::size_t accessors = member(before.doc, "accessors").items.size();
        REQUIRE(member(after.doc, "accessors").items.size() == accessors);
        const std::set<std::size_t> geometry = geometry_accessors(before);
        for (std::size_t i = 0; i < accessors; ++i) {
            CAPTURE(i);
            if (!geometry.count(i)) CHECK(accessor_bytes(after, i) == accessor_bytes(before, i));
        }
        for (const char* part : {"nodes", "scenes", "materials", "animations"}) {
            CAPTURE(part);
            const auto* a = before.doc.find(part);
            const auto* b = after.doc.find(part);
            REQUIRE((a == nullptr) == (b == nullptr));
            if (a) CHECK(same_json(a->value, b->value));
        }
        const auto& meshes = member(before.doc, "meshes").items;
        REQUIRE(member(after.doc, "meshes").items.size() == meshes.size());
        for (std::size_t m = 0; m < meshes.size(); ++m) {
            // Unedited, the positions stay the file's, exactly.
            CHECK(mesh_positions(after, m) == mesh_positions(before, m));
            CHECK(mesh_triangles(after, m) == mesh_triangles(before, m));
        }
    }
}

TEST_CASE("round trip: an edit saved as glTF is what headless Blender imports") {
    const std::filesystem::path dir = scratch_dir("blender_edit");
    const ContextPtr context = make_context();
    std::vector<std::filesystem::path> files;
    std::vector<std::vector<double>> expected_world;

    // cow.glb: its node is the identity; scene.glb's cow sits under two
    // transformed nodes, edited in its own space.
    for (const char* in : {"cow.glb", "scene.glb#mesh=Cow"}) {
        CAPTURE(in);
        const MeshPtr mesh = load_mesh(context.get(), asset_path(in));
        const std::vector<double> rest = rest_positions(mesh.get());
        edit_limb(mesh.get(), on_cow(mesh.get(), leg_step), true);
        const std::vector<double> deformed = rest_positions(mesh.get());
        CHECK(max_distance(deformed, rest) > 0.01 * diagonal(mesh.get()));
        const std::filesystem::path out =
            dir / (std::string(in).substr(0, std::string(in).find('.')) + "-step.glb");
        REQUIRE_MESSAGE(dfm_mesh_save(mesh.get(), out.c_str()) == DFM_OK, failure());
        check_valid(out);

        const Asset asset = read_asset(out);
        const std::size_t cow = mesh_index(asset, "Cow");
        CHECK(max_distance(mesh_positions(asset, cow), deformed) < 1e-6 * diagonal(mesh.get()));
        // The POSITION bounds are the new positions' (the spec requires them).
        const JsonValue& position =
            member(member(asset.doc, "accessors")
                       .items.at(static_cast<std::size_t>(
                           member(member(cow_primitive(asset), "attributes"), "POSITION").number)),
                   "min");
        const std::vector<double> p = mesh_positions(asset, cow);
        for (std::size_t k = 0; k < 3; ++k) {
            double low = p[k];
            for (std::size_t i = k; i < p.size(); i += 3) low = std::min(low, p[i]);
            CHECK(position.items.at(k).number == low);
        }
        files.push_back(out);
        expected_world.push_back(transformed(mesh_world_matrix(asset, cow), deformed));
    }

    // The whole scene, in world space: its meshes in the scene's depth-first
    // order (the ball, then the cow), node transforms applied.
    const Asset scene = read_asset(asset_path("scene.glb"));
    const std::size_t ball = mesh_index(scene, "Ball");
    const std::size_t cow = mesh_index(scene, "Cow");
    const std::vector<double> ball_world =
        transformed(mesh_world_matrix(scene, ball), mesh_positions(scene, ball));
    std::vector<double> scene_world = ball_world;
    const std::vector<double> cow_world =
        transformed(mesh_world_matrix(scene, cow), mesh_positions(scene, cow));
    scene_world.insert(scene_world.end(), cow_world.begin(), cow_world.end());
    const MeshPtr whole = load_mesh(context.get(), asset_path("scene.glb"));
    const double d = diagonal(whole.get());
    CHECK(max_distance(rest_positions(whole.get()), scene_world) < 1e-12 * d);
    LimbEdit step =
        on_cow(load_mesh(context.get(), asset_path("scene.glb#mesh=Cow")).get(), leg_step);
    const auto offset = static_cast<std::uint32_t>(ball_world.size() / 3);
    step.first += offset;
    step.last += offset;
    step.handle += offset;
    edit_limb(whole.get(), step, true);
    const std::vector<double> deformed = rest_positions(whole.get());
    CHECK(max_distance(deformed, scene_world) > 0.01 * d);
    const std::filesystem::path out = dir / "scene-world-step.glb";
    REQUIRE_MESSAGE(dfm_mesh_save(whole.get(), out.c_str()) == DFM_OK, failure());
    check_valid(out);
    const Asset saved = read_asset(out);
    std::vector<double> saved_world =
        transformed(mesh_world_matrix(saved, ball), mesh_positions(saved, ball));
    const std::vector<double> saved_cow =
        transformed(mesh_world_matrix(saved, cow), mesh_positions(saved, cow));
    saved_world.insert(saved_world.end(), saved_cow.begin(), saved_cow.end());
    CHECK(max_distance(saved_world, deformed) < 1e-6 * d);
    files.push_back(out);
    expected_world.push_back({deformed.begin() + 3 * offset, deformed.end()});

    const auto read = blender_read(files, dir);
    for (std::size_t f = 0; f < files.size(); ++f) {
        CAPTURE(files[f]);
        const BlenderObject& cow = blender_object(read[f], "Cow");
        REQUIRE(cow.world.size() == expected_world[f].size());
        // Blender holds float32 positions and matrices.
        CHECK(max_distance(cow.world, expected_world[f]) < 1e-5);
    }
    // The ball of the scene did not move.
    CHECK(max_distance(blender_object(read[1], "Ball").world, ball_world) < 1e-5);
    CHECK(max_distance(blender_object(read[2], "Ball").world, ball_world) < 1e-5);
}

TEST_CASE("morph target: the edit as a target, the existing one kept, weight 1 gives the edit") {
    const std::filesystem::path dir = scratch_dir("blender_morph");
    const ContextPtr context = make_context();
    const Asset original = read_asset(asset_path("scene.glb"));
    const JsonValue& original_prim = cow_primitive(original);

    const MeshPtr mesh = load_mesh(context.get(), asset_path("scene.glb#mesh=Cow"));
    const std::vector<double> rest = rest_positions(mesh.get());
    edit_limb(mesh.get(), on_cow(mesh.get(), leg_step), true);
    const std::vector<double> stepped = rest_positions(mesh.get());
    save(mesh.get(), dir / "step.glb", "Step");
    check_valid(dir / "step.glb");

    // A second bake of the saved file becomes a second target.
    const MeshPtr again = load_mesh(context.get(), dir / "step.glb#mesh=Cow");
    CHECK(rest_positions(again.get()) == rest);
    edit_limb(again.get(), on_cow(again.get(), tail_swing), true);
    const std::vector<double> swung = rest_positions(again.get());
    save(again.get(), dir / "swing.glb", "Swing");
    check_valid(dir / "swing.glb");

    const double d = diagonal(mesh.get());
    const Asset step = read_asset(dir / "step.glb");
    const Asset swing = read_asset(dir / "swing.glb");
    for (const Asset* a : {&step, &swing}) {
        CAPTURE(a->path);
        const JsonValue& prim = cow_primitive(*a);
        const std::size_t cow = mesh_index(*a, "Cow");
        // The base stays the asset's; Squash stays as it was.
        CHECK(mesh_positions(*a, cow) == mesh_positions(original, mesh_index(original, "Cow")));
        CHECK(accessor_bytes(*a, target_accessor(prim, 0, "POSITION")) ==
              accessor_bytes(original, target_accessor(original_prim, 0, "POSITION")));
        CHECK(accessor_bytes(*a, target_accessor(prim, 0, "NORMAL")) ==
              accessor_bytes(original, target_accessor(original_prim, 0, "NORMAL")));
        // Weight 1 on the new target: the edit, to float32 rounding.
        const std::size_t added = member(prim, "targets").items.size() - 1;
        const std::vector<double> expected = a == &step ? stepped : swung;
        const std::vector<double> blended = plus(
            mesh_positions(*a, cow), accessor_floats(*a, target_accessor(prim, added, "POSITION")));
        CHECK(max_distance(blended, expected) < 1e-6 * d);
        CHECK(member(prim, "targets").items.at(added).find("NORMAL") != nullptr);
    }
    const auto names = [](const Asset& a) {
        std::vector<std::string> out;
        for (const JsonValue& n :
             member(member(member(a.doc, "meshes").items.at(mesh_index(a, "Cow")), "extras"),
                    "targetNames")
                 .items)
            out.push_back(n.text);
        return out;
    };
    CHECK(names(step) == std::vector<std::string>{"Squash", "Step"});
    CHECK(names(swing) == std::vector<std::string>{"Squash", "Step", "Swing"});
    CHECK(member(cow_primitive(swing), "targets").items.size() == 3);

    // Blender sees the targets as shape keys.
    const auto read = blender_read({dir / "swing.glb"}, dir);
    const BlenderObject& cow = blender_object(read[0], "Cow");
    REQUIRE(cow.shape_keys.size() == 4);
    CHECK(cow.shape_keys[0].first == "Basis");
    CHECK(max_distance(cow.shape_keys[0].second, rest) < 1e-6 * d);
    CHECK(cow.shape_keys[1].first == "Squash");
    CHECK(cow.shape_keys[2].first == "Step");
    CHECK(max_distance(cow.shape_keys[2].second, stepped) < 1e-5 * d);
    CHECK(cow.shape_keys[3].first == "Swing");
    CHECK(max_distance(cow.shape_keys[3].second, swung) < 1e-5 * d);
}

TEST_CASE("morph target: dualform deform --morph-target on a glTF scenario") {
    const std::filesystem::path dir = scratch_dir("blender_cli_morph");
    const ContextPtr context = make_context();
    const MeshPtr mesh = load_mesh(context.get(), asset_path("scene.glb#mesh=Cow"));
    const LimbEdit e = on_cow(mesh.get(), leg_step);
    const std::string scenario = dir / "step.json";
    write_text(scenario,
               "{\"mesh\": \"" + asset_path("scene.glb").string() +
                   "#mesh=Cow\", \"roi\": {\"water_fill\": {\"first\": " + std::to_string(e.first) +
                   ", \"last\": " + std::to_string(e.last) +
                   "}}, \"handles\": [{\"ball\": {\"center\": " + std::to_string(e.handle) +
                   ", \"radius\": 0.03}, \"translate\": [0.08, 0.03, 0.0]}]}");
    const std::filesystem::path out = dir / "step.glb";
    const ProcessResult r = run_process(
        DUALFORM_CLI, {"deform", scenario, "--out", out.string(), "--morph-target", "Step"});
    INFO(r.out << r.err);
    REQUIRE(r.exit_code == 0);
    check_valid(out);
    const Asset a = read_asset(out);
    const JsonValue& prim = cow_primitive(a);
    REQUIRE(member(prim, "targets").items.size() == 2);
    const std::vector<double> base = mesh_positions(a, mesh_index(a, "Cow"));
    CHECK(base == rest_positions(mesh.get()));
    const std::vector<double> blended =
        plus(base, accessor_floats(a, target_accessor(prim, 1, "POSITION")));
    CHECK(max_distance(blended, base) > 0.01 * diagonal(mesh.get()));
}
