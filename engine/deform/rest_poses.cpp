#include "deform/rest_poses.hpp"

namespace dfm::deform {

RestPoses::Pose RestPoses::current() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return current_;
}

Status RestPoses::add_step(const Pose& expected, Pose next, const std::function<Status()>& before) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (current_ != expected) {
        return Status(Errc::busy,
                      "the rest pose changed (a bake, an undo or another update) meanwhile; "
                      "nothing changed");
    }
    // Room first, so that running out of memory changes nothing.
    undo_.reserve(undo_.size() + 1);
    if (before) {
        if (Status s = before(); !s) return s;
    }
    undo_.push_back(std::move(current_));
    redo_.clear();
    current_ = std::move(next);
    return Status::ok();
}

bool RestPoses::step(std::vector<Pose>& from, std::vector<Pose>& to) {
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
    visit(*current_);
    for (const Pose& pose : undo_) visit(*pose);
    for (const Pose& pose : redo_) visit(*pose);
}

}  // namespace dfm::deform
