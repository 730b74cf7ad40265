#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>

#include "render/render_helpers.hpp"
#include "support/procedural_meshes.hpp"
#include "support/test_files.hpp"

using namespace dfm;
using namespace dfm::test;

namespace {

// Looks at a unit sphere from +z, aimed below its centre so that the sphere
// sits above the image centre: a flipped y would show.
pick::Camera sphere_camera(std::uint32_t width, std::uint32_t height) {
    pick::Camera c;
    c.eye = {0.0, 0.0, 5.0};
    c.target = {0.0, -0.8, 0.0};
    c.up = {0.0, 1.0, 0.0};
    c.fov_y_degrees = 45.0;
    c.width = width;
    c.height = height;
    return c;
}

std::size_t at(const pick::Camera& c, glm::dvec2 pixel) {
    return static_cast<std::size_t>(pixel.y) * c.width + static_cast<std::size_t>(pixel.x);
}

}  // namespace

TEST_CASE("render: a sphere lands where the pick camera projects it") {
    const mesh::Mesh sphere = make_icosphere(4);
    HeadlessScene scene(sphere);
    const pick::Camera camera = sphere_camera(200, 150);
    const std::vector<std::uint8_t> rgba = scene.render(to_c_camera(camera));

    const auto centre = pick::project(camera, {0.0, 0.0, 0.0});
    REQUIRE(centre);
    CHECK(centre->y < 75.0);  // above the image centre, as the camera says
    // The silhouette's radius in pixels: the sphere subtends asin(1 / 5).
    const double angular = std::asin(1.0 / 5.0);
    const double radius_px =
        std::tan(angular) / std::tan(camera.fov_y_degrees * std::numbers::pi / 360.0) * 75.0;
    for (glm::dvec2 dir :
         {glm::dvec2(1, 0), glm::dvec2(-1, 0), glm::dvec2(0, 1), glm::dvec2(0, -1)}) {
        CHECK_FALSE(is_background(rgba, at(camera, *centre + 0.85 * radius_px * dir)));
        CHECK(is_background(rgba, at(camera, *centre + 1.15 * radius_px * dir)));
    }
    CHECK(is_background(rgba, at(camera, {100.0, 140.0})));
    CHECK(scene.messages() == 0);
}

TEST_CASE("render: two renders of the same state are identical") {
    const mesh::Mesh limb = make_limb(24, 12, 0.3, 2.0);
    HeadlessScene scene(limb);
    dfm_camera camera = {};
    const dfm_vec3_input positions = positions_of(limb);
    REQUIRE(dfm_vk_framing_camera(&positions, 160, 120, &camera) == DFM_OK);
    const std::vector<std::uint8_t> first = scene.render(camera, DFM_VK_FLAG_WIREFRAME);
    const std::vector<std::uint8_t> second = scene.render(camera, DFM_VK_FLAG_WIREFRAME);
    CHECK(first == second);
    const std::size_t covered = first.size() / 4 - count_pixels(first, is_background);
    CHECK(covered > first.size() / 4 / 20);
    CHECK(scene.messages() == 0);
}

TEST_CASE("render: marks colour the vertices, flat shading and wireframe change the picture") {
    const mesh::Mesh sphere = make_icosphere(3);
    HeadlessScene scene(sphere);
    const dfm_camera camera = to_c_camera(sphere_camera(160, 120));
    const std::vector<std::uint8_t> plain = scene.render(camera);
    CHECK(count_pixels(plain, is_red) == 0);
    CHECK(count_pixels(plain, is_green) == 0);

    std::vector<std::uint8_t> marks(sphere.vertex_count(), DFM_VK_MARK_SURFACE);
    for (std::size_t v = 0; v < sphere.vertex_count(); ++v) {
        if (sphere.positions[v].x > 0.3) marks[v] = DFM_VK_MARK_ROI;
        if (sphere.positions[v].x < -0.5) marks[v] = DFM_VK_MARK_HANDLE;
    }
    REQUIRE(dfm_vk_renderer_set_marks(scene.renderer(), marks.data(), marks.size()) == DFM_OK);
    const std::vector<std::uint8_t> marked = scene.render(camera);
    CHECK(count_pixels(marked, is_red) > 200);
    CHECK(count_pixels(marked, is_green) > 100);
    REQUIRE(dfm_vk_renderer_set_marks(scene.renderer(), nullptr, 0) == DFM_OK);
    CHECK(scene.render(camera) == plain);

    CHECK(scene.render(camera, DFM_VK_FLAG_FLAT) != plain);
    CHECK(scene.render(camera, DFM_VK_FLAG_WIREFRAME) != plain);
    CHECK(scene.messages() == 0);
}

