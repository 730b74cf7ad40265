#pragma once

#include <cstdint>
#include <span>

#include <glm/mat4x4.hpp>

#include "mesh/mesh.hpp"
#include "pick/camera.hpp"

namespace dfm::render {

// The clip-space transform that puts a world point on the pixel where
// pick::project puts it (continuous pixels, (0,0) top-left, y down, fov_y
// the full vertical opening), so a rendered pixel and a pick through the same
// camera agree. Near and far planes enclose `scene` (Vulkan depth 0..1).
// Assumes check_camera passed.
glm::mat4 clip_from_world(const pick::Camera& camera, const mesh::Bounds& scene);

// A camera that frames all of `points` in a width × height image with a
// small margin, aimed at their bounding box's centre from the front (+z), a
// little from the right and above, y up.
pick::Camera framing_camera(std::span<const glm::dvec3> points, std::uint32_t width,
                            std::uint32_t height);

}  // namespace dfm::render
