#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/pooled_allocator.hpp"
#include "core/status.hpp"
#include "solver/csr_matrix.hpp"

namespace dfm::solver {

// One block update of the numeric phase: descendant supernode `source`
// updates a later supernode with its rows [first, last) (positions in the
// source's row list) that fall in the target's columns, and with all its
// rows from `first` on.
struct SupernodeUpdate {
    std::uint32_t source;
    std::uint32_t first;
    std::uint32_t last;
};

// The structure of the supernodal Cholesky factor L of P A Pᵀ, computed from
// A's pattern alone; any matrix with the same pattern reuses it.
//
// Columns are in the factor's order (new numbering). Supernode s holds the
// contiguous columns [column_begin[s], column_begin[s + 1]) and the rows
// rows[row_begin[s] .. row_begin[s + 1]), ascending, its own columns first.
// Its values are a dense block (rows × columns) at value_begin[s] in the
// factor's value array, laid out for the solves (supernode_kernels.hpp); it
// is factored column-major in a scratch block and written there once.
struct CholeskySymbolic {
    std::size_t n = 0;
    std::vector<std::uint32_t> perm;     // perm[new] = old, postordered
    std::vector<std::uint32_t> inverse;  // inverse[old] = new

    std::vector<std::uint32_t> column_begin{0};
    std::vector<std::uint32_t> parent;  // supernodal elimination tree, no_parent at roots
    std::vector<std::size_t> row_begin{0};
    PooledVector<std::uint32_t> rows;
    std::vector<std::size_t> value_begin{0};

    // The updates each supernode receives, by ascending source:
    // updates[update_begin[s] .. update_begin[s + 1]).
    std::vector<std::size_t> update_begin{0};
    PooledVector<SupernodeUpdate> updates;

    // Where A's entries go: for supernode s, the entries
    // [entry_begin[s], entry_begin[s + 1]) copy A.values[entry_source[e]] to
    // value entry_target[e] of s's column-major block. Of each pair of twins
    // A(i, j), A(j, i) one is read: the one in the row eliminated first.
    PooledVector<std::size_t> entry_begin{0};
    PooledVector<std::uint32_t> entry_source;
    PooledVector<std::uint32_t> entry_target;

    // The last supernode of the subtree rooted at s is s; its first is
    // subtree_begin[s] (postorder makes subtrees contiguous).
    std::vector<std::uint32_t> subtree_begin;
    // The backward solve's order: each supernode before its children, and
    // these in ascending order (a preorder of the tree), so that the small
    // supernodes near the leaves are mostly read upwards in memory. The
    // subtree rooted at s is backward_order[backward_position[s] ..] for
    // its s − subtree_begin[s] + 1 supernodes.
    std::vector<std::uint32_t> backward_order;
    std::vector<std::uint32_t> backward_position;
    // Estimated work of each supernode: Σ over its columns of (rows from the
    // diagonal down)², the work that column's elimination causes.
    PooledVector<double> work;

    // A's pattern, to recognise a matrix the analysis fits.
    PooledVector<std::size_t> pattern_row_offsets;
    PooledVector<std::uint32_t> pattern_col_indices;

    std::size_t factor_nonzeros = 0;  // nonzeros of L without the amalgamation's padding
    std::size_t stored_values = 0;    // values held, padding and upper diagonal blocks included
    std::size_t max_update_size = 0;  // largest scratch block an update needs
    std::size_t max_rows = 0;         // longest row list of a supernode
    std::size_t max_supernode_values = 0;  // values of the largest supernode's block
    std::size_t max_below_values = 0;      // the most values below a diagonal block
    double flops = 0.0;  // Σ of work: about the numeric phase's floating-point operations

    std::size_t supernode_count() const { return column_begin.size() - 1; }

    // True when `a` has exactly the pattern this analysis was made for.
    bool matches(const CsrMatrix& a) const;
};

// Analyses the pattern of the symmetric matrix `a` (both triangles stored)
// for the ordering `perm` (perm[new] = old): postorders the elimination tree,
// counts columns, finds and amalgamates supernodes, and lays out the factor.
// Fails when `a` is not square, its pattern is not symmetric, it stores 2³²
// entries or more, `perm` is not a permutation of its rows, or a
// supernode's block would hold 2³² values or more.
Status analyze_cholesky(const CsrMatrix& a, std::span<const std::uint32_t> perm,
                        CholeskySymbolic& out);

// The checks of analyze_cholesky that concern `a` alone: square, with a
// symmetric pattern, fewer than 2³² entries.
Status check_cholesky_pattern(const CsrMatrix& a);

// analyze_cholesky for a matrix that passed check_cholesky_pattern, without
// a second pass over its pattern to check it (perm is still checked).
Status analyze_checked_cholesky(const CsrMatrix& a, std::span<const std::uint32_t> perm,
                                CholeskySymbolic& out);

}  // namespace dfm::solver
