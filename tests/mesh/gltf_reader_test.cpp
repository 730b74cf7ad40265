#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "mesh/gltf_io.hpp"
#include "mesh/host_mesh.hpp"
#include "support/gltf_builder.hpp"
#include "support/procedural_meshes.hpp"
#include "support/test_files.hpp"

using namespace dfm;
using dfm::mesh::Mesh;
using dfm::test::GltfBuilder;

namespace {

const std::string one_primitive =
    R"("meshes":[{"name":"grid","primitives":[{"attributes":{"POSITION":0},"indices":1}]}])";

Status read(const std::string& bytes, Mesh& host, mesh::GltfAsset& asset,
            const std::string& selector = "", mesh::LoadReport* report = nullptr) {
    mesh::LoadReport local;
    mesh::Skin skin;
    return mesh::read_gltf(bytes, "t.glb", nullptr, selector, host, asset, skin,
                           report ? *report : local);
}

std::vector<std::uint32_t> flat(const Mesh& m) {
    std::vector<std::uint32_t> out;
    for (const auto& t : m.triangles) out.insert(out.end(), t.begin(), t.end());
    return out;
}

template <class T>
std::vector<T> narrow(const std::vector<std::uint32_t>& v) {
    return std::vector<T>(v.begin(), v.end());
}

// The grid as a one-primitive glTF with indices of the given width.
GltfBuilder grid_gltf(const Mesh& grid, int width) {
    GltfBuilder b;
    b.positions(test::float_positions(grid));
    const std::vector<std::uint32_t> idx = flat(grid);
    if (width == 1) b.indices_u8(narrow<std::uint8_t>(idx));
    if (width == 2) b.indices_u16(narrow<std::uint16_t>(idx));
    if (width == 4) b.indices_u32(idx);
    b.members = one_primitive;
    return b;
}

}  // namespace

TEST_CASE("glTF reader: indices of every width give the same mesh") {
    const Mesh grid = test::make_grid(3, 3);
    for (int width : {1, 2, 4}) {
        CAPTURE(width);
        Mesh host;
        mesh::GltfAsset asset;
        REQUIRE(read(grid_gltf(grid, width).glb(), host, asset));
        CHECK(host.positions == test::rounded_to_float(grid).positions);
        CHECK(host.triangles == grid.triangles);
        REQUIRE(asset.ranges.size() == 1);
        CHECK(asset.ranges[0].position.in_place);
        CHECK(asset.primitives.size() == 1);
    }
}

TEST_CASE("glTF reader: a non-indexed primitive welds back to the indexed mesh") {
    const Mesh grid = test::make_grid(2, 2);
    std::vector<float> xyz;
    for (const auto& t : grid.triangles) {
        for (std::uint32_t v : t) {
            for (int c = 0; c < 3; ++c) xyz.push_back(static_cast<float>(grid.positions[v][c]));
        }
    }
    GltfBuilder b;
    b.positions(xyz);
    b.members = R"("meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}])";
    const auto dir = test::scratch_dir("gltf_non_indexed");
    test::write_text(dir / "flat.glb", b.glb());
    Mesh surface;
    mesh::HostMesh host;
    REQUIRE(mesh::load_host_mesh(dir / "flat.glb", surface, host));
    CHECK(host.weld->host_vertex_count() == 3 * grid.face_count());
    CHECK(surface.vertex_count() == grid.vertex_count());
    CHECK(surface.face_count() == grid.face_count());
}

