// The skin and pose calls: what poses a mesh, and setting the pose the rest
// pose is shown (and edited) in.
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include "c_boundary.hpp"
#include "host_numbering.hpp"
#include "mesh/skin_pose.hpp"
#include "objects.hpp"
#include "shared_calls.hpp"
#include "vec3_arrays.hpp"

using namespace dfm;
using namespace dfm::sdk;

namespace {

// The mesh's skin, or a report that it has none.
const mesh::Skin* skin_of(const char* fn, const MeshObject& m, dfm_result& r) {
    const mesh::Skin* skin = m.state->poses.skin();
    if (skin == nullptr) {
        r = report(fn, DFM_ERROR_UNSUPPORTED,
                   "the mesh has no skin and no morph targets: nothing poses it");
    }
    return skin;
}

// The calls that describe one item of the skin (a joint, an animation, a
// morph target): their one opening (out, the mesh, its skin, the index
// within `count(skin)`, named `what` in the message), then `fill`.
template <class Out, class Count, class Fill>
dfm_result skin_item(const char* fn, const dfm_mesh* mesh, std::uint32_t index, Out* out,
                     const char* what, Count&& count, Fill&& fill) {
    return guarded(fn, [&] {
        if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
        *out = Out{};
        MeshObject* m = resolve_mesh(mesh);
        if (m == nullptr) return bad_handle(fn, "mesh", mesh);
        dfm_result r = DFM_OK;
        const mesh::Skin* skin = skin_of(fn, *m, r);
        if (skin == nullptr) return r;
        const std::size_t n = count(*skin);
        if (index >= n) {
            return report(fn, DFM_ERROR_OUT_OF_RANGE,
                          std::string(what) + " " + std::to_string(index) +
                              " does not exist (the mesh has " + std::to_string(n) + ")");
        }
        fill(*skin, *out);
        return DFM_OK;
    });
}

}  // namespace

namespace dfm::sdk {

void log_damped_corrective(const MeshState& mesh, const char* fn) {
    if (!mesh.poses.skin_pose()) return;
    const mesh::CorrectiveReport corrective = mesh.poses.last_corrective();
    if (corrective.damped.empty()) return;
    const HostNumbering numbering(mesh, mesh.poses.skin()->vertex_count());
    std::string list;
    constexpr std::size_t named = 20;
    for (std::size_t i = 0; i < corrective.damped.size() && i < named; ++i) {
        list += (i ? ", " : "") + std::to_string(numbering.to_host(corrective.damped[i]));
    }
    if (corrective.damped.size() > named) list += ", ...";
    std::string condition = std::to_string(corrective.worst_condition);
    mesh.context->emit(DFM_LOG_WARNING, DFM_LOG_ID_CORRECTIVE_DAMPED,
                       std::string(fn) + ": " + std::to_string(corrective.damped.size()) +
                           " vertices moved where their skinning is ill-conditioned (condition "
                           "number up to " +
                           condition +
                           "); their bind-space corrective is damped, so the pose meets the edit "
                           "only approximately there: vertices " +
                           list);
}

}  // namespace dfm::sdk

