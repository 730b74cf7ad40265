#pragma once

#include <atomic>

#include "deform/outer_iteration.hpp"
#include "deform/rigidity_rows.hpp"

// The default method's outer iteration (docs/method.md): a local step fits
// the rotations and the global step solves the fixed normal system, each
// lowering the energy of deform_energy.hpp; Anderson acceleration proposes
// each next iterate and is kept only when it lowers that energy too, else
// the plain step is taken, so the energy never rises from one iterate to
// the next.
namespace dfm::deform {

class FittedIteration final : public OuterIteration {
public:
    // The rigidity rows of the edit's dual rows and the coarse field of
    // their clusters (RotationFrames::build).
    FittedIteration(const MeshModel& model, const UnknownMap& unknowns, const SystemRows& rows,
                    const RotationClusters& clusters);

    // N = AᵀA + w² H + ε I over the dual and rigidity rows; sets
    // state.epsilon.
    solver::CsrMatrix assemble_normal_matrix(IterationState& state,
                                             const std::atomic<bool>* stop) const;

    double start(IterationState& state, SolveReport& report) override;
    double advance(IterationState& state, SolveReport& report, double energy) override;
    std::size_t rows() const override {
        return rotations_.dual_rows() + rotations_.rigidity_rows();
    }
    std::size_t memory_bytes() const override { return rotations_.memory_bytes(); }

private:
    // Fits the rotations to the unknowns at `x` with at most
    // `rotation_steps` Newton steps, and prepares the global step's
    // right-hand side; returns the energy of `x`. The session's positions
    // are left as they are: the fit reads only the fixed vertices there.
    double fit_and_prepare(IterationState& state, std::span<const double> x, int rotation_steps,
                           SolveReport& report);

    RotationFrames rotations_;
};

}  // namespace dfm::deform
