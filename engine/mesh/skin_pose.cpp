#include "mesh/skin_pose.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/matrix.hpp>

#include "mesh/animation_sampling.hpp"

namespace dfm::mesh {

namespace {

glm::dmat4 local_matrix(const SkeletonNode& node, const NodeTransform& t) {
    if (node.has_matrix) return node.matrix;
    glm::dmat4 m = glm::translate(glm::dmat4(1.0), t.translation);
    m *= glm::mat4_cast(t.rotation);
    return glm::scale(m, t.scale);
}

// Every node's world matrix from its local transform and its parent's. The
// reader made the hierarchy a forest, so following parents ends.
std::vector<glm::dmat4> world_matrices(const Skin& skin, const std::vector<NodeTransform>& local) {
    const std::size_t n = skin.nodes.size();
    std::vector<glm::dmat4> world(n);
    std::vector<bool> done(n, false);
    std::vector<std::uint32_t> chain;
    for (std::uint32_t start = 0; start < n; ++start) {
        chain.clear();
        for (std::uint32_t at = start; at != no_index && !done[at]; at = skin.nodes[at].parent) {
            chain.push_back(at);
        }
        for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
            const std::uint32_t node = *it;
            const glm::dmat4 own = local_matrix(skin.nodes[node], local[node]);
            const std::uint32_t parent = skin.nodes[node].parent;
            world[node] = parent == no_index ? own : world[parent] * own;
            done[node] = true;
        }
    }
    return world;
}

void finish_pose(const Skin& skin, const std::vector<NodeTransform>& local, SkinPose& out) {
    const std::vector<glm::dmat4> world = world_matrices(skin, local);
    out.joint_world.resize(skin.joint_count());
    for (std::size_t j = 0; j < skin.joint_count(); ++j) {
        const std::uint32_t node = skin.joint_nodes[j];
        // A host's joint has no node: at rest it stands where it was bound.
        out.joint_world[j] = node == no_index ? glm::inverse(skin.inverse_bind[j]) : world[node];
    }
    out.skinning.resize(skin.joint_count());
    for (std::size_t j = 0; j < skin.joint_count(); ++j) {
        out.skinning[j] = out.joint_world[j] * skin.inverse_bind[j];
    }
}

std::vector<NodeTransform> rest_transforms(const Skin& skin) {
    std::vector<NodeTransform> local(skin.nodes.size());
    for (std::size_t i = 0; i < skin.nodes.size(); ++i) {
        local[i] = {skin.nodes[i].translation, skin.nodes[i].rotation, skin.nodes[i].scale};
    }
    return local;
}

std::vector<double> default_weights(const Skin& skin) {
    std::vector<double> w(skin.morph_targets.size());
    for (std::size_t t = 0; t < w.size(); ++t) w[t] = skin.morph_targets[t].default_weight;
    return w;
}

bool finite(const glm::dmat4& m) {
    for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) {
            if (!std::isfinite(m[c][r])) return false;
        }
    }
    return true;
}

// The 3x4 affine part of sum_i w_i S_{j_i} for vertex v, column-major: the
// linear part in m[0..8], the translation in m[9..11].
void blend(const Skin& skin, const SkinPose& pose, std::size_t v, double m[12]) {
    std::fill(m, m + 12, 0.0);
    for (std::uint32_t k = skin.influence_offsets[v]; k < skin.influence_offsets[v + 1]; ++k) {
        const glm::dmat4& s = pose.skinning[skin.influence_joints[k]];
        const double w = skin.influence_weights[k];
        for (int c = 0; c < 4; ++c) {
            for (int r = 0; r < 3; ++r) m[3 * c + r] += w * s[c][r];
        }
    }
}

// The largest and smallest singular values of a 3x3 matrix (column-major),
// from the eigenvalues of its Gram matrix by cyclic Jacobi rotations.
struct Singular {
    double largest = 0.0;
    double smallest = 0.0;
};

