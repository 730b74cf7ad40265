#include "solver/preconditioner.hpp"

namespace dfm::solver {

CholeskyPreconditioner::CholeskyPreconditioner(OrderingMethod ordering, ThreadPool* pool)
    : ordering_(ordering), pool_(pool) {}

Status CholeskyPreconditioner::setup(const CsrMatrix& a) {
    return cholesky_.compute(a, ordering_, pool_);
}

void CholeskyPreconditioner::reserve(std::size_t k) {
    if (work_.size() < cholesky_.size() * k) work_.resize(cholesky_.size() * k);
}

void CholeskyPreconditioner::apply(std::span<const double> r, std::span<double> z, std::size_t k) {
    reserve(k);
    cholesky_.solve(r, z, k, work_);
}

}  // namespace dfm::solver
