// The report calls of dualform.h: quality figures, solver figures and their
// details, Loop subdivision, load figures, the mesh summary and save options:
// what the dualform tool needs to do its work through the C API alone.

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "c_boundary.hpp"
#include "deform/quality.hpp"
#include "host_numbering.hpp"
#include "mesh/load.hpp"
#include "mesh/model_cache.hpp"
#include "mesh/subdivide.hpp"
#include "mesh/summary.hpp"
#include "mesh/write.hpp"
#include "objects.hpp"
#include "shared_calls.hpp"

using namespace dfm;
using namespace dfm::sdk;

namespace {

constexpr std::uint32_t max_subdivision_steps = 3;
constexpr std::size_t save_options_0_2 = DFM_END_OF(dfm_save_options, obj_normals);
constexpr std::size_t solve_details_first = DFM_END_OF(dfm_solve_details, predicted);

}  // namespace

extern "C" DFM_API dfm_result dfm_session_measure_quality(dfm_session* session, dfm_quality* out,
                                                          dfm_frame_info* info) {
    constexpr const char* fn = "dfm_session_measure_quality";
    return guarded(fn, [&] {
        if (info != nullptr) *info = dfm_frame_info{};
        SessionObject* s = resolve_session(session);
        if (s == nullptr) return bad_handle(fn, "session", session);
        if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
        *out = dfm_quality{};
        const deform::QualityReport q =
            s->edit->measure_quality([&](const deform::Frame& f) { fill_frame_info(f, info); });
        out->max_handle_error = q.max_handle_error;
        out->mean_abs_log_edge = q.mean_abs_log_edge;
        out->max_abs_log_edge = q.max_abs_log_edge;
        out->mean_normal_change_deg = q.mean_normal_change_deg;
        out->max_fixed_move = q.max_fixed_move;
        out->dual_magnitude_error = q.dual_magnitude_error;
        out->flipped_faces = q.flipped_faces;
        out->creased_edges = q.creased_edges;
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_session_get_solve_report(dfm_session* session,
                                                           dfm_solve_report* out,
                                                           dfm_frame_info* info) {
    constexpr const char* fn = "dfm_session_get_solve_report";
    return guarded(fn, [&] {
        if (info != nullptr) *info = dfm_frame_info{};
        SessionObject* s = resolve_session(session);
        if (s == nullptr) return bad_handle(fn, "session", session);
        if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
        *out = dfm_solve_report{};
        const deform::SetupReport setup = s->edit->async().setup_report();
        out->unknowns = setup.unknowns;
        out->rows = setup.rows;
        out->normal_nonzeros = setup.normal_nonzeros;
        out->setup_ms = setup.setup_ms;
        s->edit->async().read([&](const deform::Frame& f) {
            out->krylov_iterations = f.report.krylov_iterations;
            out->linear_residual = f.report.linear_residual;
            out->linear_converged = f.report.linear_converged;
            fill_frame_info(f, info);
        });
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_session_get_solve_details(dfm_session* session,
                                                            dfm_solve_details* out,
                                                            dfm_frame_info* info) {
    constexpr const char* fn = "dfm_session_get_solve_details";
    return guarded(fn, [&] {
        if (info != nullptr) *info = dfm_frame_info{};
        SessionObject* s = resolve_session(session);
        if (s == nullptr) return bad_handle(fn, "session", session);
        // The host's struct_size says how many bytes are its own to write.
        dfm_solve_details details;
        if (dfm_result r = read_descriptor(fn, "out", out, solve_details_first, details);
            r != DFM_OK) {
            return r;
        }
        const std::uint32_t struct_size = details.struct_size;
        const std::size_t size = struct_size != 0 ? struct_size : solve_details_first;
        details = dfm_solve_details{};
        details.struct_size = struct_size;
        const deform::SetupReport setup = s->edit->async().setup_report();
        details.setup_rows_ms = setup.rows_ms;
        details.setup_assembly_ms = setup.assembly_ms;
        details.setup_ordering_ms = setup.ordering_ms;
        details.setup_symbolic_ms = setup.symbolic_ms;
        details.setup_numeric_ms = setup.numeric_ms;
        s->edit->async().read([&](const deform::Frame& f) {
            details.linear_solve_ms = f.report.linear_ms;
            details.right_hand_side_ms = f.report.rhs_ms;
            details.normals_ms = f.report.normals_ms;
            details.anderson_ms = f.report.anderson_ms;
            details.predicted = f.report.predicted;
            fill_frame_info(f, info);
        });
        // A newer, larger struct keeps its zero tail (read_descriptor checked it).
        std::memcpy(out, &details, std::min(size, sizeof details));
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_mesh_subdivide(const dfm_mesh* mesh, uint32_t steps,
                                                 dfm_mesh** out) {
    constexpr const char* fn = "dfm_mesh_subdivide";
    return guarded(fn, [&] {
        if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
        *out = nullptr;
        MeshObject* m = resolve_mesh(mesh);
        if (m == nullptr) return bad_handle(fn, "mesh", mesh);
        if (steps < 1 || steps > max_subdivision_steps) {
            return report(fn, DFM_ERROR_INVALID_ARGUMENT,
                          "steps " + std::to_string(steps) + " is not 1, 2 or 3");
        }
        if (!HostNumbering(*m->state, 0).identity()) {
            return report(fn, DFM_ERROR_UNSUPPORTED,
                          "the mesh has split copies (a weld); subdivision would renumber them");
        }
        mesh::Mesh fine = m->state->current()->mesh;
        for (std::uint32_t k = 0; k < steps; ++k) fine = mesh::subdivide_loop(fine);
        const std::shared_ptr<const ContextState>& context = m->state->context;
        return make_mesh_handle(*context, context, std::move(fine), out);
    });
}

extern "C" DFM_API dfm_result dfm_mesh_load_with_report(dfm_context* context, const char* path,
                                                        dfm_load_report* report_out,
                                                        dfm_mesh** out) {
    constexpr const char* fn = "dfm_mesh_load_with_report";
    return guarded(fn, [&] {
        if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
        *out = nullptr;
        if (report_out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "report is NULL");
        *report_out = dfm_load_report{};
        ContextObject* c = resolve_context(context);
        if (c == nullptr) return bad_handle(fn, "context", context);
        if (path == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "path is NULL");
        mesh::LoadReport load_report;
        if (dfm_result r = load_mesh_file(fn, *c, path, load_report, out); r != DFM_OK) return r;
        report_out->polygons = load_report.polygons;
        report_out->triangulated_polygons = load_report.triangulated_polygons;
        report_out->dropped_faces = load_report.dropped_faces;
        return DFM_OK;
    });
}

extern "C" DFM_API dfm_result dfm_mesh_get_summary(const dfm_mesh* mesh, dfm_mesh_summary* out) {
    constexpr const char* fn = "dfm_mesh_get_summary";
    return guarded(fn, [&] {
        if (out == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "out is NULL");
        *out = dfm_mesh_summary{};
        MeshObject* m = resolve_mesh(mesh);
        if (m == nullptr) return bad_handle(fn, "mesh", mesh);
        const mesh::MeshSummary s = mesh::summarize(m->state->current()->mesh);
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
    return guarded(fn, [&] {
        MeshObject* m = resolve_mesh(mesh);
        if (m == nullptr) return bad_handle(fn, "mesh", mesh);
        if (path == nullptr) return report(fn, DFM_ERROR_INVALID_ARGUMENT, "path is NULL");
        mesh::WriteOptions write;
        if (options != nullptr) {
            dfm_save_options o;
            if (dfm_result r = read_descriptor(fn, "options", options, save_options_0_2, o);
                r != DFM_OK) {
                return r;
            }
            // Read as an integer: a host's out-of-range value is not an enum load.
            int encoding = 0;
            static_assert(sizeof(encoding) == sizeof(o.ply_encoding));
            std::memcpy(&encoding, &o.ply_encoding, sizeof encoding);
            switch (encoding) {
                case DFM_PLY_BINARY_LITTLE_ENDIAN:
                    write.ply_encoding = mesh::PlyEncoding::binary_little_endian;
                    break;
                case DFM_PLY_BINARY_BIG_ENDIAN:
                    write.ply_encoding = mesh::PlyEncoding::binary_big_endian;
                    break;
                case DFM_PLY_ASCII: write.ply_encoding = mesh::PlyEncoding::ascii; break;
                default:
                    return report(
                        fn, DFM_ERROR_INVALID_ARGUMENT,
                        "options->ply_encoding " + std::to_string(encoding) + " is unknown");
            }
            write.ply_double = !o.ply_float;
            write.obj_normals = o.obj_normals;
            if (o.morph_target_name != nullptr) write.morph_target = o.morph_target_name;
        }
        return report(fn,
                      mesh::save_host_mesh(path, m->state->current()->mesh, m->state->host, write));
    });
}
