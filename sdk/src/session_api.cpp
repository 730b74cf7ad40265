#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>

#include "c_boundary.hpp"
#include "mesh/normals.hpp"
#include "objects.hpp"
#include "vec3_arrays.hpp"

using namespace dfm;
using namespace dfm::sdk;

namespace {

constexpr double default_tolerance = 1e-5;
constexpr std::uint32_t default_max_iterations = 100;

Status settings_from(const dfm_solver_settings& in, deform::DeformSettings& out) {
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
    if (!(out.tolerance > 0.0) || !std::isfinite(out.tolerance)) {
        return Status(Errc::invalid_argument, "solver.tolerance must be positive and finite");
    }
    if (!(out.handle_weight > 0.0) || !std::isfinite(out.handle_weight)) {
        return Status(Errc::invalid_argument, "solver.handle_weight must be positive and finite");
    }
    return Status::ok();
}

// What a session runs on: the engine session behind its worker, built for one
// rest pose. Building it is all the set-up work of an edit.
struct Engine {
    std::unique_ptr<solver::ThreadPool> pool;
    std::unique_ptr<deform::AsyncSession> async;
    std::vector<glm::dvec3> handle_rest;
    std::vector<glm::dvec3> rest_normals;
};

Status start_engine(const deform::MeshModel& model, const std::vector<std::uint32_t>& roi,
                    const std::vector<std::vector<std::uint32_t>>& groups,
                    deform::DeformSettings settings, std::uint32_t workers, Engine& out) {
    if (workers > 1) out.pool = std::make_unique<solver::ThreadPool>(workers);
    settings.pool = out.pool.get();
    std::unique_ptr<deform::DeformSession> session;
    if (Status s = deform::DeformSession::create(model, roi, groups, settings, session); !s) {
        return s;
    }
    for (std::uint32_t v : session->handle_vertices()) {
        out.handle_rest.push_back(model.mesh.positions[v]);
    }
    mesh::compute_vertex_normals(model.mesh, model.mesh.positions, out.rest_normals);
    return deform::AsyncSession::create(std::move(session), roi, out.async);
}

void install(dfm_session& s, Engine engine, std::shared_ptr<const deform::MeshModel> model) {
    std::lock_guard<std::mutex> lock(s.staging_mutex);
    s.async.reset();
    s.pool = std::move(engine.pool);
    s.async = std::move(engine.async);
    s.model = std::move(model);
    s.handle_rest = std::move(engine.handle_rest);
    s.rest_normals = std::move(engine.rest_normals);
    s.staged = s.handle_rest;
    s.submitting = s.handle_rest;
}

void fill_info(const deform::Frame& frame, dfm_frame_info* out) {
    if (out == nullptr) return;
    out->generation = frame.generation;
    out->status = to_result(frame.status);
    out->converged = frame.report.converged;
    out->partial = frame.partial;
    out->iterations = static_cast<std::uint32_t>(frame.report.iterations);
    out->last_update = frame.report.last_update;
    out->solve_ms = frame.report.solve_ms;
    out->checksum = frame.checksum;
}

bool live_session(const char* fn, dfm_session* session, dfm_result& result) {
    if (is_live(session, Kind::session)) return true;
    result = bad_handle(fn, "session", session);
    return false;
}

// Copies the staged targets out for a submit or a solve.
std::span<const glm::dvec3> take_staged(dfm_session& s) {
    std::lock_guard<std::mutex> lock(s.staging_mutex);
    std::copy(s.staged.begin(), s.staged.end(), s.submitting.begin());
    return s.submitting;
}

}  // namespace

