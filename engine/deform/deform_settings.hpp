#pragma once

#include <cstddef>

#include "jobs/worker_pool.hpp"
#include "solver/preconditioner_kind.hpp"

// An edit's settings and the reports of its set-up and solves.
namespace dfm::deform {

// The outer iteration (docs/method.md).
enum class DeformMethod {
    // Rotations fitted to each dual 1-ring and to a few clusters of the ROI
    // turn the rest dual Laplacian coordinates, rigidity rows keep the dual
    // and face edges' lengths, and Anderson steps are kept only when they
    // lower the energy. Converges in about as many iterations at every level
    // of detail, and keeps large bends from folding.
    fitted_rotations,
    // The paper's: l_f = -h_f n_f from the plane of the new dual 1-ring.
    paper,
};

const char* method_name(DeformMethod m);

struct DeformSettings {
    double tolerance = 1e-5;  // largest vertex update / rest diagonal that ends the iteration
    int max_iterations = 100;
    double handle_weight = 1.0;  // weight of the soft handle rows
    bool hard_handles = false;   // handles as eliminated unknowns, met exactly
    solver::PreconditionerKind preconditioner = solver::PreconditionerKind::cholesky;
    // Starts a solve whose targets moved on from the last two converged
    // solves at the extrapolation of those solutions (FramePredictor), with
    // the Anderson history of the solves before it; the iteration still
    // runs to the tolerance. Off: from the last solution, history cleared.
    bool predict_frames = true;
    // Threads for the factor and its solves (not owned; must outlive the
    // session). Null: the calling thread alone. Results do not depend on it.
    jobs::WorkerPool* pool = nullptr;
    DeformMethod method = DeformMethod::fitted_rotations;
};

struct SolveReport {
    int iterations = 0;
    bool converged = false;
    double last_update = 0.0;  // largest vertex move of the last iteration / diagonal
    std::size_t krylov_iterations = 0;
    // ‖b − N x‖ / ‖b‖ of the final, verified linear solve; NaN when that
    // solve did not reach its error tolerance (linear_converged false) and
    // the unchecked step was kept.
    double linear_residual = 0.0;
    bool linear_converged = false;
    double solve_ms = 0.0;
    // Where solve_ms went: the linear solves, the right-hand sides, the
    // normals (dual targets) and the Anderson steps. The default method fits
    // its rotations in the pass that adds their rows to the right-hand side:
    // that pass counts as normals, the handle rows as right-hand side.
    double linear_ms = 0.0;
    double rhs_ms = 0.0;
    double normals_ms = 0.0;
    double anderson_ms = 0.0;
    bool predicted = false;  // started from FramePredictor's extrapolation
    // Stopped early by the interrupt flag: positions hold the last iterate,
    // neither converged nor verified.
    bool interrupted = false;
    // Stopped at Control::pause_after: DeformSession::resume goes on.
    bool paused = false;
    // fitted_rotations: the energy (deform_energy.hpp) of the iterate the
    // last global step started from, and how many Anderson steps were
    // refused for raising it. The paper's method reports 0 for both.
    double energy = 0.0;
    std::size_t rejected_steps = 0;
};

struct SetupReport {
    std::size_t unknowns = 0;
    std::size_t rows = 0;
    std::size_t normal_nonzeros = 0;
    double setup_ms = 0.0;
    // Where setup_ms went: collecting the rows, assembling N, and the
    // factor's ordering, symbolic and numeric phases.
    double rows_ms = 0.0;
    double assembly_ms = 0.0;
    double ordering_ms = 0.0;
    double symbolic_ms = 0.0;
    double numeric_ms = 0.0;
};

// Bytes an edit holds, by part (capacities of its arrays).
struct SessionMemory {
    std::size_t factor = 0;  // the preconditioner: the complete factor's values, indices, analysis
    std::size_t system = 0;  // N, the rows it is built from, the rigidity rows, the unknowns
    // The iteration's vectors: positions, targets, right-hand sides,
    // Anderson's history, the frame prediction, the Krylov workspace.
    std::size_t iteration = 0;
    std::size_t frames = 0;   // the published frames and their normals (AsyncSession)
    std::size_t staging = 0;  // targets queued and being solved, the ROI (AsyncSession)
};

}  // namespace dfm::deform
