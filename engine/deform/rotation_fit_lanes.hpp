#pragma once

#include <cmath>
#include <cstdint>

#include "core/simd.hpp"
#include "deform/rotation_fit.hpp"

// fit_rotation (rotation_fit.hpp) for four covariances at once, one per
// lane of a four-double vector: every lane sees the operations of the
// one-at-a-time fit in the same order, so each lane's rotation, quaternion
// and alignment are the same bits as fit_rotation's for that lane. A lane
// that stops (converged, refused, or past its steps) keeps its values while
// the others go on. All inline, for the callers compiled for a wider
// instruction set.
// Helpers return vectors by value: always inlined, they never use the
// calling convention GCC warns about (-Wpsabi). GCC gives that warning at
// the end of the translation unit, so it is off for the includer's rest too.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace dfm::deform {

namespace fit_lanes {

using Quad = simd::Doubles4;
using Mask = std::int64_t __attribute__((vector_size(sizeof(Quad))));  // all ones where true

inline constexpr std::size_t width = simd::lanes<Quad>;

struct Quat {
    Quad w, x, y, z;
};

// Column-major as glm's: m[column][row].
struct Mat3 {
    Quad m[3][3];
};

[[gnu::always_inline]] inline Quad splat(double v) {
    return Quad{v, v, v, v};
}

[[gnu::always_inline]] inline Quad select(const Mask& m, const Quad& yes, const Quad& no) {
    return m ? yes : no;
}

// Lane by lane, which the compiler turns into one vector square root where
// the includer is compiled with -fno-math-errno (rigidity_rows.cpp and its
// test are). Otherwise each lane takes a scalar root and a check for a
// negative argument (errno), and the fit is slower. Either way each
// lane's root is correctly rounded: the same bits.
[[gnu::always_inline]] inline Quad sqrt(const Quad& v) {
    Quad out;
    for (std::size_t l = 0; l < width; ++l) out[l] = std::sqrt(v[l]);
    return out;
}

[[gnu::always_inline]] inline Mask is_finite(const Quad& v) {
    return (v - v) == splat(0.0);
}

[[gnu::always_inline]] inline bool any(const Mask& m) {
    return (m[0] | m[1] | m[2] | m[3]) != 0;
}

// glm::mat3_cast.
[[gnu::always_inline]] inline void rotation_of(const Quat& q, Mat3& r) {
    const Quad qxx = q.x * q.x, qyy = q.y * q.y, qzz = q.z * q.z;
    const Quad qxz = q.x * q.z, qxy = q.x * q.y, qyz = q.y * q.z;
    const Quad qwx = q.w * q.x, qwy = q.w * q.y, qwz = q.w * q.z;
    const Quad one = splat(1.0), two = splat(2.0);
    r.m[0][0] = one - two * (qyy + qzz);
    r.m[0][1] = two * (qxy + qwz);
    r.m[0][2] = two * (qxz - qwy);
    r.m[1][0] = two * (qxy - qwz);
    r.m[1][1] = one - two * (qxx + qzz);
    r.m[1][2] = two * (qyz + qwx);
    r.m[2][0] = two * (qxz + qwy);
    r.m[2][1] = two * (qyz - qwx);
    r.m[2][2] = one - two * (qxx + qyy);
}

// rotation_fit_detail::alignment: Σ over columns of glm::dot, each
// (x + y) + z, the columns added in order.
[[gnu::always_inline]] inline Quad alignment(const Mat3& r, const Mat3& a) {
    Quad sum[3];
    for (int c = 0; c < 3; ++c)
        sum[c] = r.m[c][0] * a.m[c][0] + r.m[c][1] * a.m[c][1] + r.m[c][2] * a.m[c][2];
    return sum[0] + sum[1] + sum[2];
}

[[gnu::always_inline]] inline void select(const Mask& m, const Quat& yes, Quat& inout) {
    inout.w = select(m, yes.w, inout.w);
    inout.x = select(m, yes.x, inout.x);
    inout.y = select(m, yes.y, inout.y);
    inout.z = select(m, yes.z, inout.z);
}

[[gnu::always_inline]] inline void select(const Mask& m, const Mat3& yes, Mat3& inout) {
    for (int c = 0; c < 3; ++c)
        for (int i = 0; i < 3; ++i) inout.m[c][i] = select(m, yes.m[c][i], inout.m[c][i]);
}

}  // namespace fit_lanes

