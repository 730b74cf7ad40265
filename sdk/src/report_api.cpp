// The report calls of dualform.h: quality figures, solver figures, Loop
// subdivision, load figures, the mesh summary and save options: what the
// dualform tool needs to do its work through the C API alone.

#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "c_boundary.hpp"
#include "deform/quality.hpp"
#include "mesh/load.hpp"
#include "mesh/model_cache.hpp"
#include "mesh/subdivide.hpp"
#include "mesh/summary.hpp"
#include "mesh/write.hpp"
#include "objects.hpp"

using namespace dfm;
using namespace dfm::sdk;

namespace {

void fill_frame_info(const deform::Frame& frame, dfm_frame_info* out) {
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

constexpr std::uint32_t max_subdivision_steps = 3;

// A new mesh handle over `m` whose memory comes from the context's hooks.
dfm_result new_mesh_handle(const std::shared_ptr<const ContextState>& context, mesh::Mesh m,
                           dfm_mesh** out) {
    auto model = std::allocate_shared<deform::MeshModel>(
        HostAllocator<deform::MeshModel>(context->allocator),
        deform::build_mesh_model(std::move(m)));
    auto state = std::allocate_shared<MeshState>(HostAllocator<MeshState>(context->allocator));
    state->context = context;
    state->model = std::move(model);
    *out = host_new<dfm_mesh>(*context, Kind::mesh, std::move(state));
    return DFM_OK;
}

}  // namespace

extern "C" DFM_API dfm_result dfm_session_measure_quality(dfm_session* session, dfm_quality* out,
                                                          dfm_frame_info* info) {
    constexpr const char* fn = "dfm_session_measure_quality";
    if (info != nullptr) *info = dfm_frame_info{};
    if (!is_live(session, Kind::session)) return bad_handle(fn, "session", session);
    if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
    *out = dfm_quality{};
    return guarded(fn, [&] {
        const deform::AsyncSession& async = *session->async;
        const deform::MeshModel& model = async.model();
        std::vector<glm::dvec3> deformed = model.mesh.positions;
        std::vector<std::uint8_t> in_roi(model.mesh.vertex_count(), 0);
        for (const std::uint32_t v : session->roi) in_roi[v] = 1;
        session->async->read([&](const deform::Frame& f) {
            const std::span<const std::uint32_t> moving = async.moving();
            for (std::size_t i = 0; i < moving.size(); ++i) deformed[moving[i]] = f.positions[i];
            fill_frame_info(f, info);
        });
        std::vector<glm::dvec3> targets;
        {
            std::lock_guard<std::mutex> lock(session->staging_mutex);
            targets = session->staged;
        }
        const deform::QualityReport q =
            deform::measure_quality(model, deformed, in_roi, async.handle_vertices(), targets);
        out->max_handle_error = q.max_handle_error;
        out->mean_abs_log_edge = q.mean_abs_log_edge;
        out->max_abs_log_edge = q.max_abs_log_edge;
        out->mean_normal_change_deg = q.mean_normal_change_deg;
        out->max_fixed_move = q.max_fixed_move;
        out->dual_magnitude_error = q.dual_magnitude_error;
        out->flipped_faces = q.flipped_faces;
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_session_get_solve_report(dfm_session* session,
                                                           dfm_solve_report* out,
                                                           dfm_frame_info* info) {
    constexpr const char* fn = "dfm_session_get_solve_report";
    if (info != nullptr) *info = dfm_frame_info{};
    if (!is_live(session, Kind::session)) return bad_handle(fn, "session", session);
    if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
    *out = dfm_solve_report{};
    const deform::SetupReport& setup = session->async->setup_report();
    out->unknowns = setup.unknowns;
    out->rows = setup.rows;
    out->normal_nonzeros = setup.normal_nonzeros;
    out->setup_ms = setup.setup_ms;
    session->async->read([&](const deform::Frame& f) {
        out->krylov_iterations = f.report.krylov_iterations;
        out->linear_residual = f.report.linear_residual;
        out->linear_converged = f.report.linear_converged;
        fill_frame_info(f, info);
    });
    return DFM_OK;
}

extern "C" DFM_API dfm_result dfm_mesh_subdivide(const dfm_mesh* mesh, uint32_t steps,
                                                 dfm_mesh** out) {
    constexpr const char* fn = "dfm_mesh_subdivide";
    if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
    *out = nullptr;
    if (!is_live(mesh, Kind::mesh)) return bad_handle(fn, "mesh", mesh);
    if (steps < 1 || steps > max_subdivision_steps) {
        return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                      "steps " + std::to_string(steps) + " is not 1, 2 or 3");
    }
    return guarded(fn, [&] {
        mesh::Mesh fine = mesh->state->current()->mesh;
        for (std::uint32_t k = 0; k < steps; ++k) fine = mesh::subdivide_loop(fine);
        return new_mesh_handle(mesh->state->context, std::move(fine), out);
    });
}

extern "C" DFM_API dfm_result dfm_mesh_load_with_report(dfm_context* context, const char* path,
                                                        dfm_load_report* report_out,
                                                        dfm_mesh** out) {
    constexpr const char* fn = "dfm_mesh_load_with_report";
    if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
    *out = nullptr;
    if (report_out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "report is NULL");
    *report_out = dfm_load_report{};
    if (!is_live(context, Kind::context)) return bad_handle(fn, "context", context);
    if (path == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "path is NULL");
    return guarded(fn, [&] {
        std::filesystem::path file;
        const std::string& models = context->state->models_directory;
        if (Status s = mesh::resolve_mesh_spec(path, std::filesystem::current_path(), models, file);
            !s) {
            if (models.empty() && s.code() == Errc::not_found) {
                return report(fn, DFM_ERROR_NOT_FOUND,
                              s.message() + " (set dfm_context_desc.models_directory)");
            }
            return report(fn, s);
        }
        mesh::Mesh m;
        mesh::LoadReport load_report;
        if (Status s = mesh::load_mesh(file, m, &load_report); !s) return report(fn, s);
        for (const std::string& warning : load_report.warnings) {
            context->state->emit(DFM_LOG_WARNING, DFM_LOG_ID_LOAD_WARNING, warning);
        }
        if (m.vertex_count() == 0 || m.face_count() == 0) {
            return report(fn, DFM_ERROR_PARSE, file.string() + ": the mesh has no triangles");
        }
        if (dfm_result r = new_mesh_handle(context->state, std::move(m), out); r != DFM_OK) {
            return r;
        }
        report_out->polygons = load_report.polygons;
        report_out->triangulated_polygons = load_report.triangulated_polygons;
        report_out->dropped_faces = load_report.dropped_faces;
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_mesh_get_summary(const dfm_mesh* mesh, dfm_mesh_summary* out) {
    constexpr const char* fn = "dfm_mesh_get_summary";
    if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
    *out = dfm_mesh_summary{};
    if (!is_live(mesh, Kind::mesh)) return bad_handle(fn, "mesh", mesh);
    return guarded(fn, [&] {
        const mesh::MeshSummary s = mesh::summarize(mesh->state->current()->mesh);
        out->edges = s.edges;
        out->boundary_edges = s.boundary_edges;
        out->non_manifold_edges = s.non_manifold_edges;
        out->inconsistent_edges = s.inconsistent_edges;
        out->components = s.components;
        out->isolated_vertices = s.isolated_vertices;
        out->degenerate_triangles = s.degenerate_faces;
        out->closed = s.closed;
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_mesh_save_with_options(const dfm_mesh* mesh, const char* path,
                                                         const dfm_save_options* options) {
    constexpr const char* fn = "dfm_mesh_save_with_options";
    if (!is_live(mesh, Kind::mesh)) return bad_handle(fn, "mesh", mesh);
    if (path == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "path is NULL");
    mesh::WriteOptions write;
    if (options != nullptr) {
        // Read as an integer: a host's out-of-range value is not an enum load.
        int encoding = 0;
        static_assert(sizeof(encoding) == sizeof(options->ply_encoding));
        std::memcpy(&encoding, &options->ply_encoding, sizeof encoding);
        switch (encoding) {
            case DFM_PLY_BINARY_LITTLE_ENDIAN:
                write.ply_encoding = mesh::PlyEncoding::binary_little_endian;
                break;
            case DFM_PLY_BINARY_BIG_ENDIAN:
                write.ply_encoding = mesh::PlyEncoding::binary_big_endian;
                break;
            case DFM_PLY_ASCII: write.ply_encoding = mesh::PlyEncoding::ascii; break;
            default:
                return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                              "options.ply_encoding " + std::to_string(encoding) + " is unknown");
        }
        write.ply_double = !options->ply_float;
        write.obj_normals = options->obj_normals;
    }
    return guarded(
        fn, [&] { return report(fn, mesh::save_mesh(path, mesh->state->current()->mesh, write)); });
}
