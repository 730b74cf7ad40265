#pragma once

#include <span>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/vec3.hpp>

#include "mesh/skin.hpp"

namespace dfm::mesh {

// A node's local transform as an animation sets it.
struct NodeTransform {
    glm::dvec3 translation{0.0};
    glm::dquat rotation{1.0, 0.0, 0.0, 0.0};
    glm::dvec3 scale{1.0};
};

// Samples every channel of `animation` at `time` (each channel clamped to
// its own keys, as glTF says) into the nodes' local transforms and the
// morph targets' weights (a weights channel sets the targets its node
// drives, column by column). LINEAR rotations are slerped along the shorter
// arc; CUBICSPLINE is the Hermite spline of glTF's appendix, rotations
// normalised after it.
void apply_animation(const Skin& skin, const Animation& animation, double time,
                     std::span<NodeTransform> local, std::span<double> morph_weights);

}  // namespace dfm::mesh
