#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mesh/gltf_io.hpp"
#include "mesh/host_mesh.hpp"
#include "support/gltf_builder.hpp"
#include "support/procedural_meshes.hpp"
#include "support/test_files.hpp"

using namespace dfm;
using dfm::mesh::Mesh;
using nlohmann::json;

namespace {

// A written file as a reader sees it: its JSON and its buffers' bytes.
struct Written {
    json doc;
    mesh::GltfAsset asset;
    Mesh host;
};

Written reread(const std::filesystem::path& path) {
    Written w;
    std::string bytes;
    REQUIRE(mesh::read_file_bytes(path, bytes));
    mesh::LoadReport report;
    mesh::Skin skin;
    const Status s =
        mesh::read_gltf(bytes, path.string(), nullptr, "", w.host, w.asset, skin, report);
    REQUIRE_MESSAGE(s, s.message());
    w.doc = json::parse(w.asset.json);
    return w;
}

int component_bytes(int type) {
    return type == 5120 || type == 5121 ? 1 : type <= 5123 ? 2 : 4;
}
int type_width(const std::string& t) {
    return t == "SCALAR" ? 1 : t == "VEC2" ? 2 : t == "VEC3" ? 3 : t == "VEC4" ? 4 : 16;
}

// Every byte an accessor reads, in element order (sparse parts after).
std::string accessor_bytes(const Written& w, std::size_t index) {
    const json& a = w.doc["accessors"][index];
    const std::size_t element =
        component_bytes(a["componentType"]) * type_width(a["type"].get<std::string>());
    std::string out;
    const auto view_bytes = [&](int view, std::size_t offset, std::size_t count, std::size_t size,
                                std::size_t stride) {
        const json& v = w.doc["bufferViews"][view];
        const std::string& buffer = w.asset.buffers[v["buffer"].get<int>()];
        const std::size_t base = v.value("byteOffset", std::size_t{0}) + offset;
        for (std::size_t e = 0; e < count; ++e) out += buffer.substr(base + e * stride, size);
    };
    if (a.contains("bufferView")) {
        const json& v = w.doc["bufferViews"][a["bufferView"].get<int>()];
        const std::size_t stride = v.value("byteStride", element);
        view_bytes(a["bufferView"], a.value("byteOffset", std::size_t{0}), a["count"], element,
                   stride);
    }
    if (a.contains("sparse")) {
        const json& s = a["sparse"];
        const std::size_t n = s["count"];
        const std::size_t isize = component_bytes(s["indices"]["componentType"]);
        view_bytes(s["indices"]["bufferView"], s["indices"].value("byteOffset", std::size_t{0}), n,
                   isize, isize);
        view_bytes(s["values"]["bufferView"], s["values"].value("byteOffset", std::size_t{0}), n,
                   element, element);
    }
    return out;
}

std::vector<float> floats_of(const Written& w, std::size_t accessor) {
    const std::string bytes = accessor_bytes(w, accessor);
    std::vector<float> out(bytes.size() / 4);
    std::memcpy(out.data(), bytes.data(), bytes.size());
    return out;
}

// A seam-split sphere with UVs interleaved with the positions, normals,
// tangents, an existing morph target, a material with an image in the
// buffer, an animation, a second mesh outside the scene, and extras.
std::string rich_asset(const Mesh& split) {
    test::GltfBuilder b;
    const std::size_t n = split.vertex_count();
    std::string interleaved;
    std::vector<float> normals, tangents, smile;
    for (std::size_t v = 0; v < n; ++v) {
        const glm::dvec3 p = split.positions[v];
        const float xyzuv[5] = {static_cast<float>(p.x), static_cast<float>(p.y),
                                static_cast<float>(p.z), static_cast<float>(v % 7) / 7.0f,
                                static_cast<float>(v % 5) / 5.0f};
        interleaved.append(reinterpret_cast<const char*>(xyzuv), sizeof xyzuv);
        const glm::dvec3 u = glm::normalize(p);
        for (int c = 0; c < 3; ++c) normals.push_back(static_cast<float>(u[c]));
        const glm::dvec3 t = glm::normalize(glm::cross(glm::dvec3(0, 0, 1), u) + glm::dvec3(1e-3));
        for (int c = 0; c < 3; ++c) tangents.push_back(static_cast<float>(t[c]));
        tangents.push_back(v % 2 ? 1.0f : -1.0f);
        for (int c = 0; c < 3; ++c) smile.push_back(c == 1 ? 0.01f * static_cast<float>(v % 3) : 0);
    }
    const int view = b.view(interleaved, 20);
    b.accessor(view, 5126, n, "VEC3", 0, ",\"min\":[-1.01,-1.01,-1.01],\"max\":[1.01,1.01,1.01]");
    b.accessor(view, 5126, n, "VEC2", 12);  // 1 TEXCOORD_0
    b.floats(normals, "VEC3");              // 2 NORMAL
    b.floats(tangents, "VEC4");             // 3 TANGENT
    std::vector<std::uint16_t> idx;
    for (const auto& t : split.triangles) idx.insert(idx.end(), t.begin(), t.end());
    b.indices_u16(idx);  // 4
    b.accessor(b.view_of(smile), 5126, n, "VEC3", 0,
               ",\"min\":[0,0,0],\"max\":[0,0.02,0]");  // 5 smile target
    const int image = b.view("\x89PNG fake image bytes, kept as they are");
    b.floats({0.0f, 1.0f}, "SCALAR");          // 6 times
    b.floats({0, 0, 0, 0, 1, 0}, "VEC3");      // 7 translations
    b.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});  // 8 other mesh
    b.members =
        R"("meshes":[{"name":"ball","weights":[0.5],"extras":{"targetNames":["smile"],"note":"keep"},)"
        R"("primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":1,"NORMAL":2,"TANGENT":3},)"
        R"("indices":4,"material":0,"targets":[{"POSITION":5}]}]},)"
        R"({"name":"other","primitives":[{"attributes":{"POSITION":8}}]}],)"
        R"("materials":[{"name":"skin","pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}],)"
        R"("textures":[{"source":0}],"images":[{"bufferView":)" +
        std::to_string(image) +
        R"(,"mimeType":"image/png"}],)"
        R"("animations":[{"samplers":[{"input":6,"output":7}],)"
        R"("channels":[{"sampler":0,"target":{"node":0,"path":"translation"}}]}],)"
        R"("scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0,"name":"ball"}],)"
        R"("extras":{"studio":"tests"})";
    return b.glb();
}

