#include "render/view_transform.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

namespace dfm::render {

glm::mat4 clip_from_world(const pick::Camera& camera, const mesh::Bounds& scene) {
    const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, camera.up));
    const glm::dvec3 up = glm::cross(right, forward);
    const double half_height = std::tan(camera.fov_y_degrees * std::numbers::pi / 360.0);
    const double half_width =
        half_height * static_cast<double>(camera.width) / static_cast<double>(camera.height);

    const glm::dvec3 center = scene.empty ? camera.target : 0.5 * (scene.min + scene.max);
    const double radius = std::max(scene.empty ? 1.0 : 0.5 * scene.diagonal(), 1e-9);
    const double center_depth = glm::dot(center - camera.eye, forward);
    const double far_plane = std::max(center_depth + 1.01 * radius, 2e-3 * radius);
    const double near_plane = std::max(center_depth - 1.01 * radius, 1e-3 * radius);
    const double a = far_plane / (far_plane - near_plane);
    const double b = -near_plane * a;

    // Rows of the transform: x along right, y along -up (Vulkan's y points
    // down, as pixel y does), z and w from the depth along forward.
    const glm::dvec3 rows[4] = {right / half_width, -up / half_height, a * forward, forward};
    const double offsets[4] = {
        -glm::dot(right, camera.eye) / half_width, glm::dot(up, camera.eye) / half_height,
        -a * glm::dot(forward, camera.eye) + b, -glm::dot(forward, camera.eye)};
    glm::mat4 m(0.0f);
    for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 3; ++c) m[c][r] = static_cast<float>(rows[r][c]);
        m[3][r] = static_cast<float>(offsets[r]);
    }
    return m;
}

pick::Camera framing_camera(std::span<const glm::dvec3> points, std::uint32_t width,
                            std::uint32_t height) {
    pick::Camera camera;
    camera.width = width;
    camera.height = height;
    camera.fov_y_degrees = 40.0;
    camera.up = glm::dvec3(0.0, 1.0, 0.0);
    const mesh::Bounds bounds = mesh::compute_bounds(points);
    const glm::dvec3 center = bounds.empty ? glm::dvec3(0.0) : 0.5 * (bounds.min + bounds.max);
    const glm::dvec3 toward_eye = glm::normalize(glm::dvec3(0.35, 0.3, 1.0));
    const glm::dvec3 right = glm::normalize(glm::cross(-toward_eye, camera.up));
    const glm::dvec3 up = glm::cross(right, -toward_eye);
    const double tan_y = std::tan(camera.fov_y_degrees * std::numbers::pi / 360.0);
    const double tan_x = tan_y * width / std::max(height, 1u);
    // The nearest eye distance from the centre at which every point lies
    // inside the view: a point at height h above the view axis and depth z
    // towards the eye needs distance z + h / tan(half opening).
    double distance = 0.0;
    for (const glm::dvec3& p : points) {
        const glm::dvec3 d = p - center;
        const double z = glm::dot(d, toward_eye);
        distance = std::max({distance, z + std::abs(glm::dot(d, right)) / tan_x,
                             z + std::abs(glm::dot(d, up)) / tan_y});
    }
    const double size = bounds.empty ? 1.0 : std::max(bounds.diagonal(), 1e-9);
    distance = std::max(1.08 * distance, 0.5 * size);
    camera.target = center;
    camera.eye = center + distance * toward_eye;
    return camera;
}

}  // namespace dfm::render
