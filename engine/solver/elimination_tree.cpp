#include "solver/elimination_tree.hpp"

namespace dfm::solver {

namespace {

// Rows of A ahead whose entries permuted_columns fetches.
constexpr std::size_t row_prefetch_distance = 8;

}  // namespace

PermutedColumns permuted_columns(const CsrMatrix& a, std::span<const std::uint32_t> perm,
                                 std::span<const std::uint32_t> inverse) {
    PermutedColumns out;
    out.begin.resize(a.rows + 1);
    out.lower_end.resize(a.rows);
    out.rows.resize(a.nonzeros());
    out.source.resize(a.nonzeros());
    std::size_t column_begin = 0;
    for (std::size_t j = 0; j < a.rows; ++j) {
        // The rows come in the ordering's order, from anywhere in A: their
        // extents are fetched two steps ahead of their entries, and those
        // well before they are read.
        if (j + 2 * row_prefetch_distance < a.rows)
            __builtin_prefetch(&a.row_offsets[perm[j + 2 * row_prefetch_distance]]);
        if (j + row_prefetch_distance < a.rows)
            __builtin_prefetch(a.col_indices.data() +
                               a.row_offsets[perm[j + row_prefetch_distance]]);
        const std::uint32_t r = perm[j];
        const std::size_t column_end = column_begin + (a.row_offsets[r + 1] - a.row_offsets[r]);
        // Lower entries fill the column from the front, upper ones from the
        // back; selecting the slot rather than branching keeps the
        // unpredictable comparison out of the branch predictor's way.
        std::size_t front = column_begin;
        std::size_t back = column_end;
        for (std::size_t p = a.row_offsets[r]; p < a.row_offsets[r + 1]; ++p) {
            const std::uint32_t i = inverse[a.col_indices[p]];
            const bool lower = i >= j;
            const std::size_t slot = lower ? front : back - 1;
            out.rows[slot] = i;
            out.source[slot] = static_cast<std::uint32_t>(p);
            front += lower ? 1 : 0;
            back -= lower ? 0 : 1;
        }
        out.lower_end[j] = front;
        out.begin[j + 1] = column_end;
        column_begin = column_end;
    }
    return out;
}

PermutedColumns renumbered_columns(const PermutedColumns& from,
                                   std::span<const std::uint32_t> order,
                                   std::span<const std::uint32_t> renumber) {
    PermutedColumns out;
    out.begin.resize(from.size() + 1);
    out.lower_end.resize(from.size());
    out.rows.resize(from.rows.size());
    out.source.resize(from.source.size());
    std::size_t e = 0;
    for (std::size_t k = 0; k < from.size(); ++k) {
        const std::size_t j = order[k];
        out.lower_end[k] = e + (from.lower_end[j] - from.begin[j]);
        for (std::size_t f = from.begin[j]; f < from.begin[j + 1]; ++f, ++e) {
            out.rows[e] = renumber[from.rows[f]];
            out.source[e] = from.source[f];
        }
        out.begin[k + 1] = e;
    }
    return out;
}

std::vector<std::uint32_t> elimination_tree(const PermutedColumns& pattern) {
    const std::size_t n = pattern.size();
    std::vector<std::uint32_t> parent(n, no_parent);
    std::vector<std::uint32_t> ancestor(n, no_parent);
    for (std::uint32_t k = 0; k < n; ++k) {
        for (std::uint32_t i : pattern.upper(k)) {
            // Climb from i to the root of its current subtree, pointing every
            // node on the way at k.
            while (i < k) {
                const std::uint32_t next = ancestor[i];
                ancestor[i] = k;
                if (next == no_parent) {
                    parent[i] = k;
                    break;
                }
                i = next;
            }
        }
    }
    return parent;
}

std::vector<std::uint32_t> tree_postorder(std::span<const std::uint32_t> parent) {
    const std::size_t n = parent.size();
    std::vector<std::uint32_t> head(n, no_parent);
    std::vector<std::uint32_t> next(n, no_parent);
    // Pushing children in descending order leaves each list ascending.
    for (std::size_t j = n; j-- > 0;) {
        if (parent[j] == no_parent) continue;
        next[j] = head[parent[j]];
        head[parent[j]] = static_cast<std::uint32_t>(j);
    }
    std::vector<std::uint32_t> post;
    post.reserve(n);
    std::vector<std::uint32_t> stack;
    for (std::uint32_t root = 0; root < n; ++root) {
        if (parent[root] != no_parent) continue;
        stack.push_back(root);
        while (!stack.empty()) {
            const std::uint32_t p = stack.back();
            const std::uint32_t child = head[p];
            if (child == no_parent) {
                stack.pop_back();
                post.push_back(p);
            } else {
                head[p] = next[child];
                stack.push_back(child);
            }
        }
    }
    return post;
}

std::vector<std::uint32_t> factor_column_counts(const PermutedColumns& pattern,
                                                std::span<const std::uint32_t> parent) {
    const std::size_t n = parent.size();
    constexpr std::uint32_t none = no_parent;
    // Postordered: the first descendant of j is the start of its subtree.
    std::vector<std::uint32_t> first(n, none);
    std::vector<std::int64_t> delta(n, 0);
    for (std::uint32_t k = 0; k < n; ++k) {
        delta[k] = first[k] == none ? 1 : 0;  // a leaf of the tree
        for (std::uint32_t j = k; j != no_parent && first[j] == none; j = parent[j]) first[j] = k;
    }
    std::vector<std::uint32_t> max_first(n, none);
    std::vector<std::uint32_t> prev_leaf(n, none);
    std::vector<std::uint32_t> ancestor(n);
    for (std::uint32_t i = 0; i < n; ++i) ancestor[i] = i;
    for (std::uint32_t j = 0; j < n; ++j) {
        if (parent[j] != no_parent) --delta[parent[j]];
        for (const std::uint32_t i : pattern.lower(j)) {
            // Is j a leaf of the row subtree of i? Only the first descendant
            // of each new subtree counts (skeleton entries).
            if (i <= j || (max_first[i] != none && first[j] <= max_first[i])) continue;
            max_first[i] = first[j];
            const std::uint32_t previous = prev_leaf[i];
            prev_leaf[i] = j;
            ++delta[j];
            if (previous == none) continue;
            // The least common ancestor of this leaf and the previous one
            // already counts row i once.
            std::uint32_t q = previous;
            while (q != ancestor[q]) q = ancestor[q];
            for (std::uint32_t s = previous; s != q;) {
                const std::uint32_t up = ancestor[s];
                ancestor[s] = q;
                s = up;
            }
            --delta[q];
        }
        if (parent[j] != no_parent) ancestor[j] = parent[j];
    }
    for (std::size_t j = 0; j < n; ++j)
        if (parent[j] != no_parent) delta[parent[j]] += delta[j];
    std::vector<std::uint32_t> counts(n);
    for (std::size_t j = 0; j < n; ++j) counts[j] = static_cast<std::uint32_t>(delta[j]);
    return counts;
}

}  // namespace dfm::solver
