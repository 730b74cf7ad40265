#pragma once

#include "dualform/dualform.h"
#include "pick/camera.hpp"

// dfm_camera is the engine's pick::Camera at the C boundary: the same fields,
// the same conventions. Inline, so libdualform and libdualform_vulkan copy
// one camera the same way.
namespace dfm::sdk {

inline pick::Camera to_camera(const dfm_camera& c) {
    pick::Camera camera;
    camera.eye = {c.eye[0], c.eye[1], c.eye[2]};
    camera.target = {c.target[0], c.target[1], c.target[2]};
    camera.up = {c.up[0], c.up[1], c.up[2]};
    camera.fov_y_degrees = c.fov_y_degrees;
    camera.width = c.width;
    camera.height = c.height;
    return camera;
}

inline dfm_camera to_c_camera(const pick::Camera& c) {
    dfm_camera camera = {};
    for (int k = 0; k < 3; ++k) {
        camera.eye[k] = c.eye[k];
        camera.target[k] = c.target[k];
        camera.up[k] = c.up[k];
    }
    camera.fov_y_degrees = c.fov_y_degrees;
    camera.width = c.width;
    camera.height = c.height;
    return camera;
}

}  // namespace dfm::sdk