Mesh seamed_sphere() {
    return test::split_corners(test::make_icosphere(1), [](std::size_t t) { return t % 4 == 0; });
}

struct Loaded {
    Mesh surface;
    mesh::HostMesh host;
};

Loaded load(const std::filesystem::path& path) {
    Loaded l;
    const Status s = mesh::load_host_mesh(path, l.surface, l.host);
    REQUIRE_MESSAGE(s, s.message());
    return l;
}

// Lifts the top of the ball.
void lift(Mesh& surface) {
    for (glm::dvec3& p : surface.positions) {
        if (p.z > 0.5) p += glm::dvec3(0.1, 0.0, 0.3 * p.z);
    }
}

}  // namespace

TEST_CASE("glTF writer: a round trip without an edit keeps every accessor's bytes") {
    const auto dir = test::scratch_dir("gltf_round_trip");
    test::write_text(dir / "in.glb", rich_asset(seamed_sphere()));
    Loaded in = load(dir / "in.glb");
    CHECK(in.surface.vertex_count() == test::make_icosphere(1).vertex_count());
    for (const char* out_name : {"out.glb", "out.gltf"}) {
        CAPTURE(out_name);
        REQUIRE(mesh::save_host_mesh(dir / out_name, in.surface, in.surface, in.host));
        const Written a = reread(dir / "in.glb");
        const Written b = reread(dir / out_name);
        REQUIRE(a.doc["accessors"].size() == b.doc["accessors"].size());
        for (std::size_t i = 0; i < a.doc["accessors"].size(); ++i) {
            CAPTURE(i);
            CHECK(accessor_bytes(a, i) == accessor_bytes(b, i));
            CHECK(a.doc["accessors"][i] == b.doc["accessors"][i]);
        }
        for (const char* key : {"meshes", "materials", "textures", "images", "animations", "scenes",
                                "nodes", "extras", "bufferViews"}) {
            CAPTURE(key);
            CHECK(a.doc[key] == b.doc[key]);
        }
        CHECK(b.host.positions == a.host.positions);
    }
}