extern "C" DFM_API dfm_result dfm_session_create(dfm_mesh* mesh, const dfm_session_desc* desc,
                                                 dfm_session** out) {
    constexpr const char* fn = "dfm_session_create";
    if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
    *out = nullptr;
    if (!is_live(mesh, Kind::mesh)) return bad_handle(fn, "mesh", mesh);
    if (desc == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "desc is NULL");
    if (!is_live(desc->roi, Kind::roi)) return bad_handle(fn, "desc->roi", desc->roi);
    if (desc->roi->mesh != mesh->state) {
        return report(fn, DFM_ERROR_INVALID_ARGUMENT, "desc->roi belongs to another mesh");
    }
    if (desc->groups == nullptr || desc->group_count == 0) {
        return report(fn, DFM_ERROR_INVALID_ARGUMENT, "the edit needs at least one handle group");
    }
    for (std::size_t g = 0; g < desc->group_count; ++g) {
        if (desc->groups[g].vertices == nullptr || desc->groups[g].count == 0) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                          "handle group " + std::to_string(g) + " is empty");
        }
    }
    return guarded(fn, [&] {
        deform::DeformSettings settings;
        if (Status s = settings_from(desc->solver, settings); !s) return report(fn, s);
        std::vector<std::vector<std::uint32_t>> groups(desc->group_count);
        std::vector<std::size_t> offsets{0};
        for (std::size_t g = 0; g < groups.size(); ++g) {
            groups[g].assign(desc->groups[g].vertices,
                             desc->groups[g].vertices + desc->groups[g].count);
            offsets.push_back(offsets.back() + groups[g].size());
        }
        const auto model = mesh->state->current();
        Engine engine;
        if (Status s = start_engine(*model, desc->roi->vertices, groups, settings,
                                    mesh->state->context->worker_count, engine);
            !s) {
            return report(fn, s);
        }
        dfm_session* session = host_new<dfm_session>(*mesh->state->context, Kind::session);
        // Filling the session allocates too; a failure there must not leave
        // a registered, half-built handle behind.
        try {
            session->mesh = mesh->state;
            session->roi = desc->roi->vertices;
            session->groups = std::move(groups);
            session->group_offsets = std::move(offsets);
            session->settings = settings;
            install(*session, std::move(engine), model);
        } catch (...) {
            host_delete(session);
            throw;
        }
        *out = session;
        return DFM_OK;
    });
}

extern "C" DFM_API void dfm_session_destroy(dfm_session* session) {
    if (!is_live(session, Kind::session)) return;
    host_delete(session);
}

extern "C" DFM_API dfm_result dfm_session_set_group_transform(dfm_session* session, uint32_t group,
                                                              const double matrix[16]) {
    constexpr const char* fn = "dfm_session_set_group_transform";
    dfm_result r = DFM_OK;
    if (!live_session(fn, session, r)) return r;
    if (matrix == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "matrix is NULL");
    if (group >= session->groups.size()) {
        return report(fn, DFM_ERROR_OUT_OF_RANGE,
                      "group " + std::to_string(group) + " is out of range (the session has " +
                          std::to_string(session->groups.size()) + ")");
    }
    for (int i = 0; i < 16; ++i) {
        if (!std::isfinite(matrix[i])) {
            return report(fn, DFM_ERROR_NUMERICAL,
                          "matrix element " + std::to_string(i) + " is not finite");
        }
    }
    std::lock_guard<std::mutex> lock(session->staging_mutex);
    for (std::size_t h = session->group_offsets[group]; h < session->group_offsets[group + 1];
         ++h) {
        const glm::dvec3& p = session->handle_rest[h];
        for (int c = 0; c < 3; ++c) {
            session->staged[h][c] =
                matrix[c] * p.x + matrix[4 + c] * p.y + matrix[8 + c] * p.z + matrix[12 + c];
        }
    }
    return DFM_OK;
}

