#pragma once

#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

namespace dfm::deform {

// The 3×3 Procrustes fit of ARAP's local step: the rotation R that maximises
// tr(Rᵀ A) for a covariance A = Σ w e_new e_restᵀ, i.e. that best maps the
// rest vectors onto the new ones. Found by Newton's method on the rotations
// from a warm start (one step is enough when the rotation changed little
// since the last fit), with the step of Müller et al. ("A robust method to extract the
// rotational part of deformations", 2016) where Newton's model is not
// concave; never a reflection, no SVD, no trigonometry. `q` is the warm start
// on entry and the fit on exit, after at most `steps` steps; the fit is
// never worse than the start.
struct RotationFit {
    glm::dmat3 rotation;  // of q
    double alignment;     // tr(Rᵀ A), which the fit maximises
};
RotationFit fit_rotation(const glm::dmat3& covariance, glm::dquat& q, int steps);

}  // namespace dfm::deform
