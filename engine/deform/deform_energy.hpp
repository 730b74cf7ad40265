#pragma once

#include <cstdint>
#include <span>

#include <glm/vec3.hpp>

#include "deform/normal_system.hpp"

// The energy that the default method decreases (docs/method.md):
//   E = Σ_r |A_r p − t_r|² + w² Σ_h |p_h − u_h|²,
// the least-squares objective of the global step for the row targets t of
// the fitted rotations (its ε term, which vanishes at the fixed point, left
// out). The local and the global step each lower it. The rows' share comes
// with the rotation fit (RotationFrames::fit_and_add); this is the rest.
namespace dfm::deform {

// Writes ε x + w² u into rhs (3 interleaved columns, over the unknowns `x`),
// the start of the right-hand side that the rows then add to, and returns
// the soft handles' share of E.
double write_handle_terms(std::span<const double> x, std::span<const std::uint32_t> soft_handles,
                          std::span<const glm::dvec3> handle_targets, double handle_weight,
                          double epsilon, std::span<double> rhs);

}  // namespace dfm::deform
