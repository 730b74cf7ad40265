#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

// The character, made in code: an arm along +x, a tapered tube with round
// ends, bound to two joints (the shoulder at the origin, the elbow at
// x = upper_length) whose weights blend smoothly across the elbow, and the
// animation the sample plays: the elbow bending about +z from 0 to
// max_bend_degrees and back. It holds what an engine holds for a skinned
// mesh (float positions, joint indices and weights per vertex, inverse bind
// matrices) and skins it as an engine's vertex shader does.
namespace arm {

constexpr int joint_count = 2;
constexpr int influences = 2;  // per vertex: the shoulder and the elbow

// A column-major 4x4 affine matrix, as dualform.h takes them.
using Matrix = std::array<double, 16>;

struct Arm {
    double upper_length = 1.0;     // shoulder to elbow
    double forearm_length = 1.0;   // elbow to wrist
    std::vector<float> positions;  // the bind pose, x y z per vertex
    std::vector<std::uint32_t> indices;
    std::vector<std::uint8_t> joints;  // `influences` joint indices per vertex
    std::vector<float> weights;        // and their weights, summing to 1
    std::array<Matrix, joint_count> inverse_bind;

    std::size_t vertex_count() const { return positions.size() / 3; }
    std::size_t triangle_count() const { return indices.size() / 3; }
};

Arm make_arm();

// The animation: the elbow's angle in degrees at `seconds`, from 0 (straight)
// up to max_bend_degrees and back over period_seconds, eased at both ends.
constexpr double max_bend_degrees = 120.0;
constexpr double period_seconds = 2.0;
double elbow_degrees_at(double seconds);

// The joints' world matrices with the elbow bent by `degrees` about +z: what
// the host hands to dfm_mesh_set_pose_joints.
std::array<Matrix, joint_count> joint_matrices(const Arm& arm, double degrees);

// Where the elbow bent by `degrees` takes bind position `bind` rigidly, with
// no blending: what the elbow's share of a bend should do to a vertex
// across it, where linear blend skinning pulls it towards the joint.
void turn_about_elbow(const Arm& arm, double degrees, const float bind[3], double out[3]);

// Linear blend skinning of bind + corrective_weight * corrective (the
// corrective applied before skinning, as engines apply morph targets) at
// the joints' world matrices `joints`: vertex v lands at
// sum_k w_vk J[j_vk] inverse_bind[j_vk] (bind_v + corrective_weight * d_v),
// written as x y z doubles to `out` (3 per vertex).
void skin(const Arm& arm, const std::array<Matrix, joint_count>& joints,
          const std::vector<float>& corrective, double corrective_weight, double* out);

}  // namespace arm
