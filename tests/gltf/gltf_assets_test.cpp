// What Blender's exporter wrote (the gltf_assets fixture), and that the
// tools the glTF tests rely on read it as the tests assume: the validator
// accepts it and rejects broken copies, and headless Blender imports it in
// the file's vertex order.
#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "gltf_file.hpp"
#include "support/test_files.hpp"
#include "third_party.hpp"

using namespace dfm::test;
using namespace dfm::test::gltf;

namespace {

using Point = std::array<double, 3>;

std::set<Point> distinct(const std::vector<double>& p) {
    std::set<Point> out;
    for (std::size_t i = 0; i + 2 < p.size(); i += 3) out.insert({p[i], p[i + 1], p[i + 2]});
    return out;
}

// The vertex positions of an OFF file as written by make_assets.py.
std::vector<double> off_positions(const std::filesystem::path& path, std::size_t& faces) {
    std::istringstream in(read_text(path));
    std::string magic;
    std::size_t nv = 0, edges = 0;
    in >> magic >> nv >> faces >> edges;
    REQUIRE(magic == "OFF");
    std::vector<double> out(3 * nv);
    for (double& x : out) in >> x;
    REQUIRE(in);
    return out;
}

const dfm::json::JsonValue& only_primitive(const Asset& a, std::size_t mesh) {
    const auto& prims = member(member(a.doc, "meshes").items.at(mesh), "primitives").items;
    REQUIRE(prims.size() == 1);
    return prims[0];
}

std::size_t triangles(const Asset& a, const dfm::json::JsonValue& prim) {
    return index_or(member(a.doc, "accessors").items.at(index_or(prim, "indices", 0)), "count", 0) /
           3;
}

double max_difference(const std::vector<double>& a, const std::vector<double>& b) {
    REQUIRE(a.size() == b.size());
    double d = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, std::abs(a[i] - b[i]));
    return d;
}

}  // namespace

TEST_CASE("assets: Blender's subdivided Suzanne is split at her UV seams") {
    const Asset a = read_asset(asset_path("suzanne.glb"));
    const std::size_t mesh = mesh_index(a, "Suzanne");
    const auto& prim = only_primitive(a, mesh);
    for (const char* name : {"NORMAL", "TEXCOORD_0", "TANGENT"}) {
        CAPTURE(name);
        CHECK(member(prim, "attributes").find(name) != nullptr);
    }
    const std::vector<double> p = mesh_positions(a, mesh);
    const std::set<Point> positions = distinct(p);
    std::size_t off_faces = 0;
    const std::vector<double> welded = off_positions(asset_path("suzanne.off"), off_faces);
    // Subdivision level 2 gives 7,958 vertices; Blender 3.4's exporter
    // splits 231 of them along the seams of Suzanne's UVs.
    CHECK(welded.size() / 3 == 7958);
    CHECK(positions.size() == 7958);
    CHECK(p.size() / 3 == 8189);
    CHECK(distinct(welded) == positions);
    CHECK(triangles(a, prim) == off_faces);
}

TEST_CASE("assets: Blender's cow is split at every corner, one position shared by two") {
    const Asset glb = read_asset(asset_path("cow.glb"));
    const std::size_t mesh = mesh_index(glb, "Cow");
    const std::vector<double> p = mesh_positions(glb, mesh);
    // Flat shaded: each of the 5,804 triangles has its own three corners.
    CHECK(p.size() / 3 == 17412);
    CHECK(distinct(p).size() == 2903);
    std::size_t off_faces = 0;
    const std::vector<double> welded = off_positions(asset_path("cow.off"), off_faces);
    CHECK(welded.size() / 3 == 2904);  // two surface vertices at one position
    CHECK(distinct(welded) == distinct(p));
    CHECK(off_faces == 5804);

    // The separate and the embedded buffer hold the same accessors.
    for (const char* other : {"cow.gltf", "cow-embedded.gltf"}) {
        CAPTURE(other);
        const Asset b = read_asset(asset_path(other));
        const std::size_t accessors = member(glb.doc, "accessors").items.size();
        REQUIRE(member(b.doc, "accessors").items.size() == accessors);
        for (std::size_t i = 0; i < accessors; ++i)
            CHECK(accessor_bytes(b, i) == accessor_bytes(glb, i));
    }
    CHECK(member(read_asset(asset_path("cow.gltf")).doc, "buffers")
              .items.at(0)
              .find("uri")
              ->value.text == "cow.bin");
}

