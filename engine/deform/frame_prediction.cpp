#include "deform/frame_prediction.hpp"

#include <algorithm>

#include <glm/geometric.hpp>

#include "solver/parallel_kernels.hpp"

namespace dfm::deform {

namespace {

// A host that submits faster than the solver finishes skips targets, so
// the step since the last solved frame can be many times the one before
// it; the extrapolation follows it up to this share (measured on
// sdk_bench's 60 Hz drag, where a cap of 2 left the skipped frames'
// iterations in place), and never backwards.
constexpr double largest_share = 16.0;

}  // namespace

void FramePredictor::reset(std::size_t size, std::size_t handles) {
    frames_ = 0;
    last_.assign(size, 0.0);
    before_.assign(size, 0.0);
    last_targets_.assign(handles, glm::dvec3(0.0));
    before_targets_.assign(handles, glm::dvec3(0.0));
}

void FramePredictor::record(std::span<const double> solution, std::span<const glm::dvec3> targets,
                            jobs::WorkerPool* pool) {
    std::swap(last_, before_);
    std::swap(last_targets_, before_targets_);
    solver::kernels::copy(solution, last_, pool);
    std::copy(targets.begin(), targets.end(), last_targets_.begin());
    frames_ = std::min<std::size_t>(frames_ + 1, 2);
}

bool FramePredictor::predict(std::span<const glm::dvec3> targets, std::span<double> start,
                             jobs::WorkerPool* pool) const {
    if (frames_ < 2) return false;
    // The share s of the last target step that the new one repeats, by
    // least squares: new − last ≈ s (last − before).
    double along = 0.0;
    double squared = 0.0;
    for (std::size_t h = 0; h < targets.size(); ++h) {
        const glm::dvec3 previous_step = last_targets_[h] - before_targets_[h];
        along += glm::dot(targets[h] - last_targets_[h], previous_step);
        squared += glm::dot(previous_step, previous_step);
    }
    if (!(squared > 0.0)) return false;
    const double share = std::clamp(along / squared, 0.0, largest_share);
    if (share == 0.0) return false;
    jobs::for_parts(pool, last_.size(), [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i)
            start[i] = last_[i] + share * (last_[i] - before_[i]);
    });
    return true;
}

}  // namespace dfm::deform