// The rotations of four covariances `a` from the warm starts `q` (each
// replaced by its fit), at most `max_steps` Newton steps each; `rotation`
// and `alignment` receive the fits as fit_rotation returns them.
[[gnu::always_inline]] inline void fit_rotations(const fit_lanes::Mat3& a, fit_lanes::Quat& q,
                                                 int max_steps, fit_lanes::Mat3& rotation,
                                                 fit_lanes::Quad& alignment) {
    using namespace fit_lanes;
    const Quad zero = splat(0.0);
    Mat3 r;
    rotation_of(q, r);
    const Quad scale = fit_lanes::sqrt(fit_lanes::alignment(a, a));
    // A lane without a usable covariance keeps its start, as fit_rotation's
    // early return does; its start alignment is what that return gives.
    Mask active = (scale > zero) & is_finite(scale);
    const Quat start = q;
    const Quad start_alignment = fit_lanes::alignment(r, a);
    Quad t = start_alignment;
    const Quad tiny = splat(1e-9) * scale;
    const Quad tiny2 = tiny * tiny;
    const Quad tiny3 = tiny2 * tiny;
    const Quad smallest_turn = splat(1e-9);
    for (int step = 0; step < max_steps && any(active); ++step) {
        // torque = Σ_c cross(r_c, a_c), the three added in order.
        Quad torque[3];
        for (int i = 0; i < 3; ++i) {
            const int j = (i + 1) % 3;
            const int k = (i + 2) % 3;
            Quad sum[3];
            for (int c = 0; c < 3; ++c) sum[c] = r.m[c][j] * a.m[c][k] - a.m[c][j] * r.m[c][k];
            torque[i] = sum[0] + sum[1] + sum[2];
        }
        // m = a rᵀ, glm's product of a and transpose(r): m[c][i] =
        // a[0][i] r[0][c] + a[1][i] r[1][c] + a[2][i] r[2][c].
        Quad m[3][3];
        for (int c = 0; c < 3; ++c)
            for (int i = 0; i < 3; ++i)
                m[c][i] = a.m[0][i] * r.m[0][c] + a.m[1][i] * r.m[1][c] + a.m[2][i] * r.m[2][c];
        const Quad half = splat(0.5);
        const Quad k00 = t - m[0][0];
        const Quad k01 = -half * (m[0][1] + m[1][0]);
        const Quad k02 = -half * (m[0][2] + m[2][0]);
        const Quad k11 = t - m[1][1];
        const Quad k12 = -half * (m[1][2] + m[2][1]);
        const Quad k22 = t - m[2][2];
        // rotation_fit_detail::solve_positive_definite, every lane.
        const Quad c22 = k00 * k11 - k01 * k01;
        const Quad c00 = k11 * k22 - k12 * k12;
        const Quad c01 = k02 * k12 - k01 * k22;
        const Quad c02 = k01 * k12 - k02 * k11;
        const Quad det = k00 * c00 + k01 * c01 + k02 * c02;
        const Quad c11 = k00 * k22 - k02 * k02;
        const Quad c12 = k01 * k02 - k00 * k12;
        const Mask definite = (k00 > tiny) & (c22 > tiny2) & (det > tiny3);
        const Quad newton[3] = {(c00 * torque[0] + c01 * torque[1] + c02 * torque[2]) / det,
                                (c01 * torque[0] + c11 * torque[1] + c12 * torque[2]) / det,
                                (c02 * torque[0] + c12 * torque[1] + c22 * torque[2]) / det};
        const Mask sign = (Mask)splat(-0.0);
        const Quad abs_t = (Quad)((Mask)t & ~sign);
        const Quad damping = abs_t + splat(1e-12) * scale;
        Quad omega[3];
        for (int i = 0; i < 3; ++i) omega[i] = select(definite, newton[i], torque[i] / damping);
        const Quad turn =
            fit_lanes::sqrt(omega[0] * omega[0] + omega[1] * omega[1] + omega[2] * omega[2]);
        active &= (turn > smallest_turn) & is_finite(turn);
        if (!any(active)) break;
        // glm: dquat(1, ω/2) * q, then normalize.
        const Quad pw = splat(1.0), px = half * omega[0], py = half * omega[1],
                   pz = half * omega[2];
        Quat turned;
        turned.w = pw * q.w - px * q.x - py * q.y - pz * q.z;
        turned.x = pw * q.x + px * q.w + py * q.z - pz * q.y;
        turned.y = pw * q.y + py * q.w + pz * q.x - px * q.z;
        turned.z = pw * q.z + pz * q.w + px * q.y - py * q.x;
        const Quad length = fit_lanes::sqrt((turned.w * turned.w + turned.x * turned.x) +
                                            (turned.y * turned.y + turned.z * turned.z));
        const Quad inverse = splat(1.0) / length;
        const Mask degenerate = length <= zero;
        Quat normalized;
        normalized.w = select(degenerate, splat(1.0), turned.w * inverse);
        normalized.x = select(degenerate, zero, turned.x * inverse);
        normalized.y = select(degenerate, zero, turned.y * inverse);
        normalized.z = select(degenerate, zero, turned.z * inverse);
        select(active, normalized, q);
        Mat3 turned_r;
        rotation_of(normalized, turned_r);
        select(active, turned_r, r);
        t = select(active, fit_lanes::alignment(turned_r, a), t);
    }
    const Mask worse = ~(t >= start_alignment);
    select(worse, start, q);
    Mat3 start_r;
    rotation_of(start, start_r);
    rotation = r;
    select(worse, start_r, rotation);
    alignment = select(worse, start_alignment, t);
}

}  // namespace dfm::deform
