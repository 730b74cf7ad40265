#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/pooled_allocator.hpp"
#include "solver/csr_matrix.hpp"

namespace dfm::solver {

// The undirected graph of a square sparsity pattern: vertex i is row/column
// i, and i–j is an edge when A(i, j) or A(j, i) is stored, i != j. The
// neighbours of v are neighbors[offsets[v] .. offsets[v + 1]), ascending.
struct SymmetricGraph {
    PooledVector<std::size_t> offsets{0};
    PooledVector<std::uint32_t> neighbors;

    std::size_t size() const { return offsets.size() - 1; }
    std::size_t degree(std::uint32_t v) const { return offsets[v + 1] - offsets[v]; }
    std::span<const std::uint32_t> of(std::uint32_t v) const {
        return std::span(neighbors).subspan(offsets[v], offsets[v + 1] - offsets[v]);
    }
};

// The graph of the pattern of A + Aᵀ, without self-loops, over A's rows
// (entries in columns beyond the last row are ignored).
SymmetricGraph symmetric_graph(const CsrMatrix& a);

// True when A is square and A(j, i) is stored wherever A(i, j) is.
bool has_symmetric_pattern(const CsrMatrix& a);

// symmetric_graph of a matrix known to pass has_symmetric_pattern, without
// checking it again: its off-diagonal entries as they are.
SymmetricGraph symmetric_pattern_graph(const CsrMatrix& a);

}  // namespace dfm::solver
