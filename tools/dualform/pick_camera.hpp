#pragma once

#include "dualform/dualform.h"
#include "pick/camera.hpp"

namespace dfm::cli {

// The engine's form of the camera (the same fields).
pick::Camera to_pick_camera(const dfm_camera& camera);

}  // namespace dfm::cli