extern "C" DFM_API dfm_result dfm_session_set_targets(dfm_session* session,
                                                      const dfm_vec3_input* targets) {
    constexpr const char* fn = "dfm_session_set_targets";
    dfm_result r = DFM_OK;
    if (!live_session(fn, session, r)) return r;
    if (std::string e = check_vec3_input(targets, "targets"); !e.empty()) {
        return report(fn, DFM_ERROR_INVALID_ARGUMENT, e);
    }
    std::lock_guard<std::mutex> lock(session->staging_mutex);
    if (targets->count != session->staged.size()) {
        return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                      "targets->count is " + std::to_string(targets->count) + ", the session has " +
                          std::to_string(session->staged.size()) + " handle vertices");
    }
    for (std::size_t h = 0; h < targets->count; ++h) {
        const glm::dvec3 t = read_vec3(*targets, h);
        if (!std::isfinite(t.x) || !std::isfinite(t.y) || !std::isfinite(t.z)) {
            return report(fn, DFM_ERROR_NUMERICAL,
                          "target " + std::to_string(h) + " is not finite; nothing was staged");
        }
    }
    for (std::size_t h = 0; h < targets->count; ++h) session->staged[h] = read_vec3(*targets, h);
    return DFM_OK;
}

extern "C" DFM_API dfm_result dfm_session_get_handle_count(const dfm_session* session,
                                                           size_t* out) {
    constexpr const char* fn = "dfm_session_get_handle_count";
    if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
    *out = 0;
    if (!is_live(session, Kind::session)) return bad_handle(fn, "session", session);
    *out = session->group_offsets.back();
    return DFM_OK;
}

