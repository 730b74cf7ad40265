#include "mesh/animation_sampling.hpp"

#include <algorithm>
#include <cmath>

namespace dfm::mesh {

namespace {

// The key interval holding `t` (clamped): keys k and k + 1 and the fraction
// between them; a single key, or a time at or past either end, gives that
// key with fraction 0.
struct KeySpan {
    std::size_t k = 0;
    std::size_t next = 0;
    double s = 0.0;
    double dt = 0.0;
};

KeySpan find_keys(const std::vector<double>& times, double t) {
    KeySpan span;
    if (times.size() < 2 || t <= times.front()) return span;
    if (t >= times.back()) {
        span.k = span.next = times.size() - 1;
        return span;
    }
    const auto after = std::upper_bound(times.begin(), times.end(), t);
    span.next = static_cast<std::size_t>(after - times.begin());
    span.k = span.next - 1;
    span.dt = times[span.next] - times[span.k];
    span.s = span.dt > 0.0 ? (t - times[span.k]) / span.dt : 0.0;
    return span;
}

// Value component c of key k: the value itself, or of a cubic spline's key
// its in-tangent (part 0), value (1) or out-tangent (2).
double key_value(const AnimationChannel& ch, std::size_t k, int part, std::uint32_t c) {
    if (ch.interpolation != Interpolation::cubic_spline) return ch.values[k * ch.width + c];
    return ch.values[(3 * k + static_cast<std::size_t>(part)) * ch.width + c];
}

glm::dquat key_quat(const AnimationChannel& ch, std::size_t k, int part) {
    return glm::dquat(key_value(ch, k, part, 3), key_value(ch, k, part, 0),
                      key_value(ch, k, part, 1), key_value(ch, k, part, 2));
}

// Spherical linear interpolation along the shorter arc.
glm::dquat slerp_short(glm::dquat a, glm::dquat b, double s) {
    double d = glm::dot(a, b);
    if (d < 0.0) {
        b = -b;
        d = -d;
    }
    if (d > 1.0 - 1e-12) return glm::normalize(a * (1.0 - s) + b * s);
    const double angle = std::acos(std::min(d, 1.0));
    const double sin_angle = std::sin(angle);
    return a * (std::sin((1.0 - s) * angle) / sin_angle) + b * (std::sin(s * angle) / sin_angle);
}

// Component c of the channel at `span`.
double sample_component(const AnimationChannel& ch, const KeySpan& span, std::uint32_t c) {
    const double v0 = key_value(ch, span.k, 1, c);
    if (span.k == span.next || ch.interpolation == Interpolation::step) return v0;
    const double v1 = key_value(ch, span.next, 1, c);
    const double s = span.s;
    if (ch.interpolation == Interpolation::linear) return v0 + (v1 - v0) * s;
    const double b0 = key_value(ch, span.k, 2, c) * span.dt;     // out-tangent of k
    const double a1 = key_value(ch, span.next, 0, c) * span.dt;  // in-tangent of k + 1
    const double s2 = s * s, s3 = s2 * s;
    return (2 * s3 - 3 * s2 + 1) * v0 + (s3 - 2 * s2 + s) * b0 + (-2 * s3 + 3 * s2) * v1 +
           (s3 - s2) * a1;
}

glm::dquat sample_rotation(const AnimationChannel& ch, const KeySpan& span) {
    if (span.k == span.next || ch.interpolation == Interpolation::step) {
        return glm::normalize(key_quat(ch, span.k, 1));
    }
    if (ch.interpolation == Interpolation::linear) {
        return glm::normalize(slerp_short(glm::normalize(key_quat(ch, span.k, 1)),
                                          glm::normalize(key_quat(ch, span.next, 1)), span.s));
    }
    glm::dquat q(sample_component(ch, span, 3), sample_component(ch, span, 0),
                 sample_component(ch, span, 1), sample_component(ch, span, 2));
    const double len = glm::length(q);
    return len > 0.0 ? q / len : glm::dquat(1.0, 0.0, 0.0, 0.0);
}

}  // namespace

void apply_animation(const Skin& skin, const Animation& animation, double time,
                     std::span<NodeTransform> local, std::span<double> morph_weights) {
    for (const AnimationChannel& ch : animation.channels) {
        if (ch.times.empty()) continue;
        const KeySpan span = find_keys(ch.times, time);
        NodeTransform& node = local[ch.node];
        switch (ch.path) {
            case AnimationPath::translation:
            case AnimationPath::scale: {
                glm::dvec3 v;
                for (std::uint32_t c = 0; c < 3; ++c) v[c] = sample_component(ch, span, c);
                (ch.path == AnimationPath::translation ? node.translation : node.scale) = v;
                break;
            }
            case AnimationPath::rotation: node.rotation = sample_rotation(ch, span); break;
            case AnimationPath::weights:
                for (std::size_t t = 0; t < skin.morph_targets.size(); ++t) {
                    const MorphTarget& target = skin.morph_targets[t];
                    if (target.node == ch.node && target.column < ch.width) {
                        morph_weights[t] = sample_component(ch, span, target.column);
                    }
                }
                break;
        }
    }
}

}  // namespace dfm::mesh
