#include <chrono>
#include <cmath>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <string>
#include <type_traits>

#include "c_boundary.hpp"
#include "core/number_text.hpp"
#include "host_numbering.hpp"
#include "mesh/normals.hpp"
#include "objects.hpp"
#include "shared_calls.hpp"
#include "vec3_arrays.hpp"

using namespace dfm;
using namespace dfm::sdk;

void dfm::sdk::fill_frame_info(const deform::Frame& frame, dfm_frame_info* out) {
    if (out == nullptr) return;
    out->generation = frame.generation;
    out->status = to_result(frame.status);
    out->converged = frame.report.converged;
    out->partial = frame.partial;
    out->iterations = static_cast<std::uint32_t>(frame.report.iterations);
    out->last_update = frame.report.last_update;
    out->solve_ms = frame.report.solve_ms;
    out->checksum = frame.checksum;
    out->preparing = frame.preparing;
}

namespace {

constexpr double default_tolerance = 1e-5;
constexpr std::uint32_t default_max_iterations = 100;
// What struct_size 0 stands for: dfm_session_desc as version 0.2 had it.
constexpr std::size_t session_desc_0_2 = DFM_END_OF(dfm_session_desc, on_frame_user);

// The field read as an integer, as the method: a host may pass any value.
std::underlying_type_t<dfm_preconditioner> preconditioner_value(const dfm_preconditioner& in) {
    std::underlying_type_t<dfm_preconditioner> value;
    std::memcpy(&value, &in, sizeof value);
    return value;
}

// False for a value no enumerator has.
bool preconditioner_from(const dfm_preconditioner& in, solver::PreconditionerKind& out) {
    switch (preconditioner_value(in)) {
        case DFM_PRECONDITIONER_DEFAULT:
        case DFM_PRECONDITIONER_CHOLESKY: out = solver::PreconditionerKind::cholesky; return true;
        case DFM_PRECONDITIONER_INCOMPLETE_CHOLESKY:
            out = solver::PreconditionerKind::incomplete_cholesky;
            return true;
        case DFM_PRECONDITIONER_JACOBI: out = solver::PreconditionerKind::jacobi; return true;
        default: return false;
    }
}

Status settings_from(const dfm_solver_settings& in, deform::DeformSettings& out) {
    for (std::size_t i = 0; i < std::size(in.reserved); ++i) {
        if (in.reserved[i] != 0) {
            return Status(Errc::unsupported, "solver.reserved[" + std::to_string(i) +
                                                 "] is not zero: a setting this library does "
                                                 "not know");
        }
    }
    out.tolerance = in.tolerance != 0.0 ? in.tolerance : default_tolerance;
    out.max_iterations = static_cast<int>(in.max_iterations != 0
                                              ? std::min<std::uint32_t>(in.max_iterations, 1000000)
                                              : default_max_iterations);
    out.handle_weight = in.handle_weight != 0.0 ? in.handle_weight : 1.0;
    out.hard_handles = in.hard_handles;
    std::underlying_type_t<dfm_method> method;  // read as an integer: a host may pass any value
    std::memcpy(&method, &in.method, sizeof method);
    if (method != DFM_METHOD_DEFAULT && method != DFM_METHOD_FITTED_ROTATIONS &&
        method != DFM_METHOD_PAPER) {
        return Status(Errc::invalid_argument, "solver.method: unknown method " +
                                                  std::to_string(method) +
                                                  " (DFM_METHOD_DEFAULT, _FITTED_ROTATIONS or "
                                                  "_PAPER expected)");
    }
    out.method = method == DFM_METHOD_PAPER ? deform::DeformMethod::paper
                                            : deform::DeformMethod::fitted_rotations;
    if (!preconditioner_from(in.preconditioner, out.preconditioner)) {
        return Status(Errc::invalid_argument,
                      "solver.preconditioner: unknown preconditioner " +
                          std::to_string(preconditioner_value(in.preconditioner)) +
                          " (DFM_PRECONDITIONER_DEFAULT, _CHOLESKY, _INCOMPLETE_CHOLESKY or "
                          "_JACOBI expected)");
    }
    out.predict_frames = !in.disable_prediction;
    if (!(out.tolerance > 0.0) || !std::isfinite(out.tolerance)) {
        return Status(Errc::invalid_argument, "solver.tolerance must be positive and finite");
    }
    if (!(out.handle_weight > 0.0) || !std::isfinite(out.handle_weight)) {
        return Status(Errc::invalid_argument, "solver.handle_weight must be positive and finite");
    }
    return Status::ok();
}

// The handle groups (surface vertices) against the ROI, here on the
// caller's thread so that create reports them at once: every vertex in
// range, in the ROI and in one place only. Messages name the host's index.
Status check_groups(std::size_t vertex_count, std::span<const std::uint32_t> roi,
                    const std::vector<std::vector<std::uint32_t>>& groups,
                    const HostNumbering& numbering) {
    std::vector<std::uint8_t> in_roi(vertex_count, 0);
    for (std::uint32_t v : roi) in_roi[v] = 1;
    constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
    std::vector<std::uint32_t> group_of(vertex_count, none);
    std::vector<std::uint32_t> entry_of(vertex_count, 0);
    for (std::size_t g = 0; g < groups.size(); ++g) {
        for (std::size_t i = 0; i < groups[g].size(); ++i) {
            const std::uint32_t v = groups[g][i];
            const std::string where = "handle group " + std::to_string(g) + " entry " +
                                      std::to_string(i) + ": vertex " +
                                      std::to_string(v < vertex_count ? numbering.to_host(v) : v);
            if (v >= vertex_count) {
                return Status(Errc::out_of_range, where + " is out of range (the mesh has " +
                                                      std::to_string(vertex_count) + " vertices)");
            }
            if (!in_roi[v]) return Status(Errc::invalid_argument, where + " is outside the ROI");
            if (group_of[v] == g) {
                return Status(
                    Errc::invalid_argument,
                    where + " repeats entry " + std::to_string(entry_of[v]) + " of the same group");
            }
            if (group_of[v] != none) {
                return Status(Errc::invalid_argument,
                              where + " is in group " + std::to_string(group_of[v]) +
                                  " too (entry " + std::to_string(entry_of[v]) +
                                  "); a vertex follows one group");
            }
            group_of[v] = static_cast<std::uint32_t>(g);
            entry_of[v] = static_cast<std::uint32_t>(i);
        }
    }
    return Status::ok();
}

// Starts (or restarts, after a bake) the session's worker on `model`: the
// set-up runs there. The session's earlier worker is stopped only once the
// new one exists, so a failure leaves the session as it was.
Status start_worker(SessionObject& s, std::shared_ptr<const deform::MeshModel> model,
                    std::uint64_t first_generation, std::uint64_t submitted_through) {
    const std::uint32_t workers = s.mesh->context->worker_count;
    std::unique_ptr<solver::ThreadPool> pool;
    if (workers > 1) pool = std::make_unique<solver::ThreadPool>(workers);
    deform::DeformSettings settings = s.settings;
    settings.pool = pool.get();
    std::vector<glm::dvec3> handle_rest;
    handle_rest.reserve(s.handle_vertices.size());
    for (std::uint32_t v : s.handle_vertices) handle_rest.push_back(model->mesh.positions[v]);
    deform::AsyncSession::Setup setup = [model, &roi = s.roi, &groups = s.groups, settings](
                                            std::unique_ptr<deform::DeformSession>& out,
                                            const std::atomic<bool>* stop) {
        return deform::DeformSession::create(*model, roi, groups, settings, out, stop);
    };
    deform::AsyncSession::Start start;
    start.first_generation = first_generation;
    start.submitted_through = submitted_through;
    if (s.on_frame != nullptr) {
        start.on_frame = [fn = s.on_frame, user = s.on_frame_user,
                          handle = s.handle](const deform::Frame& frame) {
            dfm_frame_info info{};
            fill_frame_info(frame, &info);
            fn(user, handle, &info);
        };
    }
    std::unique_ptr<deform::AsyncSession> async;
    if (Status st = deform::AsyncSession::create(*model, s.roi, s.handle_vertices, std::move(setup),
                                                 std::move(start), async);
        !st) {
        return st;
    }
    {
        std::lock_guard<std::mutex> lock(s.staging_mutex);
        s.async.reset();
        s.pool = std::move(pool);
        s.async = std::move(async);
        s.model = std::move(model);
        s.staged = handle_rest;
        s.solving = handle_rest;
        s.handle_rest = std::move(handle_rest);
    }
    std::lock_guard<std::mutex> lock(s.rest_normals_mutex);
    s.rest_normals.clear();
    return Status::ok();
}

// Resolves the session handle of a call, or records why it is not live.
SessionObject* session_of(const char* fn, const dfm_session* session, dfm_result& result) {
    SessionObject* s = resolve_session(session);
    if (s == nullptr) result = bad_handle(fn, "session", session);
    return s;
}

}  // namespace

