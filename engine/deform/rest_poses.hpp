#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <vector>

#include "core/status.hpp"
#include "deform/mesh_model.hpp"
#include "mesh/skin_pose.hpp"

namespace dfm::deform {

// A mesh's history of rest poses: the current one, the earlier ones undo
// brings back and the undone ones redo brings back. A bake or a host's new
// positions add a step (and forget what could be redone). Thread-safe.
//
// A mesh with a skin (mesh/skin.hpp) keeps its history in bind space, and
// may be posed: then the rest pose every edit sees, picks and reads is the
// current bind-space pose skinned at that pose (built on first need), and a
// step given in that posed space is kept as its exact bind-space corrective
// (mesh::corrective_positions). Without a pose, or without a skin, the
// shown pose is the bind-space one, as it always was.
class RestPoses {
public:
    using Pose = std::shared_ptr<const MeshModel>;
    // A new model record, for the shapes the history builds itself (the SDK
    // takes them from the host's allocator).
    using MakeModel = std::function<std::shared_ptr<MeshModel>()>;

    explicit RestPoses(Pose first, std::shared_ptr<const mesh::Skin> skin = nullptr,
                       MakeModel make_model = nullptr);

    // The rest pose as shown: the bind-space one, or the posed one.
    Pose current() const;
    // The current bind-space rest pose: what a save of a skinned asset writes.
    Pose bind() const;
    // Calls `visit(bind, positions)` under the lock with the current
    // bind-space pose and the positions shown: a reader of the shown shape
    // that needs no posed model (its dual Laplacian) gets them without
    // building it, as skinned when the pose was set.
    void read_shown(
        const std::function<void(const MeshModel&, std::span<const glm::dvec3>)>& visit) const;

    // Makes `next` the current pose, a new step of the history, if `expected`
    // is still the current (shown) one; `before` runs first under the
    // history's lock (a session's restart on the new pose), and a failure
    // there changes nothing. Errc::busy (nothing changed) when the pose
    // changed. On a posed mesh `next` is in the posed space: the step keeps
    // its bind-space corrective, and `next` stays the shown pose.
    Status add_step(const Pose& expected, Pose next, const std::function<Status()>& before);

    // Undo: the current pose goes to the redo list and the last earlier one
    // returns; redo the other way round. False when there is none.
    bool undo();
    bool redo();

    std::size_t undo_count() const;
    std::size_t redo_count() const;

    // Calls `visit(pose)` for the current shown pose, then every other model
    // the history holds (bind-space poses behind posed ones, the poses undo
    // or redo can bring back), under the lock.
    void for_each(const std::function<void(const MeshModel&)>& visit) const;

    // The skin, or null.
    const mesh::Skin* skin() const { return skin_.get(); }
    // Poses the mesh (its joint matrices and morph weights, checked by the
    // caller against the skin): the shown rest pose changes, so sessions
    // made before can no longer bake. Errc::unsupported without a skin.
    Status set_skin_pose(mesh::SkinPose pose);
    // Back to the bind space.
    void clear_skin_pose();
    // The pose set, if any.
    std::optional<mesh::SkinPose> skin_pose() const;
    // What the last step in the posed space found of its corrective.
    mesh::CorrectiveReport last_corrective() const;

private:
    struct Step {
        Pose bind;
        // The bind pose skinned at the pose of version `shown_for`.
        mutable Pose shown;
        mutable std::uint64_t shown_for = 0;
    };
    const Pose& shown_locked(const Step& step) const;
    // The current bind pose's positions at the pose set (posed_), skinned
    // now unless they already are.
    const std::vector<glm::dvec3>& posed_locked() const;
    bool step(std::vector<Step>& from, std::vector<Step>& to);
    std::shared_ptr<MeshModel> make_model() const;

    mutable std::mutex mutex_;
    Step current_;
    std::vector<Step> undo_;
    std::vector<Step> redo_;
    std::shared_ptr<const mesh::Skin> skin_;
    MakeModel make_model_;
    std::optional<mesh::SkinPose> pose_;
    std::uint64_t pose_version_ = 0;  // grows with every set_skin_pose
    // The positions of the bind pose `posed_of_` at pose version
    // `posed_for_`: what set_skin_pose skinned, kept for the reads and the
    // posed model that follow.
    mutable std::vector<glm::dvec3> posed_;
    mutable Pose posed_of_;  // held, so that no later model takes its address
    mutable std::uint64_t posed_for_ = 0;
    mesh::CorrectiveReport last_corrective_;
};

}  // namespace dfm::deform
