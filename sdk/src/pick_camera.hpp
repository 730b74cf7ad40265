#pragma once

#include <functional>

#include "camera_convert.hpp"
#include "core/status.hpp"
#include "objects.hpp"

namespace dfm::sdk {

// Runs `use` with the mesh's Embree scene for its current rest pose, built or
// refit first as needed, under the mesh's lock.
Status with_scene(MeshState& state, const std::function<Status(const pick::EmbreeScene&)>& use);

}  // namespace dfm::sdk
