#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "core/status.hpp"
#include "deform/deform_settings.hpp"
#include "deform/frame_prediction.hpp"
#include "deform/linear_solver.hpp"
#include "deform/mesh_model.hpp"
#include "deform/normal_system.hpp"
#include "deform/outer_iteration.hpp"

namespace dfm::deform {

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

    std::span<const glm::dvec3> positions() const { return state_.positions; }
    std::span<const std::uint32_t> handle_vertices() const { return state_.handle_vertices; }
    std::span<const glm::dvec3> targets() const { return state_.targets; }
    const UnknownMap& unknowns() const { return unknowns_; }
    const SetupReport& setup_report() const { return setup_; }
    // factor, system and iteration; not thread-safe against a solve.
    SessionMemory memory() const;
    const MeshModel& model() const { return model_; }

private:
    explicit DeformSession(const MeshModel& model, const DeformSettings& settings);

    // create()'s steps.
    Status select_unknowns(std::span<const std::uint32_t> roi,
                           std::span<const std::vector<std::uint32_t>> handle_groups);
    Status build_system(const std::atomic<bool>* stop);
    void start_iteration();

    void verify_last_solve(SolveReport& report);
    double plain_step_length() const;
    // The iterations from `first` on: solve() starts them at 0, resume()
    // where a pause stopped them, with the value the method carries from
    // one iteration to the next.
    Status iterate(SolveReport& report, const Control* control, int first, double carried,
                   std::chrono::steady_clock::time_point start);
    // True, with the loop's state kept for resume(), when the solve stops
    // before iteration `it` for Control::pause_after.
    bool pause_before(int it, int first, double carried,
                      std::chrono::steady_clock::time_point start, const Control* control,
                      SolveReport& report);

    const MeshModel& model_;
    DeformSettings settings_;
    UnknownMap unknowns_;
    LinearSolver linear_;
    IterationState state_;
    std::unique_ptr<OuterIteration> method_;
    FramePredictor predictor_;
    SetupReport setup_;
    // A solve that Control::pause_after stopped: where its loop was.
    struct Paused {
        bool active = false;
        int iteration = 0;
        double carried = 0.0;  // what the method carries between iterations
        double elapsed_ms = 0.0;
        SolveReport report;
    } paused_;
};

}  // namespace dfm::deform
