#pragma once

namespace dfm::solver {

// Which preconditioner the conjugate gradients use: the one name for the
// choice, from the solver (make_preconditioner) up to the edit's settings.
enum class PreconditionerKind { jacobi, incomplete_cholesky, cholesky };

}  // namespace dfm::solver
