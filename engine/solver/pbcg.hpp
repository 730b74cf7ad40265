#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "core/memory_bytes.hpp"
#include "core/status.hpp"
#include "jobs/worker_pool.hpp"
#include "solver/csr_matrix.hpp"
#include "solver/preconditioner.hpp"

namespace dfm::solver {

struct PbcgOptions {
    // Stop a column once max_j |(M⁻¹ r)_j| ≤ tolerance: an absolute bound in
    // solution units (say 1e-10 × the mesh's bounding-box diagonal). With
    // M ≈ A, M⁻¹ r ≈ A⁻¹ (b − A x) is the error itself, so a warm start
    // close to the solution cannot stop early with a large error, as a stop
    // relative to the first residual can. (With a weak M such as Jacobi the
    // estimate can be far below the true error.)
    double tolerance = 1e-10;
    std::size_t max_iterations = 1000;
    // Stop a column, unconverged, once this many iterations in a row bring
    // no new smallest error estimate (a limit above max_iterations never
    // does). 0 chooses: 3 when M is exact (Preconditioner::is_exact), whose
    // estimate stalls only when the tolerance lies below what rounding
    // allows for the system; never otherwise, since weak preconditioners'
    // estimates can stall for hundreds of iterations and still converge.
    std::size_t stagnation_limit = 0;
    // Spreads the vector work and products with A over its threads (not
    // owned; null runs inline). Results are the same bits either way.
    jobs::WorkerPool* pool = nullptr;
};

struct PbcgColumnResult {
    std::size_t iterations = 0;
    bool converged = false;
    bool breakdown = false;       // ρ or p̃ᵀAp vanished (or stopped being finite) first
    bool stagnated = false;       // stopped by options.stagnation_limit
    double error_estimate = 0.0;  // the last max |M⁻¹ r|, r = b − A x recomputed
    // The start's max |r₀| and max |M⁻¹ r₀|, r₀ = b − A x for the x passed in.
    double start_residual = 0.0;
    double start_error_estimate = 0.0;
    // ‖b − A x‖₂ / ‖b‖₂ recomputed from the final x (‖A x‖₂ when b = 0).
    double relative_residual = 0.0;
};

struct PbcgResult {
    std::size_t iterations = 0;  // the most any column took
    bool converged = false;      // every column
    std::vector<PbcgColumnResult> columns;
};

// Work vectors for systems of n unknowns with up to k right-hand sides,
// allocated once so that solves allocate nothing.
class PbcgWorkspace {
public:
    PbcgWorkspace() = default;
    PbcgWorkspace(std::size_t n, std::size_t k);

    std::size_t size() const { return n_; }
    std::size_t columns() const { return k_; }
    std::size_t memory_bytes() const {
        return capacity_bytes(r_, z_, p_, q_, partial_, rho_, rho_old_, pq_, error_, b_norm_, best_,
                              stalled_, active_);
    }

private:
    friend Status pbcg_solve(const CsrMatrix&, Preconditioner&, std::span<const double>,
                             std::span<double>, std::size_t, const PbcgOptions&, PbcgWorkspace&,
                             PbcgResult&);

    std::size_t n_ = 0;
    std::size_t k_ = 0;
    std::vector<double> r_, z_, p_, q_;
    std::vector<double> partial_;
    std::vector<double> rho_, rho_old_, pq_, error_, b_norm_, best_;
    std::vector<std::size_t> stalled_;
    std::vector<unsigned char> active_;
};

// Solves A x = b for k interleaved right-hand sides (b[j * k + c] is entry j
// of column c) by the preconditioned bi-conjugate gradient, starting from
// the x passed in (warm start). A and M must be symmetric, A positive
// definite, as the edit's normal matrix and every preconditioner here are:
// the shadow sequence then equals the primal one, and the method is
// preconditioned conjugate gradients at half the work. All k columns share
// each pass over A and each application of M; every column keeps its own
// scalars and stops updating once converged or broken down. Stops when
// every column has stopped or at options.max_iterations. M must be set up
// for A. Fails only on bad arguments (sizes, M not set up for a matrix of
// A's order, a workspace too small, a tolerance that is negative or NaN);
// a solve that does not converge is reported in `result`.
// Allocates nothing once `result` has held k columns and M has been reserved
// for k. Not thread-safe for a shared workspace, preconditioner or result.
Status pbcg_solve(const CsrMatrix& a, Preconditioner& m, std::span<const double> b,
                  std::span<double> x, std::size_t k, const PbcgOptions& options,
                  PbcgWorkspace& work, PbcgResult& result);

}  // namespace dfm::solver
