#pragma once

#include <atomic>

#include "core/memory_bytes.hpp"
#include "core/pooled_allocator.hpp"
#include "deform/normal_system.hpp"
#include "deform/outer_iteration.hpp"

// The paper's outer iteration (docs/method.md): each dual row asks for
// l_f = −h_f n_f, the rest height along the normal of the plane through its
// new dual 1-ring; every Anderson extrapolation is taken, the history
// restarted when a step grows past twice the shortest so far.
namespace dfm::deform {

class PaperIteration final : public OuterIteration {
public:
    // Keeps the dual rows of the edit (collect_rows).
    PaperIteration(const MeshModel& model, SystemRows rows);

    // N = AᵀA + w² H + ε I over the dual rows (assemble_normal_matrix);
    // sets state.epsilon.
    solver::CsrMatrix assemble_normal_matrix(IterationState& state,
                                             const std::atomic<bool>* stop) const;

    double start(IterationState& state, SolveReport& report) override;
    double advance(IterationState& state, SolveReport& report, double smallest_update) override;
    std::size_t rows() const override { return rows_.size(); }
    std::size_t memory_bytes() const override {
        return rows_.memory_bytes() + capacity_bytes(centroids_, dual_targets_);
    }

private:
    // The dual targets of state.positions, and the right-hand side
    // Aᵀ (l − A_fixed p_fixed) + w² u + ε p.
    void prepare(IterationState& state, SolveReport& report);

    const MeshModel& model_;
    SystemRows rows_;
    PooledVector<glm::dvec3> centroids_;     // per face of the mesh; the rows' 1-rings
    PooledVector<glm::dvec3> dual_targets_;  // l_r per row
};

}  // namespace dfm::deform
