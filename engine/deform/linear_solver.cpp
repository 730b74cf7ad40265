#include "deform/linear_solver.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <new>
#include <string>
#include <vector>

#include "core/memory_bytes.hpp"
#include "solver/parallel_kernels.hpp"
#include "solver/pbcg.hpp"
#include "solver/preconditioner.hpp"

namespace dfm::deform {

struct LinearSolver::State {
    solver::CsrMatrix matrix;
    std::unique_ptr<solver::Preconditioner> preconditioner;
    solver::PbcgWorkspace workspace;
    solver::PbcgResult result;
    jobs::WorkerPool* pool = nullptr;  // the factor's, also the residual's and the Krylov solve's
    bool exact = false;                // the preconditioner is the complete factor of the matrix
    // The largest max |M⁻¹ r₀| / max |r₀| a Krylov solve has started from
    // (0: none yet): with the complete factor, how much a residual of its
    // solves grows into an error.
    double amplification = 0.0;
    bool by_residual = false;      // the last verified solve was confirmed by its residual
    std::vector<double> residual;  // b − N x of a confirmation by the residual
    std::vector<double> partial;   // the kernels' partial sums
    std::array<double, 3> largest{}, residual2{}, rhs2{};

    // Confirms x by its residual alone (Accuracy::verified); fills the
    // result as a Krylov solve that converged at its start would.
    bool confirmed_by_residual(std::span<const double> rhs, std::span<const double> x,
                               double tolerance);
    // Learns from a Krylov solve's start how the complete factor's
    // residuals grow into errors.
    void learn_amplification();
};

namespace {

constexpr double residual_check_margin = 16.0;

}  // namespace

bool LinearSolver::State::confirmed_by_residual(std::span<const double> rhs,
                                                std::span<const double> x, double tolerance) {
    constexpr std::size_t k = 3;
    solver::kernels::residual(matrix, rhs, x, residual, k, largest, residual2, rhs2, partial, pool);
    for (std::size_t c = 0; c < k; ++c) {
        if (!(amplification * largest[c] * residual_check_margin <= tolerance)) return false;
    }
    result.iterations = 0;
    result.converged = true;
    for (std::size_t c = 0; c < k; ++c) {
        solver::PbcgColumnResult& column = result.columns[c];
        column = solver::PbcgColumnResult{};
        column.converged = true;
        column.error_estimate = amplification * largest[c];
        column.start_residual = largest[c];
        column.start_error_estimate = column.error_estimate;
        column.relative_residual =
            rhs2[c] > 0.0 ? std::sqrt(residual2[c] / rhs2[c]) : std::sqrt(residual2[c]);
    }
    return true;
}

void LinearSolver::State::learn_amplification() {
    for (const solver::PbcgColumnResult& c : result.columns) {
        if (!(c.start_residual > 0.0)) continue;
        const double ratio = c.start_error_estimate / c.start_residual;
        if (std::isfinite(ratio)) amplification = std::max(amplification, ratio);
    }
}

LinearSolver::LinearSolver() = default;
LinearSolver::~LinearSolver() = default;
LinearSolver::LinearSolver(LinearSolver&&) noexcept = default;
LinearSolver& LinearSolver::operator=(LinearSolver&&) noexcept = default;

Status LinearSolver::setup(solver::CsrMatrix matrix, solver::PreconditionerKind preconditioner,
                           jobs::WorkerPool* pool, const std::atomic<bool>* stop) {
    auto state = std::make_unique<State>();
    state->matrix = std::move(matrix);
    state->pool = pool;
    if (analyzed_ != nullptr && preconditioner == solver::PreconditionerKind::cholesky) {
        state->preconditioner = std::move(analyzed_);
    } else {
        state->preconditioner = solver::make_preconditioner(preconditioner, pool);
    }
    analyzed_.reset();
    if (auto* cholesky = dynamic_cast<solver::CholeskyPreconditioner*>(state->preconditioner.get()))
        cholesky->set_stop(stop);
    if (Status s = state->preconditioner->setup(state->matrix); !s) return s;
    state->preconditioner->reserve(3);
    state->workspace = solver::PbcgWorkspace(state->matrix.rows, 3);
    state->result.columns.resize(3);
    state->residual.assign(state->matrix.rows * 3, 0.0);
    state->partial.assign(solver::kernels::block_count(state->matrix.rows) * 3 * 3, 0.0);
    state->exact = state->preconditioner->is_exact();
    if (auto* cholesky = dynamic_cast<solver::CholeskyPreconditioner*>(state->preconditioner.get()))
        cholesky->set_stop(nullptr);
    state_ = std::move(state);
    return Status::ok();
}

Status LinearSolver::analyze(const solver::CsrMatrix& pattern,
                             solver::PreconditionerKind preconditioner, jobs::WorkerPool* pool,
                             const std::atomic<bool>* stop) {
    analyzed_.reset();
    if (preconditioner != solver::PreconditionerKind::cholesky) return Status::ok();
    auto cholesky = std::make_unique<solver::CholeskyPreconditioner>(
        solver::OrderingMethod::minimum_degree, pool);
    cholesky->set_stop(stop);
    if (Status s = cholesky->analyze(pattern); !s) return s;
    cholesky->set_stop(nullptr);
    analyzed_ = std::move(cholesky);
    return Status::ok();
}

LinearSolver::Memory LinearSolver::memory() const {
    if (!state_) return {};
    return {.preconditioner = state_->preconditioner->memory_bytes(),
            .matrix = state_->matrix.memory_bytes(),
            .workspace = state_->workspace.memory_bytes() +
                         capacity_bytes(state_->residual, state_->partial)};
}

Status LinearSolver::solve(std::span<const double> rhs, std::span<double> x, double tolerance,
                           Accuracy accuracy, std::size_t& iterations) {
    State& s = *state_;
    if (s.exact && accuracy == Accuracy::one_step) {
        // With the complete factor one application is the exact solution up
        // to rounding, warm start or not; the check that would confirm it
        // costs a second solve, so inside the outer iteration it is left to
        // the final, verified solve.
        s.preconditioner->apply(rhs, x, 3);
        iterations = 1;
        return Status::ok();
    }
    s.by_residual = s.exact && s.amplification > 0.0 && s.confirmed_by_residual(rhs, x, tolerance);
    if (s.by_residual) {
        iterations = 0;
        return Status::ok();
    }
    solver::PbcgOptions options;
    options.tolerance = tolerance;
    options.pool = s.pool;
    if (Status st = solver::pbcg_solve(s.matrix, *s.preconditioner, rhs, x, 3, options, s.workspace,
                                       s.result);
        !st) {
        return st;
    }
    iterations = s.result.iterations;
    if (s.exact) s.learn_amplification();
    for (double v : x) {
        if (!std::isfinite(v)) return Status(Errc::numerical, "the linear solve diverged");
    }
    return Status::ok();
}

bool LinearSolver::converged() const {
    return state_->result.converged;
}

bool LinearSolver::confirmed_by_residual() const {
    return state_->by_residual;
}

solver::CholeskyTimes LinearSolver::factor_times() const {
    const auto* cholesky =
        dynamic_cast<const solver::CholeskyPreconditioner*>(state_->preconditioner.get());
    return cholesky != nullptr ? cholesky->factor().times() : solver::CholeskyTimes{};
}

double LinearSolver::relative_residual() const {
    double worst = 0.0;
    for (const solver::PbcgColumnResult& c : state_->result.columns) {
        worst = std::max(worst, c.relative_residual);
    }
    return worst;
}

}  // namespace dfm::deform