extern "C" DFM_API dfm_result dfm_session_create(dfm_mesh* mesh, const dfm_session_desc* desc,
                                                 dfm_session** out) {
    constexpr const char* fn = "dfm_session_create";
    return guarded(fn, [&] {
        if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
        *out = nullptr;
        MeshObject* m = resolve_mesh(mesh);
        if (m == nullptr) return bad_handle(fn, "mesh", mesh);
        dfm_session_desc d;
        if (dfm_result r = read_descriptor(fn, "desc", desc, session_desc_0_2, d); r != DFM_OK) {
            return r;
        }
        RoiObject* roi = resolve_roi(d.roi);
        if (roi == nullptr) return bad_handle(fn, "desc->roi", d.roi);
        if (roi->mesh != m->state) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "desc->roi belongs to another mesh");
        }
        if (d.groups == nullptr || d.group_count == 0) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                          "the edit needs at least one handle group");
        }
        for (std::size_t g = 0; g < d.group_count; ++g) {
            if (d.groups[g].vertices == nullptr || d.groups[g].count == 0) {
                return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                              "handle group " + std::to_string(g) + " is empty");
            }
        }
        deform::DeformSettings settings;
        if (Status s = settings_from(d.solver, settings); !s) return report(fn, s);
        std::vector<std::vector<std::uint32_t>> groups(d.group_count);
        std::vector<std::size_t> offsets{0};
        for (std::size_t g = 0; g < groups.size(); ++g) {
            groups[g].assign(d.groups[g].vertices, d.groups[g].vertices + d.groups[g].count);
            offsets.push_back(offsets.back() + groups[g].size());
        }
        const auto model = m->state->current();
        const HostNumbering numbering(*m->state, model->mesh.vertex_count());
        for (std::size_t g = 0; g < groups.size(); ++g) {
            if (Status s =
                    numbering.to_surface(groups[g], "handle group " + std::to_string(g), groups[g]);
                !s) {
                return report(fn, s);
            }
        }
        if (Status s = check_groups(model->mesh.vertex_count(), roi->vertices, groups, numbering);
            !s) {
            return report(fn, s);
        }
        dfm_session* handle = host_new<SessionObject>(*m->state->context);
        SessionObject& session = *resolve_session(handle);
        // Filling the session allocates too; a failure there must not leave
        // a live, half-built handle behind.
        try {
            session.mesh = m->state;
            session.roi = roi->vertices;
            for (const auto& group : groups) {
                session.handle_vertices.insert(session.handle_vertices.end(), group.begin(),
                                               group.end());
            }
            session.groups = std::move(groups);
            session.group_offsets = std::move(offsets);
            session.settings = settings;
            session.handle = handle;
            session.on_frame = d.on_frame;
            session.on_frame_user = d.on_frame_user;
            if (Status s = start_worker(session, model, 0, 0); !s) {
                host_delete<SessionObject>(handle);
                return report(fn, s);
            }
        } catch (...) {
            host_delete<SessionObject>(handle);
            throw;
        }
        *out = handle;
        return DFM_OK;
    });
}

