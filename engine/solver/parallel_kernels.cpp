#include "solver/parallel_kernels.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dfm::solver::kernels {

namespace {

constexpr double infinity = std::numeric_limits<double>::infinity();

// Runs body(begin, end, block) for every block of rows.
template <class Body>
void for_blocks(std::size_t n, jobs::WorkerPool* pool, Body&& body) {
    run_tasks(pool, block_count(n),
              [&](std::size_t b) { body(b * block_rows, std::min(n, (b + 1) * block_rows), b); });
}

// Rows [begin, end) of y = A x for K vectors, each row's sums held in
// registers and stored once: summed in y itself, every addition waited on
// the store of the one before it, since the compiler cannot tell that y
// overlaps neither x nor A. The same additions in the same order as
// CsrMatrix::multiply.
template <std::size_t K>
void multiply_rows(const CsrMatrix& a, const double* x, double* y, std::size_t begin,
                   std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
        double sum[K];
        for (std::size_t c = 0; c < K; ++c) sum[c] = 0.0;
        for (std::size_t p = a.row_offsets[i]; p < a.row_offsets[i + 1]; ++p) {
            const double v = a.values[p];
            const double* xj = x + static_cast<std::size_t>(a.col_indices[p]) * K;
            for (std::size_t c = 0; c < K; ++c) sum[c] += v * xj[c];
        }
        for (std::size_t c = 0; c < K; ++c) y[i * K + c] = sum[c];
    }
}

}  // namespace

void multiply(const CsrMatrix& a, std::span<const double> x, std::span<double> y, std::size_t k,
              jobs::WorkerPool* pool) {
    for_blocks(a.rows, pool, [&](std::size_t begin, std::size_t end, std::size_t) {
        if (k == 3) return multiply_rows<3>(a, x.data(), y.data(), begin, end);
        if (k == 1) return multiply_rows<1>(a, x.data(), y.data(), begin, end);
        for (std::size_t i = begin; i < end; ++i) {
            double* yi = &y[i * k];
            for (std::size_t c = 0; c < k; ++c) yi[c] = 0.0;
            for (std::size_t p = a.row_offsets[i]; p < a.row_offsets[i + 1]; ++p) {
                const double v = a.values[p];
                const double* xj = &x[static_cast<std::size_t>(a.col_indices[p]) * k];
                for (std::size_t c = 0; c < k; ++c) yi[c] += v * xj[c];
            }
        }
    });
}

void dot(std::span<const double> x, std::span<const double> y, std::size_t n, std::size_t k,
         std::span<double> out, std::span<double> partial, jobs::WorkerPool* pool) {
    for_blocks(n, pool, [&](std::size_t begin, std::size_t end, std::size_t b) {
        double* sum = &partial[b * k];
        for (std::size_t c = 0; c < k; ++c) sum[c] = 0.0;
        for (std::size_t i = begin; i < end; ++i)
            for (std::size_t c = 0; c < k; ++c) sum[c] += x[i * k + c] * y[i * k + c];
    });
    for (std::size_t c = 0; c < k; ++c) out[c] = 0.0;
    for (std::size_t b = 0; b < block_count(n); ++b)
        for (std::size_t c = 0; c < k; ++c) out[c] += partial[b * k + c];
}

void max_abs(std::span<const double> x, std::size_t n, std::size_t k, std::span<double> out,
             std::span<double> partial, jobs::WorkerPool* pool) {
    for_blocks(n, pool, [&](std::size_t begin, std::size_t end, std::size_t b) {
        double* largest = &partial[b * k];
        for (std::size_t c = 0; c < k; ++c) largest[c] = 0.0;
        // NaN counts as infinite, so that it can never pass for converged.
        for (std::size_t i = begin; i < end; ++i) {
            for (std::size_t c = 0; c < k; ++c) {
                const double v = x[i * k + c];
                largest[c] = std::max(largest[c], std::isnan(v) ? infinity : std::abs(v));
            }
        }
    });
    for (std::size_t c = 0; c < k; ++c) out[c] = 0.0;
    for (std::size_t b = 0; b < block_count(n); ++b)
        for (std::size_t c = 0; c < k; ++c) out[c] = std::max(out[c], partial[b * k + c]);
}

}  // namespace dfm::solver::kernels