TEST_CASE("glTF reader: sparse accessors, with and without a base buffer view") {
    const Mesh grid = test::make_grid(1, 1);
    GltfBuilder b;
    const std::vector<float> xyz = test::float_positions(grid);
    const int base = b.view_of(xyz);
    const int idx = b.view_of(std::vector<std::uint16_t>{2});
    const int val = b.view_of(std::vector<float>{0.25f, 0.5f, 3.0f});
    const std::string sparse =
        ",\"sparse\":{\"count\":1,\"indices\":{\"bufferView\":" + std::to_string(idx) +
        ",\"componentType\":5123},\"values\":{\"bufferView\":" + std::to_string(val) + "}}";
    b.accessor(base, 5126, 4, "VEC3", 0, ",\"min\":[0,0,0],\"max\":[1,1,3]" + sparse);
    b.indices_u8(narrow<std::uint8_t>(flat(grid)));
    b.accessor(-1, 5126, 4, "VEC3", 0, ",\"min\":[0,0,0],\"max\":[1,1,3]" + sparse);
    b.members = R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]},)"
                R"({"primitives":[{"attributes":{"POSITION":2},"indices":1}]}])";
    Mesh host;
    mesh::GltfAsset asset;
    REQUIRE(read(b.glb(), host, asset, "0"));
    CHECK(host.positions[2] == glm::dvec3(0.25, 0.5, 3.0));
    CHECK(host.positions[1] == grid.positions[1]);
    CHECK_FALSE(asset.ranges[0].position.in_place);  // sparse: rewritten densely on save
    REQUIRE(read(b.glb(), host, asset, "1"));
    CHECK(host.positions[2] == glm::dvec3(0.25, 0.5, 3.0));
    CHECK(host.positions[1] == glm::dvec3(0.0));
}

TEST_CASE("glTF reader: normalized integer normals are scaled, integer positions are refused") {
    const Mesh grid = test::make_grid(1, 1);
    GltfBuilder b;
    b.positions(test::float_positions(grid));
    b.indices_u8(narrow<std::uint8_t>(flat(grid)));
    // Elements padded to 4 bytes, as glTF requires of vertex attributes.
    const std::vector<std::int8_t> normals = {0,  0, 127, 0, 0, -128, 127,  0,
                                              64, 0, 127, 0, 0, 0,    -127, 0};
    b.accessor(b.view(std::string(reinterpret_cast<const char*>(normals.data()), 16), 4), 5120, 4,
               "VEC3", 0, ",\"normalized\":true");
    b.members =
        R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,"NORMAL":2},"indices":1}]}])";
    Mesh host;
    mesh::GltfAsset asset;
    REQUIRE(read(b.glb(), host, asset));
    CHECK(asset.normals[0] == glm::dvec3(0, 0, 1));
    CHECK(asset.normals[1] == glm::dvec3(0, -1, 1));
    CHECK(asset.normals[2].x == doctest::Approx(64.0 / 127.0));
    CHECK_FALSE(asset.ranges[0].normal.in_place);  // not float: a new float view on save

    GltfBuilder q;
    std::vector<std::uint16_t> quantized = {0, 0, 0, 65535, 0, 0, 0, 65535, 0, 65535, 65535, 0};
    q.accessor(q.view_of(quantized), 5123, 4, "VEC3", 0, ",\"normalized\":true");
    q.indices_u8(narrow<std::uint8_t>(flat(grid)));
    q.members = one_primitive + R"(,"extensionsUsed":["KHR_mesh_quantization"])";
    const Status s = read(q.glb(), host, asset);
    CHECK(s.code() == Errc::unsupported);
    CHECK(s.message() ==
          "t.glb: mesh 0 primitive 0 POSITION (accessor 0): component type 5123 "
          "(quantized, KHR_mesh_quantization) is not supported");
    CHECK(host.vertex_count() == 0);
}

TEST_CASE("glTF reader: Draco is refused naming the primitive") {
    GltfBuilder b;
    b.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    b.members =
        R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},)"
        R"("extensions":{"KHR_draco_mesh_compression":{"bufferView":0,"attributes":{}}}}]}])";
    Mesh host;
    mesh::GltfAsset asset;
    const Status s = read(b.glb(), host, asset);
    CHECK(s.code() == Errc::unsupported);
    CHECK(s.message().find("mesh 0 primitive 0: Draco compression") != std::string::npos);
}

