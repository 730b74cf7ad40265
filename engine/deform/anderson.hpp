#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "core/memory_bytes.hpp"
#include "core/pooled_allocator.hpp"

namespace dfm::deform {

// Anderson acceleration of a fixed-point iteration x <- G(x) (type II, the
// "AA(m)" of Walker and Ni). The two-step dual Laplacian iteration contracts
// linearly, at 0.6 to 0.99 per step (docs/design.md); extrapolating from the last
// m steps cuts the step count several times on large ROIs. The fixed point
// is the same: only the path to it changes. Buffers are sized once, so a
// step allocates nothing.
class AndersonAccelerator {
public:
    void reset(std::size_t size, std::size_t memory);

    // Forgets the history (after a failed step or when the problem changes).
    void restart() {
        count_ = 0;
        next_slot_ = 0;
        has_previous_ = false;
    }

    // Starts a new sequence of iterates but keeps the history, for a map
    // that changed by a constant only (the next frame of a drag: G moves by
    // N⁻¹ w² H Δt): the stored differences still describe it.
    void continue_history() { has_previous_ = false; }

    // Given x and g = G(x), writes the next iterate into `next`. The first
    // step after a restart is the plain one, next = g.
    void step(std::span<const double> x, std::span<const double> g, std::span<double> next);

    std::size_t memory_bytes() const {
        return capacity_bytes(previous_f_, previous_g_, delta_f_, delta_g_, f_, products_, gram_,
                              gamma_, column_products_);
    }

private:
    std::size_t size_ = 0;
    std::size_t memory_ = 0;
    std::size_t count_ = 0;  // stored differences, at most memory_
    std::size_t next_slot_ = 0;
    bool has_previous_ = false;
    // Each written before it is read: the history's columns below count_,
    // the previous iterate once has_previous_ is set.
    UnzeroedPooledVector<double> previous_f_;
    UnzeroedPooledVector<double> previous_g_;
    UnzeroedPooledVector<double> delta_f_;  // memory_ columns of size_
    UnzeroedPooledVector<double> delta_g_;
    UnzeroedPooledVector<double> f_;
    std::vector<double> products_;  // ΔFᵀΔF over the ring's slots, memory_ × memory_
    std::vector<double> gram_;      // the normal equations of one step, count_ × count_
    std::vector<double> gamma_;
    std::vector<double> column_products_;  // the newest column's inner products, count_ of them
};

}  // namespace dfm::deform
