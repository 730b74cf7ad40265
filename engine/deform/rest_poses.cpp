#include "deform/rest_poses.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace dfm::deform {

RestPoses::RestPoses(Pose first, std::shared_ptr<const mesh::Skin> skin, MakeModel make_model)
    : skin_(std::move(skin)), make_model_(std::move(make_model)) {
    current_.bind = std::move(first);
}

std::shared_ptr<MeshModel> RestPoses::make_model() const {
    return make_model_ ? make_model_() : std::make_shared<MeshModel>();
}

const std::vector<glm::dvec3>& RestPoses::posed_locked() const {
    if (posed_of_ != current_.bind || posed_for_ != pose_version_) {
        const MeshModel& bind = *current_.bind;
        posed_.resize(bind.mesh.vertex_count());
        mesh::pose_positions(*skin_, *pose_, bind.mesh.positions, posed_);
        posed_of_ = current_.bind;
        posed_for_ = pose_version_;
    }
    return posed_;
}

const RestPoses::Pose& RestPoses::shown_locked(const Step& step) const {
    if (!pose_) return step.bind;
    if (step.shown && step.shown_for == pose_version_) return step.shown;
    const MeshModel& bind = *step.bind;
    std::vector<glm::dvec3> posed;
    if (&step == &current_) {
        posed = posed_locked();
    } else {
        posed.resize(bind.mesh.vertex_count());
        mesh::pose_positions(*skin_, *pose_, bind.mesh.positions, posed);
    }
    std::shared_ptr<MeshModel> model = make_model();
    if (Status s = bake_positions(bind, posed, *model); !s) {
        // set_skin_pose checked the current shape posed; a shape that undo
        // or redo brings back can still overflow under that pose, which the
        // caller's guard reports.
        throw std::runtime_error("posing the rest pose: " + s.message());
    }
    step.shown = std::move(model);
    step.shown_for = pose_version_;
    return step.shown;
}

RestPoses::Pose RestPoses::current() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return shown_locked(current_);
}

RestPoses::Pose RestPoses::bind() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return current_.bind;
}

void RestPoses::read_shown(
    const std::function<void(const MeshModel&, std::span<const glm::dvec3>)>& visit) const {
    std::lock_guard<std::mutex> lock(mutex_);
    const MeshModel& bind = *current_.bind;
    if (!pose_) {
        visit(bind, bind.mesh.positions);
    } else if (current_.shown && current_.shown_for == pose_version_) {
        visit(bind, current_.shown->mesh.positions);
    } else {
        visit(bind, posed_locked());
    }
}

Status RestPoses::add_step(const Pose& expected, Pose next, const std::function<Status()>& before) {
    std::lock_guard<std::mutex> lock(mutex_);
    const bool posed = pose_.has_value();
    if ((posed ? current_.shown : current_.bind) != expected ||
        (posed && current_.shown_for != pose_version_)) {
        return Status(Errc::busy,
                      "the rest pose changed (a bake, an undo, a new pose or another update) "
                      "meanwhile; nothing changed");
    }
    Step added;
    mesh::CorrectiveReport corrective;
    if (posed) {
        // The edit in the posed space, kept as its bind-space corrective.
        const MeshModel& bind = *current_.bind;
        std::vector<glm::dvec3> bind_after;
        mesh::corrective_positions(*skin_, *pose_, bind.mesh.positions,
                                   current_.shown->mesh.positions, next->mesh.positions, bind_after,
                                   corrective);
        std::shared_ptr<MeshModel> model = make_model();
        if (Status s = bake_positions(bind, bind_after, *model); !s) return s;
        added.bind = std::move(model);
        added.shown = std::move(next);
        added.shown_for = pose_version_;
    } else {
        added.bind = std::move(next);
    }
    // Room first, so that running out of memory changes nothing.
    undo_.reserve(undo_.size() + 1);
    if (before) {
        if (Status s = before(); !s) return s;
    }
    undo_.push_back(std::move(current_));
    redo_.clear();
    current_ = std::move(added);
    if (posed) last_corrective_ = std::move(corrective);
    return Status::ok();
}

bool RestPoses::step(std::vector<Step>& from, std::vector<Step>& to) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (from.empty()) return false;
    to.reserve(to.size() + 1);
    to.push_back(std::move(current_));
    current_ = std::move(from.back());
    from.pop_back();
    return true;
}

bool RestPoses::undo() {
    return step(undo_, redo_);
}

bool RestPoses::redo() {
    return step(redo_, undo_);
}

std::size_t RestPoses::undo_count() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return undo_.size();
}

std::size_t RestPoses::redo_count() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return redo_.size();
}

void RestPoses::for_each(const std::function<void(const MeshModel&)>& visit) const {
    std::lock_guard<std::mutex> lock(mutex_);
    const Pose& shown = shown_locked(current_);
    visit(*shown);
    const auto rest = [&](const Step& s) {
        if (s.bind != shown) visit(*s.bind);
        if (s.shown && s.shown != shown) visit(*s.shown);
    };
    rest(current_);
    for (const Step& s : undo_) rest(s);
    for (const Step& s : redo_) rest(s);
}

Status RestPoses::set_skin_pose(mesh::SkinPose pose) {
    if (!skin_) return Status(Errc::unsupported, "the mesh has no skin to pose");
    std::lock_guard<std::mutex> lock(mutex_);
    const MeshModel& bind = *current_.bind;
    std::vector<glm::dvec3> posed(bind.mesh.vertex_count());
    mesh::pose_positions(*skin_, pose, bind.mesh.positions, posed);
    for (const glm::dvec3& p : posed) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            return Status(Errc::numerical,
                          "the pose puts vertices at positions that are not finite (its "
                          "matrices overflow the shape); the pose was not set");
        }
    }
    pose_ = std::move(pose);
    ++pose_version_;
    posed_ = std::move(posed);
    posed_of_ = current_.bind;
    posed_for_ = pose_version_;
    return Status::ok();
}

void RestPoses::clear_skin_pose() {
    std::lock_guard<std::mutex> lock(mutex_);
    pose_.reset();
    ++pose_version_;
    posed_of_.reset();
    posed_.clear();
}

std::optional<mesh::SkinPose> RestPoses::skin_pose() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return pose_;
}

mesh::CorrectiveReport RestPoses::last_corrective() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return last_corrective_;
}

}  // namespace dfm::deform
