#include "solver/cholesky_symbolic.hpp"

#include <algorithm>
#include <limits>
#include <string>

#include "solver/elimination_tree.hpp"
#include "solver/ordering.hpp"
#include "solver/symmetric_graph.hpp"

namespace dfm::solver {

namespace {

// Relaxed amalgamation thresholds (those of CHOLMOD): a merged supernode of
// at most `columns` columns may hold up to this share of explicit zeros.
struct Relaxation {
    std::size_t columns;
    double zero_share;
};
constexpr std::size_t always_merge_columns = 4;
constexpr Relaxation relaxations[] = {{16, 0.8}, {48, 0.1}, {~std::size_t{0}, 0.05}};

// Column j + 1 continues j's supernode when j is its only child and their
// structures nest exactly.
std::vector<std::uint32_t> fundamental_supernodes(std::span<const std::uint32_t> parent,
                                                  std::span<const std::uint32_t> counts) {
    const std::size_t n = parent.size();
    std::vector<std::uint32_t> children(n, 0);
    for (std::size_t j = 0; j < n; ++j)
        if (parent[j] != no_parent) ++children[parent[j]];
    std::vector<std::uint32_t> begin;
    for (std::uint32_t j = 0; j < n; ++j) {
        const bool continues =
            j > 0 && parent[j - 1] == j && counts[j - 1] == counts[j] + 1 && children[j] == 1;
        if (!continues) begin.push_back(j);
    }
    begin.push_back(static_cast<std::uint32_t>(n));
    return begin;
}

// Merges each supernode into its parent when it is the parent's last child
// and the merged block stays dense enough; returns the merged boundaries.
std::vector<std::uint32_t> amalgamate(std::span<const std::uint32_t> fundamental,
                                      std::span<const std::uint32_t> parent,
                                      std::span<const std::uint32_t> counts) {
    const std::size_t f_count = fundamental.size() - 1;
    if (f_count < 2) return {fundamental.begin(), fundamental.end()};
    std::vector<std::uint32_t> column_to_f(parent.size());
    for (std::size_t f = 0; f < f_count; ++f)
        for (std::uint32_t c = fundamental[f]; c < fundamental[f + 1]; ++c)
            column_to_f[c] = static_cast<std::uint32_t>(f);
    // Per group, kept at its top member: columns, rows of its first column,
    // explicit zeros.
    std::vector<std::size_t> top(f_count);
    std::vector<std::size_t> columns(f_count);
    std::vector<std::size_t> rows(f_count);
    std::vector<double> zeros(f_count, 0.0);
    for (std::size_t f = 0; f < f_count; ++f) {
        top[f] = f;
        columns[f] = fundamental[f + 1] - fundamental[f];
        rows[f] = counts[fundamental[f]];
    }
    for (std::size_t j = f_count - 1; j-- > 0;) {
        const std::uint32_t last_column = fundamental[j + 1] - 1;
        if (parent[last_column] == no_parent || column_to_f[parent[last_column]] != j + 1) continue;
        const std::size_t t = top[j + 1];
        const std::size_t width = columns[j];
        const std::size_t merged_columns = width + columns[t];
        const std::size_t merged_rows = width + rows[t];
        const double merged_zeros =
            zeros[t] + static_cast<double>(width) * static_cast<double>(merged_rows - rows[j]);
        const double size =
            static_cast<double>(merged_columns) * static_cast<double>(merged_columns + 1) / 2.0 +
            static_cast<double>(merged_columns) * static_cast<double>(merged_rows - merged_columns);
        bool merge = merged_columns <= always_merge_columns;
        for (const Relaxation& r : relaxations)
            merge = merge || (merged_columns <= r.columns && merged_zeros < r.zero_share * size);
        if (!merge) continue;
        top[j] = t;
        columns[t] = merged_columns;
        rows[t] = merged_rows;
        zeros[t] = merged_zeros;
    }
    std::vector<std::uint32_t> begin;
    for (std::size_t f = 0; f < f_count; ++f)
        if (f == 0 || top[f] != top[f - 1]) begin.push_back(fundamental[f]);
    begin.push_back(fundamental[f_count]);
    return begin;
}

// The pattern of P A Pᵀ with P postordered (every elimination subtree
// contiguous), and its elimination tree; sets out.perm and out.inverse.
PermutedColumns postordered_pattern(const CsrMatrix& a, std::span<const std::uint32_t> perm,
                                    CholeskySymbolic& out, std::vector<std::uint32_t>& tree) {
    const std::size_t n = a.rows;
    PermutedColumns pattern = permuted_columns(a, perm, inverse_permutation(perm));
    const std::vector<std::uint32_t> first_tree = elimination_tree(pattern);
    const std::vector<std::uint32_t> post = tree_postorder(first_tree);
    out.perm.resize(n);
    for (std::size_t k = 0; k < n; ++k) out.perm[k] = perm[post[k]];
    out.inverse = inverse_permutation(out.perm);
    tree = first_tree;
    if (post == identity_ordering(n)) return pattern;
    const std::vector<std::uint32_t> post_inverse = inverse_permutation(post);
    for (std::size_t k = 0; k < n; ++k)
        tree[k] = first_tree[post[k]] == no_parent ? no_parent : post_inverse[first_tree[post[k]]];
    return renumbered_columns(pattern, post, post_inverse);
}

// Row lists, children before parents: a supernode's rows are its columns,
// A's entries below them and its children's rows below them. Places A's
// entries and sizes the value blocks in the same pass. Fails when a block
// would outgrow the 32-bit entry targets.
Status lay_out_supernodes(const PermutedColumns& pattern, CholeskySymbolic& out) {
    const std::size_t s_count = out.supernode_count();
    std::vector<std::uint32_t> child_head(s_count, no_parent);
    std::vector<std::uint32_t> child_next(s_count, no_parent);
    for (std::size_t s = s_count; s-- > 0;) {
        if (out.parent[s] == no_parent) continue;
        child_next[s] = child_head[out.parent[s]];
        child_head[out.parent[s]] = static_cast<std::uint32_t>(s);
    }
    std::vector<std::uint32_t> mark(out.n, no_parent);
    std::vector<std::uint32_t> position(out.n);
    std::vector<std::uint32_t> list;
    const std::size_t entries = pattern.rows.size() / 2 + out.n;
    out.entry_source.reserve(entries);
    out.entry_target.reserve(entries);
    for (std::uint32_t s = 0; s < s_count; ++s) {
        const std::uint32_t first = out.column_begin[s];
        const std::uint32_t end = out.column_begin[s + 1];
        list.clear();
        for (std::uint32_t c = first; c < end; ++c) {
            list.push_back(c);
            mark[c] = s;
        }
        const auto add = [&](std::uint32_t i) {
            if (mark[i] == s) return;
            mark[i] = s;
            list.push_back(i);
        };
        for (std::uint32_t c = first; c < end; ++c)
            for (const std::uint32_t i : pattern.lower(c))
                if (i >= end) add(i);
        for (std::uint32_t ch = child_head[s]; ch != no_parent; ch = child_next[ch]) {
            const std::size_t width = out.column_begin[ch + 1] - out.column_begin[ch];
            for (std::size_t p = out.row_begin[ch] + width; p < out.row_begin[ch + 1]; ++p)
                if (out.rows[p] >= end) add(out.rows[p]);
        }
        std::sort(list.begin() + (end - first), list.end());
        const std::size_t m = list.size();
        const std::size_t w = end - first;
        if (m * w > std::numeric_limits<std::uint32_t>::max())
            return {Errc::invalid_argument, "Cholesky: supernode " + std::to_string(s) +
                                                " would hold " + std::to_string(m) + "×" +
                                                std::to_string(w) +
                                                " values, more than 4294967295"};
        for (std::size_t t = 0; t < m; ++t) position[list[t]] = static_cast<std::uint32_t>(t);
        // Column c of P A Pᵀ is read from row perm[c] of A, A being symmetric.
        for (std::uint32_t c = first; c < end; ++c) {
            const auto column = static_cast<std::uint32_t>((c - first) * m);
            for (std::size_t e = pattern.begin[c]; e < pattern.lower_end[c]; ++e) {
                out.entry_source.push_back(pattern.source[e]);
                out.entry_target.push_back(column + position[pattern.rows[e]]);
            }
        }
        out.entry_begin.push_back(out.entry_source.size());
        out.rows.insert(out.rows.end(), list.begin(), list.end());
        out.row_begin.push_back(out.rows.size());
        out.value_begin.push_back(out.value_begin.back() + m * w);
        out.max_rows = std::max(out.max_rows, m);
        out.max_supernode_values = std::max(out.max_supernode_values, m * w);
        out.max_below_values = std::max(out.max_below_values, (m - w) * w);
        double work = 0.0;
        for (std::size_t c = 0; c < w; ++c) {
            const double below = static_cast<double>(m - c);
            work += below * below;
        }
        out.work.push_back(work);
        out.flops += work;
    }
    out.stored_values = out.value_begin.back();
    return Status::ok();
}

// CholeskySymbolic::backward_order and backward_position, from the
// subtrees: the children of s are the roots of the subtrees that tile
// [subtree_begin[s], s), the forest's roots those that tile all of it.
void order_backward(CholeskySymbolic& out) {
    const std::size_t s_count = out.supernode_count();
    out.backward_order.clear();
    out.backward_order.reserve(s_count);
    out.backward_position.assign(s_count, 0);
    std::vector<std::uint32_t> stack;
    // The roots of the subtrees in [begin, end), pushed from the last, so
    // that the first comes off the stack first.
    const auto push_roots = [&](std::uint32_t begin, std::uint32_t end) {
        for (std::uint32_t after = end; after > begin; after = out.subtree_begin[after - 1])
            stack.push_back(after - 1);
    };
    push_roots(0, static_cast<std::uint32_t>(s_count));
    while (!stack.empty()) {
        const std::uint32_t s = stack.back();
        stack.pop_back();
        out.backward_position[s] = static_cast<std::uint32_t>(out.backward_order.size());
        out.backward_order.push_back(s);
        push_roots(out.subtree_begin[s], s);
    }
}

// Who updates whom: each supernode's rows below its columns, cut into runs
// by the supernode that owns them, listed per target by ascending source.
void list_updates(std::span<const std::uint32_t> column_to_super, CholeskySymbolic& out) {
    const std::size_t s_count = out.supernode_count();
    const auto for_each_run = [&](auto&& visit) {
        for (std::uint32_t d = 0; d < s_count; ++d) {
            const std::size_t base = out.row_begin[d];
            const std::size_t m = out.row_begin[d + 1] - base;
            std::size_t p = out.column_begin[d + 1] - out.column_begin[d];
            while (p < m) {
                const std::uint32_t s = column_to_super[out.rows[base + p]];
                std::size_t q = p + 1;
                while (q < m && out.rows[base + q] < out.column_begin[s + 1]) ++q;
                visit(d, s, p, q, m);
                p = q;
            }
        }
    };
    std::vector<std::size_t> count(s_count + 1, 0);
    for_each_run([&](std::uint32_t, std::uint32_t s, std::size_t p, std::size_t q, std::size_t m) {
        ++count[s + 1];
        out.max_update_size = std::max(out.max_update_size, (m - p) * (q - p));
    });
    for (std::size_t s = 0; s < s_count; ++s) count[s + 1] += count[s];
    out.update_begin = count;
    out.updates.resize(count[s_count]);
    for_each_run([&](std::uint32_t d, std::uint32_t s, std::size_t p, std::size_t q, std::size_t) {
        out.updates[count[s]++] = {d, static_cast<std::uint32_t>(p), static_cast<std::uint32_t>(q)};
    });
}

}  // namespace

bool CholeskySymbolic::matches(const CsrMatrix& a) const {
    return a.rows == n && a.cols == n && a.row_offsets == pattern_row_offsets &&
           a.col_indices == pattern_col_indices;
}

Status check_cholesky_pattern(const CsrMatrix& a) {
    if (a.rows != a.cols)
        return {Errc::invalid_argument, "Cholesky: the matrix is " + std::to_string(a.rows) + "×" +
                                            std::to_string(a.cols) + ", not square"};
    if (!has_symmetric_pattern(a))
        return {Errc::invalid_argument,
                "Cholesky: the matrix's pattern is not symmetric (store both triangles)"};
    if (a.nonzeros() > std::numeric_limits<std::uint32_t>::max())
        return {Errc::invalid_argument, "Cholesky: the matrix stores " +
                                            std::to_string(a.nonzeros()) +
                                            " entries, more than 4294967295"};
    return Status::ok();
}

Status analyze_cholesky(const CsrMatrix& a, std::span<const std::uint32_t> perm,
                        CholeskySymbolic& out) {
    if (Status st = check_cholesky_pattern(a); !st) {
        out = CholeskySymbolic{};
        return st;
    }
    return analyze_checked_cholesky(a, perm, out);
}

Status analyze_checked_cholesky(const CsrMatrix& a, std::span<const std::uint32_t> perm,
                                CholeskySymbolic& out) {
    out = CholeskySymbolic{};
    const std::size_t n = a.rows;
    if (!is_permutation(perm, n))
        return {Errc::invalid_argument,
                "Cholesky: the ordering is not a permutation of " + std::to_string(n) + " rows"};
    out.n = n;
    std::vector<std::uint32_t> tree;
    const PermutedColumns pattern = postordered_pattern(a, perm, out, tree);
    const std::vector<std::uint32_t> counts = factor_column_counts(pattern, tree);
    for (const std::uint32_t c : counts) out.factor_nonzeros += c;

    out.column_begin = amalgamate(fundamental_supernodes(tree, counts), tree, counts);
    const std::size_t s_count = out.supernode_count();
    std::vector<std::uint32_t> column_to_super(n);
    for (std::uint32_t s = 0; s < s_count; ++s)
        for (std::uint32_t c = out.column_begin[s]; c < out.column_begin[s + 1]; ++c)
            column_to_super[c] = s;
    out.parent.assign(s_count, no_parent);
    out.subtree_begin.resize(s_count);
    for (std::uint32_t s = 0; s < s_count; ++s) {
        out.subtree_begin[s] = s;
        const std::uint32_t up = tree[out.column_begin[s + 1] - 1];
        if (up != no_parent) out.parent[s] = column_to_super[up];
    }
    for (std::uint32_t s = 0; s < s_count; ++s)
        if (out.parent[s] != no_parent)
            out.subtree_begin[out.parent[s]] =
                std::min(out.subtree_begin[out.parent[s]], out.subtree_begin[s]);
    order_backward(out);

    if (Status st = lay_out_supernodes(pattern, out); !st) {
        out = CholeskySymbolic{};
        return st;
    }
    list_updates(column_to_super, out);
    out.pattern_row_offsets = a.row_offsets;
    out.pattern_col_indices = a.col_indices;
    return Status::ok();
}

}  // namespace dfm::solver