extern "C" DFM_API dfm_result dfm_mesh_get_skin_info(const dfm_mesh* mesh, dfm_skin_info* out) {
    constexpr const char* fn = "dfm_mesh_get_skin_info";
    return guarded(fn, [&] {
        if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
        *out = dfm_skin_info{};
        out->pose_animation = -1;
        MeshObject* m = resolve_mesh(mesh);
        if (m == nullptr) return bad_handle(fn, "mesh", mesh);
        const deform::RestPoses& poses = m->state->poses;
        const mesh::Skin* skin = poses.skin();
        if (skin == nullptr) return DFM_OK;
        out->joint_count = static_cast<std::uint32_t>(skin->joint_count());
        out->max_influences = skin->max_influences;
        const HostNumbering numbering(*m->state, skin->vertex_count());
        for (std::uint32_t s = 0; s < skin->vertex_count(); ++s) {
            if (skin->influence_offsets[s + 1] == skin->influence_offsets[s]) continue;
            numbering.for_copies(s, [&](std::uint32_t) { ++out->skinned_vertex_count; });
        }
        out->animation_count = static_cast<std::uint32_t>(skin->animations.size());
        out->morph_target_count = static_cast<std::uint32_t>(skin->morph_targets.size());
        if (const std::optional<mesh::SkinPose> pose = poses.skin_pose()) {
            out->posed = true;
            out->pose_animation = pose->animation;
            out->pose_time = pose->time;
        }
        const mesh::CorrectiveReport corrective = poses.last_corrective();
        out->corrective_vertex_count = corrective.moved;
        out->corrective_worst_condition = corrective.moved > 0 ? corrective.worst_condition : 0.0;
        out->corrective_damped_count = corrective.damped.size();
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_mesh_get_joint_info(const dfm_mesh* mesh, uint32_t joint,
                                                      dfm_joint_info* out) {
    return skin_item(
        "dfm_mesh_get_joint_info", mesh, joint, out, "joint",
        [](const mesh::Skin& skin) { return skin.joint_count(); },
        [&](const mesh::Skin& skin, dfm_joint_info& info) {
            info.name = skin.joint_names[joint].c_str();
            info.parent = UINT32_MAX;
            // The nearest ancestor node that is a joint of the skin.
            const std::uint32_t node = skin.joint_nodes[joint];
            if (node == mesh::no_index) return;
            for (std::uint32_t at = skin.nodes[node].parent; at != mesh::no_index;
                 at = skin.nodes[at].parent) {
                for (std::size_t j = 0; j < skin.joint_count(); ++j) {
                    if (skin.joint_nodes[j] == at) {
                        info.parent = static_cast<std::uint32_t>(j);
                        return;
                    }
                }
            }
        });
}

extern "C" DFM_API dfm_result dfm_mesh_get_animation_info(const dfm_mesh* mesh, uint32_t animation,
                                                          dfm_animation_info* out) {
    return skin_item(
        "dfm_mesh_get_animation_info", mesh, animation, out, "animation",
        [](const mesh::Skin& skin) { return skin.animations.size(); },
        [&](const mesh::Skin& skin, dfm_animation_info& info) {
            const mesh::Animation& a = skin.animations[animation];
            info.name = a.name.c_str();
            info.start = a.start;
            info.end = a.end;
            for (const mesh::AnimationChannel& ch : a.channels) {
                switch (ch.path) {
                    case mesh::AnimationPath::translation: ++info.translation_channels; break;
                    case mesh::AnimationPath::rotation: ++info.rotation_channels; break;
                    case mesh::AnimationPath::scale: ++info.scale_channels; break;
                    case mesh::AnimationPath::weights: ++info.weight_channels; break;
                }
            }
        });
}

extern "C" DFM_API dfm_result dfm_mesh_find_animation(const dfm_mesh* mesh, const char* name,
                                                      uint32_t* animation) {
    constexpr const char* fn = "dfm_mesh_find_animation";
    return guarded(fn, [&] {
        if (animation == nullptr) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "animation is NULL");
        }
        *animation = 0;
        MeshObject* m = resolve_mesh(mesh);
        if (m == nullptr) return bad_handle(fn, "mesh", mesh);
        if (name == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "name is NULL");
        dfm_result r = DFM_OK;
        const mesh::Skin* skin = skin_of(fn, *m, r);
        if (skin == nullptr) return r;
        std::string names;
        for (std::size_t a = 0; a < skin->animations.size(); ++a) {
            if (skin->animations[a].name == name) {
                *animation = static_cast<std::uint32_t>(a);
                return DFM_OK;
            }
            if (a < 20) names += (a ? ", '" : "'") + skin->animations[a].name + "'";
        }
        return report(fn, DFM_ERROR_NOT_FOUND,
                      "no animation named '" + std::string(name) + "' (the mesh has " +
                          std::to_string(skin->animations.size()) +
                          (names.empty() ? ")" : ": " + names + ")"));
    });
}

extern "C" DFM_API dfm_result dfm_mesh_get_morph_target_info(const dfm_mesh* mesh, uint32_t target,
                                                             dfm_morph_target_info* out) {
    return skin_item(
        "dfm_mesh_get_morph_target_info", mesh, target, out, "morph target",
        [](const mesh::Skin& skin) { return skin.morph_targets.size(); },
        [&](const mesh::Skin& skin, dfm_morph_target_info& info) {
            const mesh::MorphTarget& t = skin.morph_targets[target];
            info.name = t.name.c_str();
            info.default_weight = t.default_weight;
            info.vertex_count = t.vertices.size();
        });
}

extern "C" DFM_API dfm_result dfm_mesh_set_pose_animation(dfm_mesh* mesh, uint32_t animation,
                                                          double time_seconds) {
    constexpr const char* fn = "dfm_mesh_set_pose_animation";
    return guarded(fn, [&] {
        MeshObject* m = resolve_mesh(mesh);
        if (m == nullptr) return bad_handle(fn, "mesh", mesh);
        dfm_result r = DFM_OK;
        const mesh::Skin* skin = skin_of(fn, *m, r);
        if (skin == nullptr) return r;
        mesh::SkinPose pose;
        if (Status s = mesh::sample_pose(*skin, animation, time_seconds, pose); !s) {
            return report(fn, s);
        }
        return report(fn, m->state->poses.set_skin_pose(std::move(pose)));
    });
}

extern "C" DFM_API dfm_result dfm_mesh_set_pose_joints(dfm_mesh* mesh, const double* joint_matrices,
                                                       size_t joint_count,
                                                       const double* morph_weights,
                                                       size_t morph_weight_count) {
    constexpr const char* fn = "dfm_mesh_set_pose_joints";
    return guarded(fn, [&] {
        MeshObject* m = resolve_mesh(mesh);
        if (m == nullptr) return bad_handle(fn, "mesh", mesh);
        if (joint_matrices == nullptr && joint_count > 0) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "joint_matrices is NULL");
        }
        if (morph_weights == nullptr && morph_weight_count > 0) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "morph_weights is NULL");
        }
        dfm_result r = DFM_OK;
        const mesh::Skin* skin = skin_of(fn, *m, r);
        if (skin == nullptr) return r;
        if (joint_count != skin->joint_count()) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                          "joint_count is " + std::to_string(joint_count) + ", the skin has " +
                              std::to_string(skin->joint_count()) + " joints");
        }
        std::vector<glm::dmat4> world(joint_count);
        for (std::size_t j = 0; j < joint_count; ++j) {
            world[j] = glm::make_mat4(joint_matrices + 16 * j);
        }
        mesh::SkinPose pose;
        if (Status s = mesh::pose_from_joints(
                *skin, world, std::span<const double>(morph_weights, morph_weight_count), pose);
            !s) {
            return report(fn, s);
        }
        return report(fn, m->state->poses.set_skin_pose(std::move(pose)));
    });
}

