#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <type_traits>

#include "c_boundary.hpp"
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
        if (dfm_result r = read_descriptor(fn, "desc", desc, d); r != DFM_OK) {
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
        for (std::size_t g = 0; g < groups.size(); ++g) {
            groups[g].assign(d.groups[g].vertices, d.groups[g].vertices + d.groups[g].count);
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
        deform::AsyncSession::FrameHook on_frame;
        if (d.on_frame != nullptr) {
            on_frame = [fn = d.on_frame, user = d.on_frame_user,
                        handle](const deform::Frame& frame) {
                dfm_frame_info info{};
                fill_frame_info(frame, &info);
                fn(user, handle, &info);
            };
        }
        // Filling the session allocates too; a failure there must not leave
        // a live, half-built handle behind.
        try {
            session.mesh = m->state;
            if (Status s = deform::Edit::create(model, roi->vertices, std::move(groups), settings,
                                                std::move(on_frame), *m->state->context->scheduler,
                                                session.edit);
                !s) {
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
        return report(fn, s->edit->set_group_transform(group, matrix));
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
        return report(fn, s->edit->set_targets(targets->count, [&](std::size_t h) {
            return read_vec3(*targets, h);
        }));
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
        *out = s->edit->handle_count();
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
        deform::Edit::SolverChange change;
        if (preconditioner_value(settings->preconditioner) != DFM_PRECONDITIONER_DEFAULT) {
            solver::PreconditionerKind preconditioner{};
            if (!preconditioner_from(settings->preconditioner, preconditioner)) {
                return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                              "settings->preconditioner is unknown");
            }
            change.preconditioner = preconditioner;
        }
        if (settings->tolerance != 0.0 &&
            (!(settings->tolerance > 0.0) || !std::isfinite(settings->tolerance))) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "tolerance must be positive and finite");
        }
        change.tolerance = settings->tolerance;
        change.max_iterations =
            static_cast<int>(std::min<std::uint32_t>(settings->max_iterations, 1000000));
        change.handle_weight = settings->handle_weight;
        change.hard_handles = settings->hard_handles;
        change.disable_prediction = settings->disable_prediction;
        return report(fn, s->edit->change_solver(change));
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
        if (Status st = s->edit->submit(g); !st) return report(fn, st);
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
        std::uint64_t g = 0;
        bool converged = false;
        const Status st = s->edit->solve(g, converged);
        if (generation != nullptr) *generation = g;
        const auto& context = *s->mesh->context;
        if (!st) {
            context.emit(DFM_LOG_ERROR, DFM_LOG_ID_SOLVE_FAILED, st.message());
            return report(fn, st);
        }
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
        s->edit->async().cancel();
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
        s->edit->async().read([&](const deform::Frame& f) { fill_frame_info(f, out); });
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
        if (generation > s->edit->async().submitted_generation()) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                          "generation " + std::to_string(generation) +
                              " was never submitted (the newest is " +
                              std::to_string(s->edit->async().submitted_generation()) + ")");
        }
        const auto timeout = timeout_ms < 0 ? std::chrono::nanoseconds::max()
                                            : std::chrono::nanoseconds(std::chrono::milliseconds(
                                                  std::min<int64_t>(timeout_ms, 1000000000)));
        switch (s->edit->async().wait(generation, timeout)) {
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
            s->edit->async().read([&](const deform::Frame& f) { fill_frame_info(f, out); });
        return DFM_OK;
    });
}

namespace {

// Copies the newest frame into a whole-mesh array: rest values for the part
// that does not move, the frame's for the rest. `normals` picks which.
dfm_result read_whole(const char* fn, dfm_session* session, const dfm_vec3_output* out,
                      dfm_frame_info* info, bool normals) {
    return guarded(fn, [&] {
        if (info != nullptr) *info = dfm_frame_info{};
        dfm_result r = DFM_OK;
        SessionObject* s = session_of(fn, session, r);
        if (s == nullptr) return r;
        const deform::MeshModel& model = s->edit->async().model();
        const HostNumbering numbering(*s->mesh, model.mesh.vertex_count());
        if (std::string e = check_vec3_output(out, numbering.host_count(), "out"); !e.empty()) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, e);
        }
        const std::span<const glm::dvec3> rest =
            normals ? std::span<const glm::dvec3>(s->edit->rest_normals()) : model.mesh.positions;
        numbering.write_all(*out, rest);
        s->edit->async().read([&](const deform::Frame& f) {
            const std::span<const std::uint32_t> changing =
                normals ? f.normal_vertices : s->edit->async().moving();
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
        if (r = read_descriptor(fn, "out", out, o); r != DFM_OK) return r;
        const deform::MeshModel& model = s->edit->async().model();
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
                const std::vector<glm::dvec3>& rest = s->edit->rest_normals();
                for (std::uint32_t v = 0; v < surface; ++v) {
                    numbering.for_copies(
                        v, [&](std::uint32_t h) { put_vec3(o, h, o.normal_offset, rest[v]); });
                }
            }
        }
        const std::span<const std::uint32_t> moving = s->edit->async().moving();
        s->edit->async().read([&](const deform::Frame& f) {
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
        if (std::string e = check_vec3_output(out, s->edit->async().moving().size(), "out");
            !e.empty()) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, e);
        }
        s->edit->async().read([&](const deform::Frame& f) {
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
        const deform::Frame* frame = s->edit->async().acquire();
        if (frame == nullptr) {
            return report(fn, DFM_ERROR_BUSY, "a frame is already held; release it first");
        }
        out->roi_positions = frame->positions_f32.data();
        out->roi_positions_f64 = &frame->positions.front().x;
        out->roi_vertices = s->edit->async().moving().data();
        out->roi_count = frame->positions.size();
        out->normals = frame->normals_f32.data();
        out->normal_vertices = frame->normal_vertices.data();
        const HostNumbering numbering(*s->mesh, s->edit->async().model().mesh.vertex_count());
        if (!numbering.identity()) {
            // The lists in the host's numbering, held with the frame (one
            // frame at a time, so one pair of lists suffices).
            try {
                s->held_roi_vertices.assign(s->edit->async().moving().begin(),
                                            s->edit->async().moving().end());
                s->held_normal_vertices.assign(frame->normal_vertices.begin(),
                                               frame->normal_vertices.end());
            } catch (...) {
                s->edit->async().release();
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
        if (!s->edit->async().release())
            return report(fn, DFM_ERROR_INVALID_ARGUMENT, "no frame is held");
        return DFM_OK;
    });
}

namespace {

dfm_result bake(const char* fn, dfm_session* session, std::uint64_t generation) {
    return guarded(fn, [&] {
        dfm_result r = DFM_OK;
        SessionObject* s = session_of(fn, session, r);
        if (s == nullptr) return r;
        MeshState& mesh = *s->mesh;
        auto baked = std::allocate_shared<deform::MeshModel>(
            HostAllocator<deform::MeshModel>(mesh.context->allocator));
        if (Status st = s->edit->bake(mesh.poses, generation, std::move(baked)); !st) {
            return report(fn, st);
        }
        log_damped_corrective(mesh, fn);
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
