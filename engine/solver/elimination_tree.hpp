#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "core/pooled_allocator.hpp"
#include "solver/csr_matrix.hpp"

namespace dfm::solver {

// Marks a root of the elimination tree.
inline constexpr std::uint32_t no_parent = std::numeric_limits<std::uint32_t>::max();

// The pattern of P A Pᵀ by columns, for a symmetric pattern: column j holds
// the rows of the entries of A's row perm[j], renumbered: first those on or
// below the diagonal (up to lower_end[j]), then those above; source[e] is
// entry e's position in A (which check_cholesky_pattern limits to 32
// bits). Built in one pass over A, so that the symbolic analysis then
// reads memory in order.
struct PermutedColumns {
    PooledVector<std::size_t> begin{0};
    PooledVector<std::size_t> lower_end;
    PooledVector<std::uint32_t> rows;
    PooledVector<std::uint32_t> source;

    std::size_t size() const { return begin.size() - 1; }
    // Rows i ≥ j of column j, the diagonal included.
    std::span<const std::uint32_t> lower(std::size_t j) const {
        return std::span(rows).subspan(begin[j], lower_end[j] - begin[j]);
    }
    // Rows i < j of column j.
    std::span<const std::uint32_t> upper(std::size_t j) const {
        return std::span(rows).subspan(lower_end[j], begin[j + 1] - lower_end[j]);
    }
};

// perm[new] = old, inverse[old] = new; A's pattern must be symmetric.
PermutedColumns permuted_columns(const CsrMatrix& a, std::span<const std::uint32_t> perm,
                                 std::span<const std::uint32_t> inverse);

// The same pattern numbered again: column k of the result is column
// order[k] of `from`, and row i becomes renumber[i] (renumber being the
// inverse of order). `order` must keep every entry on its side of the
// diagonal, as a postorder of the elimination tree does.
PermutedColumns renumbered_columns(const PermutedColumns& from,
                                   std::span<const std::uint32_t> order,
                                   std::span<const std::uint32_t> renumber);

// The elimination tree of the Cholesky factor of the pattern: parent[j] is
// the first row below the diagonal in column j of L, or no_parent. Liu's
// algorithm with path compression.
std::vector<std::uint32_t> elimination_tree(const PermutedColumns& pattern);

// A postorder of the forest `parent`: children before their parent, each
// subtree contiguous, siblings in ascending order. post[k] is the k-th node.
std::vector<std::uint32_t> tree_postorder(std::span<const std::uint32_t> parent);

// The number of nonzeros in each column of the factor, the diagonal included
// (Gilbert, Ng and Peyton, in almost linear time). `parent` is the
// pattern's elimination tree, which must be postordered (every node numbered
// after its descendants, subtrees contiguous).
std::vector<std::uint32_t> factor_column_counts(const PermutedColumns& pattern,
                                                std::span<const std::uint32_t> parent);

}  // namespace dfm::solver
