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

// Row i of A x for K vectors into `sum`, held in registers (summed in the
// output itself, every addition would wait on the store of the one before
// it, since the compiler cannot tell that the output overlaps neither x
// nor A); the same additions in the same order as CsrMatrix::multiply.
template <std::size_t K>
[[gnu::always_inline]] inline void row_product(const CsrMatrix& a, const double* x, std::size_t i,
                                               double (&sum)[K]) {
    for (std::size_t c = 0; c < K; ++c) sum[c] = 0.0;
    for (std::size_t p = a.row_offsets[i]; p < a.row_offsets[i + 1]; ++p) {
        const double v = a.values[p];
        const double* xj = x + static_cast<std::size_t>(a.col_indices[p]) * K;
        for (std::size_t c = 0; c < K; ++c) sum[c] += v * xj[c];
    }
}

// Rows [begin, end) of y = A x for K vectors, each row stored once.
template <std::size_t K>
void multiply_rows(const CsrMatrix& a, const double* x, double* y, std::size_t begin,
                   std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
        double sum[K];
        row_product(a, x, i, sum);
        for (std::size_t c = 0; c < K; ++c) y[i * K + c] = sum[c];
    }
}

// Rows [begin, end) of r = b − A x for K vectors, with the rows' largest
// |r| and their sums of r² and b² (in row order) for each vector.
template <std::size_t K>
void residual_rows(const CsrMatrix& a, const double* b, const double* x, double* r,
                   std::size_t begin, std::size_t end, double* largest, double* r2, double* b2) {
    for (std::size_t c = 0; c < K; ++c) largest[c] = r2[c] = b2[c] = 0.0;
    for (std::size_t i = begin; i < end; ++i) {
        double sum[K];
        row_product(a, x, i, sum);
        for (std::size_t c = 0; c < K; ++c) {
            const double bi = b[i * K + c];
            const double ri = bi - sum[c];
            r[i * K + c] = ri;
            largest[c] = std::max(largest[c], std::isnan(ri) ? infinity : std::abs(ri));
            r2[c] += ri * ri;
            b2[c] += bi * bi;
        }
    }
}

}  // namespace

void residual(const CsrMatrix& a, std::span<const double> b, std::span<const double> x,
              std::span<double> r, std::size_t k, std::span<double> largest, std::span<double> r2,
              std::span<double> b2, std::span<double> partial, jobs::WorkerPool* pool) {
    const std::size_t n = a.rows;
    for_blocks(n, pool, [&](std::size_t begin, std::size_t end, std::size_t block) {
        double* block_largest = &partial[block * 3 * k];
        double* block_r2 = block_largest + k;
        double* block_b2 = block_r2 + k;
        if (k == 3) {
            return residual_rows<3>(a, b.data(), x.data(), r.data(), begin, end, block_largest,
                                    block_r2, block_b2);
        }
        for (std::size_t c = 0; c < k; ++c) block_largest[c] = block_r2[c] = block_b2[c] = 0.0;
        for (std::size_t i = begin; i < end; ++i) {
            for (std::size_t c = 0; c < k; ++c) {
                double sum = 0.0;
                for (std::size_t p = a.row_offsets[i]; p < a.row_offsets[i + 1]; ++p)
                    sum += a.values[p] * x[static_cast<std::size_t>(a.col_indices[p]) * k + c];
                const double bi = b[i * k + c];
                const double ri = bi - sum;
                r[i * k + c] = ri;
                block_largest[c] =
                    std::max(block_largest[c], std::isnan(ri) ? infinity : std::abs(ri));
                block_r2[c] += ri * ri;
                block_b2[c] += bi * bi;
            }
        }
    });
    for (std::size_t c = 0; c < k; ++c) largest[c] = r2[c] = b2[c] = 0.0;
    for (std::size_t block = 0; block < block_count(n); ++block) {
        const double* sums = &partial[block * 3 * k];
        for (std::size_t c = 0; c < k; ++c) {
            largest[c] = std::max(largest[c], sums[c]);
            r2[c] += sums[k + c];
            b2[c] += sums[2 * k + c];
        }
    }
}

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

void copy(std::span<const double> from, std::span<double> to, jobs::WorkerPool* pool) {
    jobs::for_parts(pool, from.size(), [&](std::size_t begin, std::size_t end) {
        std::copy(from.begin() + static_cast<std::ptrdiff_t>(begin),
                  from.begin() + static_cast<std::ptrdiff_t>(end),
                  to.begin() + static_cast<std::ptrdiff_t>(begin));
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
