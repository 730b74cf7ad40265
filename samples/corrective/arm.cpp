#include "arm.hpp"

#include <algorithm>
#include <cmath>

namespace arm {

namespace {

constexpr double pi = 3.14159265358979323846;

constexpr int segments = 48;    // vertices around each ring
constexpr int tube_rings = 96;  // rings from shoulder to wrist
constexpr int cap_rings = 8;    // each round end: cap_rings - 1 rings and a pole
constexpr double shoulder_radius = 0.2;
constexpr double wrist_radius = 0.14;
constexpr double blend_half_width = 0.2;  // the weights blend over elbow +- this

Matrix identity() {
    Matrix m = {};
    m[0] = m[5] = m[10] = m[15] = 1.0;
    return m;
}

Matrix translation(double x, double y, double z) {
    Matrix m = identity();
    m[12] = x, m[13] = y, m[14] = z;
    return m;
}

Matrix multiply(const Matrix& a, const Matrix& b) {
    Matrix m = {};
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
            for (int k = 0; k < 4; ++k) m[4 * c + r] += a[4 * k + r] * b[4 * c + k];
        }
    }
    return m;
}

// The tube's cross sections: centre x and radius of each ring, pole to pole.
struct Ring {
    double x, radius;
};

std::vector<Ring> rings(double length) {
    std::vector<Ring> out;
    for (int k = 1; k < cap_rings; ++k) {  // the shoulder's round end
        const double phi = 0.5 * pi * k / cap_rings;
        out.push_back({-shoulder_radius * std::cos(phi), shoulder_radius * std::sin(phi)});
    }
    for (int j = 0; j <= tube_rings; ++j) {
        const double s = static_cast<double>(j) / tube_rings;
        out.push_back({s * length, shoulder_radius + s * (wrist_radius - shoulder_radius)});
    }
    for (int k = cap_rings - 1; k >= 1; --k) {  // the hand's round end
        const double phi = 0.5 * pi * k / cap_rings;
        out.push_back({length + wrist_radius * std::cos(phi), wrist_radius * std::sin(phi)});
    }
    return out;
}

}  // namespace

Arm make_arm() {
    Arm a;
    const double length = a.upper_length + a.forearm_length;
    const std::vector<Ring> sections = rings(length);
    auto vertex = [&](double x, double y, double z) {
        a.positions.insert(a.positions.end(),
                           {static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)});
        // The elbow's share rises smoothly across the blend zone.
        const double t = std::clamp(
            (x - (a.upper_length - blend_half_width)) / (2.0 * blend_half_width), 0.0, 1.0);
        const float elbow = static_cast<float>(t * t * (3.0 - 2.0 * t));
        a.joints.insert(a.joints.end(), {0, 1});
        a.weights.insert(a.weights.end(), {1.0f - elbow, elbow});
    };
    vertex(-shoulder_radius, 0.0, 0.0);
    for (const Ring& ring : sections) {
        for (int i = 0; i < segments; ++i) {
            const double angle = 2.0 * pi * i / segments;
            vertex(ring.x, ring.radius * std::cos(angle), ring.radius * std::sin(angle));
        }
    }
    vertex(length + wrist_radius, 0.0, 0.0);

    const auto last_pole = static_cast<std::uint32_t>(a.vertex_count() - 1);
    auto at = [](std::size_t ring, int i) {
        return static_cast<std::uint32_t>(1 + ring * segments + i % segments);
    };
    // Counter-clockwise seen from outside: normals point out.
    for (int i = 0; i < segments; ++i)
        a.indices.insert(a.indices.end(), {0, at(0, i + 1), at(0, i)});
    for (std::size_t r = 0; r + 1 < sections.size(); ++r) {
        for (int i = 0; i < segments; ++i) {
            a.indices.insert(a.indices.end(), {at(r, i), at(r, i + 1), at(r + 1, i + 1)});
            a.indices.insert(a.indices.end(), {at(r, i), at(r + 1, i + 1), at(r + 1, i)});
        }
    }
    const std::size_t last_ring = sections.size() - 1;
    for (int i = 0; i < segments; ++i) {
        a.indices.insert(a.indices.end(), {last_pole, at(last_ring, i), at(last_ring, i + 1)});
    }
    // Bound with the arm straight: the shoulder at the origin, the elbow at
    // upper_length along x.
    a.inverse_bind = {identity(), translation(-a.upper_length, 0.0, 0.0)};
    return a;
}

double elbow_degrees_at(double seconds) {
    return 0.5 * max_bend_degrees * (1.0 - std::cos(2.0 * pi * seconds / period_seconds));
}

std::array<Matrix, joint_count> joint_matrices(const Arm& arm, double degrees) {
    const double c = std::cos(degrees * pi / 180.0);
    const double s = std::sin(degrees * pi / 180.0);
    Matrix turn = identity();
    turn[0] = c, turn[1] = s, turn[4] = -s, turn[5] = c;
    return {identity(), multiply(translation(arm.upper_length, 0.0, 0.0), turn)};
}

void turn_about_elbow(const Arm& arm, double degrees, const float bind[3], double out[3]) {
    const Matrix m = multiply(joint_matrices(arm, degrees)[1], arm.inverse_bind[1]);
    for (int r = 0; r < 3; ++r) {
        out[r] = m[r] * bind[0] + m[4 + r] * bind[1] + m[8 + r] * bind[2] + m[12 + r];
    }
}

void skin(const Arm& arm, const std::array<Matrix, joint_count>& joints,
          const std::vector<float>& corrective, double corrective_weight, double* out) {
    std::array<Matrix, joint_count> skinning;
    for (int j = 0; j < joint_count; ++j) skinning[j] = multiply(joints[j], arm.inverse_bind[j]);
    for (std::size_t v = 0; v < arm.vertex_count(); ++v) {
        double p[3];
        for (int c = 0; c < 3; ++c) {
            p[c] = static_cast<double>(arm.positions[3 * v + c]) +
                   corrective_weight * static_cast<double>(corrective[3 * v + c]);
        }
        // glTF's rule: the weights are normalised to sum 1.
        double total = 0.0;
        for (int k = 0; k < influences; ++k) total += arm.weights[influences * v + k];
        double q[3] = {0.0, 0.0, 0.0};
        for (int k = 0; k < influences; ++k) {
            const double w = arm.weights[influences * v + k] / total;
            const Matrix& m = skinning[arm.joints[influences * v + k]];
            for (int r = 0; r < 3; ++r) {
                q[r] += w * (m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r]);
            }
        }
        for (int c = 0; c < 3; ++c) out[3 * v + c] = q[c];
    }
}

}  // namespace arm
