#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "core/status.hpp"
#include "mesh/skin.hpp"

namespace dfm::mesh {

// A pose of a skin: each joint's world matrix J_j and skinning matrix
// S_j = J_j * inverse_bind_j, and each morph target's weight. `animation`
// and `time` say where it came from (an animation sampled at a time; -1: the
// host's joint matrices), for what a save records.
struct SkinPose {
    std::vector<glm::dmat4> joint_world;
    std::vector<glm::dmat4> skinning;
    std::vector<double> morph_weights;
    int animation = -1;
    double time = 0.0;
};

// The pose of `animation` at `time` seconds, clamped to the animation's
// range: every node at its rest transform but where a channel animates it,
// the joints' world matrices from the node hierarchy, the morph weights of
// the targets' nodes (their defaults where no channel drives them).
// Errc::out_of_range for an animation the skin does not have,
// Errc::numerical for a time that is not finite.
Status sample_pose(const Skin& skin, std::size_t animation, double time, SkinPose& out);

// The skin's nodes at their rest transforms, no animation: the pose the
// file's scene is in (a host's joints, which have no node, where they were
// bound: the inverse of their inverse bind matrices).
Status rest_pose(const Skin& skin, SkinPose& out);

// The pose from the host's joint world matrices (joint_count of them) and
// morph weights (empty: the targets' defaults; else one per target).
// Errc::invalid_argument for a count that does not match, Errc::numerical
// for a matrix or weight that is not finite or a matrix whose last row is
// not 0 0 0 1; the message names the joint or target.
Status pose_from_joints(const Skin& skin, std::span<const glm::dmat4> joint_world,
                        std::span<const double> morph_weights, SkinPose& out);

// posed_v = sum_i w_vi S_{j_vi} (bind_v + sum_t m_t delta_tv) for every
// vertex; `bind` and `posed` have the skin's vertex count.
void pose_positions(const Skin& skin, const SkinPose& pose, std::span<const glm::dvec3> bind,
                    std::span<glm::dvec3> posed);

// The pose as a JSON object's text, for the extras of a saved corrective:
// {"dualform_pose": {"animation": NAME, "animation_index": I, "time": T}}, or
// {"dualform_pose": {"joint_matrices": [[16 numbers] per joint]}}, with
// "morph_weights" where the skin has morph targets.
std::string pose_record(const Skin& skin, const SkinPose& pose);

// How well the bind-space corrective of a posed edit was determined.
struct CorrectiveReport {
    std::size_t moved = 0;         // vertices whose posed position changed
    double worst_condition = 1.0;  // the largest condition number of L_v among them
    std::uint32_t worst_vertex = no_index;
    // Vertices whose L_v shrinks some direction below the floor, the larger
    // of 1 and its largest singular value over max_condition: weights that
    // cancel (a condition number above max_condition) or a collapsed joint
    // (a tiny L_v, whatever its condition). Their corrective is the damped
    // least-squares one, the floor its damping, so the posed edit is met
    // only approximately there. Ascending.
    std::vector<std::uint32_t> damped;

    static constexpr double max_condition = 1e3;
};

// The bind-space positions whose pose is the edited shape: for each vertex
// whose posed position moved from `posed_before` to `posed_after`,
// bind_v + L_v^-1 (posed_after_v - posed_before_v), L_v = the 3x3 part of
// sum_i w_vi S_{j_vi} (morphs apply before skinning and LBS is affine in the
// rest position, so skinning the result at `pose` gives `posed_after`);
// every other vertex keeps its bind position bit for bit. Where L_v is
// ill-conditioned, a damped inverse (CorrectiveReport).
void corrective_positions(const Skin& skin, const SkinPose& pose, std::span<const glm::dvec3> bind,
                          std::span<const glm::dvec3> posed_before,
                          std::span<const glm::dvec3> posed_after,
                          std::vector<glm::dvec3>& bind_after, CorrectiveReport& report);

}  // namespace dfm::mesh
