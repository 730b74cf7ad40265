#include "solver/symmetric_graph.hpp"

#include <algorithm>

namespace dfm::solver {

namespace {

// Walks the rows in order; in a symmetric pattern the rows below the
// diagonal that hold column c, met in ascending order, are exactly row c's
// columns right of the diagonal, in order. A cursor per row, set when the
// walk passes that row's diagonal, finds every twin without searching, and
// only the entries below the diagonal are looked up.
bool match_twins(const CsrMatrix& a) {
    if (a.rows != a.cols) return false;
    std::vector<std::size_t> cursor(a.rows);
    for (std::size_t r = 0; r < a.rows; ++r) {
        std::size_t p = a.row_offsets[r];
        const std::size_t end = a.row_offsets[r + 1];
        for (; p < end && a.col_indices[p] < r; ++p) {
            const std::uint32_t c = a.col_indices[p];
            const std::size_t q = cursor[c]++;
            if (q >= a.row_offsets[c + 1] || a.col_indices[q] != r) return false;
        }
        cursor[r] = p < end && a.col_indices[p] == r ? p + 1 : p;
    }
    // Every entry right of a diagonal matched one below it.
    for (std::size_t r = 0; r < a.rows; ++r)
        if (cursor[r] != a.row_offsets[r + 1]) return false;
    return true;
}

}  // namespace

bool has_symmetric_pattern(const CsrMatrix& a) {
    return match_twins(a);
}

SymmetricGraph symmetric_pattern_graph(const CsrMatrix& a) {
    const std::size_t n = a.rows;
    SymmetricGraph g;
    g.offsets.assign(n + 1, 0);
    g.neighbors.reserve(a.nonzeros());
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t p = a.row_offsets[i]; p < a.row_offsets[i + 1]; ++p)
            if (a.col_indices[p] != i) g.neighbors.push_back(a.col_indices[p]);
        g.offsets[i + 1] = g.neighbors.size();
    }
    return g;
}

SymmetricGraph symmetric_graph(const CsrMatrix& a) {
    if (has_symmetric_pattern(a)) return symmetric_pattern_graph(a);
    const std::size_t n = a.rows;
    SymmetricGraph g;
    g.offsets.assign(n + 1, 0);
    // Both directions of every stored entry, then one copy of each. Columns
    // beyond the last row (a matrix that is not square) are left out.
    std::vector<std::size_t> start(n + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t p = a.row_offsets[i]; p < a.row_offsets[i + 1]; ++p) {
            const std::uint32_t j = a.col_indices[p];
            if (j == i || j >= n) continue;
            ++start[i + 1];
            ++start[j + 1];
        }
    }
    for (std::size_t i = 0; i < n; ++i) start[i + 1] += start[i];
    std::vector<std::uint32_t> both(start[n]);
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t p = a.row_offsets[i]; p < a.row_offsets[i + 1]; ++p) {
            const std::uint32_t j = a.col_indices[p];
            if (j == i || j >= n) continue;
            both[fill[i]++] = j;
            both[fill[j]++] = static_cast<std::uint32_t>(i);
        }
    }
    g.neighbors.reserve(start[n] / 2 + n);
    for (std::size_t i = 0; i < n; ++i) {
        const auto begin = both.begin() + static_cast<std::ptrdiff_t>(start[i]);
        const auto end = both.begin() + static_cast<std::ptrdiff_t>(start[i + 1]);
        std::sort(begin, end);
        g.neighbors.insert(g.neighbors.end(), begin, std::unique(begin, end));
        g.offsets[i + 1] = g.neighbors.size();
    }
    return g;
}

}  // namespace dfm::solver