TEST_CASE("assets: Blender's scene has two meshes under transformed nodes, a shape key") {
    const Asset a = read_asset(asset_path("scene.glb"));
    const std::size_t cow = mesh_index(a, "Cow");
    const std::size_t ball = mesh_index(a, "Ball");
    const auto& cow_prim = only_primitive(a, cow);
    only_primitive(a, ball);
    CHECK(cow_prim.find("material") != nullptr);
    const auto& targets = member(cow_prim, "targets").items;
    REQUIRE(targets.size() == 1);
    CHECK(targets[0].find("POSITION") != nullptr);
    const auto& names =
        member(member(member(a.doc, "meshes").items.at(cow), "extras"), "targetNames").items;
    REQUIRE(names.size() == 1);
    CHECK(names[0].text == "Squash");
    // Smooth shaded with UVs: split only at the UV seams.
    const std::vector<double> p = mesh_positions(a, cow);
    CHECK(p.size() / 3 > 2904);
    CHECK(distinct(p).size() == 2903);
    for (std::size_t m : {cow, ball}) {
        const glm::dmat4 w = mesh_world_matrix(a, m);
        CHECK(w != glm::dmat4{1.0});
    }
    CHECK(a.doc.find("animations") != nullptr);
}

TEST_CASE("assets: the Khronos validator accepts Blender's exports and rejects broken ones") {
    for (const char* name :
         {"suzanne.glb", "cow.glb", "cow.gltf", "cow-embedded.gltf", "scene.glb"}) {
        CAPTURE(name);
        const Validation v = validate(asset_path(name));
        INFO(v.report);
        CHECK(v.exit_code == 0);
        CHECK(validation_errors(v) == 0);
    }
    const std::filesystem::path dir = scratch_dir("blender_validator");
    const std::string glb = read_text(asset_path("cow.glb"));
    write_text(dir / "truncated.glb", glb.substr(0, glb.size() / 2));
    std::string gltf = read_text(asset_path("cow.gltf"));
    write_text(dir / "no-buffer.gltf", gltf);  // cow.bin is not beside it
    for (const char* name : {"truncated.glb", "no-buffer.gltf"}) {
        CAPTURE(name);
        const Validation v = validate(dir / name);
        INFO(v.report);
        CHECK(v.exit_code == 1);
        CHECK(validation_errors(v) > 0);
    }
}

TEST_CASE("assets: headless Blender imports them in the file's vertex order") {
    const std::vector<std::filesystem::path> files{asset_path("cow.glb"), asset_path("scene.glb")};
    const auto read = blender_read(files, scratch_dir("blender_import"));
    REQUIRE(read.size() == 2);
    {
        const Asset a = read_asset(files[0]);
        const BlenderObject& o = blender_object(read[0], "Cow");
        const std::vector<double> p = mesh_positions(a, mesh_index(a, "Cow"));
        CHECK(o.vertex_count == p.size() / 3);
        // The importer's axis swap is exact, and so is undoing it.
        CHECK(o.local == p);
        CHECK(o.world == p);
    }
    const Asset a = read_asset(files[1]);
    for (const char* name : {"Cow", "Ball"}) {
        CAPTURE(name);
        const BlenderObject& o = blender_object(read[1], name);
        const std::size_t mesh = mesh_index(a, name);
        const std::vector<double> p = mesh_positions(a, mesh);
        REQUIRE(o.vertex_count == p.size() / 3);
        CHECK(o.local == p);
        // Blender's matrices are float32.
        CHECK(max_difference(o.world, transformed(mesh_world_matrix(a, mesh), p)) < 1e-5);
    }
    const BlenderObject& cow = blender_object(read[1], "Cow");
    REQUIRE(cow.shape_keys.size() == 2);
    CHECK(cow.shape_keys[0].first == "Basis");
    CHECK(cow.shape_keys[1].first == "Squash");
    const auto& prim = only_primitive(a, mesh_index(a, "Cow"));
    const std::vector<double> delta = accessor_floats(
        a,
        static_cast<std::size_t>(member(member(prim, "targets").items.at(0), "POSITION").number));
    std::vector<double> squashed = cow.local;
    for (std::size_t i = 0; i < squashed.size(); ++i) squashed[i] += delta.at(i);
    CHECK(max_difference(cow.shape_keys[1].second, squashed) < 1e-6);
    CHECK(max_difference(cow.shape_keys[1].second, cow.local) > 0.01);
}
