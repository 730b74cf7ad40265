#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec2.hpp>

#include "dualform/dualform_vulkan.h"
#include "mesh/mesh.hpp"
#include "pick/camera.hpp"

// Helpers for the renderer's tests: a headless renderer fed from an engine
// mesh, pictures as RGBA8 vectors, and masks of where parts of a mesh project.
namespace dfm::test {

// A pixel of the default background (dfm_vk_frame.background all zero).
bool is_background(std::span<const std::uint8_t> rgba, std::size_t pixel);
// Strongly red: a ROI vertex's colour under any lighting.
bool is_red(std::span<const std::uint8_t> rgba, std::size_t pixel);
bool is_green(std::span<const std::uint8_t> rgba, std::size_t pixel);

std::size_t count_pixels(std::span<const std::uint8_t> rgba,
                         bool (*test)(std::span<const std::uint8_t>, std::size_t));

dfm_vec3_input positions_of(const mesh::Mesh& mesh);
dfm_vec3_input positions_of(std::span<const glm::dvec3> positions);

dfm_camera to_c_camera(const pick::Camera& camera);
pick::Camera to_pick_camera(const dfm_camera& camera);

// A headless renderer holding one mesh; fails the test case when anything
// fails. Tracks validation messages: tests end with CHECK(messages() == 0).
class HeadlessScene {
public:
    explicit HeadlessScene(const mesh::Mesh& mesh, std::uint32_t max_samples = 0);
    HeadlessScene(const HeadlessScene&) = delete;
    HeadlessScene& operator=(const HeadlessScene&) = delete;
    ~HeadlessScene();

    dfm_vk_renderer* renderer() const { return renderer_; }
    std::vector<std::uint8_t> render(const dfm_camera& camera, std::uint32_t flags = 0) const;
    std::uint64_t messages() const;

private:
    dfm_vk_renderer* renderer_ = nullptr;
};

// Pixels (width × height, row-major) covered by the projected bounding boxes
// of the triangles with a vertex in `selected`, grown by `margin` pixels:
// everywhere those triangles can show.
std::vector<std::uint8_t> projected_mask(const mesh::Mesh& mesh,
                                         std::span<const glm::dvec3> positions,
                                         std::span<const std::uint8_t> selected,
                                         const pick::Camera& camera, int margin);

}  // namespace dfm::test
