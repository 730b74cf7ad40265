#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/pooled_allocator.hpp"
#include "core/status.hpp"
#include "jobs/worker_pool.hpp"
#include "solver/cholesky_schedule.hpp"
#include "solver/cholesky_symbolic.hpp"
#include "solver/csr_matrix.hpp"
#include "solver/ordering.hpp"

namespace dfm::solver {

// What one thread needs to factor supernodes: where each row of the
// supernode at hand sits in its row list, room for one update block, the
// supernode's block while it is assembled and factored (`front`), and a
// descendant's rows below its diagonal block gathered by column (`panel`).
// Each array is written before it is read.
struct CholeskyScratch {
    explicit CholeskyScratch(const CholeskySymbolic& sym);

    UnzeroedPooledVector<std::uint32_t> position;
    UnzeroedPooledVector<std::uint32_t> relative;
    UnzeroedPooledVector<double> block;
    UnzeroedPooledVector<double> front;
    UnzeroedPooledVector<double> panel;
};

// Wall-clock times of the phases that built the current factor, in ms; an
// analysis reused for a new matrix keeps its ordering and symbolic times.
struct CholeskyTimes {
    double ordering_ms = 0.0;
    double symbolic_ms = 0.0;
    double numeric_ms = 0.0;
};

// A complete sparse Cholesky factorization P A Pᵀ = L Lᵀ of a symmetric
// positive definite matrix, supernodal and left-looking. The symbolic phase
// (ordering, elimination tree, supernodes, layout) depends only on A's
// pattern; the numeric phase can be repeated for every matrix with that
// pattern. The factor is bit-identical whatever the thread count.
class SparseCholesky {
public:
    // Orders A's pattern with `method` and analyses it. Forgets any factor.
    Status analyze(const CsrMatrix& a, OrderingMethod method = OrderingMethod::minimum_degree);

    // Analyses A's pattern for the given ordering (perm[new] = old).
    Status analyze(const CsrMatrix& a, std::span<const std::uint32_t> perm);

    // Computes the factor of `a`, which must be symmetric and have the
    // analysed pattern (of each pair of twins, the entry in the row
    // eliminated first is read). A pivot that is not positive (A not
    // positive definite, or NaN in A) fails with Errc::numerical naming the
    // column in A's numbering; the factor is then unusable. `pool` spreads
    // the work over its threads.
    Status factorize(const CsrMatrix& a, jobs::WorkerPool* pool = nullptr);

    // Analyses `a` unless its pattern is the one last analysed, then
    // factorizes it.
    Status compute(const CsrMatrix& a, OrderingMethod method = OrderingMethod::minimum_degree,
                   jobs::WorkerPool* pool = nullptr);

    // A flag (not owned; null: none) that analyze and factorize look at
    // between their phases and between supernodes: once it is true they
    // stop and fail with Errc::cancelled, the factor unusable. Unset or
    // false, the factor is the same bits as without one.
    void set_stop(const std::atomic<bool>* stop) { stop_ = stop; }
    // Whether the last analyze or factorize stopped for the flag.
    bool stopped() const { return stopped_; }

    // Bytes held: the factor's values and the analysis (the factorization's
    // scratch is given back when it returns).
    std::size_t memory_bytes() const;

    bool is_factored() const { return factored_; }
    std::size_t size() const { return symbolic_.n; }
    const CholeskySymbolic& symbolic() const { return symbolic_; }
    const CholeskyTimes& times() const { return times_; }

    // x = A⁻¹ b for k interleaved vectors (b[j * k + c] is entry j of vector
    // c), both in A's numbering, with one pass over the factor for all k;
    // each vector's result is the same bits whatever k and whatever the
    // thread count. `work` holds solve_work_size(k, threads) doubles. With
    // `pool`, the one the factor was computed with, independent subtrees are
    // solved on its threads (with another pool, or work sized for fewer
    // threads, on the calling thread alone; the permutations into and out
    // of the factor's order use any pool). b and x may be
    // the same span. Requires is_factored(). Allocation-free; concurrent
    // solves are safe when they use different work and pools.
    void solve(std::span<const double> b, std::span<double> x, std::size_t k,
               std::span<double> work, jobs::WorkerPool* pool = nullptr) const;

    // The doubles of work a solve of k vectors on `threads` threads needs.
    std::size_t solve_work_size(std::size_t k, std::size_t threads = 1) const;

private:
    CholeskySymbolic symbolic_;
    // For the thread count of the last factorize: the factorization's, and
    // the solves'.
    CholeskySchedule schedule_;
    CholeskySchedule solve_schedule_;
    UnzeroedPooledVector<double> values_;  // every block written by the factorization
    CholeskyTimes times_;
    const std::atomic<bool>* stop_ = nullptr;
    bool stopped_ = false;
    bool factored_ = false;

    // Records and reports a raised stop flag.
    bool stop_requested();
};

}  // namespace dfm::solver