TEST_CASE("glTF reader: node transforms compose down the hierarchy, instances load once") {
    const Mesh grid = test::make_grid(1, 1);
    GltfBuilder b = grid_gltf(grid, 1);
    // Node 0: translate (1, 2, 3) and scale 2; its child node 1 turns 90
    // degrees about z and holds the mesh; node 2 instances it again.
    const double h = std::sqrt(0.5);
    b.members = one_primitive +
                R"(,"scene":0,"scenes":[{"nodes":[0,2]}],"nodes":[)"
                R"({"translation":[1,2,3],"scale":[2,2,2],"children":[1]},)"
                R"({"rotation":[0,0,)" +
                std::to_string(h) + "," + std::to_string(h) +
                R"(],"mesh":0},{"mesh":0,"translation":[9,9,9]}])";
    Mesh host;
    mesh::GltfAsset asset;
    mesh::LoadReport report;
    REQUIRE(read(b.glb(), host, asset, "", &report));
    CHECK(host.vertex_count() == 4);
    // Vertex (1, 0, 0) turns to (0, 1, 0), scales to (0, 2, 0), moves to (1, 4, 3).
    std::size_t v = 0;
    while (grid.positions[v] != glm::dvec3(1, 0, 0)) ++v;
    CHECK(host.positions[v].x == doctest::Approx(1.0));
    CHECK(host.positions[v].y == doctest::Approx(4.0));
    CHECK(host.positions[v].z == doctest::Approx(3.0));
    CHECK(asset.local_positions[v] == glm::dvec3(1, 0, 0));
    REQUIRE(report.warnings.size() == 1);
    CHECK(report.warnings[0] ==
          "t.glb: node 2 instances mesh 0 again; only its first instance is loaded");
}

TEST_CASE("glTF reader: #mesh= picks one mesh by name or index, in its own space") {
    const Mesh grid = test::make_grid(1, 1);
    GltfBuilder b;
    b.positions(test::float_positions(grid));
    b.indices_u8(narrow<std::uint8_t>(flat(grid)));
    b.positions({0, 0, 0, 5, 0, 0, 0, 5, 0});
    b.members =
        R"("meshes":[{"name":"floor","primitives":[{"attributes":{"POSITION":0},"indices":1}]},)"
        R"({"name":"sail","primitives":[{"attributes":{"POSITION":2}}]}],)"
        R"("scenes":[{"nodes":[0]}],"nodes":[{"mesh":0,"translation":[0,0,7]}])";
    Mesh host;
    mesh::GltfAsset asset;
    REQUIRE(read(b.glb(), host, asset));
    CHECK(host.vertex_count() == 4);
    CHECK(host.positions[0].z == 7.0);
    REQUIRE(read(b.glb(), host, asset, "sail"));
    CHECK(host.vertex_count() == 3);
    CHECK(host.positions[1] == glm::dvec3(5, 0, 0));
    REQUIRE(read(b.glb(), host, asset, "0"));
    CHECK(host.positions[0].z == 0.0);
    const Status s = read(b.glb(), host, asset, "mast");
    CHECK(s.code() == Errc::not_found);
    CHECK(s.message() ==
          "t.glb: no mesh named or numbered 'mast' (the file has 2 meshes: 'floor', 'sail')");
}

TEST_CASE("glTF reader: external buffers, embedded buffers and GLB load the same mesh") {
    const Mesh grid = test::make_grid(2, 1);
    const GltfBuilder b = grid_gltf(grid, 2);
    const auto dir = test::scratch_dir("gltf_three_forms");
    b.write_external(dir / "external.gltf", "external.bin");
    test::write_text(dir / "embedded.gltf", b.gltf_embedded());
    test::write_text(dir / "binary.glb", b.glb());
    for (const char* name : {"external.gltf", "embedded.gltf", "binary.glb"}) {
        CAPTURE(name);
        Mesh surface;
        mesh::HostMesh host;
        REQUIRE(mesh::load_host_mesh(dir / name, surface, host));
        CHECK(surface.positions == test::rounded_to_float(grid).positions);
        CHECK(surface.triangles == grid.triangles);
        Mesh plain;
        REQUIRE(mesh::load_mesh(dir / name, plain));
        CHECK(plain.positions == surface.positions);
    }
    Mesh surface;
    mesh::HostMesh host;
    REQUIRE(mesh::load_host_mesh((dir / "binary.glb").string() + "#mesh=grid", surface, host));
    CHECK(surface.vertex_count() == grid.vertex_count());
}