extern "C" DFM_API dfm_result dfm_mesh_clear_pose(dfm_mesh* mesh) {
    constexpr const char* fn = "dfm_mesh_clear_pose";
    return guarded(fn, [&] {
        MeshObject* m = resolve_mesh(mesh);
        if (m == nullptr) return bad_handle(fn, "mesh", mesh);
        m->state->poses.clear_skin_pose();
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_mesh_read_joint_matrices(const dfm_mesh* mesh, double* matrices,
                                                           size_t capacity) {
    constexpr const char* fn = "dfm_mesh_read_joint_matrices";
    return guarded(fn, [&] {
        MeshObject* m = resolve_mesh(mesh);
        if (m == nullptr) return bad_handle(fn, "mesh", mesh);
        if (matrices == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "matrices is NULL");
        dfm_result r = DFM_OK;
        const mesh::Skin* skin = skin_of(fn, *m, r);
        if (skin == nullptr) return r;
        if (capacity < 16 * skin->joint_count()) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                          "room for " + std::to_string(capacity) + " doubles, " +
                              std::to_string(16 * skin->joint_count()) + " needed");
        }
        std::optional<mesh::SkinPose> pose = m->state->poses.skin_pose();
        if (!pose) {
            pose.emplace();
            if (Status s = mesh::rest_pose(*skin, *pose); !s) return report(fn, s);
        }
        for (std::size_t j = 0; j < skin->joint_count(); ++j) {
            std::memcpy(matrices + 16 * j, glm::value_ptr(pose->joint_world[j]),
                        16 * sizeof(double));
        }
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_mesh_read_bind_positions(const dfm_mesh* mesh,
                                                           const dfm_vec3_output* out) {
    constexpr const char* fn = "dfm_mesh_read_bind_positions";
    return guarded(fn, [&] {
        MeshObject* m = resolve_mesh(mesh);
        if (m == nullptr) return bad_handle(fn, "mesh", mesh);
        const auto bind = m->state->poses.bind();
        const HostNumbering numbering(*m->state, bind->mesh.vertex_count());
        if (std::string e = check_vec3_output(out, numbering.host_count(), "out"); !e.empty()) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, e);
        }
        numbering.write_all(*out, bind->mesh.positions);
        return DFM_OK;
    });
}
