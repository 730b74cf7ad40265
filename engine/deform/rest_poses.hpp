#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include "core/status.hpp"
#include "deform/mesh_model.hpp"

namespace dfm::deform {

// A mesh's history of rest poses: the current one, the earlier ones undo
// brings back and the undone ones redo brings back. A bake or a host's new
// positions add a step (and forget what could be redone). Thread-safe.
class RestPoses {
public:
    using Pose = std::shared_ptr<const MeshModel>;

    explicit RestPoses(Pose first) : current_(std::move(first)) {}

    Pose current() const;

    // Makes `next` the current pose, a new step of the history, if `expected`
    // is still the current one; `before` runs first under the history's lock
    // (a session's restart on the new pose), and a failure there changes
    // nothing. Errc::busy (nothing changed) when the pose changed.
    Status add_step(const Pose& expected, Pose next, const std::function<Status()>& before);

    // Undo: the current pose goes to the redo list and the last earlier one
    // returns; redo the other way round. False when there is none.
    bool undo();
    bool redo();

    std::size_t undo_count() const;
    std::size_t redo_count() const;

    // Calls `visit(pose)` for the current pose and each one undo or redo can
    // bring back, under the lock.
    void for_each(const std::function<void(const MeshModel&)>& visit) const;

private:
    bool step(std::vector<Pose>& from, std::vector<Pose>& to);

    mutable std::mutex mutex_;
    Pose current_;
    std::vector<Pose> undo_;
    std::vector<Pose> redo_;
};

}  // namespace dfm::deform
