// The default method's outer iteration (docs/method.md): a local step fits
// the rotations and the global step solves the fixed normal system, each
// lowering the energy of deform_energy.hpp; Anderson acceleration proposes
// each next iterate and is kept only when it lowers that energy too, else
// the plain step is taken, so the energy never rises from one iterate to
// the next.
#include <algorithm>
#include <chrono>
#include <cmath>

#include <glm/geometric.hpp>

#include "core/stopwatch.hpp"
#include "deform/deform_energy.hpp"
#include "deform/deform_session.hpp"
#include "deform/rotation_fit.hpp"

namespace dfm::deform {

namespace {

constexpr int first_fit_steps = 32;

}  // namespace

// Moves the unknowns to `x`, fits the rotations there, and prepares the
// global step's right-hand side; returns the energy of `x`.
double DeformSession::fit_and_prepare(std::span<const double> x, int rotation_steps,
                                      SolveReport& report) {
    auto phase = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < unknowns_.count(); ++i) {
        positions_[unknowns_.vertex_of_unknown[i]] = {x[3 * i], x[3 * i + 1], x[3 * i + 2]};
    }
    const double handles =
        write_handle_terms(x, soft_handles_, targets_, settings_.handle_weight, epsilon_, rhs_);
    report.rhs_ms += ms_since(phase);
    phase = std::chrono::steady_clock::now();
    const double fitted = frames_.fit_and_add(positions_, rotation_steps, rhs_, settings_.pool);
    report.normals_ms += ms_since(phase);
    return handles + fitted;
}

// With nothing outside the handles to pin it, the ROI floats: its rotation
// as a whole is set by the handles alone, and the iteration turns it only
// slowly (over 100 iterations for the whole armadillo turned by 45°). So the
// unknowns first take the rigid motion that best maps the handles onto their
// targets. The fitted energy is blind to rigid motions, and that one brings
// the handle rows closest: the energy does not rise, and a rigid edit is
// solved at once.
void DeformSession::align_to_handles() {
    const std::size_t count = handle_vertices_.size();
    if (pinned_ || count == 0) return;
    glm::dvec3 from(0.0);
    glm::dvec3 to(0.0);
    for (std::size_t h = 0; h < count; ++h) {
        from += positions_[handle_vertices_[h]];
        to += targets_[h];
    }
    from /= static_cast<double>(count);
    to /= static_cast<double>(count);
    glm::dmat3 covariance(0.0);
    for (std::size_t h = 0; h < count; ++h) {
        covariance += glm::outerProduct(targets_[h] - to, positions_[handle_vertices_[h]] - from);
    }
    glm::dquat q(1.0, 0.0, 0.0, 0.0);
    const glm::dmat3 rotation = fit_rotation(covariance, q, 64).rotation;
    for (std::size_t i = 0; i < unknowns_.count(); ++i) {
        const glm::dvec3 p(current_[3 * i], current_[3 * i + 1], current_[3 * i + 2]);
        const glm::dvec3 moved = to + rotation * (p - from);
        for (int c = 0; c < 3; ++c) current_[3 * i + c] = moved[c];
    }
}

Status DeformSession::solve_fitted(SolveReport& report, const Control* control) {
    const auto start = std::chrono::steady_clock::now();
    anderson_.restart();
    if (!report.predicted) align_to_handles();
    // A solve may start far from the last fit (new targets, a rigid
    // alignment): its first fit runs to convergence. Between iterates the
    // rotations move little, and one Newton step from the last fit is exact
    // to second order (more steps did not cut the iterations).
    double energy = fit_and_prepare(current_, first_fit_steps, report);
    frames_.keep_fit();
    report.energy = energy;
    std::copy(current_.begin(), current_.end(), x_.begin());
    return fitted_iterations(report, control, 0, energy, start);
}

Status DeformSession::fitted_iterations(SolveReport& report, const Control* control, int first,
                                        double energy,
                                        std::chrono::steady_clock::time_point start) {
    const std::atomic<bool>* interrupt = control != nullptr ? control->interrupt : nullptr;
    const double diag = model_.diagonal > 0.0 ? model_.diagonal : 1.0;
    for (int it = first; it < settings_.max_iterations; ++it) {
        if (it > 0 && interrupt != nullptr && interrupt->load(std::memory_order_acquire)) {
            report.interrupted = true;
            report.solve_ms = ms_since(start);
            return Status::ok();
        }
        if (pause_before(it, first, energy, start, control, report)) return Status::ok();
        std::size_t krylov = 0;
        auto phase = std::chrono::steady_clock::now();
        if (Status s = linear_.solve(rhs_, x_, settings_.linear_tolerance * diag,
                                     LinearSolver::Accuracy::one_step, krylov);
            !s) {
            report.solve_ms = ms_since(start);
            return s;
        }
        report.linear_ms += ms_since(phase);
        report.krylov_iterations += krylov;
        report.iterations = it + 1;
        report.last_update = plain_step_length() / diag;
        if (!std::isfinite(report.last_update)) {
            report.solve_ms = ms_since(start);
            return Status(Errc::numerical,
                          "the solve produced non-finite positions; the last "
                          "finite result is kept");
        }
        if (report.last_update < settings_.tolerance) {
            store_solution();
            report.converged = true;
            break;
        }
        if (it + 1 == settings_.max_iterations) {
            store_solution();
            break;
        }
        phase = std::chrono::steady_clock::now();
        anderson_.step(current_, x_, next_);
        report.anderson_ms += ms_since(phase);
        const double trial = fit_and_prepare(next_, 1, report);
        if (trial <= energy) {
            energy = trial;
            frames_.keep_fit();
            std::copy(next_.begin(), next_.end(), current_.begin());
        } else {
            // The plain step: the global step did not raise the energy with
            // the old rotations, and refitting them from there lowers it.
            ++report.rejected_steps;
            energy = fit_and_prepare(x_, 1, report);
            frames_.keep_fit();
            std::copy(x_.begin(), x_.end(), current_.begin());
        }
        std::copy(current_.begin(), current_.end(), x_.begin());
        report.energy = energy;
        if (control != nullptr && control->on_iteration) control->on_iteration(report);
    }
    verify_last_solve(report);
    report.solve_ms = ms_since(start);
    return Status::ok();
}

}  // namespace dfm::deform
