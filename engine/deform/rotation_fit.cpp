#include "deform/rotation_fit.hpp"

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

namespace dfm::deform {

namespace {

double alignment(const glm::dmat3& r, const glm::dmat3& a) {
    return glm::dot(r[0], a[0]) + glm::dot(r[1], a[1]) + glm::dot(r[2], a[2]);
}

// Whether the symmetric k is positive definite (its leading minors).
bool positive_definite(const glm::dmat3& k, double tiny) {
    return k[0][0] > tiny && k[0][0] * k[1][1] - k[0][1] * k[1][0] > tiny * tiny &&
           glm::determinant(k) > tiny * tiny * tiny;
}

}  // namespace

void fit_rotation(const glm::dmat3& a, glm::dquat& q, int max_steps) {
    constexpr double smallest_turn = 1e-9;  // radians
    const glm::dquat start = q;
    glm::dmat3 r = glm::mat3_cast(start);
    const double start_alignment = alignment(r, a);
    const double scale = std::sqrt(alignment(a, a));
    if (!(scale > 0.0) || !std::isfinite(scale)) return;
    for (int step = 0; step < max_steps; ++step) {
        // f(ω) = tr(Aᵀ exp([ω]) R) ≈ t + ω·τ + ½ ωᵀ (sym(A Rᵀ) − t I) ω.
        const glm::dvec3 torque =
            glm::cross(r[0], a[0]) + glm::cross(r[1], a[1]) + glm::cross(r[2], a[2]);
        const double t = alignment(r, a);
        const glm::dmat3 m = a * glm::transpose(r);
        const glm::dmat3 k = t * glm::dmat3(1.0) - 0.5 * (m + glm::transpose(m));
        const glm::dvec3 omega = positive_definite(k, 1e-9 * scale)
                                     ? glm::inverse(k) * torque
                                     : torque / (std::abs(t) + 1e-12 * scale);
        const double turn = glm::length(omega);
        if (!(turn > smallest_turn) || !std::isfinite(turn)) break;
        // The normalised (1, ω/2) turns about ω by 2 atan(|ω|/2): Newton's
        // step to second order, and a shorter step in the same direction far
        // from the fit.
        q = glm::normalize(glm::dquat(1.0, 0.5 * omega.x, 0.5 * omega.y, 0.5 * omega.z) * q);
        r = glm::mat3_cast(q);
    }
    if (!(alignment(r, a) >= start_alignment)) q = start;
}

}  // namespace dfm::deform
