#include "solver/pbcg.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "solver/parallel_kernels.hpp"

namespace dfm::solver {

PbcgWorkspace::PbcgWorkspace(std::size_t n, std::size_t k, bool general)
    : n_(n), k_(k), general_(general) {
    for (std::vector<double>* v : {&r_, &z_, &p_, &q_}) v->assign(n * k, 0.0);
    if (general)
        for (std::vector<double>* v : {&shadow_r_, &shadow_z_, &shadow_p_, &shadow_q_})
            v->assign(n * k, 0.0);
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
              std::span<double> r, std::size_t k, ThreadPool* pool) {
    kernels::multiply(a, x, r, k, pool);
    for (std::size_t i = 0; i < a.rows * k; ++i) r[i] = b[i] - r[i];
}

}  // namespace

Status pbcg_solve(const CsrMatrix& a, Preconditioner& m, std::span<const double> b,
                  std::span<double> x, std::size_t k, const PbcgOptions& options,
                  PbcgWorkspace& work, PbcgResult& result) {
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
    if (!options.symmetric && !work.general())
        return {Errc::invalid_argument,
                "PBCG: the general algorithm needs a workspace made with general = true"};
    if (m.size() != n)
        return {Errc::invalid_argument, std::string("PBCG: the ") + m.name() +
                                            " preconditioner is not set up for this matrix"};
    if (!(options.tolerance >= 0.0))
        return {Errc::invalid_argument, "PBCG: the tolerance must be a number ≥ 0"};

    ThreadPool* pool = options.pool;
    constexpr std::size_t exact_stagnation_limit = 3;
    const std::size_t stagnation_limit = options.stagnation_limit != 0 ? options.stagnation_limit
                                         : m.is_exact()                ? exact_stagnation_limit
                                                                       : 0;
    const bool general = !options.symmetric;
    const std::span<double> r(work.r_.data(), n * k);
    const std::span<double> z(work.z_.data(), n * k);
    const std::span<double> p(work.p_.data(), n * k);
    const std::span<double> q(work.q_.data(), n * k);
    // The shadow sequence: its own vectors in general, the primal ones
    // when A and M are symmetric.
    const std::span<double> rs = general ? std::span(work.shadow_r_.data(), n * k) : r;
    const std::span<double> zs = general ? std::span(work.shadow_z_.data(), n * k) : z;
    const std::span<double> ps = general ? std::span(work.shadow_p_.data(), n * k) : p;
    const std::span<double> qs = general ? std::span(work.shadow_q_.data(), n * k) : q;
    const std::span<double> partial = work.partial_;
    const std::span<double> rho(work.rho_.data(), k);
    const std::span<double> rho_old(work.rho_old_.data(), k);
    const std::span<double> pq(work.pq_.data(), k);
    const std::span<double> error(work.error_.data(), k);
    const std::span<double> b_norm(work.b_norm_.data(), k);
    const std::span<double> best(work.best_.data(), k);
    const std::span<std::size_t> stalled(work.stalled_.data(), k);
    unsigned char* active = work.active_.data();

    result.columns.resize(k);
    for (PbcgColumnResult& column : result.columns) column = PbcgColumnResult{};
    m.reserve(k);

    // r = b − A x, so that a warm start is judged on its true error.
    residual(a, b, x, r, k, pool);
    if (general)
        for (std::size_t i = 0; i < n * k; ++i) rs[i] = r[i];
    m.apply(r, z, k);
    if (general) m.apply_transposed(rs, zs, k);
    kernels::max_abs(z, n, k, error, partial, pool);
    kernels::dot(zs, r, n, k, rho, partial, pool);
    std::size_t running = 0;
    for (std::size_t c = 0; c < k; ++c) {
        best[c] = error[c];
        stalled[c] = 0;
        result.columns[c].converged = error[c] <= options.tolerance;
        active[c] = !result.columns[c].converged;
        running += active[c];
    }

    for (std::size_t iteration = 0; iteration < options.max_iterations && running > 0;
         ++iteration) {
        for (std::size_t c = 0; c < k; ++c) {
            if (!active[c]) continue;
            if (!usable(rho[c])) {
                result.columns[c].breakdown = true;
                active[c] = 0;
                --running;
                continue;
            }
            if (iteration == 0) {
                for (std::size_t i = 0; i < n; ++i) p[i * k + c] = z[i * k + c];
                if (general)
                    for (std::size_t i = 0; i < n; ++i) ps[i * k + c] = zs[i * k + c];
                continue;
            }
            const double beta = rho[c] / rho_old[c];
            for (std::size_t i = 0; i < n; ++i) p[i * k + c] = z[i * k + c] + beta * p[i * k + c];
            if (general)
                for (std::size_t i = 0; i < n; ++i)
                    ps[i * k + c] = zs[i * k + c] + beta * ps[i * k + c];
        }
        if (running == 0) break;
        kernels::multiply(a, p, q, k, pool);
        if (general) a.multiply_transposed(ps, qs, k);
        kernels::dot(ps, q, n, k, pq, partial, pool);
        for (std::size_t c = 0; c < k; ++c) {
            if (!active[c]) continue;
            const double alpha = rho[c] / pq[c];
            if (!usable(pq[c]) || !std::isfinite(alpha)) {
                result.columns[c].breakdown = true;
                active[c] = 0;
                --running;
                continue;
            }
            for (std::size_t i = 0; i < n; ++i) x[i * k + c] += alpha * p[i * k + c];
            if (general)
                for (std::size_t i = 0; i < n; ++i) rs[i * k + c] -= alpha * qs[i * k + c];
            ++result.columns[c].iterations;
        }
        // The residual recomputed from x rather than updated by −αq: an
        // updated residual keeps shrinking below what rounding in x allows
        // and would report convergence that is not there.
        residual(a, b, x, r, k, pool);
        m.apply(r, z, k);
        if (general) m.apply_transposed(rs, zs, k);
        kernels::max_abs(z, n, k, error, partial, pool);
        for (std::size_t c = 0; c < k; ++c) rho_old[c] = rho[c];
        kernels::dot(zs, r, n, k, rho, partial, pool);
        for (std::size_t c = 0; c < k; ++c) {
            if (!active[c]) continue;
            if (error[c] <= options.tolerance) {
                result.columns[c].converged = true;
            } else if (error[c] < best[c]) {
                best[c] = error[c];
                stalled[c] = 0;
                continue;
            } else if (++stalled[c] < stagnation_limit || stagnation_limit == 0) {
                continue;
            } else {
                result.columns[c].stagnated = true;
            }
            active[c] = 0;
            --running;
        }
    }

    kernels::dot(r, r, n, k, pq, partial, pool);
    kernels::dot(b, b, n, k, b_norm, partial, pool);
    result.iterations = 0;
    result.converged = true;
    for (std::size_t c = 0; c < k; ++c) {
        PbcgColumnResult& column = result.columns[c];
        column.error_estimate = error[c];
        column.relative_residual =
            b_norm[c] > 0.0 ? std::sqrt(pq[c] / b_norm[c]) : std::sqrt(pq[c]);
        result.iterations = std::max(result.iterations, column.iterations);
        result.converged = result.converged && column.converged;
    }
    return Status::ok();
}

}  // namespace dfm::solver
