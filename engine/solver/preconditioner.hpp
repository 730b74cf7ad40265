#pragma once

#include <atomic>
#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include "core/memory_bytes.hpp"
#include "core/status.hpp"
#include "jobs/worker_pool.hpp"
#include "solver/csr_matrix.hpp"
#include "solver/ordering.hpp"
#include "solver/preconditioner_kind.hpp"
#include "solver/sparse_cholesky.hpp"

namespace dfm::solver {

// An approximation M of a square matrix A, applied as z = M⁻¹ r to k
// interleaved vectors (r[j * k + c] is entry j of vector c). Set up once per
// matrix, applied every Krylov iteration. Not thread-safe: apply may use
// scratch held by the object.
class Preconditioner {
public:
    virtual ~Preconditioner() = default;

    // Builds M from `a`. Fails (and leaves M unusable) when `a` is not
    // square or M cannot be built from it; the status says why.
    virtual Status setup(const CsrMatrix& a) = 0;

    // Makes room so that apply allocates nothing for up to k vectors. A
    // solver calls it before its iteration loop.
    virtual void reserve(std::size_t k) { (void)k; }

    // z = M⁻¹ r for k interleaved vectors; r and z must not overlap. Requires
    // a successful setup.
    virtual void apply(std::span<const double> r, std::span<double> z, std::size_t k) = 0;

    virtual const char* name() const = 0;

    // The order of M: that of the matrix last set up successfully, 0 before.
    virtual std::size_t size() const = 0;

    // True when M equals A up to rounding (a complete factorization): its
    // error estimate then stops improving only at the rounding floor.
    virtual bool is_exact() const { return false; }

    // Bytes M holds (capacities of its arrays, scratch included).
    virtual std::size_t memory_bytes() const = 0;
};

// M = diag(A). The baseline: cheap, and weak on bi-Laplacian-like systems.
class JacobiPreconditioner final : public Preconditioner {
public:
    // Fails on a zero or non-finite diagonal entry, naming its row.
    Status setup(const CsrMatrix& a) override;
    void apply(std::span<const double> r, std::span<double> z, std::size_t k) override;
    const char* name() const override { return "jacobi"; }
    std::size_t size() const override { return inverse_diagonal_.size(); }
    std::size_t memory_bytes() const override { return capacity_bytes(inverse_diagonal_); }

private:
    std::vector<double> inverse_diagonal_;
};

// M = L Lᵀ with L restricted to the pattern of A's lower triangle, IC(0), in
// A's own order (its lower triangle is read). A must be symmetric with a
// positive diagonal. When a pivot breaks down, A + α diag(A) is factored
// instead for α = 10⁻³, 4·10⁻³, … (Manteuffel's shift).
class IncompleteCholeskyPreconditioner final : public Preconditioner {
public:
    // Fails when A is not square, a row has no positive diagonal entry, or
    // every shift up to the last one breaks down.
    Status setup(const CsrMatrix& a) override;
    void apply(std::span<const double> r, std::span<double> z, std::size_t k) override;
    const char* name() const override { return "incomplete cholesky"; }
    std::size_t size() const override { return factor_.rows; }
    std::size_t memory_bytes() const override { return factor_.memory_bytes(); }

    // The α of the last successful setup (0 when none was needed).
    double shift() const { return shift_; }

private:
    CsrMatrix factor_;  // L by rows, diagonal last in each row
    double shift_ = 0.0;
};

// M = A through a complete sparse Cholesky factor (a fill-reducing ordering,
// then a supernodal factorization): preconditioned conjugate gradients then
// converge in one or two steps. Setup with a matrix of the same pattern as
// the previous one only refactors.
class CholeskyPreconditioner final : public Preconditioner {
public:
    // `pool` (optional, not owned, must outlive this object) spreads the
    // factorization and the solves over its threads; the results are the
    // same bits whatever the thread count.
    explicit CholeskyPreconditioner(OrderingMethod ordering = OrderingMethod::minimum_degree,
                                    jobs::WorkerPool* pool = nullptr);

    // Fails when A is not square, its pattern not symmetric, or it is not
    // positive definite (Errc::numerical naming the row).
    Status setup(const CsrMatrix& a) override;
    // The ordering and symbolic analysis of A's pattern alone (its values
    // are not read): a later setup with a matrix of this pattern only
    // factors.
    Status analyze(const CsrMatrix& pattern) { return cholesky_.analyze(pattern, ordering_); }
    void reserve(std::size_t k) override;
    void apply(std::span<const double> r, std::span<double> z, std::size_t k) override;
    const char* name() const override { return "cholesky"; }
    std::size_t size() const override { return cholesky_.is_factored() ? cholesky_.size() : 0; }
    bool is_exact() const override { return true; }

    const SparseCholesky& factor() const { return cholesky_; }
    // SparseCholesky::set_stop for the factorizations of later setups.
    void set_stop(const std::atomic<bool>* stop) { cholesky_.set_stop(stop); }
    std::size_t memory_bytes() const override;

private:
    OrderingMethod ordering_;
    jobs::WorkerPool* pool_;
    SparseCholesky cholesky_;
    std::vector<double> work_;
};

// A new preconditioner of the given kind; `pool` is used by those that can
// (the Cholesky factorization) and must outlive the result.
std::unique_ptr<Preconditioner> make_preconditioner(PreconditionerKind kind,
                                                    jobs::WorkerPool* pool = nullptr);

}  // namespace dfm::solver