TEST_CASE("render: host lines are drawn over the mesh") {
    const mesh::Mesh sphere = make_icosphere(3);
    HeadlessScene scene(sphere);
    const dfm_camera camera = to_c_camera(sphere_camera(160, 120));
    const std::vector<std::uint8_t> before = scene.render(camera);

    // A loop around the sphere's equator, facing the camera, in pure green.
    std::vector<glm::dvec3> loop;
    for (int i = 0; i < 64; ++i) {
        const double a = 2.0 * std::numbers::pi * i / 64.0;
        loop.push_back({1.01 * std::cos(a), 1.01 * std::sin(a), 0.3});
    }
    dfm_vk_polyline line = {};
    line.points = positions_of(loop);
    line.closed = true;
    line.color[1] = 1.0f;
    line.color[3] = 1.0f;
    REQUIRE(dfm_vk_renderer_set_lines(scene.renderer(), &line, 1) == DFM_OK);
    const std::vector<std::uint8_t> with_line = scene.render(camera);
    CHECK(count_pixels(before, is_green) == 0);
    CHECK(count_pixels(with_line, is_green) > 100);
    REQUIRE(dfm_vk_renderer_set_lines(scene.renderer(), nullptr, 0) == DFM_OK);
    CHECK(scene.render(camera) == before);
    CHECK(scene.messages() == 0);
}

TEST_CASE("render: updated positions move the picture, float input matches double") {
    mesh::Mesh sphere = make_icosphere(3);
    HeadlessScene scene(sphere);
    const dfm_camera camera = to_c_camera(sphere_camera(120, 90));
    const std::vector<std::uint8_t> rest = scene.render(camera);

    std::vector<float> shifted;
    for (const glm::dvec3& p : sphere.positions) {
        shifted.insert(shifted.end(), {static_cast<float>(p.x + 0.5), static_cast<float>(p.y),
                                       static_cast<float>(p.z)});
    }
    dfm_vec3_input floats = {};
    floats.data = shifted.data();
    floats.count = sphere.vertex_count();
    floats.type = DFM_SCALAR_FLOAT32;
    REQUIRE(dfm_vk_renderer_update_positions(scene.renderer(), &floats) == DFM_OK);
    const std::vector<std::uint8_t> moved = scene.render(camera);
    CHECK(moved != rest);

    const dfm_vec3_input doubles = positions_of(sphere);
    REQUIRE(dfm_vk_renderer_update_positions(scene.renderer(), &doubles) == DFM_OK);
    CHECK(scene.render(camera) == rest);
    CHECK(scene.messages() == 0);
}