TEST_CASE("glTF writer: an edit moves every copy, updates bounds and normals, keeps the rest") {
    const auto dir = test::scratch_dir("gltf_edit");
    test::write_text(dir / "in.glb", rich_asset(seamed_sphere()));
    Loaded in = load(dir / "in.glb");
    Mesh edited = in.surface;
    lift(edited);
    REQUIRE(mesh::save_host_mesh(dir / "out.glb", edited, edited, in.host));
    const Written a = reread(dir / "in.glb");
    const Written b = reread(dir / "out.glb");
    const mesh::SeamWeld& weld = *in.host.weld;
    for (std::size_t h = 0; h < weld.host_vertex_count(); ++h) {
        const glm::vec3 want = glm::vec3(edited.positions[weld.surface_of[h]]);
        CAPTURE(h);
        CHECK(glm::vec3(b.host.positions[h]) == want);
        CHECK(glm::dvec3(glm::vec3(b.host.positions[h])) == b.host.positions[h]);
    }
    for (std::size_t i : {1, 4, 5, 6, 7, 8}) {
        CAPTURE(i);
        CHECK(accessor_bytes(a, i) == accessor_bytes(b, i));
    }
    const std::vector<float> xyz = floats_of(b, 0);
    const json& acc = b.doc["accessors"][0];
    for (int c = 0; c < 3; ++c) {
        float lo = 1e30f, hi = -1e30f;
        for (std::size_t k = c; k < xyz.size(); k += 3) {
            lo = std::min(lo, xyz[k]);
            hi = std::max(hi, xyz[k]);
        }
        CHECK(acc["min"][c].get<double>() == lo);
        CHECK(acc["max"][c].get<double>() == hi);
    }
    // Normals: unchanged bytes far from the edit; unit and recomputed per
    // copy near it, so copies on the two sides of a seam keep their own.
    const std::vector<float> n0 = floats_of(a, 2), n1 = floats_of(b, 2);
    const std::vector<float> t0 = floats_of(a, 3), t1 = floats_of(b, 3);
    bool hard_edge_kept = false;
    for (std::size_t h = 0; h < weld.host_vertex_count(); ++h) {
        const glm::dvec3 n(n1[3 * h], n1[3 * h + 1], n1[3 * h + 2]);
        CHECK(glm::length(n) == doctest::Approx(1.0).epsilon(1e-5));
        CHECK(t1[4 * h + 3] == t0[4 * h + 3]);
        if (in.surface.positions[weld.surface_of[h]].z < -0.5) {
            CHECK(std::memcmp(&n0[3 * h], &n1[3 * h], 12) == 0);
        }
        for (std::uint32_t other : weld.copies_of(weld.surface_of[h])) {
            if (std::memcmp(&n1[3 * other], &n1[3 * h], 12) != 0) hard_edge_kept = true;
        }
    }
    CHECK(hard_edge_kept);
}

TEST_CASE("glTF writer: the edit as a morph target reproduces it at weight 1") {
    const auto dir = test::scratch_dir("gltf_morph");
    test::write_text(dir / "in.glb", rich_asset(seamed_sphere()));
    Loaded in = load(dir / "in.glb");
    Mesh edited = in.surface;
    lift(edited);
    mesh::WriteOptions options;
    options.morph_target = "lift";
    REQUIRE(mesh::save_host_mesh(dir / "lift.glb", edited, edited, in.host, options));
    const Written a = reread(dir / "in.glb");
    const Written b = reread(dir / "lift.glb");
    CHECK(accessor_bytes(a, 0) == accessor_bytes(b, 0));  // the base stays
    const json& ball = b.doc["meshes"][0];
    CHECK(ball["weights"] == json::array({0.5, 0.0}));
    CHECK(ball["extras"]["targetNames"] == json::array({"smile", "lift"}));
    CHECK(ball["extras"]["note"] == "keep");
    const json& targets = ball["primitives"][0]["targets"];
    REQUIRE(targets.size() == 2);
    CHECK(targets[0]["POSITION"] == 5);
    CHECK(targets[1].contains("NORMAL"));
    CHECK(b.doc["meshes"][1] == a.doc["meshes"][1]);
    const std::vector<float> base = floats_of(b, 0);
    const std::vector<float> delta = floats_of(b, targets[1]["POSITION"].get<std::size_t>());
    const mesh::SeamWeld& weld = *in.host.weld;
    for (std::size_t h = 0; h < weld.host_vertex_count(); ++h) {
        const glm::dvec3 want = edited.positions[weld.surface_of[h]];
        for (int c = 0; c < 3; ++c) {
            const double got = static_cast<double>(base[3 * h + c]) + delta[3 * h + c];
            CHECK(std::abs(got - want[c]) <= 1e-6 * std::max(1.0, std::abs(want[c])));
        }
    }

    // A second bake from the saved file adds a second target.
    Loaded again = load(dir / "lift.glb");
    Mesh twice = again.surface;
    for (glm::dvec3& p : twice.positions) p.x += 0.05;
    options.morph_target = "shift";
    REQUIRE(mesh::save_host_mesh(dir / "shift.glb", twice, twice, again.host, options));
    const Written c = reread(dir / "shift.glb");
    CHECK(c.doc["meshes"][0]["primitives"][0]["targets"].size() == 3);
    CHECK(c.doc["meshes"][0]["extras"]["targetNames"] == json::array({"smile", "lift", "shift"}));
    CHECK(c.doc["meshes"][0]["weights"] == json::array({0.5, 0.0, 0.0}));
}

