#pragma once

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

namespace dfm::deform {

struct RotationFit {
    glm::dmat3 rotation;  // of q
    double alignment;     // tr(Rᵀ A), which the fit maximises
};

namespace rotation_fit_detail {

inline double alignment(const glm::dmat3& r, const glm::dmat3& a) {
    return glm::dot(r[0], a[0]) + glm::dot(r[1], a[1]) + glm::dot(r[2], a[2]);
}

// Solves k ω = τ for the symmetric k (its upper triangle k00 k01 k02 k11 k12
// k22) by its adjugate, when k is positive definite (its leading minors
// above `tiny`); returns false otherwise.
inline bool solve_positive_definite(double k00, double k01, double k02, double k11, double k12,
                                    double k22, const glm::dvec3& tau, double tiny,
                                    glm::dvec3& omega) {
    const double c22 = k00 * k11 - k01 * k01;
    if (!(k00 > tiny) || !(c22 > tiny * tiny)) return false;
    const double c00 = k11 * k22 - k12 * k12;
    const double c01 = k02 * k12 - k01 * k22;
    const double c02 = k01 * k12 - k02 * k11;
    const double det = k00 * c00 + k01 * c01 + k02 * c02;
    if (!(det > tiny * tiny * tiny)) return false;
    const double c11 = k00 * k22 - k02 * k02;
    const double c12 = k01 * k02 - k00 * k12;
    omega =
        glm::dvec3(c00 * tau.x + c01 * tau.y + c02 * tau.z, c01 * tau.x + c11 * tau.y + c12 * tau.z,
                   c02 * tau.x + c12 * tau.y + c22 * tau.z) /
        det;
    return true;
}

}  // namespace rotation_fit_detail

// The 3×3 Procrustes fit of ARAP's local step: the rotation R that maximises
// tr(Rᵀ A) for a covariance A = Σ w e_new e_restᵀ, i.e. that best maps the
// rest vectors onto the new ones. Found by Newton's method on the rotations
// from a warm start (one step is enough when the rotation changed little
// since the last fit), with the step of Müller et al. ("A robust method to extract the
// rotational part of deformations", 2016) where Newton's model is not
// concave; never a reflection, no SVD, no trigonometry. `q` is the warm start
// on entry and the fit on exit, after at most `steps` steps; the fit is
// never worse than the start.
// The local step runs four of these at once (rotation_fit_lanes.hpp, the
// same bits lane by lane); this one fits the handles' rigid alignment and is
// that version's reference.
[[gnu::always_inline]] inline RotationFit fit_rotation(const glm::dmat3& a, glm::dquat& q,
                                                       int max_steps) {
    using rotation_fit_detail::alignment;
    using rotation_fit_detail::solve_positive_definite;
    constexpr double smallest_turn = 1e-9;  // radians
    glm::dmat3 r = glm::mat3_cast(q);
    const double scale = std::sqrt(alignment(a, a));
    if (!(scale > 0.0) || !std::isfinite(scale)) return {r, alignment(r, a)};
    const glm::dquat start = q;
    const double start_alignment = alignment(r, a);
    double t = start_alignment;
    for (int step = 0; step < max_steps; ++step) {
        // f(ω) = tr(Aᵀ exp([ω]) R) ≈ t + ω·τ + ½ ωᵀ (sym(A Rᵀ) − t I) ω.
        const glm::dvec3 torque =
            glm::cross(r[0], a[0]) + glm::cross(r[1], a[1]) + glm::cross(r[2], a[2]);
        const glm::dmat3 m = a * glm::transpose(r);  // sym(m) = sym(A Rᵀ)
        glm::dvec3 omega;
        if (!solve_positive_definite(
                t - m[0][0], -0.5 * (m[0][1] + m[1][0]), -0.5 * (m[0][2] + m[2][0]), t - m[1][1],
                -0.5 * (m[1][2] + m[2][1]), t - m[2][2], torque, 1e-9 * scale, omega)) {
            omega = torque / (std::abs(t) + 1e-12 * scale);
        }
        const double turn = glm::length(omega);
        if (!(turn > smallest_turn) || !std::isfinite(turn)) break;
        // The normalised (1, ω/2) turns about ω by 2 atan(|ω|/2): Newton's
        // step to second order, and a shorter step in the same direction far
        // from the fit.
        q = glm::normalize(glm::dquat(1.0, 0.5 * omega.x, 0.5 * omega.y, 0.5 * omega.z) * q);
        r = glm::mat3_cast(q);
        t = alignment(r, a);
    }
    if (!(t >= start_alignment)) {
        q = start;
        return {glm::mat3_cast(start), start_alignment};
    }
    return {r, t};
}

}  // namespace dfm::deform
