#include "deform/edit.hpp"

#include <algorithm>
#include <initializer_list>
#include <new>

#include "core/memory_bytes.hpp"
#include "core/number_text.hpp"
#include "mesh/normals.hpp"

namespace dfm::deform {

Status Edit::create(std::shared_ptr<const MeshModel> model, std::vector<std::uint32_t> roi,
                    std::vector<std::vector<std::uint32_t>> groups, const DeformSettings& settings,
                    AsyncSession::FrameHook on_frame, jobs::Scheduler& scheduler,
                    std::unique_ptr<Edit>& out) {
    out.reset();
    std::unique_ptr<Edit> e(new Edit(scheduler));
    e->roi_ = std::move(roi);
    e->group_offsets_.push_back(0);
    for (const std::vector<std::uint32_t>& group : groups) {
        e->handle_vertices_.insert(e->handle_vertices_.end(), group.begin(), group.end());
        e->group_offsets_.push_back(e->handle_vertices_.size());
    }
    e->groups_ = std::move(groups);
    e->settings_ = settings;
    e->settings_.pool = &scheduler;
    e->on_frame_ = std::move(on_frame);
    e->solving_.resize(e->handle_vertices_.size());
    std::unique_ptr<AsyncSession> none;
    if (Status s = e->start(std::move(model), 0, 0, none); !s) return s;
    e->async_->begin();
    out = std::move(e);
    return Status::ok();
}

Status Edit::start(std::shared_ptr<const MeshModel> model, std::uint64_t first_generation,
                   std::uint64_t submitted_through, std::unique_ptr<AsyncSession>& previous) {
    std::vector<glm::dvec3> handle_rest;
    handle_rest.reserve(handle_vertices_.size());
    for (std::uint32_t v : handle_vertices_) handle_rest.push_back(model->mesh.positions[v]);
    AsyncSession::Setup setup = [model, this, settings = settings_](
                                    std::unique_ptr<DeformSession>& out,
                                    const std::atomic<bool>* stop) {
        return DeformSession::create(*model, roi_, groups_, settings, out, stop);
    };
    AsyncSession::Start start;
    start.first_generation = first_generation;
    start.submitted_through = submitted_through;
    start.on_frame = on_frame_;
    std::unique_ptr<AsyncSession> async;
    if (Status s = AsyncSession::create(*model, roi_, handle_vertices_, std::move(setup),
                                        std::move(start), scheduler_, async);
        !s) {
        return s;
    }
    {
        std::lock_guard<std::mutex> lock(staging_mutex_);
        previous = std::move(async_);
        async_ = std::move(async);
        model_ = std::move(model);
        staged_ = handle_rest;
        handle_rest_ = std::move(handle_rest);
    }
    std::lock_guard<std::mutex> lock(rest_normals_mutex_);
    rest_normals_.clear();
    return Status::ok();
}

Status Edit::set_group_transform(std::size_t group, const double* matrix) {
    if (group >= groups_.size()) {
        return Status(Errc::out_of_range, "group " + std::to_string(group) +
                                              " is out of range (the session has " +
                                              std::to_string(groups_.size()) + ")");
    }
    for (int i = 0; i < 16; ++i) {
        if (!std::isfinite(matrix[i])) {
            return Status(Errc::numerical,
                          "matrix element " + std::to_string(i) + " is not finite");
        }
    }
    // An all-zero or row-major matrix fails here instead of collapsing or
    // misplacing the group.
    if (matrix[3] != 0.0 || matrix[7] != 0.0 || matrix[11] != 0.0 || matrix[15] != 1.0) {
        std::string message =
            "matrix: the bottom row (elements 3, 7, 11, 15, column-major) must be 0 0 0 1 "
            "for an affine transform; found";
        for (const int i : {3, 7, 11, 15}) {
            message += ' ';
            append_number(message, matrix[i]);
        }
        return Status(Errc::invalid_argument, message);
    }
    const auto target = [&](const glm::dvec3& p) {
        glm::dvec3 t;
        for (int c = 0; c < 3; ++c) {
            t[c] = matrix[c] * p.x + matrix[4 + c] * p.y + matrix[8 + c] * p.z + matrix[12 + c];
        }
        return t;
    };
    std::lock_guard<std::mutex> lock(staging_mutex_);
    const std::size_t begin = group_offsets_[group];
    const std::size_t end = group_offsets_[group + 1];
    for (std::size_t h = begin; h < end; ++h) {
        const glm::dvec3 t = target(handle_rest_[h]);
        if (!std::isfinite(t.x) || !std::isfinite(t.y) || !std::isfinite(t.z)) {
            return Status(Errc::numerical, "the matrix takes vertex " + std::to_string(h - begin) +
                                               " of group " + std::to_string(group) +
                                               " beyond the finite numbers; nothing was staged");
        }
    }
    for (std::size_t h = begin; h < end; ++h) staged_[h] = target(handle_rest_[h]);
    return Status::ok();
}

Status Edit::submit(std::uint64_t& generation) {
    // The queue takes its copy under the staging lock, so no other
    // thread's staging can change what is read.
    std::unique_lock<std::mutex> lock(staging_mutex_);
    return async_->submit(staged_, lock, generation);
}

Status Edit::solve(std::uint64_t& generation, bool& converged) {
    converged = false;
    std::lock_guard<std::mutex> solving(solving_mutex_);
    {
        std::lock_guard<std::mutex> lock(staging_mutex_);
        std::copy(staged_.begin(), staged_.end(), solving_.begin());
    }
    if (Status s = async_->solve_now(solving_, generation); !s) return s;
    async_->read([&](const Frame& f) { converged = f.report.converged; });
    return Status::ok();
}

Status Edit::change_solver(const SolverChange& change) {
    if ((change.handle_weight != 0.0 && change.handle_weight != settings_.handle_weight) ||
        (change.hard_handles && !settings_.hard_handles)) {
        return Status(Errc::unsupported,
                      "handle_weight and hard_handles are fixed when the session is created");
    }
    if ((change.preconditioner && *change.preconditioner != settings_.preconditioner) ||
        (change.disable_prediction && settings_.predict_frames)) {
        return Status(Errc::unsupported,
                      "preconditioner and disable_prediction are fixed when the session is "
                      "created");
    }
    DeformSettings next = settings_;
    if (change.tolerance != 0.0) next.tolerance = change.tolerance;
    if (change.max_iterations != 0) next.max_iterations = change.max_iterations;
    if (Status s = async_->set_stopping_rule(next.tolerance, next.max_iterations); !s) return s;
    settings_ = next;
    return Status::ok();
}

Status Edit::bake(RestPoses& poses, std::uint64_t generation, std::shared_ptr<MeshModel> baked) {
    if (async_->holding()) {
        return Status(Errc::busy, "a frame is held; release it before baking");
    }
    if (async_->preparing()) {
        return Status(Errc::busy, "the session is preparing: nothing is solved yet to bake");
    }
    if (Status s = async_->setup_status(); !s) return s;
    if (poses.current() != model_) {
        return Status(Errc::busy,
                      "the mesh's rest pose changed (a bake, an undo or new positions) since "
                      "this session started; create a new session to edit it");
    }
    // The frame exactly as it was published: what the host showed.
    std::vector<glm::dvec3> positions = model_->mesh.positions;
    const std::span<const std::uint32_t> moving = async_->moving();
    std::uint64_t baked_generation = 0;
    const bool found = async_->read_finished(generation, [&](const Frame& f) {
        for (std::size_t i = 0; i < moving.size(); ++i) positions[moving[i]] = f.positions[i];
        baked_generation = f.generation;
    });
    if (!found) {
        std::uint64_t newest = 0;
        async_->read_finished(0, [&](const Frame& f) { newest = f.generation; });
        return Status(Errc::not_found, "generation " + std::to_string(generation) +
                                           " is not the newest finished frame (that is "
                                           "generation " +
                                           std::to_string(newest) + ")");
    }
    if (Status s = bake_positions(*model_, positions, *baked); !s) return s;
    // The restart runs under the history's lock, between the check that the
    // pose is still the edit's and the new step, so that no other bake or
    // undo slips in; it does not wait for the new set-up.
    const std::shared_ptr<const MeshModel> from = model_;
    const std::uint64_t submitted = async_->submitted_generation();
    // The session's solve stops first, with no lock held: its frames and
    // their on_frame, which may call the library, end before the edit turns
    // to the new session.
    async_->cancel();
    std::unique_ptr<AsyncSession> previous;
    const Status restarted = poses.add_step(
        from, baked, [&] { return start(baked, baked_generation, submitted, previous); });
    // With the lock let go: the earlier session goes and the new set-up is
    // queued (which may call the host's job system).
    previous.reset();
    if (restarted) async_->begin();
    return restarted;
}

const std::vector<glm::dvec3>& Edit::rest_normals() {
    std::lock_guard<std::mutex> lock(rest_normals_mutex_);
    if (rest_normals_.empty()) {
        mesh::compute_vertex_normals(model_->mesh, model_->mesh.positions, rest_normals_);
    }
    return rest_normals_;
}

QualityReport Edit::measure_quality(const std::function<void(const Frame&)>& seen) {
    const MeshModel& model = *model_;
    std::vector<glm::dvec3> deformed = model.mesh.positions;
    std::vector<std::uint8_t> in_roi(model.mesh.vertex_count(), 0);
    for (const std::uint32_t v : roi_) in_roi[v] = 1;
    const std::span<const std::uint32_t> moving = async_->moving();
    async_->read([&](const Frame& f) {
        for (std::size_t i = 0; i < moving.size(); ++i) deformed[moving[i]] = f.positions[i];
        seen(f);
    });
    std::vector<glm::dvec3> targets;
    {
        std::lock_guard<std::mutex> lock(staging_mutex_);
        targets = staged_;
    }
    return deform::measure_quality(model, deformed, in_roi, handle_vertices_, targets);
}

SessionMemory Edit::memory() const {
    SessionMemory m;
    std::size_t staging = capacity_bytes(roi_, groups_, handle_vertices_, group_offsets_);
    for (const std::vector<std::uint32_t>& group : groups_) staging += capacity_bytes(group);
    {
        std::lock_guard<std::mutex> lock(staging_mutex_);
        m = async_->memory();
        staging += capacity_bytes(staged_, handle_rest_, solving_);
    }
    {
        std::lock_guard<std::mutex> lock(rest_normals_mutex_);
        staging += capacity_bytes(rest_normals_);
    }
    m.staging += staging;
    return m;
}

}  // namespace dfm::deform