TEST_CASE("glTF writer: sparse positions are written densely, other meshes get a fresh asset") {
    const auto dir = test::scratch_dir("gltf_sparse_fresh");
    const Mesh grid = test::make_grid(2, 2);
    test::GltfBuilder b;
    const int base = b.view_of(test::float_positions(grid));
    const int idx = b.view_of(std::vector<std::uint8_t>{4, 0, 0, 0});
    const int val = b.view_of(std::vector<float>{1.0f, 1.0f, 0.5f});
    std::vector<std::uint8_t> tris;
    for (const auto& t : grid.triangles) tris.insert(tris.end(), t.begin(), t.end());
    b.accessor(base, 5126, grid.vertex_count(), "VEC3", 0,
               ",\"min\":[0,0,0],\"max\":[2,2,0.5],\"sparse\":{\"count\":1,\"indices\":"
               "{\"bufferView\":" +
                   std::to_string(idx) + ",\"componentType\":5121},\"values\":{\"bufferView\":" +
                   std::to_string(val) + "}}");
    b.indices_u8(tris);
    b.members = R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}])";
    test::write_text(dir / "sparse.gltf", b.gltf_embedded());
    Loaded in = load(dir / "sparse.gltf");
    CHECK(in.surface.positions[4] == glm::dvec3(1.0, 1.0, 0.5));
    Mesh edited = in.surface;
    edited.positions[0].z = -1.0;
    REQUIRE(mesh::save_host_mesh(dir / "out.gltf", edited, edited, in.host));
    const Written w = reread(dir / "out.gltf");
    CHECK_FALSE(w.doc["accessors"][0].contains("sparse"));
    CHECK(w.host.positions[0] == glm::dvec3(0, 0, -1));
    CHECK(w.host.positions[4] == glm::dvec3(1.0, 1.0, 0.5));
    CHECK(w.doc["accessors"][0]["min"][2] == -1.0);

    const Mesh sphere = test::rounded_to_float(test::make_icosphere(1));
    REQUIRE(mesh::save_mesh(dir / "fresh.glb", sphere));
    Loaded fresh = load(dir / "fresh.glb");
    REQUIRE(fresh.surface.vertex_count() == sphere.vertex_count());
    for (std::size_t v = 0; v < sphere.vertex_count(); ++v) {
        CAPTURE(v);
        CHECK(fresh.surface.positions[v] == sphere.positions[v]);
    }
    CHECK(fresh.surface.triangles == sphere.triangles);
    mesh::WriteOptions morph;
    morph.morph_target = "x";
    const Status s = mesh::save_host_mesh(dir / "fresh2.glb", sphere, sphere, {}, morph);
    CHECK(s.code() == Errc::unsupported);
    CHECK_FALSE(std::filesystem::exists(dir / "fresh2.glb"));
}

TEST_CASE("glTF writer: an edit in world space goes back through the node's transform") {
    const auto dir = test::scratch_dir("gltf_node_transform");
    const Mesh grid = test::make_grid(2, 2);
    test::GltfBuilder b;
    b.positions(test::float_positions(grid));
    std::vector<std::uint8_t> tris;
    for (const auto& t : grid.triangles) tris.insert(tris.end(), t.begin(), t.end());
    b.indices_u8(tris);
    b.members = R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],)"
                R"("scenes":[{"nodes":[0]}],"nodes":[{"translation":[5,0,0],"scale":[2,2,2],)"
                R"("children":[1]},{"rotation":[0,0.6,0,0.8],"mesh":0}])";
    test::write_text(dir / "in.glb", b.glb());
    Loaded in = load(dir / "in.glb");
    Mesh edited = in.surface;
    edited.positions[4] += glm::dvec3(0.0, 1.0, 0.0);  // world up by 1: local up by 1/2
    REQUIRE(mesh::save_host_mesh(dir / "out.glb", edited, edited, in.host));
    const Written a = reread(dir / "in.glb");
    const Written w = reread(dir / "out.glb");
    for (std::size_t v = 0; v < grid.vertex_count(); ++v) {
        CAPTURE(v);
        const glm::dvec3 local = w.asset.local_positions[v];
        if (v == 4) {
            // The rotation is about y, so only the scale acts on the move.
            CHECK(local.x == doctest::Approx(1.0));
            CHECK(local.y == doctest::Approx(1.5));
            CHECK(local.z == doctest::Approx(0.0));
        } else {
            CHECK(local == a.asset.local_positions[v]);  // untouched, bit for bit
        }
        CHECK(w.host.positions[v].x == doctest::Approx(edited.positions[v].x));
        CHECK(w.host.positions[v].y == doctest::Approx(edited.positions[v].y));
        CHECK(w.host.positions[v].z == doctest::Approx(edited.positions[v].z));
    }
}
