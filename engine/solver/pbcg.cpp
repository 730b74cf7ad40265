#include "solver/pbcg.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "solver/parallel_kernels.hpp"

namespace dfm::solver {

PbcgWorkspace::PbcgWorkspace(std::size_t n, std::size_t k) : n_(n), k_(k) {
    for (std::vector<double>* v : {&r_, &z_, &p_, &q_}) v->assign(n * k, 0.0);
    partial_.assign(kernels::block_count(n) * k, 0.0);
    for (std::vector<double>* v : {&rho_, &rho_old_, &pq_, &error_, &b_norm_, &best_})
        v->assign(k, 0.0);
    stalled_.assign(k, 0);
    active_.assign(k, 0);
}

namespace {

bool usable(double v) {
    return v != 0.0 && std::isfinite(v);
}

// r = b − A x.
void residual(const CsrMatrix& a, std::span<const double> b, std::span<const double> x,
              std::span<double> r, std::size_t k, jobs::WorkerPool* pool) {
    kernels::multiply(a, x, r, k, pool);
    for (std::size_t i = 0; i < a.rows * k; ++i) r[i] = b[i] - r[i];
}

// The vectors and per-column scalars of one solve, views into the
// workspace.
struct Iterate {
    std::size_t n, k;
    std::span<double> r, z, p, q;
    std::span<double> partial, rho, rho_old, pq, error, b_norm, best;
    std::span<std::size_t> stalled;
    unsigned char* active;
    std::size_t running = 0;  // columns still iterating