extern "C" DFM_API void dfm_session_destroy(dfm_session* session) {
    guarded_void("dfm_session_destroy", [&] { host_delete<SessionObject>(session); });
}

extern "C" DFM_API dfm_result dfm_session_set_group_transform(dfm_session* session, uint32_t group,
                                                              const double matrix[16]) {
    constexpr const char* fn = "dfm_session_set_group_transform";
    return guarded(fn, [&] {
        dfm_result r = DFM_OK;
        SessionObject* s = session_of(fn, session, r);
        if (s == nullptr) return r;
        if (matrix == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "matrix is NULL");
        if (group >= s->groups.size()) {
            return report(fn, DFM_ERROR_OUT_OF_RANGE,
                          "group " + std::to_string(group) + " is out of range (the session has " +
                              std::to_string(s->groups.size()) + ")");
        }
        for (int i = 0; i < 16; ++i) {
            if (!std::isfinite(matrix[i])) {
                return report(fn, DFM_ERROR_NUMERICAL,
                              "matrix element " + std::to_string(i) + " is not finite");
            }
        }
        // An all-zero or row-major matrix fails here instead of collapsing
        // or misplacing the group.
        if (matrix[3] != 0.0 || matrix[7] != 0.0 || matrix[11] != 0.0 || matrix[15] != 1.0) {
            std::string message =
                "matrix: the bottom row (elements 3, 7, 11, 15, column-major) must be 0 0 0 1 "
                "for an affine transform; found";
            for (const int i : {3, 7, 11, 15}) {
                message += ' ';
                append_number(message, matrix[i]);
            }
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, message);
        }
        std::lock_guard<std::mutex> lock(s->staging_mutex);
        for (std::size_t h = s->group_offsets[group]; h < s->group_offsets[group + 1]; ++h) {
            const glm::dvec3& p = s->handle_rest[h];
            for (int c = 0; c < 3; ++c) {
                s->staged[h][c] =
                    matrix[c] * p.x + matrix[4 + c] * p.y + matrix[8 + c] * p.z + matrix[12 + c];
            }
        }
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_session_set_targets(dfm_session* session,
                                                      const dfm_vec3_input* targets) {
    constexpr const char* fn = "dfm_session_set_targets";
    return guarded(fn, [&] {
        dfm_result r = DFM_OK;
        SessionObject* s = session_of(fn, session, r);
        if (s == nullptr) return r;
        if (std::string e = check_vec3_input(targets, "targets"); !e.empty()) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, e);
        }
        std::lock_guard<std::mutex> lock(s->staging_mutex);
        if (targets->count != s->staged.size()) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                          "targets->count is " + std::to_string(targets->count) +
                              ", the session has " + std::to_string(s->staged.size()) +
                              " handle vertices");
        }
        for (std::size_t h = 0; h < targets->count; ++h) {
            const glm::dvec3 t = read_vec3(*targets, h);
            if (!std::isfinite(t.x) || !std::isfinite(t.y) || !std::isfinite(t.z)) {
                return report(fn, DFM_ERROR_NUMERICAL,
                              "target " + std::to_string(h) + " is not finite; nothing was staged");
            }
        }
        for (std::size_t h = 0; h < targets->count; ++h) s->staged[h] = read_vec3(*targets, h);
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_session_get_handle_count(const dfm_session* session,
                                                           size_t* out) {
    constexpr const char* fn = "dfm_session_get_handle_count";
    return guarded(fn, [&] {
        if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
        *out = 0;
        dfm_result r = DFM_OK;
        const SessionObject* s = session_of(fn, session, r);
        if (s == nullptr) return r;
        *out = s->group_offsets.back();
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_session_set_solver(dfm_session* session,
                                                     const dfm_solver_settings* settings) {
    constexpr const char* fn = "dfm_session_set_solver";
    return guarded(fn, [&] {
        dfm_result r = DFM_OK;
        SessionObject* s = session_of(fn, session, r);
        if (s == nullptr) return r;
        if (settings == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "settings is NULL");
        for (std::size_t i = 0; i < std::size(settings->reserved); ++i) {
            if (settings->reserved[i] != 0) {
                return report(fn, DFM_ERROR_UNSUPPORTED,
                              "settings->reserved[" + std::to_string(i) + "] is not zero");
            }
        }
        if ((settings->handle_weight != 0.0 &&
             settings->handle_weight != s->settings.handle_weight) ||
            (settings->hard_handles && !s->settings.hard_handles)) {
            return report(fn, DFM_ERROR_UNSUPPORTED,
                          "handle_weight and hard_handles are fixed when the session is created");
        }
        solver::PreconditionerKind preconditioner = s->settings.preconditioner;
        if (preconditioner_value(settings->preconditioner) != DFM_PRECONDITIONER_DEFAULT &&
            !preconditioner_from(settings->preconditioner, preconditioner)) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "settings->preconditioner is unknown");
        }
        if (preconditioner != s->settings.preconditioner ||
            (settings->disable_prediction && s->settings.predict_frames)) {
            return report(fn, DFM_ERROR_UNSUPPORTED,
                          "preconditioner and disable_prediction are fixed when the session is "
                          "created");
        }
        if (settings->tolerance != 0.0 &&
            (!(settings->tolerance > 0.0) || !std::isfinite(settings->tolerance))) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "tolerance must be positive and finite");
        }
        deform::DeformSettings next = s->settings;
        if (settings->tolerance != 0.0) next.tolerance = settings->tolerance;
        if (settings->max_iterations != 0) {
            next.max_iterations =
                static_cast<int>(std::min<std::uint32_t>(settings->max_iterations, 1000000));
        }
        if (Status st = s->async->set_stopping_rule(next.tolerance, next.max_iterations); !st) {
            return report(fn, st);
        }
        s->settings = next;
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_session_submit(dfm_session* session, uint64_t* generation) {
    constexpr const char* fn = "dfm_session_submit";
    return guarded(fn, [&] {
        if (generation != nullptr) *generation = 0;
        dfm_result r = DFM_OK;
        SessionObject* s = session_of(fn, session, r);
        if (s == nullptr) return r;
        std::uint64_t g = 0;
        {
            // The worker's queue takes its copy under the staging lock, so
            // no other thread's staging can change what is read.
            std::lock_guard<std::mutex> lock(s->staging_mutex);
            if (Status st = s->async->submit(s->staged, g); !st) return report(fn, st);
        }
        if (generation != nullptr) *generation = g;
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_session_solve(dfm_session* session, uint64_t* generation) {
    constexpr const char* fn = "dfm_session_solve";
    return guarded(fn, [&] {
        if (generation != nullptr) *generation = 0;
        dfm_result r = DFM_OK;
        SessionObject* s = session_of(fn, session, r);
        if (s == nullptr) return r;
        std::lock_guard<std::mutex> solving(s->solving_mutex);
        {
            std::lock_guard<std::mutex> lock(s->staging_mutex);
            std::copy(s->staged.begin(), s->staged.end(), s->solving.begin());
        }
        std::uint64_t g = 0;
        const Status st = s->async->solve_now(s->solving, g);
        if (generation != nullptr) *generation = g;
        const auto& context = *s->mesh->context;
        if (!st) {
            context.emit(DFM_LOG_ERROR, DFM_LOG_ID_SOLVE_FAILED, st.message());
            return report(fn, st);
        }
        bool converged = true;
        s->async->read([&](const deform::Frame& f) { converged = f.report.converged; });
        if (!converged) {
            context.emit(DFM_LOG_WARNING, DFM_LOG_ID_SOLVE_NOT_CONVERGED,
                         "generation " + std::to_string(g) +
                             " stopped at the iteration cap before the tolerance");
        }
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_session_cancel(dfm_session* session) {
    constexpr const char* fn = "dfm_session_cancel";
    return guarded(fn, [&] {
        dfm_result r = DFM_OK;
        SessionObject* s = session_of(fn, session, r);
        if (s == nullptr) return r;
        s->async->cancel();
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_session_poll(dfm_session* session, uint64_t known_generation,
                                               dfm_frame_info* out, bool* is_new) {
    constexpr const char* fn = "dfm_session_poll";
    return guarded(fn, [&] {
        if (is_new != nullptr) *is_new = false;
        if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
        *out = dfm_frame_info{};
        dfm_result r = DFM_OK;
        SessionObject* s = session_of(fn, session, r);
        if (s == nullptr) return r;
        s->async->read([&](const deform::Frame& f) { fill_frame_info(f, out); });
        if (is_new != nullptr) *is_new = out->generation > known_generation;
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_session_wait(dfm_session* session, uint64_t generation,
                                               int64_t timeout_ms, dfm_frame_info* out) {
    constexpr const char* fn = "dfm_session_wait";
    return guarded(fn, [&] {
        if (out != nullptr) *out = dfm_frame_info{};
        dfm_result r = DFM_OK;
        SessionObject* s = session_of(fn, session, r);
        if (s == nullptr) return r;
        if (generation > s->async->submitted_generation()) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                          "generation " + std::to_string(generation) +
                              " was never submitted (the newest is " +
                              std::to_string(s->async->submitted_generation()) + ")");
        }
        const auto timeout = timeout_ms < 0 ? std::chrono::nanoseconds::max()
                                            : std::chrono::nanoseconds(std::chrono::milliseconds(
                                                  std::min<int64_t>(timeout_ms, 1000000000)));
        switch (s->async->wait(generation, timeout)) {
            case deform::AsyncSession::WaitResult::ready: break;
            case deform::AsyncSession::WaitResult::cancelled:
                return report(fn, DFM_ERROR_CANCELLED,
                              "generation " + std::to_string(generation) + " was cancelled");
            case deform::AsyncSession::WaitResult::timed_out:
                return report(fn, DFM_ERROR_BUSY,
                              "generation " + std::to_string(generation) + " is not ready after " +
                                  std::to_string(timeout_ms) + " ms");
        }
        if (out != nullptr)
            s->async->read([&](const deform::Frame& f) { fill_frame_info(f, out); });
        return DFM_OK;
    });
}

namespace {

const std::vector<glm::dvec3>& rest_normals(SessionObject& s) {
    std::lock_guard<std::mutex> lock(s.rest_normals_mutex);
    if (s.rest_normals.empty()) {
        const deform::MeshModel& model = s.async->model();
        mesh::compute_vertex_normals(model.mesh, model.mesh.positions, s.rest_normals);
    }
    return s.rest_normals;
}

// Copies the newest frame into a whole-mesh array: rest values for the part
// that does not move, the frame's for the rest. `normals` picks which.
dfm_result read_whole(const char* fn, dfm_session* session, const dfm_vec3_output* out,
                      dfm_frame_info* info, bool normals) {
    return guarded(fn, [&] {
        if (info != nullptr) *info = dfm_frame_info{};
        dfm_result r = DFM_OK;
        SessionObject* s = session_of(fn, session, r);
        if (s == nullptr) return r;
        const deform::MeshModel& model = s->async->model();
        const HostNumbering numbering(*s->mesh, model.mesh.vertex_count());
        if (std::string e = check_vec3_output(out, numbering.host_count(), "out"); !e.empty()) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, e);
        }
        const std::span<const glm::dvec3> rest =
            normals ? std::span<const glm::dvec3>(rest_normals(*s)) : model.mesh.positions;
        numbering.write_all(*out, rest);
        s->async->read([&](const deform::Frame& f) {
            const std::span<const std::uint32_t> changing =
                normals ? f.normal_vertices : s->async->moving();
            const auto& values = normals ? f.normals : f.positions;
            for (std::size_t i = 0; i < changing.size(); ++i) {
                numbering.write_one(*out, changing[i], values[i]);
            }
            fill_frame_info(f, info);
        });
        return DFM_OK;
    });
}

}  // namespace

namespace {

// What struct_size 0 stands for: dfm_vertex_output as version 0.2 had it.
constexpr std::size_t vertex_output_0_2 = DFM_END_OF(dfm_vertex_output, changed_only);

void put_float3(const dfm_vertex_output& out, std::size_t vertex, std::size_t offset,
                const float* xyz) {
    std::memcpy(static_cast<char*>(out.data) + vertex * out.stride + offset, xyz,
                3 * sizeof(float));
}

void put_vec3(const dfm_vertex_output& out, std::size_t vertex, std::size_t offset,
              const glm::dvec3& v) {
    const float xyz[3] = {static_cast<float>(v.x), static_cast<float>(v.y),
                          static_cast<float>(v.z)};
    put_float3(out, vertex, offset, xyz);
}

}  // namespace

extern "C" DFM_API dfm_result dfm_session_read_vertices(dfm_session* session,
                                                        const dfm_vertex_output* out,
                                                        dfm_frame_info* info) {
    constexpr const char* fn = "dfm_session_read_vertices";
    return guarded(fn, [&] {
        if (info != nullptr) *info = dfm_frame_info{};
        dfm_result r = DFM_OK;
        SessionObject* s = session_of(fn, session, r);
        if (s == nullptr) return r;
        dfm_vertex_output o;
        if (r = read_descriptor(fn, "out", out, vertex_output_0_2, o); r != DFM_OK) return r;
        const deform::MeshModel& model = s->async->model();
        const HostNumbering numbering(*s->mesh, model.mesh.vertex_count());
        const std::size_t n = numbering.host_count();
        if (o.data == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out->data is NULL");
        if (!o.write_positions && !o.write_normals) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                          "out asks for neither positions nor normals");
        }
        if (o.count < n) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                          "out->count is " + std::to_string(o.count) + ", the mesh has " +
                              std::to_string(n) + " vertices");
        }
        const std::size_t field = 3 * sizeof(float);
        if ((o.write_positions && o.position_offset > o.stride - std::min(o.stride, field)) ||
            (o.write_normals && o.normal_offset > o.stride - std::min(o.stride, field)) ||
            o.stride < field) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                          "out->stride " + std::to_string(o.stride) +
                              " does not hold 12 bytes at each offset written");
        }
        if (!o.changed_only) {
            const std::size_t surface = model.mesh.vertex_count();
            if (o.write_positions) {
                for (std::uint32_t v = 0; v < surface; ++v) {
                    numbering.for_copies(v, [&](std::uint32_t h) {
                        put_vec3(o, h, o.position_offset, model.mesh.positions[v]);
                    });
                }
            }
            if (o.write_normals) {
                const std::vector<glm::dvec3>& rest = rest_normals(*s);
                for (std::uint32_t v = 0; v < surface; ++v) {
                    numbering.for_copies(
                        v, [&](std::uint32_t h) { put_vec3(o, h, o.normal_offset, rest[v]); });
                }
            }
        }
        const std::span<const std::uint32_t> moving = s->async->moving();
        s->async->read([&](const deform::Frame& f) {
            if (o.write_positions) {
                for (std::size_t i = 0; i < moving.size(); ++i) {
                    numbering.for_copies(moving[i], [&](std::uint32_t h) {
                        put_float3(o, h, o.position_offset, &f.positions_f32[3 * i]);
                    });
                }
            }
            if (o.write_normals) {
                for (std::size_t i = 0; i < f.normal_vertices.size(); ++i) {
                    numbering.for_copies(f.normal_vertices[i], [&](std::uint32_t h) {
                        put_float3(o, h, o.normal_offset, &f.normals_f32[3 * i]);
                    });
                }
            }
            fill_frame_info(f, info);
        });
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_session_read_positions(dfm_session* session,
                                                         const dfm_vec3_output* out,
                                                         dfm_frame_info* info) {
    return read_whole("dfm_session_read_positions", session, out, info, false);
}

extern "C" DFM_API dfm_result dfm_session_read_normals(dfm_session* session,
                                                       const dfm_vec3_output* out,
                                                       dfm_frame_info* info) {
    return read_whole("dfm_session_read_normals", session, out, info, true);
}

extern "C" DFM_API dfm_result dfm_session_read_roi_positions(dfm_session* session,
                                                             const dfm_vec3_output* out,
                                                             dfm_frame_info* info) {
    constexpr const char* fn = "dfm_session_read_roi_positions";
    return guarded(fn, [&] {
        if (info != nullptr) *info = dfm_frame_info{};
        dfm_result r = DFM_OK;
        SessionObject* s = session_of(fn, session, r);
        if (s == nullptr) return r;
        if (std::string e = check_vec3_output(out, s->async->moving().size(), "out"); !e.empty()) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, e);
        }
        s->async->read([&](const deform::Frame& f) {
            if (out->type == DFM_SCALAR_FLOAT32 && (out->stride == 0 || out->stride == 12)) {
                std::memcpy(out->data, f.positions_f32.data(),
                            f.positions_f32.size() * sizeof(float));
            } else {
                write_vec3_range(*out, 0, f.positions);
            }
            fill_frame_info(f, info);
        });
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_session_acquire_frame(dfm_session* session, dfm_frame_view* out,
                                                        dfm_frame_info* info) {
    constexpr const char* fn = "dfm_session_acquire_frame";
    return guarded(fn, [&] {
        if (info != nullptr) *info = dfm_frame_info{};
        if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
        *out = dfm_frame_view{};
        dfm_result r = DFM_OK;
        SessionObject* s = session_of(fn, session, r);
        if (s == nullptr) return r;
        const deform::Frame* frame = s->async->acquire();
        if (frame == nullptr) {
            return report(fn, DFM_ERROR_BUSY, "a frame is already held; release it first");
        }
        out->roi_positions = frame->positions_f32.data();
        out->roi_positions_f64 = &frame->positions.front().x;
        out->roi_vertices = s->async->moving().data();
        out->roi_count = frame->positions.size();
        out->normals = frame->normals_f32.data();
        out->normal_vertices = frame->normal_vertices.data();
        const HostNumbering numbering(*s->mesh, s->async->model().mesh.vertex_count());
        if (!numbering.identity()) {
            // The lists in the host's numbering, held with the frame (one
            // frame at a time, so one pair of lists suffices).
            try {
                s->held_roi_vertices.assign(s->async->moving().begin(), s->async->moving().end());
                s->held_normal_vertices.assign(frame->normal_vertices.begin(),
                                               frame->normal_vertices.end());
            } catch (...) {
                s->async->release();
                throw;
            }
            numbering.to_host(s->held_roi_vertices);
            numbering.to_host(s->held_normal_vertices);
            out->roi_vertices = s->held_roi_vertices.data();
            out->normal_vertices = s->held_normal_vertices.data();
        }
        out->normal_count = frame->normals.size();
        fill_frame_info(*frame, info);
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_session_release_frame(dfm_session* session) {
    constexpr const char* fn = "dfm_session_release_frame";
    return guarded(fn, [&] {
        dfm_result r = DFM_OK;
        SessionObject* s = session_of(fn, session, r);
        if (s == nullptr) return r;
        if (!s->async->release()) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "no frame is held");
        return DFM_OK;
    });
}

namespace {

dfm_result bake(const char* fn, dfm_session* session, std::uint64_t generation) {
    return guarded(fn, [&] {
        dfm_result r = DFM_OK;
        SessionObject* s = session_of(fn, session, r);
        if (s == nullptr) return r;
        if (s->async->holding()) {
            return report(fn, DFM_ERROR_BUSY, "a frame is held; release it before baking");
        }
        if (s->async->preparing()) {
            return report(fn, DFM_ERROR_BUSY,
                          "the session is preparing: nothing is solved yet to bake");
        }
        if (Status st = s->async->setup_status(); !st) return report(fn, st);
        MeshState& mesh = *s->mesh;
        if (mesh.current() != s->model) {
            return report(fn, DFM_ERROR_BUSY,
                          "the mesh's rest pose changed (a bake or an undo) since this session "
                          "started; create a new session to edit it");
        }
        // The frame exactly as it was published: what the host showed.
        std::vector<glm::dvec3> positions = s->model->mesh.positions;
        const std::span<const std::uint32_t> moving = s->async->moving();
        std::uint64_t baked_generation = 0;
        const bool found = s->async->read_finished(generation, [&](const deform::Frame& f) {
            for (std::size_t i = 0; i < moving.size(); ++i) positions[moving[i]] = f.positions[i];
            baked_generation = f.generation;
        });
        if (!found) {
            std::uint64_t newest = 0;
            s->async->read_finished(0, [&](const deform::Frame& f) { newest = f.generation; });
            return report(fn, DFM_ERROR_NOT_FOUND,
                          "generation " + std::to_string(generation) +
                              " is not the newest finished frame (that is generation " +
                              std::to_string(newest) + ")");
        }
        auto baked = std::allocate_shared<deform::MeshModel>(
            HostAllocator<deform::MeshModel>(mesh.context->allocator));
        if (Status st = deform::bake_positions(*s->model, positions, *baked); !st) {
            return report(fn, st);
        }
        // Under the mesh's lock from the check to the new rest pose, so that
        // no other bake or undo slips in; the restart does not wait for a
        // set-up (that runs on the new worker).
        std::lock_guard<std::mutex> lock(mesh.mutex);
        if (mesh.model != s->model) {
            return report(fn, DFM_ERROR_BUSY, "the mesh's rest pose changed during the bake");
        }
        mesh.undo.reserve(mesh.undo.size() + 1);
        if (Status st = start_worker(*s, baked, baked_generation, s->async->submitted_generation());
            !st) {
            return report(fn, st);
        }
        mesh.undo.push_back(mesh.model);
        mesh.redo.clear();
        mesh.model = std::move(baked);
        return DFM_OK;
    });
}

}  // namespace

extern "C" DFM_API dfm_result dfm_session_bake(dfm_session* session) {
    return bake("dfm_session_bake", session, 0);
}

extern "C" DFM_API dfm_result dfm_session_bake_generation(dfm_session* session,
                                                          uint64_t generation) {
    return bake("dfm_session_bake_generation", session, generation);
}
