#include "solver/preconditioner.hpp"

namespace dfm::solver {

std::unique_ptr<Preconditioner> make_preconditioner(PreconditionerKind kind,
                                                    jobs::WorkerPool* pool) {
    switch (kind) {
        case PreconditionerKind::jacobi: return std::make_unique<JacobiPreconditioner>();
        case PreconditionerKind::incomplete_cholesky:
            return std::make_unique<IncompleteCholeskyPreconditioner>();
        case PreconditionerKind::cholesky:
            return std::make_unique<CholeskyPreconditioner>(OrderingMethod::minimum_degree, pool);
    }
    return nullptr;
}

}  // namespace dfm::solver
