#include <cmath>
#include <string>

#include "solver/preconditioner.hpp"

namespace dfm::solver {

Status JacobiPreconditioner::setup(const CsrMatrix& a) {
    inverse_diagonal_.clear();
    if (a.rows != a.cols) return {Errc::invalid_argument, "Jacobi: the matrix is not square"};
    std::vector<double> diagonal = a.diagonal();
    for (std::size_t i = 0; i < diagonal.size(); ++i) {
        if (diagonal[i] == 0.0 || !std::isfinite(diagonal[i]))
            return {Errc::numerical, "Jacobi: the diagonal entry of row " + std::to_string(i) +
                                         " is " + (diagonal[i] == 0.0 ? "zero" : "not finite")};
        diagonal[i] = 1.0 / diagonal[i];
    }
    inverse_diagonal_ = std::move(diagonal);
    return Status::ok();
}

void JacobiPreconditioner::apply(std::span<const double> r, std::span<double> z, std::size_t k) {
    for (std::size_t i = 0; i < inverse_diagonal_.size(); ++i)
        for (std::size_t c = 0; c < k; ++c) z[i * k + c] = r[i * k + c] * inverse_diagonal_[i];
}

}  // namespace dfm::solver
