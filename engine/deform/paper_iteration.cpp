#include "deform/paper_iteration.hpp"

#include <algorithm>
#include <chrono>
#include <limits>

#include "core/stopwatch.hpp"
#include "dual/dual_laplacian.hpp"

namespace dfm::deform {

PaperIteration::PaperIteration(const MeshModel& model, SystemRows rows)
    : model_(model), rows_(std::move(rows)) {
    centroids_.assign(model.mesh.face_count(), glm::dvec3(0.0));
    dual_targets_.resize(rows_.size());
}

solver::CsrMatrix PaperIteration::assemble_normal_matrix(IterationState& state,
                                                         const std::atomic<bool>* stop) const {
    return deform::assemble_normal_matrix(rows_, state.unknowns->count(), state.soft_handles,
                                          state.settings->handle_weight, relative_regularization,
                                          state.epsilon, stop);
}

void PaperIteration::prepare(IterationState& state, SolveReport& report) {
    auto phase = std::chrono::steady_clock::now();
    // Step 2 of the iteration: l_r = -h n, with the rest height and the
    // normal of the current 1-ring.
    const mesh::Mesh& mesh = model_.mesh;
    const std::span<const glm::dvec3> positions = state.positions;
    for (std::uint32_t f : rows_.centroid_faces) {
        const mesh::Triangle& t = mesh.triangles[f];
        centroids_[f] = (positions[t[0]] + positions[t[1]] + positions[t[2]]) / 3.0;
    }
    for (std::size_t r = 0; r < rows_.size(); ++r) {
        const std::uint32_t f = rows_.faces[r];
        dual_targets_[r] = -model_.dual.heights[f] * dual::ring_normal(model_.dual, centroids_, f);
    }
    report.normals_ms += ms_since(phase);
    phase = std::chrono::steady_clock::now();
    std::span<double> rhs = state.rhs;
    std::fill(rhs.begin(), rhs.end(), 0.0);
    for (std::size_t r = 0; r < rows_.size(); ++r) {
        glm::dvec3 b = dual_targets_[r];
        for (std::uint32_t p = rows_.entry_offsets[r]; p < rows_.entry_offsets[r + 1]; ++p) {
            const RowEntry& e = rows_.entries[p];
            if (e.unknown == mesh::no_index) b -= e.coefficient * positions[e.vertex];
        }
        for (std::uint32_t p = rows_.entry_offsets[r]; p < rows_.entry_offsets[r + 1]; ++p) {
            const RowEntry& e = rows_.entries[p];
            if (e.unknown == mesh::no_index) continue;
            for (int c = 0; c < 3; ++c) rhs[3 * e.unknown + c] += e.coefficient * b[c];
        }
    }
    const double w2 = state.settings->handle_weight * state.settings->handle_weight;
    for (std::size_t h = 0; h < state.soft_handles.size(); ++h) {
        for (int c = 0; c < 3; ++c) rhs[3 * state.soft_handles[h] + c] += w2 * state.targets[h][c];
    }
    const UnknownMap& unknowns = *state.unknowns;
    for (std::size_t i = 0; i < unknowns.count(); ++i) {
        const glm::dvec3& p = positions[unknowns.vertex_of_unknown[i]];
        for (int c = 0; c < 3; ++c) rhs[3 * i + c] += state.epsilon * p[c];
    }
    report.rhs_ms += ms_since(phase);
}

double PaperIteration::start(IterationState& state, SolveReport& report) {
    std::copy(state.current.begin(), state.current.end(), state.x.begin());
    if (report.predicted) {
        state.store(state.x);
        state.anderson.continue_history();
    } else {
        state.anderson.restart();
    }
    prepare(state, report);
    return std::numeric_limits<double>::infinity();
}

double PaperIteration::advance(IterationState& state, SolveReport& report, double smallest_update) {
    // The extrapolated iterates are not monotone, and restarting at every
    // growth stalls them (measured on the whole cow); a step more than
    // twice the smallest so far means the history has gone astray.
    const auto phase = std::chrono::steady_clock::now();
    if (report.last_update > 2.0 * smallest_update) state.anderson.restart();
    smallest_update = std::min(smallest_update, report.last_update);
    state.anderson.step(state.current, state.x, state.next);
    report.anderson_ms += ms_since(phase);
    std::copy(state.next.begin(), state.next.end(), state.current.begin());
    std::copy(state.next.begin(), state.next.end(), state.x.begin());
    state.store(state.x);
    prepare(state, report);
    return smallest_update;
}

}  // namespace dfm::deform
