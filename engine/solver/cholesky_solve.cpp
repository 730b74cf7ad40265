#include <algorithm>
#include <cstddef>

#include "solver/dense_kernels.hpp"
#include "solver/sparse_cholesky.hpp"

namespace dfm::solver {

namespace {

// L y = y over one supernode: its diagonal block, then the updates it makes
// to the rows below it, pushed into those rows that come before `push_end`
// (gathered into `below`, one column per vector, and scattered back).
void forward_supernode(const CholeskySymbolic& sym, std::span<const double> values, std::uint32_t s,
                       double* y, std::size_t k, double* below, std::uint32_t push_end) {
    const std::size_t first = sym.column_begin[s];
    const std::size_t w = sym.column_begin[s + 1] - first;
    const std::size_t m = sym.row_begin[s + 1] - sym.row_begin[s];
    const std::uint32_t* rows = &sym.rows[sym.row_begin[s]] + w;
    const double* l = &values[sym.value_begin[s]];
    double* yf = y + first * k;
    for (std::size_t j = 0; j < w; ++j) {
        const double* lj = l + j * m;
        double* yj = yf + j * k;
        for (std::size_t c = 0; c < k; ++c) yj[c] /= lj[j];
        for (std::size_t i = j + 1; i < w; ++i)
            for (std::size_t c = 0; c < k; ++c) yf[i * k + c] -= lj[i] * yj[c];
    }
    const std::size_t h =
        static_cast<std::size_t>(std::lower_bound(rows, rows + (m - w), push_end) - rows);
    if (h == 0) return;
    for (std::size_t t = 0; t < h; ++t)
        for (std::size_t c = 0; c < k; ++c) below[c * h + t] = y[rows[t] * k + c];
    dense::subtract_product(h, w, k, l + w, m, yf, below);
    for (std::size_t t = 0; t < h; ++t)
        for (std::size_t c = 0; c < k; ++c) y[rows[t] * k + c] = below[c * h + t];
}

// The updates of all its descendants into supernode s's own entries, pulled
// in the order pushing would have applied them (by source, then column),
// so that the bits are the same either way.
void pull_updates(const CholeskySymbolic& sym, std::span<const double> values, std::uint32_t s,
                  double* y, std::size_t k) {
    for (std::size_t u = sym.update_begin[s]; u < sym.update_begin[s + 1]; ++u) {
        const SupernodeUpdate& update = sym.updates[u];
        const std::uint32_t d = update.source;
        const std::size_t md = sym.row_begin[d + 1] - sym.row_begin[d];
        const std::size_t wd = sym.column_begin[d + 1] - sym.column_begin[d];
        const std::uint32_t* rows = &sym.rows[sym.row_begin[d]];
        const double* ld = &values[sym.value_begin[d]];
        const double* yd = y + static_cast<std::size_t>(sym.column_begin[d]) * k;
        for (std::size_t j = 0; j < wd; ++j) {
            const double* lj = ld + j * md;
            const double* yj = yd + j * k;
            for (std::size_t t = update.first; t < update.last; ++t) {
                double* yt = y + static_cast<std::size_t>(rows[t]) * k;
                for (std::size_t c = 0; c < k; ++c) yt[c] -= lj[t] * yj[c];
            }
        }
    }
}

// Lᵀ y = y over one supernode: its rows below, gathered into `below` (one
// column per vector), then its diagonal block. Writes only its own entries.
void backward_supernode(const CholeskySymbolic& sym, std::span<const double> values,
                        std::uint32_t s, double* y, std::size_t k, double* below) {
    const std::size_t first = sym.column_begin[s];
    const std::size_t w = sym.column_begin[s + 1] - first;
    const std::size_t m = sym.row_begin[s + 1] - sym.row_begin[s];
    const std::size_t h = m - w;
    const std::uint32_t* rows = &sym.rows[sym.row_begin[s]] + w;
    const double* l = &values[sym.value_begin[s]];
    double* yf = y + first * k;
    if (h > 0) {
        for (std::size_t t = 0; t < h; ++t)
            for (std::size_t c = 0; c < k; ++c) below[c * h + t] = y[rows[t] * k + c];
        dense::subtract_transposed_product(h, w, k, l + w, m, below, yf);
    }
    for (std::size_t j = w; j-- > 0;) {
        const double* lj = l + j * m;
        double* yj = yf + j * k;
        for (std::size_t i = j + 1; i < w; ++i)
            for (std::size_t c = 0; c < k; ++c) yj[c] -= lj[i] * yf[i * k + c];
        for (std::size_t c = 0; c < k; ++c) yj[c] /= lj[j];
    }
}

}  // namespace

std::size_t SparseCholesky::solve_work_size(std::size_t k, std::size_t threads) const {
    return (symbolic_.n + std::max<std::size_t>(threads, 1) * symbolic_.max_rows) * k;
}

void SparseCholesky::solve(std::span<const double> b, std::span<double> x, std::size_t k,
                           std::span<double> work, ThreadPool* pool) const {
    const CholeskySymbolic& sym = symbolic_;
    const std::size_t n = sym.n;
    double* y = work.data();
    double* below = y + n * k;
    for (std::size_t i = 0; i < n; ++i) {
        const double* from = &b[static_cast<std::size_t>(sym.perm[i]) * k];
        for (std::size_t c = 0; c < k; ++c) y[i * k + c] = from[c];
    }
    const std::size_t threads = pool != nullptr ? pool->thread_count() : 1;
    const bool split = threads > 1 && schedule_.subtrees.size() == threads &&
                       work.size() >= solve_work_size(k, threads);
    if (split) {
        // Each subtree on one thread, pushing updates only inside itself;
        // the supernodes above pull theirs. Back in the opposite order: the
        // top first, then the subtrees.
        pool->run(threads, [&](std::size_t t) {
            double* mine = below + t * sym.max_rows * k;
            for (const std::uint32_t root : schedule_.subtrees[t])
                for (std::uint32_t s = sym.subtree_begin[root]; s <= root; ++s)
                    forward_supernode(sym, values_, s, y, k, mine, sym.column_begin[root + 1]);
        });
        for (const std::uint32_t s : schedule_.top) {
            pull_updates(sym, values_, s, y, k);
            forward_supernode(sym, values_, s, y, k, below, 0);
        }
        for (std::size_t p = schedule_.top.size(); p-- > 0;)
            backward_supernode(sym, values_, schedule_.top[p], y, k, below);
        pool->run(threads, [&](std::size_t t) {
            double* mine = below + t * sym.max_rows * k;
            for (const std::uint32_t root : schedule_.subtrees[t])
                for (std::uint32_t s = root + 1; s-- > sym.subtree_begin[root];)
                    backward_supernode(sym, values_, s, y, k, mine);
        });
    } else {
        const std::uint32_t s_count = static_cast<std::uint32_t>(sym.supernode_count());
        const auto everywhere = static_cast<std::uint32_t>(n);
        for (std::uint32_t s = 0; s < s_count; ++s)
            forward_supernode(sym, values_, s, y, k, below, everywhere);
        for (std::uint32_t s = s_count; s-- > 0;) backward_supernode(sym, values_, s, y, k, below);
    }
    for (std::size_t i = 0; i < n; ++i) {
        double* to = &x[static_cast<std::size_t>(sym.perm[i]) * k];
        for (std::size_t c = 0; c < k; ++c) to[c] = y[i * k + c];
    }
}

}  // namespace dfm::solver
