#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/pooled_allocator.hpp"
#include "deform/anderson.hpp"
#include "deform/deform_settings.hpp"
#include "deform/mesh_model.hpp"
#include "deform/normal_system.hpp"

// The two-step iteration (docs/design.md, docs/method.md) is one loop
// (DeformSession): solve N x = rhs from the current iterate, stop once the
// step is short enough, else let the method choose the next iterate and
// prepare its right-hand side. What the methods share is IterationState;
// what differs is an OuterIteration: the paper's dual targets from the new
// 1-rings (paper_iteration.*), or the fitted rotations and their energy
// (fitted_iteration.*).
namespace dfm::deform {

// The vectors of one edit's iteration, over its unknowns (3 interleaved
// columns) and its mesh.
struct IterationState {
    const MeshModel* model = nullptr;
    const DeformSettings* settings = nullptr;
    const UnknownMap* unknowns = nullptr;
    std::vector<std::uint32_t> handle_vertices;  // in group order
    std::vector<std::uint32_t> soft_handles;     // unknown of each handle vertex (soft mode)
    double epsilon = 0.0;                        // the regularization's weight (normal_system.hpp)
    bool pinned = true;                          // the ROI has a fixed boundary
    PooledVector<glm::dvec3> targets;            // per handle vertex
    // The whole mesh, the unknowns where the last solve left them or, after
    // OuterIteration::advance, at the current iterate.
    PooledVector<glm::dvec3> positions;
    PooledVector<double> rhs;
    PooledVector<double> x;        // the linear solve's solution: G(current)
    PooledVector<double> current;  // the iterate the right-hand side was prepared for
    PooledVector<double> next;
    AndersonAccelerator anderson;

    // Moves the unknowns' positions to `iterate`.
    void store(std::span<const double> iterate);
};

// The method's half of the iteration.
class OuterIteration {
public:
    virtual ~OuterIteration() = default;

    // Starts a solve from state.current (predicted or not, as `report`
    // says); may move it, then prepares the right-hand side for it and sets
    // x to it. Returns the value the iteration carries from one step to the
    // next (resume() gets it back).
    virtual double start(IterationState& state, SolveReport& report) = 0;

    // After a plain step x from state.current that did not converge:
    // chooses the next iterate (the Anderson extrapolation, or the plain
    // step), makes it current, x and the positions' unknowns, and prepares
    // its right-hand side.
    // Takes and returns the carried value.
    virtual double advance(IterationState& state, SolveReport& report, double carried) = 0;

    virtual std::size_t rows() const = 0;  // of A, for the set-up report
    virtual std::size_t memory_bytes() const = 0;
};

}  // namespace dfm::deform
