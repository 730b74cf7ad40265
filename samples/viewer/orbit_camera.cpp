#include "orbit_camera.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace viewer {

namespace {

constexpr double pi = 3.14159265358979323846;

Vec3 sub(const Vec3& a, const Vec3& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
double dot(const Vec3& a, const Vec3& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec3 scale(const Vec3& a, double s) {
    return {a[0] * s, a[1] * s, a[2] * s};
}
Vec3 normalize(const Vec3& a) {
    return scale(a, 1.0 / std::sqrt(dot(a, a)));
}

}  // namespace

void OrbitCamera::reset(const dfm_camera& start) {
    target_ = {start.target[0], start.target[1], start.target[2]};
    const Vec3 offset = sub({start.eye[0], start.eye[1], start.eye[2]}, target_);
    distance_ = std::sqrt(dot(offset, offset));
    yaw_ = std::atan2(offset[0], offset[2]);
    pitch_ = std::asin(std::clamp(offset[1] / distance_, -1.0, 1.0));
    fov_y_degrees_ = start.fov_y_degrees;
}

void OrbitCamera::set_viewport(int width, int height) {
    width_ = std::max(width, 1);
    height_ = std::max(height, 1);
}

void OrbitCamera::orbit(double dx, double dy) {
    yaw_ -= dx * 0.01;
    pitch_ = std::clamp(pitch_ + dy * 0.01, -1.5, 1.5);
}

void OrbitCamera::pan(double dx, double dy) {
    const Vec3 move = drag_in_view_plane(target_, -dx, -dy);
    for (int c = 0; c < 3; ++c) target_[c] += move[c];
}

void OrbitCamera::zoom(double steps) {
    distance_ *= std::pow(0.9, steps);
}

Vec3 OrbitCamera::forward() const {
    return {-std::cos(pitch_) * std::sin(yaw_), -std::sin(pitch_),
            -std::cos(pitch_) * std::cos(yaw_)};
}

void OrbitCamera::basis(Vec3& right, Vec3& up, Vec3& fwd) const {
    fwd = forward();
    right = normalize(cross(fwd, {0, 1, 0}));
    up = cross(right, fwd);
}

dfm_camera OrbitCamera::camera() const {
    dfm_camera c = {};
    const Vec3 eye = sub(target_, scale(forward(), distance_));
    for (int i = 0; i < 3; ++i) {
        c.eye[i] = eye[i];
        c.target[i] = target_[i];
    }
    c.up[1] = 1.0;
    c.fov_y_degrees = fov_y_degrees_;
    c.width = static_cast<std::uint32_t>(width_);
    c.height = static_cast<std::uint32_t>(height_);
    return c;
}

Vec3 OrbitCamera::drag_in_view_plane(const Vec3& at, double dx, double dy) const {
    Vec3 right, up, fwd;
    basis(right, up, fwd);
    const Vec3 eye = sub(target_, scale(fwd, distance_));
    const double depth = dot(sub(at, eye), fwd);
    const double world_per_pixel =
        2.0 * depth * std::tan(0.5 * fov_y_degrees_ * pi / 180.0) / height_;
    const Vec3 r = scale(right, dx * world_per_pixel);
    const Vec3 u = scale(up, -dy * world_per_pixel);
    return {r[0] + u[0], r[1] + u[1], r[2] + u[2]};
}

bool OrbitCamera::project(const Vec3& p, double& x, double& y) const {
    Vec3 right, up, fwd;
    basis(right, up, fwd);
    const Vec3 d = sub(p, sub(target_, scale(fwd, distance_)));
    const double z = dot(d, fwd);
    if (z <= 0.0) return false;
    const double focal = 0.5 * height_ / std::tan(0.5 * fov_y_degrees_ * pi / 180.0);
    x = 0.5 * width_ + focal * dot(d, right) / z;
    y = 0.5 * height_ - focal * dot(d, up) / z;
    return true;
}

}  // namespace viewer
