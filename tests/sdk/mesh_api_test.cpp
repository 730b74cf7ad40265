#include <doctest/doctest.h>

#include <cmath>
#include <cstddef>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "dualform/dualform.h"
#include "sdk/sdk_fixture.hpp"
#include "support/gltf_builder.hpp"
#include "support/procedural_meshes.hpp"
#include "support/test_files.hpp"

using namespace dfm;
using namespace dfm::test;

namespace {

struct Context {
    dfm_context* context = nullptr;
    Context() { REQUIRE(dfm_context_create(nullptr, &context) == DFM_OK); }
    ~Context() { dfm_context_destroy(context); }
};

// An interleaved host vertex: the SDK must read positions through a stride.
struct HostVertex {
    double position[3];
    float uv[2];
};

}  // namespace

TEST_CASE("mesh api: a mesh from strided double positions reads back exactly") {
    Context c;
    const mesh::Mesh sphere = make_icosphere(1);
    std::vector<HostVertex> vertices(sphere.vertex_count());
    for (std::size_t i = 0; i < vertices.size(); ++i) {
        vertices[i] = {{sphere.positions[i].x, sphere.positions[i].y, sphere.positions[i].z},
                       {0.f, 0.f}};
    }
    struct Tri {
        std::uint32_t corners[3];
        std::uint32_t material;
    };
    std::vector<Tri> tris;
    for (const auto& t : sphere.triangles) tris.push_back({{t[0], t[1], t[2]}, 7});
    dfm_mesh_desc desc = {};
    desc.positions = {vertices.data(), vertices.size(), sizeof(HostVertex), DFM_SCALAR_FLOAT64};
    desc.indices = tris.front().corners;
    desc.triangle_count = tris.size();
    desc.index_stride = sizeof(Tri);
    dfm_mesh* mesh = nullptr;
    REQUIRE_MESSAGE(dfm_mesh_create(c.context, &desc, &mesh) == DFM_OK, last_error());

    dfm_mesh_info info = {};
    REQUIRE(dfm_mesh_get_info(mesh, &info) == DFM_OK);
    CHECK(info.vertex_count == sphere.vertex_count());
    CHECK(info.triangle_count == sphere.face_count());
    CHECK(info.components == 1);
    CHECK(info.boundary_edges == 0);
    CHECK(info.diagonal == doctest::Approx(std::sqrt(12.0)).epsilon(0.05));

    std::vector<double> back(3 * sphere.vertex_count());
    dfm_vec3_output out = {back.data(), sphere.vertex_count(), 0, DFM_SCALAR_FLOAT64};
    REQUIRE(dfm_mesh_read_positions(mesh, &out) == DFM_OK);
    for (std::size_t i = 0; i < sphere.vertex_count(); ++i) {
        CHECK(back[3 * i] == sphere.positions[i].x);
        CHECK(back[3 * i + 2] == sphere.positions[i].z);
    }
    std::vector<std::uint32_t> indices(3 * sphere.face_count());
    REQUIRE(dfm_mesh_read_indices(mesh, indices.data(), indices.size()) == DFM_OK);
    CHECK(indices[3] == sphere.triangles[1][0]);
    CHECK(dfm_mesh_read_indices(mesh, indices.data(), indices.size() - 1) ==
          DFM_ERROR_INVALID_ARGUMENT);
    std::vector<float> normals(3 * sphere.vertex_count());
    dfm_vec3_output nout = {normals.data(), sphere.vertex_count(), 0, DFM_SCALAR_FLOAT32};
    REQUIRE(dfm_mesh_read_normals(mesh, &nout) == DFM_OK);
    // On a unit sphere the normal is the position.
    CHECK(normals[0] == doctest::Approx(sphere.positions[0].x).epsilon(0.05));
    nout.count -= 1;
    CHECK(dfm_mesh_read_normals(mesh, &nout) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(message_has("needed"));
    dfm_mesh_destroy(mesh);
}

TEST_CASE("mesh api: bad mesh descriptors are refused with the element named") {
    Context c;
    const mesh::Mesh grid = make_grid(2, 2);
    std::vector<double> xyz;
    for (const glm::dvec3& p : grid.positions) xyz.insert(xyz.end(), {p.x, p.y, p.z});
    std::vector<std::uint32_t> idx;
    for (const auto& t : grid.triangles) idx.insert(idx.end(), t.begin(), t.end());
    auto desc = [&] {
        dfm_mesh_desc d = {};
        d.positions = {xyz.data(), grid.vertex_count(), 0, DFM_SCALAR_FLOAT64};
        d.indices = idx.data();
        d.triangle_count = grid.face_count();
        return d;
    };
    dfm_mesh* mesh = reinterpret_cast<dfm_mesh*>(0x1);
    dfm_mesh_desc d = desc();
    CHECK(dfm_mesh_create(nullptr, &d, &mesh) == DFM_ERROR_INVALID_HANDLE);
    CHECK(mesh == nullptr);
    CHECK(dfm_mesh_create(c.context, nullptr, &mesh) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(dfm_mesh_create(c.context, &d, nullptr) == DFM_ERROR_INVALID_ARGUMENT);
    d.positions.data = nullptr;
    CHECK(dfm_mesh_create(c.context, &d, &mesh) == DFM_ERROR_INVALID_ARGUMENT);
    d = desc();
    d.positions.stride = 8;
    CHECK(dfm_mesh_create(c.context, &d, &mesh) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(message_has("stride 8"));
    d = desc();
    d.positions.type = static_cast<dfm_scalar_type>(5);
    CHECK(dfm_mesh_create(c.context, &d, &mesh) == DFM_ERROR_INVALID_ARGUMENT);
    d = desc();
    d.index_stride = 4;
    CHECK(dfm_mesh_create(c.context, &d, &mesh) == DFM_ERROR_INVALID_ARGUMENT);
    d = desc();
    d.triangle_count = 0;
    CHECK(dfm_mesh_create(c.context, &d, &mesh) == DFM_ERROR_INVALID_ARGUMENT);
    d = desc();
    idx[7] = 999;
    CHECK(dfm_mesh_create(c.context, &d, &mesh) == DFM_ERROR_OUT_OF_RANGE);
    CHECK(message_has("triangle 2 corner 1: vertex 999"));
    idx[7] = grid.triangles[2][1];
    xyz[4] = std::numeric_limits<double>::quiet_NaN();
    CHECK(dfm_mesh_create(c.context, &d, &mesh) == DFM_ERROR_NUMERICAL);
    CHECK(message_has("vertex 1 is not finite"));
    CHECK(mesh == nullptr);
}

TEST_CASE("mesh api: a triangle that repeats a vertex is dropped with a warning, as on load") {
    std::vector<std::string> warnings;
    dfm_context_desc cd = {};
    cd.log = [](void* user, dfm_log_level level, dfm_log_id id, const char* message) {
        if (level == DFM_LOG_WARNING && id == DFM_LOG_ID_LOAD_WARNING) {
            static_cast<std::vector<std::string>*>(user)->emplace_back(message);
        }
    };
    cd.log_user = &warnings;
    dfm_context* context = nullptr;
    REQUIRE(dfm_context_create(&cd, &context) == DFM_OK);
    const mesh::Mesh grid = make_grid(2, 2);
    std::vector<std::uint32_t> idx;
    for (const auto& t : grid.triangles) idx.insert(idx.end(), t.begin(), t.end());
    idx[7] = idx[6];
    dfm_mesh_desc d = {};
    d.positions = {grid.positions.data(), grid.vertex_count(), 0, DFM_SCALAR_FLOAT64};
    d.indices = idx.data();
    d.triangle_count = grid.face_count();
    dfm_mesh* mesh = nullptr;
    REQUIRE_MESSAGE(dfm_mesh_create(context, &d, &mesh) == DFM_OK, dfm_last_error_message());
    REQUIRE(warnings.size() == 1);
    CHECK(warnings[0] == "dfm_mesh_create: triangle 2 repeats a vertex; dropped");
    dfm_mesh_info info = {};
    REQUIRE(dfm_mesh_get_info(mesh, &info) == DFM_OK);
    CHECK(info.triangle_count == grid.face_count() - 1);
    std::vector<std::uint32_t> kept(3 * info.triangle_count);
    REQUIRE(dfm_mesh_read_indices(mesh, kept.data(), kept.size()) == DFM_OK);
    idx.erase(idx.begin() + 6, idx.begin() + 9);
    CHECK(kept == idx);
    dfm_mesh_destroy(mesh);

    const std::uint32_t degenerate[] = {0, 1, 1, 2, 2, 3};
    d.indices = degenerate;
    d.triangle_count = 2;
    CHECK(dfm_mesh_create(context, &d, &mesh) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(message_has("every triangle repeats a vertex"));
    CHECK(warnings.back() ==
          "dfm_mesh_create: 2 triangles repeat a vertex; dropped (the first: triangle 0)");
    dfm_context_destroy(context);
}

TEST_CASE("mesh api: loading reports the file and line and element") {
    Context c;
    dfm_mesh* mesh = nullptr;
    CHECK(dfm_mesh_load(c.context, nullptr, &mesh) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(dfm_mesh_load(c.context, "/nonexistent/nothing.off", &mesh) == DFM_ERROR_NOT_FOUND);
    CHECK(message_has("nothing.off"));
    const std::string bad = (data_dir() / "malformed" / "off-index-too-big.off").string();
    const dfm_result r = dfm_mesh_load(c.context, bad.c_str(), &mesh);
    CHECK(r != DFM_OK);
    CHECK(mesh == nullptr);
    CHECK(message_has("off-index-too-big.off:8:"));
    CHECK(message_has("face 1"));

    const std::string path = (scratch_dir("sdk_mesh") / "sdk_sphere.off").string();
    dfm_mesh* sphere = make_c_mesh(c.context, make_icosphere(1));
    REQUIRE(dfm_mesh_save(sphere, path.c_str()) == DFM_OK);
    CHECK(dfm_mesh_save(sphere, "/nonexistent/dir/x.off") != DFM_OK);
    CHECK(dfm_mesh_save(sphere, "x.unknown") != DFM_OK);
    REQUIRE(dfm_mesh_load(c.context, path.c_str(), &mesh) == DFM_OK);
    dfm_mesh_info info = {};
    REQUIRE(dfm_mesh_get_info(mesh, &info) == DFM_OK);
    CHECK(info.vertex_count == 42);
    dfm_mesh_destroy(mesh);
    dfm_mesh_destroy(sphere);
}

TEST_CASE(
    "mesh api: a glTF's external buffer outside its folder is refused unless the host "
    "widens the rule") {
    GltfBuilder b;
    b.positions({0, 0, 0, 1, 0, 0, 0, 1, 0});
    b.indices_u16({0, 1, 2});
    b.members = R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}])";
    const auto dir = scratch_dir("sdk_gltf_references");
    std::filesystem::create_directories(dir / "asset");
    write_text(dir / "outside.bin", b.bin());
    write_text(dir / "asset" / "x.gltf", b.json("../outside.bin"));
    const std::string path = (dir / "asset" / "x.gltf").string();

    Context c;
    dfm_mesh* mesh = nullptr;
    CHECK(dfm_mesh_load(c.context, path.c_str(), &mesh) == DFM_ERROR_UNSUPPORTED);
    CHECK(mesh == nullptr);
    CHECK(message_has("external file URI '../outside.bin' refused"));

    const std::string folder = dir.string();
    dfm_context_desc desc = {};
    desc.struct_size = sizeof desc;
    desc.reference_folder = folder.c_str();
    dfm_context* wide = nullptr;
    REQUIRE(dfm_context_create(&desc, &wide) == DFM_OK);
    REQUIRE(dfm_mesh_load(wide, path.c_str(), &mesh) == DFM_OK);
    dfm_mesh_info info = {};
    REQUIRE(dfm_mesh_get_info(mesh, &info) == DFM_OK);
    CHECK(info.vertex_count == 3);
    dfm_mesh_destroy(mesh);
    // A descriptor of the size before the field: the document's folder only.
    desc.struct_size = offsetof(dfm_context_desc, models_directory) + sizeof(const char*);
    dfm_context* narrow = nullptr;
    REQUIRE(dfm_context_create(&desc, &narrow) == DFM_OK);
    CHECK(dfm_mesh_load(narrow, path.c_str(), &mesh) == DFM_ERROR_UNSUPPORTED);
    dfm_context_destroy(narrow);
    dfm_context_destroy(wide);
}

TEST_CASE("mesh api: picking through a camera hits the sphere and a miss is no error") {
    Context c;
    dfm_mesh* mesh = make_c_mesh(c.context, make_icosphere(3));
    dfm_camera camera = {{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 30.0, 200, 100};
    dfm_hit hit = {};
    REQUIRE(dfm_mesh_pick(mesh, &camera, 100, 50, &hit) == DFM_OK);
    CHECK(hit.hit);
    CHECK(hit.distance == doctest::Approx(4.0).epsilon(0.01));
    CHECK(hit.point[2] == doctest::Approx(1.0).epsilon(0.01));
    REQUIRE(dfm_mesh_pick(mesh, &camera, 2, 2, &hit) == DFM_OK);
    CHECK_FALSE(hit.hit);
    const double origin[3] = {5, 0, 0}, direction[3] = {-2, 0, 0}, zero[3] = {0, 0, 0};
    REQUIRE(dfm_mesh_pick_ray(mesh, origin, direction, &hit) == DFM_OK);
    CHECK(hit.hit);
    CHECK(hit.point[0] == doctest::Approx(1.0).epsilon(0.01));
    CHECK(dfm_mesh_pick_ray(mesh, origin, zero, &hit) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(dfm_mesh_pick(mesh, nullptr, 1, 1, &hit) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(dfm_mesh_pick(mesh, &camera, std::nan(""), 1, &hit) == DFM_ERROR_INVALID_ARGUMENT);
    camera.width = 0;
    CHECK(dfm_mesh_pick(mesh, &camera, 1, 1, &hit) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(dfm_mesh_pick(mesh, &camera, 1, 1, nullptr) == DFM_ERROR_INVALID_ARGUMENT);
    dfm_mesh_destroy(mesh);
}

TEST_CASE("mesh api: ROI tools on a limb") {
    LimbEdit limb;
    dfm_mesh_info info = {};
    REQUIRE(dfm_mesh_get_info(limb.mesh, &info) == DFM_OK);
    // Water-Filling from the tip's centre to a vertex half-way down.
    std::uint32_t first = 0, last = 0;
    double best_top = -1, best_mid = 1e9;
    for (std::uint32_t v = 0; v < limb.shape.vertex_count(); ++v) {
        const double y = limb.shape.positions[v].y;
        if (y > best_top) best_top = y, first = v;
        if (std::abs(y - 1.0) < best_mid) best_mid = std::abs(y - 1.0), last = v;
    }
    dfm_roi* fill = nullptr;
    dfm_water_fill_diagnosis diagnosis = {};
    REQUIRE_MESSAGE(dfm_roi_water_fill(limb.mesh, first, last, &fill, &diagnosis) == DFM_OK,
                    last_error());
    std::size_t n = 0;
    REQUIRE(dfm_roi_count(fill, &n) == DFM_OK);
    CHECK(n > 10);
    CHECK(n < info.vertex_count / 2 + 20);
    CHECK(diagnosis.loops == 1);
    CHECK_FALSE(diagnosis.suspect);
    std::vector<std::uint32_t> vertices(n);
    REQUIRE(dfm_roi_read(fill, vertices.data(), n) == DFM_OK);
    for (std::uint32_t v : vertices) CHECK(limb.shape.positions[v].y > 0.99);
    CHECK(dfm_roi_read(fill, vertices.data(), n - 1) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(dfm_roi_water_fill(limb.mesh, first, first, &fill, nullptr) != DFM_OK);
    CHECK(fill == nullptr);
    CHECK(dfm_roi_water_fill(limb.mesh, first, 1u << 30, &fill, nullptr) == DFM_ERROR_OUT_OF_RANGE);

    dfm_roi *grown = nullptr, *shrunk = nullptr, *both = nullptr, *diff = nullptr, *edge = nullptr,
            *ball = nullptr;
    REQUIRE(dfm_roi_grow(limb.roi, 1, &grown) == DFM_OK);
    REQUIRE(dfm_roi_grow(limb.roi, -1, &shrunk) == DFM_OK);
    std::size_t n_roi = 0, n_grown = 0, n_shrunk = 0, n_edge = 0, n_diff = 0;
    dfm_roi_count(limb.roi, &n_roi);
    dfm_roi_count(grown, &n_grown);
    dfm_roi_count(shrunk, &n_shrunk);
    CHECK(n_grown == n_roi + 16);
    CHECK(n_shrunk == n_roi - 16);
    REQUIRE(dfm_roi_boundary(limb.roi, &edge) == DFM_OK);
    dfm_roi_count(edge, &n_edge);
    CHECK(n_edge == 16);
    REQUIRE(dfm_roi_difference(limb.roi, shrunk, &diff) == DFM_OK);
    dfm_roi_count(diff, &n_diff);
    CHECK(n_diff == 16);
    REQUIRE(dfm_roi_union(shrunk, diff, &both) == DFM_OK);
    std::size_t n_both = 0;
    dfm_roi_count(both, &n_both);
    CHECK(n_both == n_roi);
    CHECK(dfm_roi_grow(limb.roi, -1000, &shrunk) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(dfm_roi_ball(limb.mesh, first, 0.1, &ball) == DFM_OK);
    CHECK(dfm_roi_ball(limb.mesh, first, -1.0, &ball) == DFM_ERROR_INVALID_ARGUMENT);
    const std::uint32_t list[] = {3, 1, 3, 99999};
    dfm_roi* listed = nullptr;
    CHECK(dfm_roi_from_vertices(limb.mesh, list, 4, &listed) == DFM_ERROR_OUT_OF_RANGE);
    CHECK(message_has("99999"));
    REQUIRE(dfm_roi_from_vertices(limb.mesh, list, 3, &listed) == DFM_OK);
    dfm_roi_count(listed, &n);
    CHECK(n == 2);

    // Another mesh's ROI cannot mix.
    dfm_mesh* other = make_c_mesh(limb.context, limb.shape);
    dfm_roi* foreign = nullptr;
    REQUIRE(dfm_roi_all(other, &foreign) == DFM_OK);
    dfm_roi* mixed = nullptr;
    CHECK(dfm_roi_union(limb.roi, foreign, &mixed) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(message_has("different meshes"));
    for (dfm_roi* r : {fill, grown, shrunk, both, diff, edge, ball, listed, foreign}) {
        dfm_roi_destroy(r);
    }
    dfm_mesh_destroy(other);
}

TEST_CASE("mesh api: Water-Filling from two clicks through a camera") {
    LimbEdit limb;
    // Looking at the limb's front (z = 0.2) from z = 5: y = 1.9 projects to
    // row 60 and y = 1.0 to row 200 of a 200 x 400 image.
    const dfm_camera camera = {{0, 1, 5}, {0, 1, 0}, {0, 1, 0}, 30.0, 200, 400};
    const double tip[2] = {100.0, 60.0}, middle[2] = {100.0, 200.0}, sky[2] = {5.0, 5.0};
    dfm_roi* roi = nullptr;
    dfm_water_fill_diagnosis diagnosis = {};
    REQUIRE_MESSAGE(
        dfm_roi_water_fill_clicks(limb.mesh, &camera, tip, middle, &roi, &diagnosis) == DFM_OK,
        last_error());
    std::size_t n = 0;
    REQUIRE(dfm_roi_count(roi, &n) == DFM_OK);
    std::vector<std::uint32_t> vertices(n);
    REQUIRE(dfm_roi_read(roi, vertices.data(), n) == DFM_OK);
    CHECK(n > 100);
    CHECK(diagnosis.loops == 1);
    for (std::uint32_t v : vertices) CHECK(limb.shape.positions[v].y > 0.85);
    dfm_roi_destroy(roi);
    CHECK(dfm_roi_water_fill_clicks(limb.mesh, &camera, sky, middle, &roi, nullptr) ==
          DFM_ERROR_NOT_FOUND);
    CHECK(message_has("the first click"));
    CHECK(message_has("misses the mesh"));
    CHECK(dfm_roi_water_fill_clicks(limb.mesh, &camera, tip, sky, &roi, nullptr) ==
          DFM_ERROR_NOT_FOUND);
    CHECK(message_has("the last click"));
    CHECK(dfm_roi_water_fill_clicks(limb.mesh, nullptr, tip, middle, &roi, nullptr) ==
          DFM_ERROR_INVALID_ARGUMENT);
    CHECK(roi == nullptr);
}

TEST_CASE("mesh api: handles of the wrong kind or already destroyed are refused") {
    Context c;
    dfm_mesh* mesh = make_c_mesh(c.context, make_icosphere(1));
    dfm_roi* roi = nullptr;
    REQUIRE(dfm_roi_all(mesh, &roi) == DFM_OK);
    dfm_mesh_info info = {};
    // A ROI where a mesh belongs.
    CHECK(dfm_mesh_get_info(reinterpret_cast<dfm_mesh*>(roi), &info) == DFM_ERROR_INVALID_HANDLE);
    CHECK(message_has("mesh is not a live handle"));
    dfm_roi_destroy(roi);
    std::size_t n = 0;
    CHECK(dfm_roi_count(roi, &n) == DFM_ERROR_INVALID_HANDLE);
    dfm_roi_destroy(roi);
    dfm_mesh_destroy(mesh);
    CHECK(dfm_mesh_get_info(mesh, &info) == DFM_ERROR_INVALID_HANDLE);
    dfm_roi* again = nullptr;
    CHECK(dfm_roi_all(mesh, &again) == DFM_ERROR_INVALID_HANDLE);
    CHECK(dfm_mesh_get_info(nullptr, &info) == DFM_ERROR_INVALID_HANDLE);
    CHECK(message_has("mesh is NULL"));
}
