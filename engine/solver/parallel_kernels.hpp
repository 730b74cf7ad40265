#pragma once

#include <cstddef>
#include <span>

#include "jobs/worker_pool.hpp"
#include "solver/csr_matrix.hpp"

// The Krylov solver's vector work on k interleaved vectors (x[j * k + c]),
// split into fixed blocks of rows. Block partial results are combined in
// block order, so every result is bit-identical whatever the thread count;
// `pool` may be null (all inline).
namespace dfm::solver::kernels {

// Rows per block; fixed, so that reductions do not depend on threads.
inline constexpr std::size_t block_rows = 2048;

// How many blocks n rows make, which is how many partial sums per vector a
// reduction needs room for.
constexpr std::size_t block_count(std::size_t n) {
    return (n + block_rows - 1) / block_rows;
}

// y = A x; each row computed as CsrMatrix::multiply does.
void multiply(const CsrMatrix& a, std::span<const double> x, std::span<double> y, std::size_t k,
              jobs::WorkerPool* pool);

// r = b − A x, each row's sum as multiply computes it, and in the same
// pass, for each c, largest[c] = max_j |r[j k + c]| (a NaN counting as
// infinite), r2[c] = Σ_j r[j k + c]² and b2[c] = Σ_j b[j k + c]², the bits
// of max_abs and dot over r and b. `partial` holds block_count(n) × 3k
// doubles.
void residual(const CsrMatrix& a, std::span<const double> b, std::span<const double> x,
              std::span<double> r, std::size_t k, std::span<double> largest, std::span<double> r2,
              std::span<double> b2, std::span<double> partial, jobs::WorkerPool* pool);

// to = from (the same size), in contiguous parts (jobs::for_parts).
void copy(std::span<const double> from, std::span<double> to, jobs::WorkerPool* pool);

// out[c] = Σ_j x[j k + c] y[j k + c] for each c. `partial` holds
// block_count(n) × k doubles.
void dot(std::span<const double> x, std::span<const double> y, std::size_t n, std::size_t k,
         std::span<double> out, std::span<double> partial, jobs::WorkerPool* pool);

// out[c] = max_j |x[j k + c]|, a NaN counting as infinite.
void max_abs(std::span<const double> x, std::size_t n, std::size_t k, std::span<double> out,
             std::span<double> partial, jobs::WorkerPool* pool);

}  // namespace dfm::solver::kernels
