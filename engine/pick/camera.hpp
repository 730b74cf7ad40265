#pragma once

#include <cstdint>
#include <optional>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "core/status.hpp"

namespace dfm::pick {

// A pinhole camera as docs/scenarios.md defines it: at `eye`, looking at
// `target`, `up` giving the image's up direction, `fov_y_degrees` the full
// vertical opening, an image of width × height pixels. The one camera of
// the project: the C API's dfm_camera has the same fields and conventions,
// and, like a zero-initialised dfm_camera, a default-made one has no view
// yet (check_camera refuses it) until every field is given.
struct Camera {
    glm::dvec3 eye{0.0};
    glm::dvec3 target{0.0};
    glm::dvec3 up{0.0};
    double fov_y_degrees = 0.0;
    std::uint32_t width = 0;
    std::uint32_t height = 0;
};

// A ray from `origin` along the unit vector `direction`.
struct Ray {
    glm::dvec3 origin{0.0};
    glm::dvec3 direction{0.0, 0.0, -1.0};
};

// Fails, naming the field, unless the camera can make rays: finite vectors,
// target != eye, up not parallel to the view, 0 < fov < 180, a non-empty
// image.
Status check_camera(const Camera& camera);

// The ray through a pixel. Pixels are continuous: (0, 0) is the image's
// top-left corner, (width, height) its bottom-right, x right, y down;
// (width/2, height/2) looks straight at the target. Assumes check_camera
// passed.
Ray pixel_ray(const Camera& camera, glm::dvec2 pixel);

// The pixel at which `point` appears (pixel_ray's inverse), or nothing when
// the point is not in front of the eye. The pixel may lie outside the image.
std::optional<glm::dvec2> project(const Camera& camera, glm::dvec3 point);

}  // namespace dfm::pick
