#include "deform/fitted_iteration.hpp"

#include <algorithm>
#include <chrono>

#include <glm/geometric.hpp>

#include "core/stopwatch.hpp"
#include "deform/deform_energy.hpp"
#include "deform/rotation_fit.hpp"
#include "solver/parallel_kernels.hpp"

namespace dfm::deform {

namespace {

// A solve may start far from the last fit (new targets, a rigid
// alignment): its first fit runs to convergence. Between iterates the
// rotations move little, and one Newton step from the last fit is exact to
// second order (more steps did not cut the iterations).
constexpr int first_fit_steps = 32;

// With nothing outside the handles to pin it, the ROI floats: its rotation
// as a whole is set by the handles alone, and the iteration turns it only
// slowly (over 100 iterations for the whole armadillo turned by 45°). So the
// unknowns first take the rigid motion that best maps the handles onto their
// targets. The fitted energy is blind to rigid motions, and that one brings
// the handle rows closest: the energy does not rise, and a rigid edit is
// solved at once.
void align_to_handles(IterationState& state) {
    const std::size_t count = state.handle_vertices.size();
    if (state.pinned || count == 0) return;
    glm::dvec3 from(0.0);
    glm::dvec3 to(0.0);
    for (std::size_t h = 0; h < count; ++h) {
        from += state.positions[state.handle_vertices[h]];
        to += state.targets[h];
    }
    from /= static_cast<double>(count);
    to /= static_cast<double>(count);
    glm::dmat3 covariance(0.0);
    for (std::size_t h = 0; h < count; ++h) {
        covariance += glm::outerProduct(state.targets[h] - to,
                                        state.positions[state.handle_vertices[h]] - from);
    }
    glm::dquat q(1.0, 0.0, 0.0, 0.0);
    const glm::dmat3 rotation = fit_rotation(covariance, q, 64).rotation;
    std::span<double> current = state.current;
    for (std::size_t i = 0; i < state.unknowns->count(); ++i) {
        const glm::dvec3 p(current[3 * i], current[3 * i + 1], current[3 * i + 2]);
        const glm::dvec3 moved = to + rotation * (p - from);
        for (int c = 0; c < 3; ++c) current[3 * i + c] = moved[c];
    }
}

}  // namespace

FittedIteration::FittedIteration(const MeshModel& model, const UnknownMap& unknowns,
                                 const SystemRows& rows, const RotationClusters& clusters) {
    rotations_.build(model, unknowns, rows, clusters);
}

solver::CsrMatrix FittedIteration::assemble_normal_matrix(IterationState& state,
                                                          const std::atomic<bool>* stop) const {
    return rotations_.assemble_normal_matrix(state.unknowns->count(), state.soft_handles,
                                             state.settings->handle_weight, relative_regularization,
                                             state.epsilon, stop);
}

double FittedIteration::fit_and_prepare(IterationState& state, std::span<const double> x,
                                        int rotation_steps, SolveReport& report) {
    auto phase = std::chrono::steady_clock::now();
    const double handles =
        write_handle_terms(x, state.soft_handles, state.targets, state.settings->handle_weight,
                           state.epsilon, state.rhs);
    report.rhs_ms += ms_since(phase);
    phase = std::chrono::steady_clock::now();
    const double fitted =
        rotations_.fit_and_add(x, state.positions, rotation_steps, state.rhs, state.settings->pool);
    report.normals_ms += ms_since(phase);
    return handles + fitted;
}

double FittedIteration::start(IterationState& state, SolveReport& report) {
    state.anderson.restart();
    if (!report.predicted) align_to_handles(state);
    const double energy = fit_and_prepare(state, state.current, first_fit_steps, report);
    rotations_.keep_fit();
    report.energy = energy;
    solver::kernels::copy(state.current, state.x, state.settings->pool);
    return energy;
}

double FittedIteration::advance(IterationState& state, SolveReport& report, double energy) {
    const auto phase = std::chrono::steady_clock::now();
    state.anderson.step(state.current, state.x, state.next);
    report.anderson_ms += ms_since(phase);
    const double trial = fit_and_prepare(state, state.next, 1, report);
    if (trial <= energy) {
        energy = trial;
        rotations_.keep_fit();
        std::copy(state.next.begin(), state.next.end(), state.current.begin());
    } else {
        // The plain step: the global step did not raise the energy with the
        // old rotations, and refitting them from there lowers it.
        ++report.rejected_steps;
        energy = fit_and_prepare(state, state.x, 1, report);
        rotations_.keep_fit();
        std::copy(state.x.begin(), state.x.end(), state.current.begin());
    }
    std::copy(state.current.begin(), state.current.end(), state.x.begin());
    // The iterate a preview shows, and what an interrupted solve leaves.
    state.store(state.x);
    report.energy = energy;
    return energy;
}

}  // namespace dfm::deform
