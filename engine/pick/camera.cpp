#include "pick/camera.hpp"

#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

namespace dfm::pick {

namespace {

bool finite(glm::dvec3 v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// The camera's orthonormal frame and the half extents of the image plane at
// unit distance along `forward`.
struct Frame {
    glm::dvec3 forward, right, up;
    double half_height = 0.0;
    double half_width = 0.0;
};

Frame frame_of(const Camera& c) {
    Frame f;
    f.forward = glm::normalize(c.target - c.eye);
    f.right = glm::normalize(glm::cross(f.forward, c.up));
    f.up = glm::cross(f.right, f.forward);
    f.half_height = std::tan(c.fov_y_degrees * std::numbers::pi / 360.0);
    f.half_width = f.half_height * static_cast<double>(c.width) / static_cast<double>(c.height);
    return f;
}

}  // namespace

Status check_camera(const Camera& c) {
    if (!finite(c.eye) || !finite(c.target) || !finite(c.up)) {
        return Status(Errc::invalid_argument, "camera: eye, target and up must be finite");
    }
    const glm::dvec3 view = c.target - c.eye;
    if (!(glm::length(view) > 0.0)) {
        return Status(Errc::invalid_argument, "camera: target must differ from eye");
    }
    const glm::dvec3 side = glm::cross(glm::normalize(view), c.up);
    if (!(glm::length(side) > 1e-12 * glm::length(c.up))) {
        return Status(Errc::invalid_argument,
                      "camera: up must be non-zero and not parallel to the view direction");
    }
    if (!(c.fov_y_degrees > 0.0 && c.fov_y_degrees < 180.0)) {
        return Status(Errc::invalid_argument,
                      "camera: fov_y_degrees must lie between 0 and 180, both excluded");
    }
    if (c.width == 0 || c.height == 0) {
        return Status(Errc::invalid_argument, "camera: width and height must be positive");
    }
    return Status::ok();
}

Ray pixel_ray(const Camera& camera, glm::dvec2 pixel) {
    const Frame f = frame_of(camera);
    const double sx = (2.0 * pixel.x / camera.width - 1.0) * f.half_width;
    const double sy = (1.0 - 2.0 * pixel.y / camera.height) * f.half_height;
    return Ray{camera.eye, glm::normalize(f.forward + sx * f.right + sy * f.up)};
}

std::optional<glm::dvec2> project(const Camera& camera, glm::dvec3 point) {
    const Frame f = frame_of(camera);
    const glm::dvec3 d = point - camera.eye;
    const double depth = glm::dot(d, f.forward);
    if (!(depth > 0.0)) return std::nullopt;
    const double sx = glm::dot(d, f.right) / depth / f.half_width;
    const double sy = glm::dot(d, f.up) / depth / f.half_height;
    return glm::dvec2((sx + 1.0) * 0.5 * camera.width, (1.0 - sy) * 0.5 * camera.height);
}

}  // namespace dfm::pick
