#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "core/simd.hpp"
#include "deform/rotation_fit.hpp"
#include "deform/rotation_fit_lanes.hpp"
#include "solver/test_matrices.hpp"

using namespace dfm;

namespace {

constexpr std::size_t width = deform::fit_lanes::width;

struct Case {
    glm::dmat3 covariance;
    glm::dquat start;
};

glm::dquat random_rotation(test::Random& random, double spread) {
    const glm::dvec3 axis(random.uniform(-1.0, 1.0), random.uniform(-1.0, 1.0),
                          random.uniform(-1.0, 1.0));
    const double length = glm::length(axis);
    if (!(length > 0.0)) return glm::dquat(1.0, 0.0, 0.0, 0.0);
    return glm::angleAxis(random.uniform(-spread, spread), axis / length);
}

// Covariances of every kind the fit meets: near its warm start, far from
// it (a new target), reflections, rank-deficient, zero and not finite.
std::vector<Case> cases() {
    test::Random random(17);
    std::vector<Case> out;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (int i = 0; i < 400; ++i) {
        const glm::dquat truth = random_rotation(random, 3.1);
        glm::dmat3 a(0.0);
        const int points = 2 + static_cast<int>(random.below(6));
        for (int p = 0; p < points; ++p) {
            const glm::dvec3 rest(random.uniform(-1.0, 1.0), random.uniform(-1.0, 1.0),
                                  random.uniform(-1.0, 1.0));
            const glm::dvec3 noise(random.uniform(-0.1, 0.1), random.uniform(-0.1, 0.1),
                                   random.uniform(-0.1, 0.1));
            a += glm::outerProduct(glm::mat3_cast(truth) * rest + noise, rest);
        }
        switch (i % 8) {
            case 5: a[2] = -a[2]; break;  // a reflection
            case 6: a[1] = a[0]; break;   // rank deficient
            case 7: a = glm::dmat3(0.0); break;
            default: break;
        }
        if (i == 13) a[1][2] = nan;
        if (i == 21) a[0][0] = std::numeric_limits<double>::infinity();
        // Warm starts near the answer (a drag's next fit) and anywhere.
        const glm::dquat start =
            i % 3 == 0 ? random_rotation(random, 3.1) : random_rotation(random, 0.05) * truth;
        out.push_back({a, glm::normalize(start)});
    }
    return out;
}

bool same_bits(double x, double y) {
    return std::bit_cast<std::uint64_t>(x) == std::bit_cast<std::uint64_t>(y);
}

using FitFunction = void (*)(const deform::fit_lanes::Mat3&, deform::fit_lanes::Quat&, int,
                             deform::fit_lanes::Mat3&, deform::fit_lanes::Quad&);

void fit_plain(const deform::fit_lanes::Mat3& a, deform::fit_lanes::Quat& q, int steps,
               deform::fit_lanes::Mat3& r, deform::fit_lanes::Quad& alignment) {
    deform::fit_rotations(a, q, steps, r, alignment);
}

#if DFM_X86_DISPATCH
DFM_TARGET_AVX2 void fit_avx2(const deform::fit_lanes::Mat3& a, deform::fit_lanes::Quat& q,
                              int steps, deform::fit_lanes::Mat3& r,
                              deform::fit_lanes::Quad& alignment) {
    deform::fit_rotations(a, q, steps, r, alignment);
}

DFM_TARGET_AVX512 void fit_avx512(const deform::fit_lanes::Mat3& a, deform::fit_lanes::Quat& q,
                                  int steps, deform::fit_lanes::Mat3& r,
                                  deform::fit_lanes::Quad& alignment) {
    deform::fit_rotations(a, q, steps, r, alignment);
}
#endif

void check_against_one_at_a_time(FitFunction fit) {
    const std::vector<Case> all = cases();
    for (const int steps : {1, 2, 32}) {
        CAPTURE(steps);
        for (std::size_t first = 0; first + width <= all.size(); first += width) {
            deform::fit_lanes::Mat3 a;
            deform::fit_lanes::Quat q;
            for (std::size_t lane = 0; lane < width; ++lane) {
                const Case& c = all[first + lane];
                for (int col = 0; col < 3; ++col)
                    for (int row = 0; row < 3; ++row) a.m[col][row][lane] = c.covariance[col][row];
                q.w[lane] = c.start.w;
                q.x[lane] = c.start.x;
                q.y[lane] = c.start.y;
                q.z[lane] = c.start.z;
            }
            deform::fit_lanes::Mat3 rotation;
            deform::fit_lanes::Quad alignment;
            fit(a, q, steps, rotation, alignment);
            for (std::size_t lane = 0; lane < width; ++lane) {
                CAPTURE(first + lane);
                glm::dquat expected_q = all[first + lane].start;
                const deform::RotationFit expected =
                    deform::fit_rotation(all[first + lane].covariance, expected_q, steps);
                CHECK(same_bits(q.w[lane], expected_q.w));
                CHECK(same_bits(q.x[lane], expected_q.x));
                CHECK(same_bits(q.y[lane], expected_q.y));
                CHECK(same_bits(q.z[lane], expected_q.z));
                CHECK(same_bits(alignment[lane], expected.alignment));
                for (int col = 0; col < 3; ++col)
                    for (int row = 0; row < 3; ++row)
                        CHECK(same_bits(rotation.m[col][row][lane], expected.rotation[col][row]));
            }
        }
    }
}

}  // namespace

TEST_CASE("rotation fit: four lanes give each lane the one-at-a-time fit's bits") {
    check_against_one_at_a_time(fit_plain);
#if DFM_X86_DISPATCH
    if (simd::available(simd::Set::avx2)) check_against_one_at_a_time(fit_avx2);
    if (simd::available(simd::Set::avx512)) check_against_one_at_a_time(fit_avx512);
#endif
}

TEST_CASE("rotation fit: a fit from far away turns the start onto the covariance's rotation") {
    // The lanes must do real work, not only copy their starts: a clean
    // covariance of a known rotation, from the identity.
    test::Random random(5);
    deform::fit_lanes::Mat3 a;
    deform::fit_lanes::Quat q;
    std::vector<glm::dquat> truths;
    for (std::size_t lane = 0; lane < width; ++lane) {
        const glm::dquat truth = random_rotation(random, 2.5);
        truths.push_back(truth);
        const glm::dmat3 m = glm::mat3_cast(truth);
        for (int col = 0; col < 3; ++col)
            for (int row = 0; row < 3; ++row) a.m[col][row][lane] = m[col][row];
        q.w[lane] = 1.0;
        q.x[lane] = q.y[lane] = q.z[lane] = 0.0;
    }
    deform::fit_lanes::Mat3 rotation;
    deform::fit_lanes::Quad alignment;
    deform::fit_rotations(a, q, 64, rotation, alignment);
    for (std::size_t lane = 0; lane < width; ++lane) {
        const glm::dmat3 expected = glm::mat3_cast(truths[lane]);
        for (int col = 0; col < 3; ++col)
            for (int row = 0; row < 3; ++row)
                CHECK(rotation.m[col][row][lane] ==
                      doctest::Approx(expected[col][row]).epsilon(1e-9));
        CHECK(alignment[lane] == doctest::Approx(3.0).epsilon(1e-12));
    }
}