Singular singular_values(const double m[9]) {
    double g[3][3];
    for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) {
            g[a][b] =
                m[3 * a] * m[3 * b] + m[3 * a + 1] * m[3 * b + 1] + m[3 * a + 2] * m[3 * b + 2];
        }
    }
    for (int sweep = 0; sweep < 32; ++sweep) {
        const double off = g[0][1] * g[0][1] + g[0][2] * g[0][2] + g[1][2] * g[1][2];
        if (off <= 1e-300) break;
        for (int p = 0; p < 2; ++p) {
            for (int q = p + 1; q < 3; ++q) {
                if (g[p][q] == 0.0) continue;
                const double theta = (g[q][q] - g[p][p]) / (2.0 * g[p][q]);
                const double t = (theta >= 0.0 ? 1.0 : -1.0) /
                                 (std::abs(theta) + std::sqrt(theta * theta + 1.0));
                const double c = 1.0 / std::sqrt(t * t + 1.0);
                const double s = t * c;
                for (int k = 0; k < 3; ++k) {
                    const double gkp = g[k][p], gkq = g[k][q];
                    g[k][p] = c * gkp - s * gkq;
                    g[k][q] = s * gkp + c * gkq;
                }
                for (int k = 0; k < 3; ++k) {
                    const double gpk = g[p][k], gqk = g[q][k];
                    g[p][k] = c * gpk - s * gqk;
                    g[q][k] = s * gpk + c * gqk;
                }
            }
        }
    }
    const double hi = std::max({g[0][0], g[1][1], g[2][2]});
    const double lo = std::min({g[0][0], g[1][1], g[2][2]});
    return {std::sqrt(std::max(hi, 0.0)), std::sqrt(std::max(lo, 0.0))};
}

// Solves a x = b for a 3x3 matrix (column-major) by Gaussian elimination
// with partial pivoting.
glm::dvec3 solve3(const double m[9], const glm::dvec3& b) {
    double a[3][4];
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) a[r][c] = m[3 * c + r];
        a[r][3] = b[r];
    }
    for (int col = 0; col < 3; ++col) {
        int pivot = col;
        for (int r = col + 1; r < 3; ++r) {
            if (std::abs(a[r][col]) > std::abs(a[pivot][col])) pivot = r;
        }
        if (pivot != col) {
            for (int c = 0; c < 4; ++c) std::swap(a[col][c], a[pivot][c]);
        }
        for (int r = col + 1; r < 3; ++r) {
            const double f = a[r][col] / a[col][col];
            for (int c = col; c < 4; ++c) a[r][c] -= f * a[col][c];
        }
    }
    glm::dvec3 x;
    for (int r = 2; r >= 0; --r) {
        double s = a[r][3];
        for (int c = r + 1; c < 3; ++c) s -= a[r][c] * x[c];
        x[r] = s / a[r][r];
    }
    return x;
}

// The damped least-squares solution (a^T a + l^2 I) x = a^T b, with l the
// floor a well-determined direction keeps (CorrectiveReport): the
// well-determined directions stay nearly exact, the others bounded.
glm::dvec3 damped_solve(const double m[9], double floor, const glm::dvec3& b) {
    double g[9];
    glm::dvec3 atb;
    for (int a = 0; a < 3; ++a) {
        atb[a] = m[3 * a] * b.x + m[3 * a + 1] * b.y + m[3 * a + 2] * b.z;
        for (int c = 0; c < 3; ++c) {
            g[3 * c + a] =
                m[3 * a] * m[3 * c] + m[3 * a + 1] * m[3 * c + 1] + m[3 * a + 2] * m[3 * c + 2];
        }
        g[3 * a + a] += floor * floor;
    }
    return solve3(g, atb);
}

}  // namespace

Status sample_pose(const Skin& skin, std::size_t animation, double time, SkinPose& out) {
    if (animation >= skin.animations.size()) {
        return Status(Errc::out_of_range, "animation " + std::to_string(animation) +
                                              " does not exist (there are " +
                                              std::to_string(skin.animations.size()) + ")");
    }
    if (!std::isfinite(time)) {
        return Status(Errc::numerical, "the time is not finite");
    }
    const Animation& a = skin.animations[animation];
    const double t = std::clamp(time, a.start, a.end);
    std::vector<NodeTransform> local = rest_transforms(skin);
    std::vector<double> weights = default_weights(skin);
    apply_animation(skin, a, t, local, weights);
    finish_pose(skin, local, out);
    out.morph_weights = std::move(weights);
    out.animation = static_cast<int>(animation);
    out.time = t;
    return Status::ok();
}

Status rest_pose(const Skin& skin, SkinPose& out) {
    finish_pose(skin, rest_transforms(skin), out);
    out.morph_weights = default_weights(skin);
    out.animation = -1;
    out.time = 0.0;
    return Status::ok();
}

