#include "cholmod_peer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include <cholmod.h>

#include "solver/ordering.hpp"

namespace dfm::solver_bench {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// A's lower triangle as a CHOLMOD matrix: A is symmetric, so its CSR rows
// are its CSC columns, of which the entries on and below the diagonal stay.
cholmod_sparse* lower_triangle(const solver::CsrMatrix& a, cholmod_common& common) {
    std::size_t kept = 0;
    for (std::size_t j = 0; j < a.rows; ++j)
        for (std::size_t p = a.row_offsets[j]; p < a.row_offsets[j + 1]; ++p)
            kept += a.col_indices[p] >= j ? 1 : 0;
    cholmod_sparse* m =
        cholmod_allocate_sparse(a.rows, a.cols, kept, 1, 1, -1, CHOLMOD_REAL, &common);
    if (m == nullptr) return nullptr;
    auto* column_begin = static_cast<int*>(m->p);
    auto* row = static_cast<int*>(m->i);
    auto* value = static_cast<double*>(m->x);
    std::size_t q = 0;
    for (std::size_t j = 0; j < a.rows; ++j) {
        column_begin[j] = static_cast<int>(q);
        for (std::size_t p = a.row_offsets[j]; p < a.row_offsets[j + 1]; ++p) {
            if (a.col_indices[p] < j) continue;
            row[q] = static_cast<int>(a.col_indices[p]);
            value[q] = a.values[p];
            ++q;
        }
    }
    column_begin[a.rows] = static_cast<int>(q);
    return m;
}

}  // namespace

CholmodMeasure measure_cholmod(const TestSystem& system, int repeat) {
    const solver::CsrMatrix& a = system.matrix;
    const std::size_t n = a.rows;
    CholmodMeasure out;
    cholmod_common common;
    cholmod_start(&common);
    common.supernodal = CHOLMOD_SUPERNODAL;
    common.nmethods = 1;
    common.method[0].ordering = CHOLMOD_GIVEN;
    common.postorder = 1;
    cholmod_sparse* lower = lower_triangle(a, common);
    cholmod_dense* b = cholmod_allocate_dense(n, 3, n, CHOLMOD_REAL, &common);
    if (lower == nullptr || b == nullptr) {
        cholmod_free_sparse(&lower, &common);
        cholmod_free_dense(&b, &common);
        cholmod_finish(&common);
        return out;
    }
    // The right-hand sides measure_factor uses, column by column.
    auto* bx = static_cast<double*>(b->x);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t c = 0; c < 3; ++c)
            bx[c * n + i] = std::sin(0.1 * static_cast<double>(i * 3 + c));
    const std::vector<std::uint32_t> order =
        solver::fill_reducing_ordering(a, solver::OrderingMethod::minimum_degree);
    std::vector<int> perm(order.begin(), order.end());

    std::vector<double> symbolic, numeric, solve;
    std::vector<double> x(n * 3);
    out.ok = true;
    for (int r = 0; r < repeat && out.ok; ++r) {
        const Clock::time_point t0 = Clock::now();
        cholmod_factor* l = cholmod_analyze_p(lower, perm.data(), nullptr, 0, &common);
        const Clock::time_point t1 = Clock::now();
        out.ok = l != nullptr && cholmod_factorize(lower, l, &common) != 0 &&
                 common.status == CHOLMOD_OK;
        const Clock::time_point t2 = Clock::now();
        symbolic.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
        numeric.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
        for (int s = 0; s < 3 && out.ok; ++s) {
            const Clock::time_point t3 = Clock::now();
            cholmod_dense* solution = cholmod_solve(CHOLMOD_A, l, b, &common);
            solve.push_back(ms_since(t3));
            out.ok = solution != nullptr;
            if (!out.ok) break;
            const auto* sx = static_cast<const double*>(solution->x);
            for (std::size_t i = 0; i < n; ++i)
                for (std::size_t c = 0; c < 3; ++c) x[i * 3 + c] = sx[c * n + i];
            cholmod_free_dense(&solution, &common);
        }
        if (l != nullptr) out.factor_nonzeros = static_cast<std::size_t>(common.lnz);
        cholmod_free_factor(&l, &common);
    }
    cholmod_free_sparse(&lower, &common);
    cholmod_free_dense(&b, &common);
    cholmod_finish(&common);
    if (!out.ok) return out;

    std::sort(symbolic.begin(), symbolic.end());
    std::sort(numeric.begin(), numeric.end());
    std::sort(solve.begin(), solve.end());
    out.symbolic_ms = symbolic[symbolic.size() / 2];
    out.numeric_ms = numeric[numeric.size() / 2];
    out.solve_k3_ms = solve[solve.size() / 2];
    out.solve_k3_min_ms = solve.front();
    std::vector<double> rhs(n * 3), ax(n * 3);
    for (std::size_t i = 0; i < n * 3; ++i) rhs[i] = std::sin(0.1 * static_cast<double>(i));
    a.multiply(x, ax, 3);
    double r2 = 0.0;
    double b2 = 0.0;
    for (std::size_t i = 0; i < n * 3; ++i) {
        r2 += (rhs[i] - ax[i]) * (rhs[i] - ax[i]);
        b2 += rhs[i] * rhs[i];
    }
    out.solve_relative_residual = std::sqrt(r2 / b2);
    return out;
}

}  // namespace dfm::solver_bench
