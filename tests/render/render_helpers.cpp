#include "render/render_helpers.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>

namespace dfm::test {

namespace {

// The default background, 0.16 0.18 0.22 in 8 bits.
constexpr std::uint8_t background_rgb[3] = {41, 46, 56};

}  // namespace

bool is_background(std::span<const std::uint8_t> rgba, std::size_t pixel) {
    const std::uint8_t* p = &rgba[pixel * 4];
    return p[0] == background_rgb[0] && p[1] == background_rgb[1] && p[2] == background_rgb[2];
}

bool is_red(std::span<const std::uint8_t> rgba, std::size_t pixel) {
    const std::uint8_t* p = &rgba[pixel * 4];
    return p[0] >= 60 && p[0] > 2 * p[1] && p[0] > 2 * p[2];
}

bool is_green(std::span<const std::uint8_t> rgba, std::size_t pixel) {
    const std::uint8_t* p = &rgba[pixel * 4];
    return p[1] >= 60 && p[1] > 2 * p[0] && p[1] > 2 * p[2];
}

std::size_t count_pixels(std::span<const std::uint8_t> rgba,
                         bool (*test)(std::span<const std::uint8_t>, std::size_t)) {
    std::size_t n = 0;
    for (std::size_t i = 0; i < rgba.size() / 4; ++i) n += test(rgba, i) ? 1 : 0;
    return n;
}

dfm_vec3_input positions_of(std::span<const glm::dvec3> positions) {
    dfm_vec3_input p = {};
    p.data = positions.data();
    p.count = positions.size();
    p.stride = sizeof(glm::dvec3);
    p.type = DFM_SCALAR_FLOAT64;
    return p;
}

dfm_vec3_input positions_of(const mesh::Mesh& mesh) {
    return positions_of(mesh.positions);
}

dfm_camera to_c_camera(const pick::Camera& c) {
    dfm_camera out = {};
    for (int k = 0; k < 3; ++k) {
        out.eye[k] = c.eye[k];
        out.target[k] = c.target[k];
        out.up[k] = c.up[k];
    }
    out.fov_y_degrees = c.fov_y_degrees;
    out.width = c.width;
    out.height = c.height;
    return out;
}

pick::Camera to_pick_camera(const dfm_camera& c) {
    return pick::Camera{{c.eye[0], c.eye[1], c.eye[2]},
                        {c.target[0], c.target[1], c.target[2]},
                        {c.up[0], c.up[1], c.up[2]},
                        c.fov_y_degrees,
                        c.width,
                        c.height};
}

HeadlessScene::HeadlessScene(const mesh::Mesh& mesh, std::uint32_t max_samples) {
    dfm_vk_renderer_desc desc = {};
    desc.max_samples = max_samples;
    desc.validation = true;
    REQUIRE_MESSAGE(dfm_vk_renderer_create_headless(&desc, &renderer_) == DFM_OK,
                    dfm_last_error_message());
    const dfm_vec3_input positions = positions_of(mesh);
    REQUIRE_MESSAGE(dfm_vk_renderer_set_mesh(renderer_, &positions, mesh.triangles.front().data(),
                                             mesh.triangles.size()) == DFM_OK,
                    dfm_last_error_message());
}

HeadlessScene::~HeadlessScene() {
    dfm_vk_renderer_destroy(renderer_);
}

std::vector<std::uint8_t> HeadlessScene::render(const dfm_camera& camera,
                                                std::uint32_t flags) const {
    dfm_vk_frame frame = {};
    frame.camera = camera;
    frame.flags = flags;
    std::vector<std::uint8_t> rgba(std::size_t{camera.width} * camera.height * 4);
    REQUIRE_MESSAGE(
        dfm_vk_renderer_render_offscreen(renderer_, &frame, rgba.data(), rgba.size()) == DFM_OK,
        dfm_last_error_message());
    return rgba;
}

std::uint64_t HeadlessScene::messages() const {
    std::uint64_t n = 0;
    REQUIRE(dfm_vk_renderer_validation_message_count(renderer_, &n) == DFM_OK);
    return n;
}

std::vector<std::uint8_t> projected_mask(const mesh::Mesh& mesh,
                                         std::span<const glm::dvec3> positions,
                                         std::span<const std::uint8_t> selected,
                                         const pick::Camera& camera, int margin) {
    const int w = static_cast<int>(camera.width);
    const int h = static_cast<int>(camera.height);
    std::vector<std::uint8_t> mask(std::size_t(w) * h, 0);
    for (const mesh::Triangle& t : mesh.triangles) {
        if (!selected[t[0]] && !selected[t[1]] && !selected[t[2]]) continue;
        glm::dvec2 lo(1e300), hi(-1e300);
        bool visible = true;
        for (std::uint32_t v : t) {
            const auto pixel = pick::project(camera, positions[v]);
            if (!pixel) {
                visible = false;
                break;
            }
            lo = glm::min(lo, *pixel);
            hi = glm::max(hi, *pixel);
        }
        if (!visible) continue;
        const int x0 = std::max(0, static_cast<int>(std::floor(lo.x)) - margin);
        const int y0 = std::max(0, static_cast<int>(std::floor(lo.y)) - margin);
        const int x1 = std::min(w - 1, static_cast<int>(std::ceil(hi.x)) + margin);
        const int y1 = std::min(h - 1, static_cast<int>(std::ceil(hi.y)) + margin);
        for (int y = y0; y <= y1; ++y) {
            for (int x = x0; x <= x1; ++x) mask[std::size_t(y) * w + x] = 1;
        }
    }
    return mask;
}

}  // namespace dfm::test
