#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "core/pooled_allocator.hpp"
#include "core/status.hpp"
#include "deform/anderson.hpp"
#include "deform/frame_prediction.hpp"
#include "deform/linear_solver.hpp"
#include "deform/mesh_model.hpp"
#include "deform/normal_system.hpp"
#include "deform/rigidity_rows.hpp"

namespace dfm::deform {

// The outer iteration (docs/method.md).
enum class DeformMethod {
    // Rotations fitted to each dual 1-ring turn the rest dual Laplacian
    // coordinates, rigidity rows keep the dual and face edges' lengths, and
    // Anderson steps are kept only when they lower the energy. Converges,
    // and keeps large bends from folding.
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
    // Ties what D cannot see to the previous iterate; relative to N's mean
    // diagonal. It vanishes at the fixed point, so it never moves the result.
    double regularization = 1e-9;
    // Accuracy of each linear solve, in units of the rest diagonal.
    double linear_tolerance = 1e-8;
    solver::PreconditionerKind preconditioner = solver::PreconditionerKind::cholesky;
    // Steps of history for Anderson acceleration of the outer iteration;
    // 0 runs the plain iteration.
    int anderson_memory = 8;
    // Starts a solve whose targets moved on from the last two converged
    // solves at the extrapolation of those solutions (FramePredictor), with
    // the Anderson history of the solves before it; the iteration still
    // runs to the tolerance. Off: from the last solution, history cleared.
    bool predict_frames = true;
    // Threads for the factor and its solves (not owned; must outlive the
    // session). Null: the calling thread alone. Results do not depend on it.
    jobs::WorkerPool* pool = nullptr;
    DeformMethod method = DeformMethod::fitted_rotations;
    // Weight of the rigidity rows against the dual Laplacian rows for a ROI
    // of up to 2,500 unknowns, smaller beyond (balanced_rigidity_weight)
    // (fitted_rotations only; 0 leaves the fitted rotations alone). More
    // keeps lengths better and converges more slowly (docs/method.md).
    double rigidity_weight = 0.1;
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

// One edit of one ROI with fixed handle groups: the system is assembled and
// factored once, then solved as often as the targets change. Vertices outside
// the ROI, and ROI vertices with a neighbour outside it that are not handles,
// keep their rest positions bit for bit.
class DeformSession {
public:
    // `roi` and every handle group hold vertex indices of model.mesh; handle
    // vertices must lie in the ROI, each in one group only. The edit starts
    // from the rest pose. `model` must outlive the session. `stop`
    // (optional) is looked at between the set-up's phases and inside the
    // factorization: once it is true, create fails with Errc::cancelled
    // within a supernode's work.
    static Status create(const MeshModel& model, std::span<const std::uint32_t> roi,
                         std::span<const std::vector<std::uint32_t>> handle_groups,
                         const DeformSettings& settings, std::unique_ptr<DeformSession>& out,
                         const std::atomic<bool>* stop = nullptr);

    // Targets, one per handle vertex, in group order. Non-finite targets are
    // refused and leave the previous ones in place.
    Status set_targets(std::span<const glm::dvec3> targets);

    // Replaces the current positions of the unknowns, where the next solve
    // starts (the fixed part always keeps its rest positions). `positions`
    // covers the whole mesh; non-finite entries are refused.
    Status set_positions(std::span<const glm::dvec3> positions);

    // Changes DeformSettings::tolerance and max_iterations for later solves.
    Status set_stopping_rule(double tolerance, int max_iterations);

    // How an asynchronous caller watches and stops a solve.
    struct Control {
        // When it becomes true the solve stops after the iteration in
        // progress (cancel, destroy); the first iteration always runs.
        const std::atomic<bool>* interrupt = nullptr;
        // Once this time has passed the solve stops before its next
        // iteration, keeping what resume() needs (host stepping's budget);
        // each call runs one iteration at least.
        std::chrono::steady_clock::time_point pause_after =
            std::chrono::steady_clock::time_point::max();
        // Called after each iteration that does not converge, with
        // positions() holding that iterate: a preview for the host.
        std::function<void(const SolveReport&)> on_iteration;
    };

    // Runs the two-step iteration from the current positions; a paused
    // solve is dropped.
    Status solve(SolveReport& report, const Control* control = nullptr);
    // Goes on with the solve that Control::pause_after stopped, with the
    // same iterates, bit for bit, as if it had not stopped; `report` goes
    // on from the paused one's. Errc::invalid_argument when none is paused.
    Status resume(SolveReport& report, const Control* control = nullptr);
    bool paused() const { return paused_.active; }

    std::span<const glm::dvec3> positions() const { return positions_; }
    std::span<const std::uint32_t> handle_vertices() const { return handle_vertices_; }
    std::span<const glm::dvec3> targets() const { return targets_; }
    const UnknownMap& unknowns() const { return unknowns_; }
    const SetupReport& setup_report() const { return setup_; }
    // factor, system and iteration; not thread-safe against a solve.
    SessionMemory memory() const;
    const MeshModel& model() const { return model_; }

private:
    explicit DeformSession(const MeshModel& model) : model_(model) {}

    void compute_dual_targets();
    void compute_right_hand_side();
    void store_solution();
    void verify_last_solve(SolveReport& report);
    double plain_step_length() const;
    // The iterations from `first` on: solve() starts them at 0, resume()
    // where a pause stopped them, with what the loop carries from one
    // iteration to the next (Paused::carried).
    Status paper_iterations(SolveReport& report, const Control* control, int first,
                            double smallest_update, std::chrono::steady_clock::time_point start);
    // True, with the loop's state kept for resume(), when the solve stops
    // before iteration `it` for Control::pause_after.
    bool pause_before(int it, int first, double carried,
                      std::chrono::steady_clock::time_point start, const Control* control,
                      SolveReport& report);
    // fitted_iteration.cpp
    Status solve_fitted(SolveReport& report, const Control* control);
    Status fitted_iterations(SolveReport& report, const Control* control, int first, double energy,
                             std::chrono::steady_clock::time_point start);
    double fit_and_prepare(std::span<const double> x, int rotation_steps, SolveReport& report);
    void align_to_handles();

    const MeshModel& model_;
    DeformSettings settings_;
    UnknownMap unknowns_;
    SystemRows rows_;  // with fitted_rotations, only the faces once set up
    LinearSolver linear_;
    double epsilon_ = 0.0;
    std::vector<std::uint32_t> handle_vertices_;
    std::vector<std::uint32_t> soft_handles_;  // unknown of each handle vertex (soft mode)
    PooledVector<glm::dvec3> targets_;
    PooledVector<glm::dvec3> positions_;
    PooledVector<glm::dvec3> centroids_;     // paper only
    PooledVector<glm::dvec3> dual_targets_;  // paper only: l_r per row
    PooledVector<double> rhs_;               // 3 interleaved columns
    PooledVector<double> x_;                 // the linear solve's solution: G(current)
    PooledVector<double> current_;           // the iterate the dual targets come from
    PooledVector<double> next_;
    AndersonAccelerator anderson_;
    FramePredictor predictor_;
    RotationFrames frames_;  // fitted_rotations only
    bool pinned_ = true;     // the ROI has a fixed boundary
    SetupReport setup_;
    // A solve that Control::pause_after stopped: where its loop was.
    struct Paused {
        bool active = false;
        int iteration = 0;
        double carried = 0.0;  // the paper's smallest update; the fitted energy
        double elapsed_ms = 0.0;
        SolveReport report;
    } paused_;
};

}  // namespace dfm::deform
