#include <algorithm>
#include <cstddef>

#include "solver/sparse_cholesky.hpp"
#include "solver/supernode_kernels.hpp"

namespace dfm::solver {

namespace {

// L y = y over one supernode: its diagonal block, then the updates it makes
// to the rows below it, pushed into those rows that come before `push_end`.
void forward_supernode(const CholeskySymbolic& sym, std::span<const double> values, std::uint32_t s,
                       double* y, std::size_t k, double* scratch, std::uint32_t push_end) {
    const std::size_t first = sym.column_begin[s];
    const std::size_t w = sym.column_begin[s + 1] - first;
    const std::size_t m = sym.row_begin[s + 1] - sym.row_begin[s];
    const std::uint32_t* rows = &sym.rows[sym.row_begin[s]] + w;
    const std::size_t push =
        static_cast<std::size_t>(std::lower_bound(rows, rows + (m - w), push_end) - rows);
    supernode::forward(m, w, push, k, &values[sym.value_begin[s]], rows, y + first * k, y, scratch);
}

// The updates of all its descendants into supernode s's own entries, pulled
// in the order pushing would have applied them (by source, then row), each
// source's rows pushed as forward pushes them, so that the bits are the same
// either way.
void pull_updates(const CholeskySymbolic& sym, std::span<const double> values, std::uint32_t s,
                  double* y, std::size_t k, double* scratch) {
    for (std::size_t u = sym.update_begin[s]; u < sym.update_begin[s + 1]; ++u) {
        const SupernodeUpdate& update = sym.updates[u];
        const std::uint32_t d = update.source;
        const std::size_t wd = sym.column_begin[d + 1] - sym.column_begin[d];
        const double* below = &values[sym.value_begin[d]] + wd * wd;
        supernode::push(update.last - update.first, wd, k, below + (update.first - wd) * wd,
                        &sym.rows[sym.row_begin[d]] + update.first,
                        y + static_cast<std::size_t>(sym.column_begin[d]) * k, y, scratch);
    }
}

// The backward solve takes each supernode before its children, which lie
// below it in memory, and reads each one's values ascending, so the
// hardware prefetcher, which follows a stream within a page, starts over
// at many supernodes: the kernel fetches the next one's values (up to this
// many bytes, spread over its rows; more was no better) while it works on
// this one. Children in ascending order (backward_order) take the small
// supernodes near the leaves mostly upwards, where the prefetcher follows;
// the narrow supernodes gain more from that than the wide ones lose.
constexpr std::size_t backward_prefetch_bytes = 16384;

// Lᵀ y = y over one supernode: its rows below, then its diagonal block.
// Writes only its own entries; fetches supernode `next` (none: no_next).
constexpr std::uint32_t no_next = ~std::uint32_t{0};

void backward_supernode(const CholeskySymbolic& sym, std::span<const double> values,
                        std::uint32_t s, double* y, std::size_t k, double* scratch,
                        std::uint32_t next) {
    const char* ahead = nullptr;
    std::size_t ahead_bytes = 0;
    if (next != no_next) {
        ahead = reinterpret_cast<const char*>(&values[sym.value_begin[next]]);
        ahead_bytes = std::min((sym.value_begin[next + 1] - sym.value_begin[next]) * sizeof(double),
                               backward_prefetch_bytes);
    }
    const std::size_t first = sym.column_begin[s];
    const std::size_t w = sym.column_begin[s + 1] - first;
    const std::size_t m = sym.row_begin[s + 1] - sym.row_begin[s];
    supernode::backward(m, w, k, &values[sym.value_begin[s]], &sym.rows[sym.row_begin[s]] + w,
                        y + first * k, y, scratch, ahead, ahead_bytes);
}

// Lᵀ y = y over backward_order[first .. first + count): the whole tree, or
// one subtree.
void backward_in_order(const CholeskySymbolic& sym, std::span<const double> values,
                       std::size_t first, std::size_t count, double* y, std::size_t k,
                       double* scratch) {
    const std::uint32_t* order = sym.backward_order.data() + first;
    for (std::size_t i = 0; i < count; ++i)
        backward_supernode(sym, values, order[i], y, k, scratch,
                           i + 1 < count ? order[i + 1] : no_next);
}

}  // namespace

std::size_t SparseCholesky::solve_work_size(std::size_t k, std::size_t threads) const {
    return symbolic_.n * k +
           std::max<std::size_t>(threads, 1) * supernode::scratch_size(symbolic_.max_rows, k);
}

void SparseCholesky::solve(std::span<const double> b, std::span<double> x, std::size_t k,
                           std::span<double> work, jobs::WorkerPool* pool) const {
    const CholeskySymbolic& sym = symbolic_;
    const std::size_t n = sym.n;
    double* y = work.data();
    double* below = y + n * k;
    jobs::for_parts(pool, n, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            const double* from = &b[static_cast<std::size_t>(sym.perm[i]) * k];
            for (std::size_t c = 0; c < k; ++c) y[i * k + c] = from[c];
        }
    });
    const std::size_t threads = pool != nullptr ? pool->thread_count() : 1;
    const bool split = threads > 1 && n >= jobs::parallel_minimum &&
                       solve_schedule_.subtrees.size() == threads &&
                       work.size() >= solve_work_size(k, threads);
    if (split) {
        // Each subtree on one thread, pushing updates only inside itself;
        // the supernodes above pull theirs. Back in the opposite order: the
        // top first, then the subtrees.
        pool->run(threads, [&](std::size_t t) {
            double* mine = below + t * supernode::scratch_size(sym.max_rows, k);
            for (const std::uint32_t root : solve_schedule_.subtrees[t])
                for (std::uint32_t s = sym.subtree_begin[root]; s <= root; ++s)
                    forward_supernode(sym, values_, s, y, k, mine, sym.column_begin[root + 1]);
        });
        for (const std::uint32_t s : solve_schedule_.top) {
            pull_updates(sym, values_, s, y, k, below);
            forward_supernode(sym, values_, s, y, k, below, 0);
        }
        for (std::size_t p = solve_schedule_.top.size(); p-- > 0;)
            backward_supernode(sym, values_, solve_schedule_.top[p], y, k, below,
                               p > 0 ? solve_schedule_.top[p - 1] : no_next);
        pool->run(threads, [&](std::size_t t) {
            double* mine = below + t * supernode::scratch_size(sym.max_rows, k);
            for (const std::uint32_t root : solve_schedule_.subtrees[t])
                backward_in_order(sym, values_, sym.backward_position[root],
                                  root - sym.subtree_begin[root] + 1, y, k, mine);
        });
    } else {
        const std::uint32_t s_count = static_cast<std::uint32_t>(sym.supernode_count());
        const auto everywhere = static_cast<std::uint32_t>(n);
        for (std::uint32_t s = 0; s < s_count; ++s)
            forward_supernode(sym, values_, s, y, k, below, everywhere);
        backward_in_order(sym, values_, 0, s_count, y, k, below);
    }
    jobs::for_parts(pool, n, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            double* to = &x[static_cast<std::size_t>(sym.perm[i]) * k];
            for (std::size_t c = 0; c < k; ++c) to[c] = y[i * k + c];
        }
    });
}

}  // namespace dfm::solver
