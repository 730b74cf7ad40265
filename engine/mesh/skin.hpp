#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <glm/gtc/quaternion.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "mesh/mesh.hpp"

namespace dfm::mesh {

// A node of the file's scene graph, as a skin's joints and an animation's
// channels reach it: its parent and its rest local transform.
struct SkeletonNode {
    std::string name;
    std::uint32_t parent = no_index;
    glm::dvec3 translation{0.0};
    glm::dquat rotation{1.0, 0.0, 0.0, 0.0};
    glm::dvec3 scale{1.0};
    // A node given by a matrix keeps it; animation cannot target it (glTF).
    bool has_matrix = false;
    glm::dmat4 matrix{1.0};
};

enum class AnimationPath : std::uint8_t { translation, rotation, scale, weights };
enum class Interpolation : std::uint8_t { linear, step, cubic_spline };

// One animated property of one node: key times (ascending, finite) and
// `width` values per key (3 for translation and scale, 4 for a rotation's
// x, y, z, w, the mesh's target count for weights); a cubic spline's key
// holds its in-tangent, value and out-tangent, 3 * width values.
struct AnimationChannel {
    std::uint32_t node = no_index;
    AnimationPath path = AnimationPath::translation;
    Interpolation interpolation = Interpolation::linear;
    std::uint32_t width = 0;
    std::vector<double> times;
    std::vector<double> values;
};

struct Animation {
    std::string name;
    double start = 0.0;  // the earliest and latest key of any channel
    double end = 0.0;
    std::vector<AnimationChannel> channels;
};

// One morph target: its deltas at the vertices it moves (ascending, in the
// space of the mesh's positions), and what drives its weight: column
// `column` of the weights of node `node` (an animation's weights channel),
// its default `default_weight`.
struct MorphTarget {
    std::string name;
    std::uint32_t node = no_index;
    std::uint32_t column = 0;
    double default_weight = 0.0;
    std::vector<std::uint32_t> vertices;
    std::vector<glm::dvec3> deltas;
};

// What poses a mesh: linear blend skinning over joints, the joints' scene
// graph and animations, and morph targets, which apply before skinning.
// Vertex v is posed as
//
//     posed_v = sum_i w_vi * S_{j_vi} * (bind_v + sum_t m_t * delta_tv)
//
// with S_j = J_j * inverse_bind_j (J_j: the joint's world matrix at the pose)
// and m_t the targets' weights. A vertex without influences keeps its bind
// position (plus its morphs). Vertex arrays are per vertex of the mesh the
// skin belongs to: the loaders build them per host vertex and
// `to_surface` (skin_weld.hpp) turns them to surface vertices.
struct Skin {
    // Joints: every skin of the file in one list.
    std::vector<std::string> joint_names;
    std::vector<std::uint32_t> joint_nodes;  // the joint's node; no_index for a host's joint
    std::vector<glm::dmat4> inverse_bind;
    // Influences per vertex, CSR: weights positive, summing to 1 per vertex.
    std::vector<std::uint32_t> influence_offsets;  // vertices + 1
    std::vector<std::uint32_t> influence_joints;
    std::vector<double> influence_weights;
    std::uint32_t max_influences = 0;
    std::vector<SkeletonNode> nodes;
    std::vector<Animation> animations;
    std::vector<MorphTarget> morph_targets;

    std::size_t joint_count() const { return inverse_bind.size(); }
    std::size_t vertex_count() const {
        return influence_offsets.empty() ? 0 : influence_offsets.size() - 1;
    }
    std::size_t skinned_vertex_count() const;
};

// One vertex's influences as a loader gathers them: (joint, weight) pairs,
// weights positive.
using InfluenceList = std::vector<std::pair<std::uint32_t, double>>;

// Adds `weight` of `joint` to `list`, to the joint's entry if it has one.
void add_influence(InfluenceList& list, std::uint32_t joint, double weight);

// The skin's influences from one list per vertex (each sorted by joint and
// normalised to sum 1 here; a list may be empty), and max_influences.
void set_influences(std::vector<InfluenceList>& lists, Skin& skin);

}  // namespace dfm::mesh
