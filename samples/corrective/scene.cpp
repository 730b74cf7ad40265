#include "scene.hpp"

#include <algorithm>
#include <cmath>

namespace scene {

namespace {

constexpr double pi = 3.14159265358979323846;

}  // namespace

// The weight follows how far linear blend skinning pulls the middle of the
// elbow in towards the joint, 1 - cos(angle / 2) of its radius, rather than
// the angle itself: half way to the edited bend the elbow has lost about a
// quarter of what it lost there, and half of the corrective would overshoot.
double driver_weight(double degrees, double edited_degrees) {
    const double collapse = 1.0 - std::cos(0.5 * degrees * pi / 180.0);
    const double edited_collapse = 1.0 - std::cos(0.5 * edited_degrees * pi / 180.0);
    return std::clamp(collapse / edited_collapse, 0.0, 1.0);
}

Scene::Scene(const arm::Arm& arm) : n(arm.vertex_count()) {
    plain.resize(3 * n);
    corrected.resize(3 * n);
    positions.resize(6 * n);
    indices = arm.indices;
    for (std::uint32_t corner : arm.indices) {
        indices.push_back(corner + static_cast<std::uint32_t>(n));
    }
}

void Scene::pose(const arm::Arm& arm, const corrective::Corrective& fix, double degrees) {
    const auto joints = arm::joint_matrices(arm, degrees);
    arm::skin(arm, joints, fix.delta, 0.0, plain.data());
    arm::skin(arm, joints, fix.delta, driver_weight(degrees, fix.degrees), corrected.data());
    for (std::size_t i = 0; i < 3 * n; ++i) {
        positions[i] = plain[i];
        positions[3 * n + i] = corrected[i] + (i % 3 == 0 ? gap : 0.0);
    }
}

dfm_camera front_camera(const std::vector<double>& positions, int width, int height) {
    double low[3] = {INFINITY, INFINITY, INFINITY}, high[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (std::size_t i = 0; i < positions.size(); ++i) {
        low[i % 3] = std::min(low[i % 3], positions[i]);
        high[i % 3] = std::max(high[i % 3], positions[i]);
    }
    constexpr double fov_y = 30.0, margin = 1.08;
    const double half_height =
        0.5 * std::max(high[1] - low[1], (high[0] - low[0]) * height / width);
    dfm_camera camera = {};
    for (int c = 0; c < 3; ++c) camera.target[c] = camera.eye[c] = 0.5 * (low[c] + high[c]);
    camera.eye[2] = high[2] + margin * half_height / std::tan(0.5 * fov_y * pi / 180.0);
    camera.up[1] = 1.0;
    camera.fov_y_degrees = fov_y;
    camera.width = static_cast<std::uint32_t>(width);
    camera.height = static_cast<std::uint32_t>(height);
    return camera;
}

}  // namespace scene
