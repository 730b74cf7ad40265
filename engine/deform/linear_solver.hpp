#pragma once

#include <atomic>
#include <cstddef>
#include <memory>
#include <span>

#include "core/status.hpp"
#include "jobs/worker_pool.hpp"
#include "solver/csr_matrix.hpp"
#include "solver/preconditioner_kind.hpp"
#include "solver/sparse_cholesky.hpp"

namespace dfm::solver {
class CholeskyPreconditioner;
}  // namespace dfm::solver

namespace dfm::deform {

// The normal matrix of an edit, prepared once and solved for x, y and z
// together every iteration. Owns the matrix, the preconditioner and the
// Krylov workspace, so a solve allocates nothing.
class LinearSolver {
public:
    LinearSolver();
    ~LinearSolver();
    LinearSolver(LinearSolver&&) noexcept;
    LinearSolver& operator=(LinearSolver&&) noexcept;

    // `pool` (optional, not owned, outliving the solver) spreads the factor's
    // work; results are bit-identical whatever its thread count. `stop`
    // (optional) stops the complete factor's set-up part way
    // (solver::SparseCholesky::set_stop): Errc::cancelled.
    Status setup(solver::CsrMatrix matrix, solver::PreconditionerKind preconditioner,
                 jobs::WorkerPool* pool = nullptr, const std::atomic<bool>* stop = nullptr);

    // The complete factor's ordering and symbolic analysis from N's pattern
    // alone (`pattern`'s values are not read), ahead of N's values, so that
    // they can run beside the assembly: the next setup with the cholesky
    // preconditioner and a matrix of this pattern only factors (with any
    // other pattern it analyses again). Does nothing for the other
    // preconditioners. The arguments are setup's.
    Status analyze(const solver::CsrMatrix& pattern, solver::PreconditionerKind preconditioner,
                   jobs::WorkerPool* pool = nullptr, const std::atomic<bool>* stop = nullptr);

    enum class Accuracy {
        // Inside the outer iteration: with the complete factor, one step
        // (exact up to rounding, unconfirmed); otherwise to the tolerance.
        one_step,
        // To the tolerance, confirmed by the error estimate; converged()
        // says whether it was reached (a nearly singular system may not).
        // With the complete factor, once a Krylov solve has measured how
        // its residuals turn into errors (max |N⁻¹ r| / max |r|), a start
        // whose residual, so amplified, lies 16 times under the tolerance
        // is confirmed by that product alone: one multiplication by N
        // instead of a second pass over the factor.
        verified,
    };

    // Solves N x = rhs (3 interleaved columns) starting from x; the
    // tolerance bounds the estimated error |M⁻¹ r|∞ in solution units.
    // Fails only when the result is not finite.
    Status solve(std::span<const double> rhs, std::span<double> x, double tolerance,
                 Accuracy accuracy, std::size_t& iterations);

    // Whether the last Krylov solve reached its tolerance in every column.
    bool converged() const;

    // Whether the last verified solve was confirmed by its residual alone.
    bool confirmed_by_residual() const;

    // The largest ‖b − N x‖ / ‖b‖ over the three columns after the last
    // solve that ran the Krylov iteration (every verified one does).
    double relative_residual() const;

    // The phases of the complete factor's set-up (zero for the other
    // preconditioners).
    solver::CholeskyTimes factor_times() const;

    // Bytes held, by part; zeros before a setup has succeeded.
    struct Memory {
        std::size_t preconditioner = 0;  // the factor (L values, indices, analysis)
        std::size_t matrix = 0;          // N
        std::size_t workspace = 0;       // the Krylov iteration's vectors and the residual check's
    };
    Memory memory() const;

private:
    struct State;
    std::unique_ptr<State> state_;
    std::unique_ptr<solver::CholeskyPreconditioner> analyzed_;  // by analyze, for the next setup
};

}  // namespace dfm::deform
