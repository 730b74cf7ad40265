#include "deform/linear_solver.hpp"

#include <algorithm>
#include <cmath>
#include <new>
#include <string>
#include <vector>

#include "solver/pbcg.hpp"
#include "solver/preconditioner.hpp"

namespace dfm::deform {

struct LinearSolver::State {
    solver::CsrMatrix matrix;
    std::unique_ptr<solver::Preconditioner> preconditioner;
    solver::PbcgWorkspace workspace;
    solver::PbcgResult result;
    bool exact = false;  // the preconditioner is the complete factor of the matrix
};

LinearSolver::LinearSolver() = default;
LinearSolver::~LinearSolver() = default;
LinearSolver::LinearSolver(LinearSolver&&) noexcept = default;
LinearSolver& LinearSolver::operator=(LinearSolver&&) noexcept = default;

Status LinearSolver::setup(solver::CsrMatrix matrix, solver::PreconditionerKind preconditioner,
                           solver::ThreadPool* pool, const std::atomic<bool>* stop) {
    auto state = std::make_unique<State>();
    state->matrix = std::move(matrix);
    state->preconditioner = solver::make_preconditioner(preconditioner, pool);
    if (auto* cholesky = dynamic_cast<solver::CholeskyPreconditioner*>(state->preconditioner.get()))
        cholesky->set_stop(stop);
    if (Status s = state->preconditioner->setup(state->matrix); !s) return s;
    state->preconditioner->reserve(3);
    state->workspace = solver::PbcgWorkspace(state->matrix.rows, 3);
    state->result.columns.resize(3);
    state->exact = state->preconditioner->is_exact();
    if (auto* cholesky = dynamic_cast<solver::CholeskyPreconditioner*>(state->preconditioner.get()))
        cholesky->set_stop(nullptr);
    state_ = std::move(state);
    return Status::ok();
}

LinearSolver::Memory LinearSolver::memory() const {
    if (!state_) return {};
    return {.preconditioner = state_->preconditioner->memory_bytes(),
            .matrix = state_->matrix.memory_bytes(),
            .workspace = state_->workspace.memory_bytes()};
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
    solver::PbcgOptions options;
    options.tolerance = tolerance;
    if (Status st = solver::pbcg_solve(s.matrix, *s.preconditioner, rhs, x, 3, options, s.workspace,
                                       s.result);
        !st) {
        return st;
    }
    iterations = s.result.iterations;
    for (double v : x) {
        if (!std::isfinite(v)) return Status(Errc::numerical, "the linear solve diverged");
    }
    return Status::ok();
}

bool LinearSolver::converged() const {
    return state_->result.converged;
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
