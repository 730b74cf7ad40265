#pragma once

#include <cstdint>
#include <span>

#include <glm/mat4x4.hpp>

#include "core/status.hpp"
#include "mesh/skin.hpp"

namespace dfm::mesh {

// A host's skin from flat arrays: `influence_count` joints and weights per
// vertex, and one inverse bind matrix per joint. Checked: every joint index
// below the joint count, every weight finite and not negative, each
// vertex's weights summing above 0, every matrix finite, affine and
// invertible; the message names the vertex and slot, or the joint. Zero
// weights are dropped, a joint named twice by one vertex is summed, and each
// vertex's weights are normalised to sum 1. The joints have no nodes (the
// host poses them with their world matrices).
Status skin_from_arrays(std::size_t vertex_count, std::uint32_t influence_count,
                        std::span<const std::uint32_t> joints, std::span<const double> weights,
                        std::span<const glm::dmat4> inverse_bind, Skin& out);

}  // namespace dfm::mesh
