// The fitted method's normal matrix from the stencils alone: a dual row and
// its rigidity rows share their vertices, so one stencil holds all of their
// coefficients, and N is summed without the rows of A ever being listed.
// Each entry takes its terms in A's row order (every dual row, then every
// rigidity row, each group in stencil order), the order in which
// assemble_normal_matrix sums the same rows: the same bits.
#include <numeric>

#include "core/pooled_allocator.hpp"
#include "deform/rigidity_rows.hpp"

namespace dfm::deform {

namespace {

// Stencils ahead whose coefficients the assembly prefetches: far enough
// for a stencil just written (out of cache by then, in a large ROI) to
// arrive before it is read. Four ahead left a large assembly waiting on
// memory; 32 ahead was no better than this.
constexpr std::size_t prefetch_distance = 16;

// Where an unknown sits in a stencil.
struct StencilUse {
    std::uint32_t stencil;
    std::uint32_t slot;
};

}  // namespace

solver::CsrMatrix RotationFrames::assemble_normal_matrix(
    std::size_t unknown_count, std::span<const std::uint32_t> soft_handles, double handle_weight,
    double relative_epsilon, double& epsilon, const std::atomic<bool>* stop) const {
    constexpr std::size_t slots = RigidityStencil::slots;
    const auto unknowns = static_cast<std::uint32_t>(unknown_count);
    const auto unknown_of = [unknowns](const RigidityStencil& s, std::size_t i) {
        return slot_unknown(s, i, unknowns);
    };
    std::vector<std::uint32_t> offsets(unknown_count + 1, 0);
    std::vector<double> squares(unknown_count, 0.0);
    for (const RigidityStencil& s : stencils_) {
        for (std::size_t i = 0; i < slots; ++i) {
            const std::uint32_t u = unknown_of(s, i);
            if (u == mesh::no_index) continue;
            ++offsets[u + 1];
            squares[u] += s.dual[i] * s.dual[i];
        }
    }
    // A rigidity row's entries are ±w s: either squared is its weight².
    for (const RigidityStencil& s : stencils_) {
        for (std::size_t k = 0; k < s.pair_count; ++k) {
            for (const std::uint8_t slot : s.pair_slot[k]) {
                const std::uint32_t u = unknown_of(s, slot);
                if (u != mesh::no_index) squares[u] += s.pair_weight2[k];
            }
        }
    }
    const std::vector<double> diagonal = normal_diagonal_start(
        std::move(squares), soft_handles, handle_weight, relative_epsilon, epsilon);

    std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());
    PooledVector<StencilUse> uses(offsets.back());
    {
        std::vector<std::uint32_t> fill(offsets.begin(), offsets.end() - 1);
        for (std::uint32_t r = 0; r < stencils_.size(); ++r) {
            const RigidityStencil& s = stencils_[r];
            for (std::uint32_t i = 0; i < slots; ++i) {
                const std::uint32_t u = unknown_of(s, i);
                if (u != mesh::no_index) uses[fill[u]++] = {r, i};
            }
        }
    }

    return gather_normal_rows(diagonal, stop, [&](std::uint32_t i, NormalRows& n) {
        for (std::uint32_t q = offsets[i]; q < offsets[i + 1]; ++q) {
            if (q + prefetch_distance < uses.size()) {
                const RigidityStencil& ahead = stencils_[uses[q + prefetch_distance].stencil];
                const auto* last = reinterpret_cast<const char*>(&ahead.slot_count);
                for (const auto* at = reinterpret_cast<const char*>(&ahead.vertex); at < last;
                     at += 64)
                    __builtin_prefetch(at);
                __builtin_prefetch(last);
            }
            const RigidityStencil& s = stencils_[uses[q].stencil];
            const double a = s.dual[uses[q].slot];
            for (std::size_t j = 0; j < slots; ++j) {
                const std::uint32_t u = unknown_of(s, j);
                if (u != mesh::no_index) n.add(u, a * s.dual[j]);
            }
        }
        // Row k's entries are +w s at v_c and −w s at v_d: their products
        // are ±(w s)², exactly.
        for (std::uint32_t q = offsets[i]; q < offsets[i + 1]; ++q) {
            const RigidityStencil& s = stencils_[uses[q].stencil];
            const std::uint32_t slot = uses[q].slot;
            // The rows that hold this slot, as bits: fewer branches to miss.
            unsigned holding = 0;
            for (std::size_t k = 0; k < s.pair_count; ++k) {
                const unsigned at_c = s.pair_slot[k][0] == slot ? 1u : 0u;
                const unsigned at_d = s.pair_slot[k][1] == slot ? 1u : 0u;
                holding |= (at_c | at_d) << k;
            }
            for (; holding != 0; holding &= holding - 1) {
                const int k = __builtin_ctz(holding);
                const std::uint8_t c = s.pair_slot[k][0];
                const std::uint8_t d = s.pair_slot[k][1];
                const double w2 = s.pair_weight2[k];
                const std::uint32_t uc = unknown_of(s, c);
                const std::uint32_t ud = unknown_of(s, d);
                if (uc != mesh::no_index) n.add(uc, slot == c ? w2 : -w2);
                if (ud != mesh::no_index) n.add(ud, slot == d ? w2 : -w2);
            }
        }
    });
}

}  // namespace dfm::deform
