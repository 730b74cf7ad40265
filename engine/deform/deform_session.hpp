#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "core/status.hpp"
#include "deform/anderson.hpp"
#include "deform/linear_solver.hpp"
#include "deform/mesh_model.hpp"
#include "deform/normal_system.hpp"

namespace dfm::deform {

struct DeformSettings {
    double tolerance = 1e-5;  // largest vertex update / rest diagonal that ends the iteration
    int max_iterations = 100;
    double handle_weight = 1.0;  // weight of the soft handle rows
    bool hard_handles = false;   // handles as eliminated unknowns, met exactly
    // Ties what D cannot see to the previous iterate; relative to N's mean
    // diagonal. It vanishes at the fixed point, so it never moves the result.
    double regularization = 1e-9;
    // Scales h by sqrt(area / rest area) so a stretched region keeps its
    // relative detail. Off by default (docs/design.md).
    bool scale_heights = false;
    // Accuracy of each linear solve, in units of the rest diagonal.
    double linear_tolerance = 1e-8;
    Preconditioner preconditioner = Preconditioner::cholesky;
    // Steps of history for Anderson acceleration of the outer iteration;
    // 0 runs the plain iteration.
    int anderson_memory = 8;
    // Threads for the factor and its solves (not owned; must outlive the
    // session). Null: the calling thread alone. Results do not depend on it.
    solver::ThreadPool* pool = nullptr;
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
    // Stopped early by the interrupt flag: positions hold the last iterate,
    // neither converged nor verified.
    bool interrupted = false;
};

struct SetupReport {
    std::size_t unknowns = 0;
    std::size_t rows = 0;
    std::size_t normal_nonzeros = 0;
    double setup_ms = 0.0;
};

// One edit of one ROI with fixed handle groups: the system is assembled and
// factored once, then solved as often as the targets change. Vertices outside
// the ROI, and ROI vertices with a neighbour outside it that are not handles,
// keep their rest positions bit for bit.
class DeformSession {
public:
    // `roi` and every handle group hold vertex indices of model.mesh; handle
    // vertices must lie in the ROI, each in one group only. The edit starts
    // from the rest pose. `model` must outlive the session.
    static Status create(const MeshModel& model, std::span<const std::uint32_t> roi,
                         std::span<const std::vector<std::uint32_t>> handle_groups,
                         const DeformSettings& settings, std::unique_ptr<DeformSession>& out);

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
        // Called after each iteration that does not converge, with
        // positions() holding that iterate: a preview for the host.
        std::function<void(const SolveReport&)> on_iteration;
    };

    // Runs the two-step iteration from the current positions.
    Status solve(SolveReport& report, const Control* control = nullptr);

    std::span<const glm::dvec3> positions() const { return positions_; }
    std::span<const std::uint32_t> handle_vertices() const { return handle_vertices_; }
    std::span<const glm::dvec3> targets() const { return targets_; }
    const UnknownMap& unknowns() const { return unknowns_; }
    const SetupReport& setup_report() const { return setup_; }
    const MeshModel& model() const { return model_; }

private:
    explicit DeformSession(const MeshModel& model) : model_(model) {}

    void compute_dual_targets();
    void compute_right_hand_side();
    void store_solution();

    const MeshModel& model_;
    DeformSettings settings_;
    UnknownMap unknowns_;
    SystemRows rows_;
    LinearSolver linear_;
    double epsilon_ = 0.0;
    std::vector<std::uint32_t> handle_vertices_;
    std::vector<std::uint32_t> soft_handles_;  // unknown of each handle vertex (soft mode)
    std::vector<glm::dvec3> targets_;
    std::vector<glm::dvec3> positions_;
    std::vector<glm::dvec3> centroids_;
    std::vector<glm::dvec3> dual_targets_;  // l_r per row
    std::vector<double> rhs_;               // 3 interleaved columns
    std::vector<double> x_;                 // the linear solve's solution: G(current)
    std::vector<double> current_;           // the iterate the dual targets come from
    std::vector<double> next_;
    AndersonAccelerator anderson_;
    SetupReport setup_;
};

}  // namespace dfm::deform