TEST_CASE("glTF reader: external buffers resolve only inside the asset's folder") {
    // A secret beside the asset's folder, of exactly the buffer's length: a
    // document that reaches it would load, and a save would embed its bytes.
    const Mesh grid = test::make_grid(2, 1);
    const GltfBuilder b = grid_gltf(grid, 2);
    const auto dir = test::scratch_dir("gltf_uri_confinement");
    const auto asset_dir = dir / "asset";
    std::filesystem::create_directories(asset_dir / "sub");
    test::write_text(dir / "secret.bin", b.bin());
    test::write_text(asset_dir / "sub" / "inside.bin", b.bin());
    const std::string secret = (dir / "secret.bin").string();
    struct Case {
        std::string uri;
        std::string why;
    };
    const Case refused[] = {
        {"../secret.bin", "it leads out of the asset's folder"},
        {"%2E%2E/secret.bin", "it leads out of the asset's folder"},
        {"sub/../../secret.bin", "it leads out of the asset's folder"},
        {secret, "an absolute path is not followed"},
        {"file://" + secret, "a URI with a scheme is not followed"},
        {"file:../secret.bin", "a URI with a scheme is not followed"},
    };
    for (const Case& c : refused) {
        CAPTURE(c.uri);
        test::write_text(asset_dir / "x.gltf", b.json(c.uri));
        Mesh surface;
        mesh::HostMesh host;
        const Status s = mesh::load_host_mesh(asset_dir / "x.gltf", surface, host);
        CHECK(s.code() == Errc::unsupported);
        CHECK(s.message().find("'" + (c.uri.starts_with('%') ? "../secret.bin" : c.uri) +
                               "' refused: " + c.why) != std::string::npos);
        CHECK(surface.vertex_count() == 0);
        Mesh plain;
        CHECK(mesh::load_mesh(asset_dir / "x.gltf", plain).code() == Errc::unsupported);
    }
    // Inside the folder, ".." included, a reference resolves.
    for (const char* uri : {"sub/inside.bin", "sub/../sub/inside.bin", "./sub/inside.bin"}) {
        CAPTURE(uri);
        test::write_text(asset_dir / "x.gltf", b.json(uri));
        Mesh surface;
        mesh::HostMesh host;
        REQUIRE(mesh::load_host_mesh(asset_dir / "x.gltf", surface, host));
        CHECK(surface.positions == test::rounded_to_float(grid).positions);
    }
    // A host widens the rule with a folder of its own; the document's own
    // folder keeps its meaning, and the rest stays refused.
    test::write_text(asset_dir / "x.gltf", b.json("../secret.bin"));
    Mesh surface;
    mesh::HostMesh host;
    CHECK(mesh::load_host_mesh(asset_dir / "x.gltf", surface, host, nullptr, dir).is_ok());
    CHECK(surface.positions == test::rounded_to_float(grid).positions);
    test::write_text(asset_dir / "x.gltf", b.json("../../secret.bin"));
    const Status wider = mesh::load_host_mesh(asset_dir / "x.gltf", surface, host, nullptr, dir);
    CHECK(wider.code() == Errc::unsupported);
    CHECK(wider.message().find("leads out of the asset's folder and of " +
                               std::filesystem::absolute(dir).lexically_normal().string()) !=
          std::string::npos);
    // A document given as bytes follows no reference at all.
    Mesh from_bytes;
    mesh::GltfAsset asset;
    CHECK_FALSE(read(b.json("sub/inside.bin"), from_bytes, asset).is_ok());
}

TEST_CASE("glTF reader: strips and fans become triangles, points are skipped with a warning") {
    GltfBuilder b;
    b.positions({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0});
    b.members =
        R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"mode":5},)"
        R"({"attributes":{"POSITION":0},"mode":6},{"attributes":{"POSITION":0},"mode":0}]}])";
    Mesh host;
    mesh::GltfAsset asset;
    mesh::LoadReport report;
    REQUIRE(read(b.glb(), host, asset, "", &report));
    REQUIRE(host.face_count() == 4);
    CHECK(host.triangles[0] == mesh::Triangle{0, 1, 2});
    CHECK(host.triangles[1] == mesh::Triangle{2, 1, 3});
    CHECK(host.triangles[2] == mesh::Triangle{0, 1, 2});
    CHECK(host.triangles[3] == mesh::Triangle{0, 2, 3});
    CHECK(asset.primitives.size() == 2);
    REQUIRE(report.warnings.size() == 1);
    CHECK(report.warnings[0].find("mesh 0 primitive 2: mode 0") != std::string::npos);
}
