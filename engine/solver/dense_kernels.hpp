#pragma once

#include <cstddef>

#include "core/simd.hpp"

// Dense kernels on column-major blocks (entry (i, j) of a block with leading
// dimension ld at [i + j * ld]) for the supernodal Cholesky factorization.
//
// Every entry is computed by the same sequence of operations whatever the
// block's size or where a caller splits it into row ranges (one per thread),
// so a split computation gives the same bits as an unsplit one.
namespace dfm::solver::dense {

// C = A Bᵀ, with A m×k and B n×k, or C −= A Bᵀ when `subtract` is set. With
// `lower`, row i of the block is row i + row_offset of the whole and only the
// entries with i + row_offset ≥ j are needed: whole tiles above that line
// are skipped (a tile that straddles it is computed in full).
void multiply_nt(std::size_t m, std::size_t n, std::size_t k, const double* a, std::size_t lda,
                 const double* b, std::size_t ldb, double* c, std::size_t ldc, bool subtract,
                 bool lower, std::size_t row_offset = 0);

// multiply_nt on the given instruction set (core/simd.hpp), which must be
// available; the call without one runs the widest the processor has. Each
// set gives the same bits (the tests compare them).
void multiply_nt(simd::Set set, std::size_t m, std::size_t n, std::size_t k, const double* a,
                 std::size_t lda, const double* b, std::size_t ldb, double* c, std::size_t ldc,
                 bool subtract, bool lower, std::size_t row_offset = 0);

// Factors the w×w symmetric block P (lower triangle read) in place,
// P = L Lᵀ. Returns w on success, else the column whose pivot was not
// positive (or not finite).
std::size_t factor_diagonal(std::size_t w, double* p, std::size_t ld);

// X ← X L⁻ᵀ for the m×w block X, L the factored w×w diagonal block.
void solve_right_lower_transposed(std::size_t m, std::size_t w, const double* l, std::size_t ldl,
                                  double* x, std::size_t ldx);
// The same on the given set, which must be available; each set gives the
// same bits.
void solve_right_lower_transposed(simd::Set set, std::size_t m, std::size_t w, const double* l,
                                  std::size_t ldl, double* x, std::size_t ldx);

// Factors the m×w panel P = [P11; P21] in place, P11 being w×w symmetric:
// P11 = L11 L11ᵀ, P21 ← P21 L11⁻ᵀ, in blocks of `panel_block` columns (the
// diagonal block, the rows below it, then the update of the columns to its
// right). Returns w on success, else the failing panel column.
std::size_t factor_panel(std::size_t m, std::size_t w, double* p, std::size_t ld);

// The column blocking factor_panel uses; a caller that splits the panel's
// row work between threads follows the same blocks.
inline constexpr std::size_t panel_block = 32;

// The transpose of `count` rows of `w` entries, row r at rows + r stride:
// entry t of row r goes to out[t out_stride + r]. It moves the factor's
// blocks between the factorization's layout (by column) and the solves'
// (the rows below the diagonal block by row); nothing else of `out` is
// written.
void transpose(std::size_t count, std::size_t w, const double* rows, std::size_t stride,
               double* out, std::size_t out_stride);

// transpose on the given set, which must be available.
void transpose(simd::Set set, std::size_t count, std::size_t w, const double* rows,
               std::size_t stride, double* out, std::size_t out_stride);

}  // namespace dfm::solver::dense
