// The report calls of dualform.h: quality figures, solver figures and Loop
// subdivision, what the dualform tool needs to report an edit through the C
// API alone.

#include <memory>
#include <vector>

#include "c_boundary.hpp"
#include "deform/quality.hpp"
#include "mesh/subdivide.hpp"
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
        const ContextState& context = *mesh->state->context;
        auto model = std::allocate_shared<deform::MeshModel>(
            HostAllocator<deform::MeshModel>(context.allocator),
            deform::build_mesh_model(std::move(fine)));
        auto state = std::allocate_shared<MeshState>(HostAllocator<MeshState>(context.allocator));
        state->context = mesh->state->context;
        state->model = std::move(model);
        *out = host_new<dfm_mesh>(context, Kind::mesh, std::move(state));
        return DFM_OK;
    });
}
