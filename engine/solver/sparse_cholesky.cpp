#include "solver/sparse_cholesky.hpp"

#include <algorithm>
#include <chrono>
#include <limits>
#include <string>

#include "core/memory_bytes.hpp"
#include "core/stopwatch.hpp"
#include "solver/cholesky_schedule.hpp"
#include "solver/dense_kernels.hpp"
#include "solver/elimination_tree.hpp"
#include "solver/symmetric_graph.hpp"

namespace dfm::solver {

namespace {

constexpr std::uint32_t no_failure = std::numeric_limits<std::uint32_t>::max();
// Supernodes above the subtrees are split between threads from this much
// estimated work on; below it, waking the threads costs more than it saves.
constexpr double split_work = 2e5;

// Each supernode is assembled and factored column by column in a thread's
// scratch (its `front`), then written to the factor once, laid out for the
// solves; its ancestors' updates read it there.

// Copies A's entries into supernode s's block `front` (zero elsewhere) and
// records where each of its rows sits in its row list.
void assemble_supernode(const CholeskySymbolic& sym, std::span<const double> a_values,
                        double* front, std::uint32_t s, std::span<std::uint32_t> position) {
    const std::size_t w = sym.column_begin[s + 1] - sym.column_begin[s];
    const std::size_t m = sym.row_begin[s + 1] - sym.row_begin[s];
    std::fill(front, front + m * w, 0.0);
    for (std::size_t e = sym.entry_begin[s]; e < sym.entry_begin[s + 1]; ++e)
        front[sym.entry_target[e]] = a_values[sym.entry_source[e]];
    const std::uint32_t* rows = &sym.rows[sym.row_begin[s]];
    for (std::size_t t = 0; t < m; ++t) position[rows[t]] = static_cast<std::uint32_t>(t);
}

// Subtracts from supernode s's block `front` the updates of all its
// descendants, restricted to s's rows [row_begin, row_end): for each
// descendant, the product of its rows landing there with its rows in s's
// columns, then a scatter.
void apply_updates(const CholeskySymbolic& sym, std::span<const double> l_values, std::uint32_t s,
                   double* front, std::span<const std::uint32_t> position, std::size_t row_begin,
                   std::size_t row_end, CholeskyScratch& scratch) {
    const std::uint32_t first = sym.column_begin[s];
    const std::size_t m = sym.row_begin[s + 1] - sym.row_begin[s];
    for (std::size_t u = sym.update_begin[s]; u < sym.update_begin[s + 1]; ++u) {
        const SupernodeUpdate& update = sym.updates[u];
        const std::uint32_t d = update.source;
        const std::size_t md = sym.row_begin[d + 1] - sym.row_begin[d];
        const std::size_t wd = sym.column_begin[d + 1] - sym.column_begin[d];
        const std::uint32_t* rows_d = &sym.rows[sym.row_begin[d]];
        // d's rows from `first` on land on ascending rows of s; keep those in
        // range.
        std::size_t lo = update.first;
        std::size_t hi = md;
        if (row_begin > 0 || row_end < m) {
            const auto lands_before = [&](std::size_t limit) {
                return [&, limit](std::uint32_t row) { return position[row] < limit; };
            };
            lo = static_cast<std::size_t>(
                std::partition_point(rows_d + update.first, rows_d + md, lands_before(row_begin)) -
                rows_d);
            hi = static_cast<std::size_t>(
                std::partition_point(rows_d + lo, rows_d + md, lands_before(row_end)) - rows_d);
            if (lo == hi) continue;
        }
        const std::size_t height = hi - lo;
        const std::size_t offset = lo - update.first;
        // d's rows below its diagonal block are stored row by row; the
        // product reads them by column, gathered into the scratch. Columns
        // of s from the gathered rows' end on have no entries in range.
        const std::size_t gathered = hi - update.first;
        const std::size_t width = std::min<std::size_t>(update.last - update.first, gathered);
        double* panel = scratch.panel.data();
        dense::transpose(gathered, wd,
                         &l_values[sym.value_begin[d]] + wd * wd + (update.first - wd) * wd, wd,
                         panel, gathered);
        double* block = scratch.block.data();
        dense::multiply_nt(height, width, wd, panel + offset, gathered, panel, gathered, block,
                           height, false, true, offset);
        std::uint32_t* relative = scratch.relative.data();
        for (std::size_t t = 0; t < height; ++t) relative[t] = position[rows_d[lo + t]];
        for (std::size_t c = 0; c < width; ++c) {
            double* target = front + static_cast<std::size_t>(rows_d[update.first + c] - first) * m;
            const double* column = block + c * height;
            for (std::size_t t = c > offset ? c - offset : 0; t < height; ++t)
                target[relative[t]] -= column[t];
        }
    }
}

// A supernode factored in `front` (m×w, column-major) is written to the
// factor in the solves' layout (supernode_kernels.hpp): its diagonal block,
// then the rows below it row by row, so that both solves stream L in order.

// The diagonal block, with L's transpose in its upper triangle: row j of L,
// left of the diagonal, is then column j above it, contiguous for the
// backward solve.
void arrange_diagonal_block(const CholeskySymbolic& sym, const double* front,
                            std::span<double> values, std::size_t s) {
    const std::size_t w = sym.column_begin[s + 1] - sym.column_begin[s];
    const std::size_t m = sym.row_begin[s + 1] - sym.row_begin[s];
    double* l = &values[sym.value_begin[s]];
    for (std::size_t j = 0; j < w; ++j)
        for (std::size_t i = 0; i < w; ++i)
            l[j * w + i] = i >= j ? front[j * m + i] : front[i * m + j];
}

// Rows [begin, end) of those below the diagonal block.
void arrange_rows_below(const CholeskySymbolic& sym, const double* front, std::span<double> values,
                        std::size_t s, std::size_t begin, std::size_t end) {
    const std::size_t w = sym.column_begin[s + 1] - sym.column_begin[s];
    const std::size_t m = sym.row_begin[s + 1] - sym.row_begin[s];
    double* below = &values[sym.value_begin[s]] + w * w;
    dense::transpose(w, end - begin, front + w + begin, m, below + begin * w, w);
}

// Assembles supernode s from A's entries and its descendants' updates,
// factors it and writes it to the factor. Returns the failing column
// (factor numbering) or no_failure.
std::uint32_t factor_supernode(const CholeskySymbolic& sym, std::span<const double> a_values,
                               std::span<double> l_values, std::uint32_t s,
                               CholeskyScratch& scratch) {
    const std::size_t m = sym.row_begin[s + 1] - sym.row_begin[s];
    const std::size_t w = sym.column_begin[s + 1] - sym.column_begin[s];
    double* front = scratch.front.data();
    assemble_supernode(sym, a_values, front, s, scratch.position);
    // A's entries of the next supernode, which this thread most often
    // takes next: they sit in A's rows in the ordering's order, anywhere,
    // and arrive while this one's updates run.
    if (s + 2 < sym.entry_begin.size())
        for (std::size_t e = sym.entry_begin[s + 1]; e < sym.entry_begin[s + 2]; ++e)
            __builtin_prefetch(&a_values[sym.entry_source[e]]);
    apply_updates(sym, l_values, s, front, scratch.position, 0, m, scratch);
    const std::size_t done = dense::factor_panel(m, w, front, m);
    if (done < w) return sym.column_begin[s] + static_cast<std::uint32_t>(done);
    arrange_diagonal_block(sym, front, l_values, s);
    arrange_rows_below(sym, front, l_values, s, 0, m - w);
    return no_failure;
}

// Cuts rows [begin, end) into `parts` ranges of about equal weight; row r
// weighs min(r − offset + 1, cap) (the columns it has in a lower trapezoid).
std::vector<std::size_t> split_rows(std::size_t begin, std::size_t end, std::size_t parts,
                                    std::size_t offset, std::size_t cap) {
    const auto weight = [&](std::size_t r) {
        return static_cast<double>(std::min(r + 1 - std::min(r + 1, offset), cap));
    };
    double total = 0.0;
    for (std::size_t r = begin; r < end; ++r) total += weight(r);
    std::vector<std::size_t> cut{begin};
    double sum = 0.0;
    for (std::size_t r = begin; r < end && cut.size() < parts; ++r) {
        sum += weight(r);
        if (sum >= total * static_cast<double>(cut.size()) / static_cast<double>(parts))
            cut.push_back(r + 1);
    }
    while (cut.size() <= parts) cut.push_back(end);
    return cut;
}

// factor_supernode with every step split by rows between the pool's
// threads: the same operations on every entry, so the same bits.
std::uint32_t factor_supernode_split(const CholeskySymbolic& sym, std::span<const double> a_values,
                                     std::span<double> l_values, std::uint32_t s,
                                     std::span<CholeskyScratch> scratch, jobs::WorkerPool& pool) {
    const std::size_t m = sym.row_begin[s + 1] - sym.row_begin[s];
    const std::size_t w = sym.column_begin[s + 1] - sym.column_begin[s];
    const std::size_t threads = pool.thread_count();
    double* front = scratch[0].front.data();
    const std::span<const std::uint32_t> position = scratch[0].position;
    assemble_supernode(sym, a_values, front, s, scratch[0].position);
    const std::vector<std::size_t> cut = split_rows(0, m, threads, 0, w);
    pool.run(threads, [&](std::size_t t) {
        apply_updates(sym, l_values, s, front, position, cut[t], cut[t + 1], scratch[t]);
    });
    for (std::size_t kb = 0; kb < w; kb += dense::panel_block) {
        const std::size_t ke = std::min(w, kb + dense::panel_block);
        double* diagonal = front + kb + kb * m;
        const std::size_t done = dense::factor_diagonal(ke - kb, diagonal, m);
        if (done < ke - kb) return sym.column_begin[s] + static_cast<std::uint32_t>(kb + done);
        const std::vector<std::size_t> rows = split_rows(ke, m, threads, ke, w - ke);
        pool.run(threads, [&](std::size_t t) {
            const std::size_t r0 = rows[t];
            const std::size_t r1 = rows[t + 1];
            if (r0 == r1) return;
            dense::solve_right_lower_transposed(r1 - r0, ke - kb, diagonal, m, front + r0 + kb * m,
                                                m);
        });
        if (ke == w) continue;
        pool.run(threads, [&](std::size_t t) {
            const std::size_t r0 = rows[t];
            const std::size_t r1 = rows[t + 1];
            if (r0 == r1) return;
            dense::multiply_nt(r1 - r0, w - ke, ke - kb, front + r0 + kb * m, m,
                               front + ke + kb * m, m, front + r0 + ke * m, m, true, true, r0 - ke);
        });
    }
    arrange_diagonal_block(sym, front, l_values, s);
    const std::vector<std::size_t> below = split_rows(0, m - w, threads, 0, 1);
    pool.run(threads, [&](std::size_t t) {
        arrange_rows_below(sym, front, l_values, s, below[t], below[t + 1]);
    });
    return no_failure;
}

// The failure to report: a failure stops the supernodes that depend on it,
// and the one reported is the first in factor order, as a sequential run
// would find it.
struct FirstFailure {
    std::uint32_t supernode = no_failure;
    std::uint32_t column = no_failure;  // factor numbering