    // Stops column c for good.
    void stop(std::size_t c) {
        active[c] = 0;
        --running;
    }
};

Status check_arguments(const CsrMatrix& a, const Preconditioner& m, std::span<const double> b,
                       std::span<const double> x, std::size_t k, const PbcgOptions& options,
                       const PbcgWorkspace& work) {
    const std::size_t n = a.rows;
    if (a.rows != a.cols) return {Errc::invalid_argument, "PBCG: the matrix is not square"};
    if (k == 0) return {Errc::invalid_argument, "PBCG: no right-hand side (k = 0)"};
    if (b.size() < n * k || x.size() < n * k)
        return {Errc::invalid_argument, "PBCG: b and x need " + std::to_string(n * k) +
                                            " entries (n = " + std::to_string(n) +
                                            ", k = " + std::to_string(k) + ")"};
    if (work.size() != n || work.columns() < k)
        return {Errc::invalid_argument,
                "PBCG: the workspace is sized for n = " + std::to_string(work.size()) +
                    ", k = " + std::to_string(work.columns())};
    if (m.size() != n)
        return {Errc::invalid_argument, std::string("PBCG: the ") + m.name() +
                                            " preconditioner is not set up for this matrix"};
    if (!(options.tolerance >= 0.0))
        return {Errc::invalid_argument, "PBCG: the tolerance must be a number ≥ 0"};
    return Status::ok();
}

// z = M⁻¹ r, the error estimate max |z| and ρ = zᵀ r.
void precondition(Preconditioner& m, Iterate& it, jobs::WorkerPool* pool) {
    m.apply(it.r, it.z, it.k);
    kernels::max_abs(it.z, it.n, it.k, it.error, it.partial, pool);
    kernels::dot(it.z, it.r, it.n, it.k, it.rho, it.partial, pool);
}

// p = z + β p (p = z on the first iteration) for every running column;
// a column whose ρ vanished breaks down.
void update_directions(Iterate& it, bool first, PbcgResult& result) {
    const std::size_t n = it.n;
    const std::size_t k = it.k;
    for (std::size_t c = 0; c < k; ++c) {
        if (!it.active[c]) continue;
        if (!usable(it.rho[c])) {
            result.columns[c].breakdown = true;
            it.stop(c);
            continue;
        }
        const double beta = first ? 0.0 : it.rho[c] / it.rho_old[c];
        for (std::size_t i = 0; i < n; ++i)
            it.p[i * k + c] = first ? it.z[i * k + c] : it.z[i * k + c] + beta * it.p[i * k + c];
    }
}

// q = A p, α = ρ / pᵀ q and x += α p for every running column; a column
// whose pᵀ q vanished breaks down.
void step_solution(const CsrMatrix& a, std::span<double> x, Iterate& it, jobs::WorkerPool* pool,
                   PbcgResult& result) {
    const std::size_t n = it.n;
    const std::size_t k = it.k;
    kernels::multiply(a, it.p, it.q, k, pool);
    kernels::dot(it.p, it.q, n, k, it.pq, it.partial, pool);
    for (std::size_t c = 0; c < k; ++c) {
        if (!it.active[c]) continue;
        const double alpha = it.rho[c] / it.pq[c];
        if (!usable(it.pq[c]) || !std::isfinite(alpha)) {
            result.columns[c].breakdown = true;
            it.stop(c);
            continue;
        }
        for (std::size_t i = 0; i < n; ++i) x[i * k + c] += alpha * it.p[i * k + c];
        ++result.columns[c].iterations;
    }
}

// Stops the columns that converged, and those whose error estimate has
// not reached a new smallest value for `stagnation_limit` iterations (0:
// never).
void judge_columns(Iterate& it, double tolerance, std::size_t stagnation_limit,
                   PbcgResult& result) {
    for (std::size_t c = 0; c < it.k; ++c) {
        if (!it.active[c]) continue;
        if (it.error[c] <= tolerance) {
            result.columns[c].converged = true;
        } else if (it.error[c] < it.best[c]) {
            it.best[c] = it.error[c];
            it.stalled[c] = 0;
            continue;
        } else if (++it.stalled[c] < stagnation_limit || stagnation_limit == 0) {
            continue;
        } else {
            result.columns[c].stagnated = true;
        }
        it.stop(c);
    }
}

// Each column's last error estimate and true relative residual, and the
// totals.
void summarize(std::span<const double> b, Iterate& it, jobs::WorkerPool* pool, PbcgResult& result) {
    kernels::dot(it.r, it.r, it.n, it.k, it.pq, it.partial, pool);
    kernels::dot(b, b, it.n, it.k, it.b_norm, it.partial, pool);
    result.iterations = 0;
    result.converged = true;
    for (std::size_t c = 0; c < it.k; ++c) {
        PbcgColumnResult& column = result.columns[c];
        column.error_estimate = it.error[c];
        column.relative_residual =
            it.b_norm[c] > 0.0 ? std::sqrt(it.pq[c] / it.b_norm[c]) : std::sqrt(it.pq[c]);
        result.iterations = std::max(result.iterations, column.iterations);
        result.converged = result.converged && column.converged;
    }
}

}  // namespace

Status pbcg_solve(const CsrMatrix& a, Preconditioner& m, std::span<const double> b,
                  std::span<double> x, std::size_t k, const PbcgOptions& options,
                  PbcgWorkspace& work, PbcgResult& result) {
    if (Status st = check_arguments(a, m, b, x, k, options, work); !st) return st;
    const std::size_t n = a.rows;
    jobs::WorkerPool* pool = options.pool;
    constexpr std::size_t exact_stagnation_limit = 3;
    const std::size_t stagnation_limit = options.stagnation_limit != 0 ? options.stagnation_limit
                                         : m.is_exact()                ? exact_stagnation_limit
                                                                       : 0;
    const auto vector = [&](std::vector<double>& v) { return std::span(v.data(), n * k); };
    const auto scalars = [&](std::vector<double>& v) { return std::span(v.data(), k); };
    Iterate it{.n = n,
               .k = k,
               .r = vector(work.r_),
               .z = vector(work.z_),
               .p = vector(work.p_),
               .q = vector(work.q_),
               .partial = work.partial_,
               .rho = scalars(work.rho_),
               .rho_old = scalars(work.rho_old_),
               .pq = scalars(work.pq_),
               .error = scalars(work.error_),
               .b_norm = scalars(work.b_norm_),
               .best = scalars(work.best_),
               .stalled = std::span(work.stalled_.data(), k),
               .active = work.active_.data(),
               .running = 0};

    result.columns.resize(k);
    for (PbcgColumnResult& column : result.columns) column = PbcgColumnResult{};
    m.reserve(k);

    // A warm start is judged on its true error: the first residual comes
    // from x, as every later one does.
    residual(a, b, x, it.r, k, pool);
    kernels::max_abs(it.r, n, k, it.best, it.partial, pool);
    for (std::size_t c = 0; c < k; ++c) result.columns[c].start_residual = it.best[c];
    precondition(m, it, pool);
    for (std::size_t c = 0; c < k; ++c) {
        result.columns[c].start_error_estimate = it.error[c];
        it.best[c] = it.error[c];
        it.stalled[c] = 0;
        result.columns[c].converged = it.error[c] <= options.tolerance;
        it.active[c] = !result.columns[c].converged;
        it.running += it.active[c];
    }

    for (std::size_t iteration = 0; iteration < options.max_iterations && it.running > 0;
         ++iteration) {
        update_directions(it, iteration == 0, result);
        if (it.running == 0) break;
        step_solution(a, x, it, pool, result);
        // The residual recomputed from x rather than updated by −αq: an
        // updated residual keeps shrinking below what rounding in x allows
        // and would report convergence that is not there.
        residual(a, b, x, it.r, k, pool);
        for (std::size_t c = 0; c < k; ++c) it.rho_old[c] = it.rho[c];
        precondition(m, it, pool);
        judge_columns(it, options.tolerance, stagnation_limit, result);
    }

    summarize(b, it, pool, result);
    return Status::ok();
}

}  // namespace dfm::solver