extern "C" DFM_API dfm_result dfm_session_set_solver(dfm_session* session,
                                                     const dfm_solver_settings* settings) {
    constexpr const char* fn = "dfm_session_set_solver";
    dfm_result r = DFM_OK;
    if (!live_session(fn, session, r)) return r;
    if (settings == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "settings is NULL");
    if ((settings->handle_weight != 0.0 &&
         settings->handle_weight != session->settings.handle_weight) ||
        (settings->hard_handles && !session->settings.hard_handles)) {
        return report(fn, DFM_ERROR_UNSUPPORTED,
                      "handle_weight and hard_handles are fixed when the session is created");
    }
    if (settings->tolerance != 0.0 &&
        (!(settings->tolerance > 0.0) || !std::isfinite(settings->tolerance))) {
        return report(fn, DFM_ERROR_INVALID_ARGUMENT, "tolerance must be positive and finite");
    }
    return guarded(fn, [&] {
        deform::DeformSettings next = session->settings;
        if (settings->tolerance != 0.0) next.tolerance = settings->tolerance;
        if (settings->max_iterations != 0) {
            next.max_iterations =
                static_cast<int>(std::min<std::uint32_t>(settings->max_iterations, 1000000));
        }
        if (Status s = session->async->set_stopping_rule(next.tolerance, next.max_iterations); !s) {
            return report(fn, s);
        }
        session->settings = next;
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_session_submit(dfm_session* session, uint64_t* generation) {
    constexpr const char* fn = "dfm_session_submit";
    if (generation != nullptr) *generation = 0;
    dfm_result r = DFM_OK;
    if (!live_session(fn, session, r)) return r;
    return guarded(fn, [&] {
        std::uint64_t g = 0;
        if (Status s = session->async->submit(take_staged(*session), g); !s) {
            return report(fn, s);
        }
        if (generation != nullptr) *generation = g;
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_session_solve(dfm_session* session, uint64_t* generation) {
    constexpr const char* fn = "dfm_session_solve";
    if (generation != nullptr) *generation = 0;
    dfm_result r = DFM_OK;
    if (!live_session(fn, session, r)) return r;
    return guarded(fn, [&] {
        std::uint64_t g = 0;
        const Status s = session->async->solve_now(take_staged(*session), g);
        if (generation != nullptr) *generation = g;
        const auto& context = *session->mesh->context;
        if (!s) {
            context.emit(DFM_LOG_ERROR, DFM_LOG_ID_SOLVE_FAILED, s.message());
            return report(fn, s);
        }
        bool converged = true;
        session->async->read([&](const deform::Frame& f) { converged = f.report.converged; });
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
    dfm_result r = DFM_OK;
    if (!live_session(fn, session, r)) return r;
    session->async->cancel();
    return DFM_OK;
}

extern "C" DFM_API dfm_result dfm_session_poll(dfm_session* session, uint64_t known_generation,
                                               dfm_frame_info* out, bool* is_new) {
    constexpr const char* fn = "dfm_session_poll";
    if (is_new != nullptr) *is_new = false;
    if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
    *out = dfm_frame_info{};
    dfm_result r = DFM_OK;
    if (!live_session(fn, session, r)) return r;
    session->async->read([&](const deform::Frame& f) { fill_info(f, out); });
    if (is_new != nullptr) *is_new = out->generation > known_generation;
    return DFM_OK;
}

extern "C" DFM_API dfm_result dfm_session_wait(dfm_session* session, uint64_t generation,
                                               int64_t timeout_ms, dfm_frame_info* out) {
    constexpr const char* fn = "dfm_session_wait";
    if (out != nullptr) *out = dfm_frame_info{};
    dfm_result r = DFM_OK;
    if (!live_session(fn, session, r)) return r;
    if (generation > session->async->submitted_generation()) {
        return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                      "generation " + std::to_string(generation) +
                          " was never submitted (the newest is " +
                          std::to_string(session->async->submitted_generation()) + ")");
    }
    const auto timeout = timeout_ms < 0 ? std::chrono::nanoseconds::max()
                                        : std::chrono::nanoseconds(std::chrono::milliseconds(
                                              std::min<int64_t>(timeout_ms, 1000000000)));
    switch (session->async->wait(generation, timeout)) {
        case deform::AsyncSession::WaitResult::ready: break;
        case deform::AsyncSession::WaitResult::cancelled:
            return report(fn, DFM_ERROR_CANCELLED,
                          "generation " + std::to_string(generation) + " was cancelled");
        case deform::AsyncSession::WaitResult::timed_out:
            return report(fn, DFM_ERROR_BUSY,
                          "generation " + std::to_string(generation) + " is not ready after " +
                              std::to_string(timeout_ms) + " ms");
    }
    if (out != nullptr) session->async->read([&](const deform::Frame& f) { fill_info(f, out); });
    return DFM_OK;
}

namespace {

// Copies the newest frame into a whole-mesh array: rest values for the part
// that does not move, the frame's for the rest. `normals` picks which.
dfm_result read_whole(const char* fn, dfm_session* session, const dfm_vec3_output* out,
                      dfm_frame_info* info, bool normals) {
    if (info != nullptr) *info = dfm_frame_info{};
    dfm_result r = DFM_OK;
    if (!live_session(fn, session, r)) return r;
    const deform::MeshModel& model = session->async->model();
    if (std::string e = check_vec3_output(out, model.mesh.vertex_count(), "out"); !e.empty()) {
        return report(fn, DFM_ERROR_INVALID_ARGUMENT, e);
    }
    const std::span<const glm::dvec3> rest =
        normals ? std::span<const glm::dvec3>(session->rest_normals) : model.mesh.positions;
    const std::span<const std::uint32_t> changing =
        normals ? session->async->normal_vertices() : session->async->moving();
    write_vec3_range(*out, 0, rest);
    session->async->read([&](const deform::Frame& f) {
        const std::vector<glm::dvec3>& values = normals ? f.normals : f.positions;
        for (std::size_t i = 0; i < changing.size(); ++i) write_vec3(*out, changing[i], values[i]);
        fill_info(f, info);
    });
    return DFM_OK;
}

}  // namespace

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
    if (info != nullptr) *info = dfm_frame_info{};
    dfm_result r = DFM_OK;
    if (!live_session(fn, session, r)) return r;
    if (std::string e = check_vec3_output(out, session->async->moving().size(), "out");
        !e.empty()) {
        return report(fn, DFM_ERROR_INVALID_ARGUMENT, e);
    }
    session->async->read([&](const deform::Frame& f) {
        if (out->type == DFM_SCALAR_FLOAT32 && (out->stride == 0 || out->stride == 12)) {
            std::memcpy(out->data, f.positions_f32.data(), f.positions_f32.size() * sizeof(float));
        } else {
            write_vec3_range(*out, 0, f.positions);
        }
        fill_info(f, info);
    });
    return DFM_OK;
}

extern "C" DFM_API dfm_result dfm_session_acquire_frame(dfm_session* session, dfm_frame_view* out,
                                                        dfm_frame_info* info) {
    constexpr const char* fn = "dfm_session_acquire_frame";
    if (info != nullptr) *info = dfm_frame_info{};
    if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
    *out = dfm_frame_view{};
    dfm_result r = DFM_OK;
    if (!live_session(fn, session, r)) return r;
    const deform::Frame* frame = session->async->acquire();
    if (frame == nullptr) {
        return report(fn, DFM_ERROR_BUSY, "a frame is already held; release it first");
    }
    out->roi_positions = frame->positions_f32.data();
    out->roi_positions_f64 = &frame->positions.front().x;
    out->roi_vertices = session->async->moving().data();
    out->roi_count = frame->positions.size();
    out->normals = frame->normals_f32.data();
    out->normal_vertices = session->async->normal_vertices().data();
    out->normal_count = frame->normals.size();
    fill_info(*frame, info);
    return DFM_OK;
}

extern "C" DFM_API dfm_result dfm_session_release_frame(dfm_session* session) {
    constexpr const char* fn = "dfm_session_release_frame";
    dfm_result r = DFM_OK;
    if (!live_session(fn, session, r)) return r;
    if (!session->async->release()) {
        return report(fn, DFM_ERROR_INVALID_ARGUMENT, "no frame is held");
    }
    return DFM_OK;
}

extern "C" DFM_API dfm_result dfm_session_bake(dfm_session* session) {
    constexpr const char* fn = "dfm_session_bake";
    dfm_result r = DFM_OK;
    if (!live_session(fn, session, r)) return r;
    if (session->async->holding()) {
        return report(fn, DFM_ERROR_BUSY, "a frame is held; release it before baking");
    }
    return guarded(fn, [&] {
        MeshState& mesh = *session->mesh;
        if (mesh.current() != session->model) {
            return report(fn, DFM_ERROR_BUSY,
                          "the mesh's rest pose changed (a bake or an undo) since this session "
                          "started; create a new session to edit it");
        }
        // The result for the staged targets, finished: a warm solve from the
        // newest frame, usually one iteration.
        std::uint64_t generation = 0;
        if (Status s = session->async->solve_now(take_staged(*session), generation); !s) {
            return report(fn, s);
        }
        std::vector<glm::dvec3> positions = session->model->mesh.positions;
        const std::span<const std::uint32_t> moving = session->async->moving();
        session->async->read([&](const deform::Frame& f) {
            for (std::size_t i = 0; i < moving.size(); ++i) positions[moving[i]] = f.positions[i];
        });
        auto baked = std::make_shared<deform::MeshModel>();
        if (Status s = deform::bake_positions(*session->model, positions, *baked); !s) {
            return report(fn, s);
        }
        Engine engine;
        if (Status s = start_engine(*baked, session->roi, session->groups, session->settings,
                                    mesh.context->worker_count, engine);
            !s) {
            return report(fn, s);
        }
        {
            std::lock_guard<std::mutex> lock(mesh.mutex);
            if (mesh.model != session->model) {
                return report(fn, DFM_ERROR_BUSY, "the mesh's rest pose changed during the bake");
            }
            mesh.undo.reserve(mesh.undo.size() + 1);
            mesh.undo.push_back(mesh.model);
            mesh.redo.clear();
            mesh.model = baked;
        }
        install(*session, std::move(engine), std::move(baked));
        return DFM_OK;
    });
}