TEST_CASE("render: bad input is refused with a message, never a crash") {
    dfm_vk_renderer_destroy(nullptr);
    dfm_vk_renderer* none = nullptr;
    CHECK(dfm_vk_renderer_set_marks(none, nullptr, 0) == DFM_ERROR_INVALID_HANDLE);
    CHECK(dfm_vk_renderer_create_headless(nullptr, nullptr) == DFM_ERROR_INVALID_ARGUMENT);
    dfm_vk_renderer_desc bad_desc = {};
    bad_desc.max_samples = 3;
    CHECK(dfm_vk_renderer_create_headless(&bad_desc, &none) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(none == nullptr);

    const mesh::Mesh sphere = make_icosphere(1);
    HeadlessScene scene(sphere);
    dfm_vk_renderer* r = scene.renderer();
    const dfm_vec3_input positions = positions_of(sphere);
    const std::uint32_t past_end[3] = {0, 1, static_cast<std::uint32_t>(sphere.vertex_count())};
    CHECK(dfm_vk_renderer_set_mesh(r, &positions, past_end, 1) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(std::strstr(dfm_last_error_message(), "past the") != nullptr);

    std::vector<std::uint8_t> marks(sphere.vertex_count(), 7);
    CHECK(dfm_vk_renderer_set_marks(r, marks.data(), marks.size()) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(dfm_vk_renderer_set_marks(r, marks.data(), 3) == DFM_ERROR_INVALID_ARGUMENT);

    std::vector<glm::dvec3> nan_positions = sphere.positions;
    nan_positions[2].y = std::nan("");
    const dfm_vec3_input bad_positions = positions_of(nan_positions);
    CHECK(dfm_vk_renderer_update_positions(r, &bad_positions) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(std::strstr(dfm_last_error_message(), "vertex 2") != nullptr);

    dfm_vk_frame frame = {};
    std::uint8_t pixel[4];
    CHECK(dfm_vk_renderer_render_offscreen(r, &frame, pixel, 4) == DFM_ERROR_INVALID_ARGUMENT);
    frame.camera = to_c_camera(sphere_camera(2, 2));
    CHECK(dfm_vk_renderer_render_offscreen(r, &frame, pixel, 4) == DFM_ERROR_INVALID_ARGUMENT);
    frame.flags = 0x80;
    CHECK(dfm_vk_renderer_render_offscreen(r, &frame, nullptr, 0) == DFM_ERROR_INVALID_ARGUMENT);
    CHECK(dfm_vk_renderer_present(r, &frame, nullptr) == DFM_ERROR_INVALID_ARGUMENT);
    frame.flags = 0;
    CHECK(dfm_vk_renderer_present(r, &frame, nullptr) == DFM_ERROR_UNSUPPORTED);
    CHECK(dfm_vk_renderer_record_upload(r, VK_NULL_HANDLE) == DFM_ERROR_UNSUPPORTED);

    // After all that, the renderer still draws.
    CHECK(scene.render(to_c_camera(sphere_camera(32, 24))).size() == 32 * 24 * 4);
    CHECK(scene.messages() == 0);
}

TEST_CASE("render: PNG output") {
    const mesh::Mesh sphere = make_icosphere(2);
    HeadlessScene scene(sphere);
    const dfm_camera camera = to_c_camera(sphere_camera(64, 48));
    const std::vector<std::uint8_t> rgba = scene.render(camera);
    const std::filesystem::path dir = scratch_dir("render_png");
    const std::string path = (dir / "sphere.png").string();
    REQUIRE(dfm_vk_write_png(path.c_str(), rgba.data(), rgba.size(), 64, 48) == DFM_OK);
    const std::string bytes = read_text(path);
    REQUIRE(bytes.size() > 33);
    CHECK(bytes.substr(1, 3) == "PNG");
    // IHDR: width and height, big endian, at bytes 16 and 20.
    CHECK(static_cast<unsigned char>(bytes[19]) == 64);
    CHECK(static_cast<unsigned char>(bytes[23]) == 48);

    CHECK(dfm_vk_write_png((dir / "no" / "such" / "dir.png").string().c_str(), rgba.data(),
                           rgba.size(), 64, 48) == DFM_ERROR_IO);
    CHECK(dfm_vk_write_png(path.c_str(), rgba.data(), rgba.size() - 1, 64, 48) ==
          DFM_ERROR_INVALID_ARGUMENT);
    CHECK(scene.messages() == 0);
}

extern "C" size_t dfm_vk_c99_struct_size(int which);

TEST_CASE("render: the C99 view of dualform_vulkan.h agrees with C++") {
    CHECK(dfm_vk_c99_struct_size(0) == sizeof(dfm_vec3_input));
    CHECK(dfm_vk_c99_struct_size(1) == sizeof(dfm_vk_polyline));
    CHECK(dfm_vk_c99_struct_size(2) == sizeof(dfm_vk_frame));
    CHECK(dfm_vk_c99_struct_size(3) == sizeof(dfm_vk_renderer_desc));
    CHECK(dfm_vk_c99_struct_size(4) == sizeof(dfm_vk_host_desc));
}
