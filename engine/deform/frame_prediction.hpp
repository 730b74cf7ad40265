#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/memory_bytes.hpp"
#include "core/pooled_allocator.hpp"
#include "jobs/worker_pool.hpp"

namespace dfm::deform {

// Predicts where the next frame of a drag converges from the two frames
// before it. A drag moves the targets smoothly, and the solution follows
// them smoothly, so extrapolating the last step of the solution by the
// share of the last target step that the new one repeats starts the outer
// iteration much closer to its fixed point than the last frame does. Only
// the start changes: the iteration still runs to its tolerance, so the
// fixed point it reaches is the same.
// Linear, not of higher order: near its fixed point the iteration contracts
// slowly (a frame's steps shrink by about 0.93 each on the whole armadillo),
// so a frame that stops at the tolerance still lies several tolerances off,
// and each extrapolation carries that error on. From two frames it stays
// bounded; a quadratic from three amplified it, and the whole armadillo's
// drag took up to 13 iterations a frame instead of 3.
class FramePredictor {
public:
    // Sizes the history for `size` unknowns (interleaved x, y, z) and
    // `handles` targets, and forgets every frame.
    void reset(std::size_t size, std::size_t handles);

    // Forgets every frame (the positions were replaced): the next starts
    // are not predicted until two frames have converged again.
    void forget() { frames_ = 0; }

    // Records a converged frame: its solution and the targets it was for.
    // `pool` (optional) spreads the copy; the same bits either way.
    void record(std::span<const double> solution, std::span<const glm::dvec3> targets,
                jobs::WorkerPool* pool = nullptr);

    // Writes the predicted solution for `targets` into `start` and returns
    // true, or leaves `start` alone and returns false when fewer than two
    // frames are known or the last target step was zero. `pool` as record's.
    bool predict(std::span<const glm::dvec3> targets, std::span<double> start,
                 jobs::WorkerPool* pool = nullptr) const;

    std::size_t memory_bytes() const {
        return capacity_bytes(last_, before_, last_targets_, before_targets_);
    }

private:
    std::size_t frames_ = 0;  // recorded since the last forget, at most 2 used
    PooledVector<double> last_, before_;
    std::vector<glm::dvec3> last_targets_, before_targets_;
};

}  // namespace dfm::deform
