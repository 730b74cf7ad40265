#pragma once

#include <string_view>

#include "core/status.hpp"
#include "dualform/scenario.hpp"
#include "pick/camera.hpp"

namespace dfm::cli {

// The engine's form of the camera (the same fields).
pick::Camera to_pick_camera(const dfm_camera& camera);

// A --camera argument: CAMERA JSON written inline when its first non-blank
// character is '{', otherwise the path of a file holding it.
Status read_camera_argument(std::string_view argument, dfm_camera& out);

}  // namespace dfm::cli