    void record(std::uint32_t s, std::uint32_t failed_column) {
        if (failed_column != no_failure && s < supernode) {
            supernode = s;
            column = failed_column;
        }
    }
};

bool raised(const std::atomic<bool>* stop) {
    return stop != nullptr && stop->load(std::memory_order_relaxed);
}

// Every supernode on the calling thread, in order, up to the first failure
// or the stop flag.
void factor_in_order(const CholeskySymbolic& sym, std::span<const double> a_values,
                     std::span<double> l_values, CholeskyScratch& scratch, FirstFailure& failure,
                     const std::atomic<bool>* stop) {
    const auto s_count = static_cast<std::uint32_t>(sym.supernode_count());
    for (std::uint32_t s = 0; s < s_count && failure.column == no_failure && !raised(stop); ++s)
        failure.record(s, factor_supernode(sym, a_values, l_values, s, scratch));
}

// The schedule's independent subtrees, each thread its own; a thread stops a
// subtree at its first failure.
void factor_subtrees(const CholeskySymbolic& sym, const CholeskySchedule& schedule,
                     std::span<const double> a_values, std::span<double> l_values,
                     std::span<CholeskyScratch> scratch, jobs::WorkerPool& pool,
                     FirstFailure& failure, const std::atomic<bool>* stop) {
    const std::size_t threads = pool.thread_count();
    std::vector<FirstFailure> failures(threads);
    pool.run(threads, [&](std::size_t t) {
        for (const std::uint32_t root : schedule.subtrees[t]) {
            for (std::uint32_t s = sym.subtree_begin[root]; s <= root; ++s) {
                if (raised(stop)) return;
                const std::uint32_t column =
                    factor_supernode(sym, a_values, l_values, s, scratch[t]);
                if (column == no_failure) continue;
                failures[t].record(s, column);
                break;
            }
        }
    });
    for (const FirstFailure& f : failures) failure.record(f.supernode, f.column);
}

// The supernodes above the subtrees, in order, the large ones split by rows
// between the threads; none after the first failure so far.
void factor_top(const CholeskySymbolic& sym, const CholeskySchedule& schedule,
                std::span<const double> a_values, std::span<double> l_values,
                std::span<CholeskyScratch> scratch, jobs::WorkerPool& pool, FirstFailure& failure,
                const std::atomic<bool>* stop) {
    for (const std::uint32_t s : schedule.top) {
        if (s > failure.supernode || raised(stop)) break;
        const std::uint32_t column =
            sym.work[s] >= split_work
                ? factor_supernode_split(sym, a_values, l_values, s, scratch, pool)
                : factor_supernode(sym, a_values, l_values, s, scratch[0]);
        if (column != no_failure) {
            failure.record(s, column);
            break;
        }
    }
}

}  // namespace

CholeskyScratch::CholeskyScratch(const CholeskySymbolic& sym)
    : position(sym.n),
      relative(sym.max_rows),
      block(sym.max_update_size),
      front(sym.max_supernode_values),
      panel(sym.max_below_values) {}

namespace {

Status stopped_status() {
    return {Errc::cancelled, "Cholesky: stopped by the stop flag"};
}

}  // namespace

bool SparseCholesky::stop_requested() {
    if (raised(stop_)) stopped_ = true;
    return stopped_;
}

std::size_t SparseCholesky::memory_bytes() const {
    const CholeskySymbolic& s = symbolic_;
    std::size_t bytes =
        capacity_bytes(s.perm, s.inverse, s.column_begin, s.parent, s.row_begin, s.rows,
                       s.value_begin, s.update_begin, s.updates, s.entry_begin, s.entry_source,
                       s.entry_target, s.subtree_begin, s.backward_order, s.backward_position,
                       s.work, s.pattern_row_offsets, s.pattern_col_indices);
    bytes += capacity_bytes(values_);
    for (const CholeskySchedule* schedule : {&schedule_, &solve_schedule_}) {
        bytes += capacity_bytes(schedule->subtrees, schedule->top);
        for (const std::vector<std::uint32_t>& roots : schedule->subtrees)
            bytes += capacity_bytes(roots);
    }
    return bytes;
}

Status SparseCholesky::analyze(const CsrMatrix& a, OrderingMethod method) {
    factored_ = false;
    stopped_ = false;
    values_.clear();
    schedule_ = CholeskySchedule{};
    solve_schedule_ = CholeskySchedule{};
    times_ = CholeskyTimes{};
    const auto start = std::chrono::steady_clock::now();
    // Checked once here: the ordering's graph and the analysis then take
    // the pattern as it is, each without a pass over it to check it.
    if (Status st = check_cholesky_pattern(a); !st) {
        symbolic_ = CholeskySymbolic{};
        return st;
    }
    if (stop_requested()) return stopped_status();
    const std::vector<std::uint32_t> perm =
        fill_reducing_ordering(symmetric_pattern_graph(a), method);
    times_.ordering_ms = ms_since(start);
    if (stop_requested()) return stopped_status();
    const auto symbolic_start = std::chrono::steady_clock::now();
    Status st = analyze_checked_cholesky(a, perm, symbolic_);
    times_.symbolic_ms = ms_since(symbolic_start);
    return st;
}

Status SparseCholesky::analyze(const CsrMatrix& a, std::span<const std::uint32_t> perm) {
    factored_ = false;
    stopped_ = false;
    values_.clear();
    schedule_ = CholeskySchedule{};
    solve_schedule_ = CholeskySchedule{};
    times_ = CholeskyTimes{};
    const auto start = std::chrono::steady_clock::now();
    Status st = analyze_cholesky(a, perm, symbolic_);
    times_.symbolic_ms = ms_since(start);
    return st;
}

Status SparseCholesky::compute(const CsrMatrix& a, OrderingMethod method, jobs::WorkerPool* pool) {
    if (!symbolic_.matches(a)) {
        if (Status st = analyze(a, method); !st) return st;
    }
    return factorize(a, pool);
}

Status SparseCholesky::factorize(const CsrMatrix& a, jobs::WorkerPool* pool) {
    factored_ = false;
    stopped_ = false;
    if (!symbolic_.matches(a))
        return {Errc::invalid_argument,
                "Cholesky: the matrix's pattern differs from the analysed one"};
    if (stop_requested()) return stopped_status();
    const auto start = std::chrono::steady_clock::now();
    const CholeskySymbolic& sym = symbolic_;
    const std::size_t threads =
        pool != nullptr && sym.n >= jobs::parallel_minimum ? pool->thread_count() : 1;
    values_.resize(sym.stored_values);
    FirstFailure failure;
    {
        // Each thread's scratch, given back to the buffer pool with the
        // factor done (kept there for the next set-up, in an SDK context).
        std::vector<CholeskyScratch> scratch;
        scratch.reserve(threads);
        for (std::size_t t = 0; t < threads; ++t) scratch.emplace_back(sym);
        if (threads == 1) {
            factor_in_order(sym, a.values, values_, scratch[0], failure, stop_);
        } else {
            if (schedule_.subtrees.size() != threads) {
                schedule_ = make_cholesky_schedule(sym, sym.work, threads);
                solve_schedule_ = make_cholesky_schedule(sym, solve_weights(sym), threads);
            }
            factor_subtrees(sym, schedule_, a.values, values_, scratch, *pool, failure, stop_);
            factor_top(sym, schedule_, a.values, values_, scratch, *pool, failure, stop_);
        }
    }
    times_.numeric_ms = ms_since(start);
    // A stop may leave supernodes unfactored behind one that failed for
    // want of their updates: the stop, not that failure, is what happened.
    if (stop_requested()) return stopped_status();
    if (failure.column != no_failure)
        return {Errc::numerical, "Cholesky: the matrix is not positive definite (pivot of row " +
                                     std::to_string(sym.perm[failure.column]) +
                                     " is not positive)"};
    factored_ = true;
    return Status::ok();
}

}  // namespace dfm::solver
