#pragma once

#include <cstddef>
#include <cstdint>

#include "core/simd.hpp"

// The triangular solves' work on one supernode, for k interleaved vectors
// (y[i k + c] is entry i of vector c). The supernode's m×w block L is laid
// out for the solves (SparseCholesky): its w×w diagonal block column-major
// (leading dimension w), L below the diagonal and Lᵀ above it, then the
// h = m − w rows below, which are the factor's rows `rows`, row by row (w
// entries each), so that both solves stream L in order. Its own w entries
// of y start at `own`; `y` is the whole vector.
//
// Each kernel moves the supernode's own entries into `scratch` (one
// contiguous column per vector) so that the diagonal block's work runs on
// contiguous data, reads L once for all k vectors, and touches the rows
// below through `rows` directly. Every entry sees the same operations in the
// same order for every k, so the bits do not depend on k or on how the
// supernodes are shared between threads.
namespace dfm::solver::supernode {

// Doubles of scratch the kernels need for a supernode of m rows: the own
// entries by vector, and the backward sums' two partial sums.
constexpr std::size_t scratch_size(std::size_t m, std::size_t k) {
    return 3 * m * k;
}

// Forward, L y = y: for each column j ascending, y_j /= L(j, j), then every
// later row i of the diagonal block subtracts L(i, j) y_j, the terms one by
// one in column order; then each of the first `push` rows below subtracts
// its row's product with the own entries, that sum taken as dot4: four
// partial sums over j (j mod 4) combined as (s0 + s1) + (s2 + s3).
void forward(std::size_t m, std::size_t w, std::size_t push, std::size_t k, const double* l,
             const std::uint32_t* rows, double* own, double* y, double* scratch);

// Backward, Lᵀ y = y: each own entry j first subtracts Σ_t L(w + t, j)
// y_rows[t] over the rows below, that sum accumulated row by row (so that L
// streams in order) in two partial sums, over even and over odd t, added
// together; then, for i descending, y_i is divided by L(i, i) and every
// earlier own entry j subtracts L(i, j) y_i. The `ahead_bytes` from `ahead`
// (the next supernode's values, in the backward solve) are fetched into
// the cache while it works, a few lines with each row below and the rest
// after those rows (none: 0 bytes); they change nothing else.
void backward(std::size_t m, std::size_t w, std::size_t k, const double* l,
              const std::uint32_t* rows, double* own, const double* y, double* scratch,
              const char* ahead, std::size_t ahead_bytes);

// forward and backward on the given instruction set, which must be
// available (core/simd.hpp); the calls above run the widest the processor
// has. Every set gives the same bits (the tests compare them).
void forward(simd::Set set, std::size_t m, std::size_t w, std::size_t push, std::size_t k,
             const double* l, const std::uint32_t* rows, double* own, double* y, double* scratch);
void backward(simd::Set set, std::size_t m, std::size_t w, std::size_t k, const double* l,
              const std::uint32_t* rows, double* own, const double* y, double* scratch,
              const char* ahead, std::size_t ahead_bytes);

// Forward's push of h rows below a supernode of w columns, made later and
// elsewhere: each row's product with the supernode's own entries `own`
// (final), subtracted from its row of y, the bits of forward's push. The
// rows start at `below` (w entries each) and go to rows `rows`; `scratch`
// holds w k doubles. With the supernodes split between threads, the one
// above them pulls what the rows of another thread's supernode push into
// it.
void push(std::size_t h, std::size_t w, std::size_t k, const double* below,
          const std::uint32_t* rows, const double* own, double* y, double* scratch);
void push(simd::Set set, std::size_t h, std::size_t w, std::size_t k, const double* below,
          const std::uint32_t* rows, const double* own, double* y, double* scratch);

}  // namespace dfm::solver::supernode
