#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/status.hpp"
#include "deform/async_session.hpp"
#include "deform/quality.hpp"
#include "deform/rest_poses.hpp"
#include "jobs/scheduler.hpp"

namespace dfm::deform {

// One edit as a host drives it, the engine object behind a dfm_session: the
// handle groups whose transforms or explicit targets it stages, the
// asynchronous session that solves what it submits, and its bakes into the
// mesh's rest poses, after which it starts again on the baked pose.
class Edit {
public:
    // `groups` hold vertices of the ROI, each in one group only (the caller
    // checked them against the host's numbering). `on_frame` is handed to
    // every AsyncSession the edit starts.
    static Status create(std::shared_ptr<const MeshModel> model, std::vector<std::uint32_t> roi,
                         std::vector<std::vector<std::uint32_t>> groups,
                         const DeformSettings& settings, AsyncSession::FrameHook on_frame,
                         jobs::Scheduler& scheduler, std::unique_ptr<Edit>& out);

    // Stages group `group`'s transform, a column-major 4x4 affine matrix
    // applied to the group's rest positions. Errc::out_of_range for a group
    // out of range, Errc::numerical for a matrix or a target that is not
    // finite (a finite matrix can overflow), Errc::invalid_argument for a
    // bottom row other than 0 0 0 1; nothing is staged then.
    Status set_group_transform(std::size_t group, const double* matrix);

    // Stages explicit targets: read(h) for each handle vertex h in group
    // order. Errc::invalid_argument for a count other than handle_count(),
    // Errc::numerical for a target that is not finite; nothing is staged
    // then. The one check of the targets: every later step takes them as
    // staged.
    template <class Read>
    Status set_targets(std::size_t count, Read&& read);

    std::size_t handle_count() const { return handle_vertices_.size(); }

    // Queues the staged targets; their generation.
    Status submit(std::uint64_t& generation);

    // Solves the staged targets on the calling thread; their generation.
    // `converged` is false when the solve stopped at the iteration cap.
    Status solve(std::uint64_t& generation, bool& converged);

    // A change of the solver's settings; zero fields keep their value.
    struct SolverChange {
        double tolerance = 0.0;
        int max_iterations = 0;
        double handle_weight = 0.0;
        bool hard_handles = false;
        std::optional<solver::PreconditionerKind> preconditioner;
        bool disable_prediction = false;
    };
    // Changes the stopping rule for later solves. The handle weight, hard
    // handles, preconditioner and prediction are fixed when the edit is
    // created: a different value is Errc::unsupported.
    Status change_solver(const SolverChange& change);

    // Bakes the newest finished frame, exactly as published (`generation`
    // 0), or that frame if it has `generation` (Errc::not_found otherwise),
    // into `poses` as a new step, built in `baked`, and starts the edit
    // again on the new pose with identity transforms; generations go on
    // growing. Errc::busy while a frame is held, while the set-up runs, or
    // when `poses` has another current pose than the edit's. Queued and
    // running solves are cancelled once the frame is baked, also when the
    // new step then fails (the pose changed meanwhile, out of memory).
    Status bake(RestPoses& poses, std::uint64_t generation, std::shared_ptr<MeshModel> baked);

    AsyncSession& async() { return *async_; }
    const AsyncSession& async() const { return *async_; }
    // The rest pose the edit works on (a bake replaces it).
    const MeshModel& model() const { return *model_; }
    std::span<const std::uint32_t> roi() const { return roi_; }

    // The whole rest pose's vertex normals, computed on the first call.
    const std::vector<glm::dvec3>& rest_normals();
    // The quality figures of the newest frame against the rest pose and the
    // targets staged now; `seen(frame)` is called with that frame.
    QualityReport measure_quality(const std::function<void(const Frame&)>& seen);

    // The session's bytes: the AsyncSession's, and the staging here in
    // SessionMemory::staging.
    SessionMemory memory() const;

private:
    Edit(jobs::Scheduler& scheduler) : scheduler_(scheduler) {}
    // Makes an AsyncSession on `model` (after a bake: the baked pose), its
    // set-up not yet queued (AsyncSession::begin), and stages identity
    // transforms; the earlier one goes to `previous` only once the new one
    // exists, so a failure leaves the edit as it was. The caller stops the
    // earlier one and queues the set-up with no lock held: both may call
    // the host (on_frame, the job system's enqueue).
    Status start(std::shared_ptr<const MeshModel> model, std::uint64_t first_generation,
                 std::uint64_t submitted_through, std::unique_ptr<AsyncSession>& previous);

    jobs::Scheduler& scheduler_;
    std::shared_ptr<const MeshModel> model_;
    std::vector<std::uint32_t> roi_;
    std::vector<std::vector<std::uint32_t>> groups_;
    std::vector<std::uint32_t> handle_vertices_;  // the groups' vertices, in order
    std::vector<std::size_t> group_offsets_;      // group g: [offsets[g], offsets[g + 1])
    DeformSettings settings_;
    AsyncSession::FrameHook on_frame_;
    // The staged targets, one per handle vertex, and the handles' rest
    // positions the transforms apply to. A submit copies them under the
    // lock, which no solve holds, and lets it go before the scheduler hears
    // of them.
    mutable std::mutex staging_mutex_;
    std::vector<glm::dvec3> staged_;
    std::vector<glm::dvec3> handle_rest_;
    // What solve() solves: the staged targets, copied out so that the solve
    // holds no staging lock, into memory set up with the edit.
    std::mutex solving_mutex_;
    std::vector<glm::dvec3> solving_;
    mutable std::mutex rest_normals_mutex_;
    std::vector<glm::dvec3> rest_normals_;
    std::unique_ptr<AsyncSession> async_;  // last: stopped before the rest goes
};

template <class Read>
Status Edit::set_targets(std::size_t count, Read&& read) {
    std::lock_guard<std::mutex> lock(staging_mutex_);
    if (count != staged_.size()) {
        return Status(Errc::invalid_argument,
                      "the targets are " + std::to_string(count) + ", the session has " +
                          std::to_string(staged_.size()) + " handle vertices");
    }
    for (std::size_t h = 0; h < count; ++h) {
        const glm::dvec3 t = read(h);
        if (!std::isfinite(t.x) || !std::isfinite(t.y) || !std::isfinite(t.z)) {
            return Status(Errc::numerical,
                          "target " + std::to_string(h) + " is not finite; nothing was staged");
        }
    }
    for (std::size_t h = 0; h < count; ++h) staged_[h] = read(h);
    return Status::ok();
}

}  // namespace dfm::deform