Status pose_from_joints(const Skin& skin, std::span<const glm::dmat4> joint_world,
                        std::span<const double> morph_weights, SkinPose& out) {
    if (joint_world.size() != skin.joint_count()) {
        return Status(Errc::invalid_argument, std::to_string(joint_world.size()) +
                                                  " joint matrices for a skin of " +
                                                  std::to_string(skin.joint_count()) + " joints");
    }
    if (!morph_weights.empty() && morph_weights.size() != skin.morph_targets.size()) {
        return Status(Errc::invalid_argument,
                      std::to_string(morph_weights.size()) + " morph weights for " +
                          std::to_string(skin.morph_targets.size()) + " morph targets");
    }
    for (std::size_t j = 0; j < joint_world.size(); ++j) {
        const glm::dmat4& m = joint_world[j];
        if (!finite(m)) {
            return Status(Errc::numerical,
                          "joint " + std::to_string(j) + "'s matrix is not finite");
        }
        if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0) {
            return Status(Errc::numerical, "joint " + std::to_string(j) +
                                               "'s matrix is not affine (its last row is not "
                                               "0 0 0 1)");
        }
    }
    for (std::size_t t = 0; t < morph_weights.size(); ++t) {
        if (!std::isfinite(morph_weights[t])) {
            return Status(Errc::numerical,
                          "morph target " + std::to_string(t) + "'s weight is not finite");
        }
    }
    out.joint_world.assign(joint_world.begin(), joint_world.end());
    out.skinning.resize(skin.joint_count());
    for (std::size_t j = 0; j < skin.joint_count(); ++j) {
        out.skinning[j] = out.joint_world[j] * skin.inverse_bind[j];
    }
    if (morph_weights.empty()) {
        out.morph_weights = default_weights(skin);
    } else {
        out.morph_weights.assign(morph_weights.begin(), morph_weights.end());
    }
    out.animation = -1;
    out.time = 0.0;
    return Status::ok();
}

void pose_positions(const Skin& skin, const SkinPose& pose, std::span<const glm::dvec3> bind,
                    std::span<glm::dvec3> posed) {
    std::copy(bind.begin(), bind.end(), posed.begin());
    for (std::size_t t = 0; t < skin.morph_targets.size(); ++t) {
        const double w = pose.morph_weights[t];
        if (w == 0.0) continue;
        const MorphTarget& target = skin.morph_targets[t];
        for (std::size_t i = 0; i < target.vertices.size(); ++i) {
            posed[target.vertices[i]] += w * target.deltas[i];
        }
    }
    for (std::size_t v = 0; v < posed.size(); ++v) {
        if (skin.influence_offsets[v + 1] == skin.influence_offsets[v]) continue;
        double m[12];
        blend(skin, pose, v, m);
        const glm::dvec3 p = posed[v];
        posed[v] = glm::dvec3(m[0] * p.x + m[3] * p.y + m[6] * p.z + m[9],
                              m[1] * p.x + m[4] * p.y + m[7] * p.z + m[10],
                              m[2] * p.x + m[5] * p.y + m[8] * p.z + m[11]);
    }
}

void corrective_positions(const Skin& skin, const SkinPose& pose, std::span<const glm::dvec3> bind,
                          std::span<const glm::dvec3> posed_before,
                          std::span<const glm::dvec3> posed_after,
                          std::vector<glm::dvec3>& bind_after, CorrectiveReport& report) {
    report = CorrectiveReport{};
    bind_after.assign(bind.begin(), bind.end());
    for (std::size_t v = 0; v < bind.size(); ++v) {
        if (posed_after[v] == posed_before[v]) continue;
        ++report.moved;
        const glm::dvec3 moved = posed_after[v] - posed_before[v];
        if (skin.influence_offsets[v + 1] == skin.influence_offsets[v]) {
            bind_after[v] = bind[v] + moved;
            continue;
        }
        double m[12];
        blend(skin, pose, v, m);
        const Singular sigma = singular_values(m);
        const double condition = sigma.smallest > 0.0 ? sigma.largest / sigma.smallest : INFINITY;
        if (report.worst_vertex == no_index || condition > report.worst_condition) {
            report.worst_condition = condition;
            report.worst_vertex = static_cast<std::uint32_t>(v);
        }
        // Skinning maps lengths nearly as a rotation does (singular values
        // about 1); a direction it shrinks below the floor, relative to
        // the larger of 1 and its largest stretch, is a collapse.
        const double floor = std::max(sigma.largest, 1.0) / CorrectiveReport::max_condition;
        const bool damped = !(sigma.smallest >= floor);
        if (damped) report.damped.push_back(static_cast<std::uint32_t>(v));
        bind_after[v] = bind[v] + (damped ? damped_solve(m, floor, moved) : solve3(m, moved));
    }
}

}  // namespace dfm::mesh
