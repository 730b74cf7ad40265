#include "solver/preconditioner.hpp"

#include "core/memory_bytes.hpp"

namespace dfm::solver {

CholeskyPreconditioner::CholeskyPreconditioner(OrderingMethod ordering, jobs::WorkerPool* pool)
    : ordering_(ordering), pool_(pool) {}

Status CholeskyPreconditioner::setup(const CsrMatrix& a) {
    return cholesky_.compute(a, ordering_, pool_);
}

std::size_t CholeskyPreconditioner::memory_bytes() const {
    return cholesky_.memory_bytes() + capacity_bytes(work_);
}

void CholeskyPreconditioner::reserve(std::size_t k) {
    const std::size_t size =
        cholesky_.solve_work_size(k, pool_ != nullptr ? pool_->thread_count() : 1);
    if (work_.size() < size) work_.resize(size);
}

void CholeskyPreconditioner::apply(std::span<const double> r, std::span<double> z, std::size_t k) {
    reserve(k);
    cholesky_.solve(r, z, k, work_, pool_);
}

}  // namespace dfm::solver
