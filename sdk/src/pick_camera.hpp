#pragma once

#include <functional>

#include "core/status.hpp"
#include "dualform/dualform.h"
#include "objects.hpp"
#include "pick/camera.hpp"

namespace dfm::sdk {

pick::Camera to_camera(const dfm_camera& camera);

// Runs `use` with the mesh's Embree scene for its current rest pose, built or
// refit first as needed, under the mesh's lock.
Status with_scene(MeshState& state, const std::function<Status(const pick::EmbreeScene&)>& use);

}  // namespace dfm::sdk
