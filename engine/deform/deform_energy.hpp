#pragma once

#include <cstdint>
#include <span>

#include <glm/vec3.hpp>

#include "deform/normal_system.hpp"

namespace dfm::deform {

// What the global step needs and what the default method decreases, in one
// pass over the rows. Writes rhs = Aᵀ (t − A_fixed p_fixed) + w² u + ε x (3
// interleaved columns) and returns the energy of `positions` for the row
// targets `targets`:
//   E = Σ_r |A_r p − t_r|² + w² Σ_h |p_h − u_h|²,
// the least-squares objective the linear solve minimises (its ε term, which
// vanishes at the fixed point, left out). With the targets of fitted
// rotations it is the energy that the local and the global step each lower.
double right_hand_side_and_energy(const SystemRows& rows, std::span<const glm::dvec3> targets,
                                  std::span<const glm::dvec3> positions, const UnknownMap& unknowns,
                                  std::span<const std::uint32_t> soft_handles,
                                  std::span<const glm::dvec3> handle_targets, double handle_weight,
                                  double epsilon, std::span<double> rhs);

}  // namespace dfm::deform
