#include "solver/dense_kernels.hpp"

#include <algorithm>
#include <cmath>

#include "core/simd.hpp"

// The arithmetic kernels are also compiled for AVX2, and the product and the
// triangular solve for AVX-512, and picked at run time where the processor
// has them (core/simd.hpp): wider vectors, the same bits. The transpose,
// which only moves values, has an AVX-512 build alone.
#if DFM_X86_DISPATCH
#include <immintrin.h>
#endif

namespace dfm::solver::dense {

namespace {

// Rows per cache block: the A rows of one block stay in L2 while each
// strip of B columns streams past them.
constexpr std::size_t row_block = 96;

// One R×C tile of A Bᵀ: sums in ascending t, then stored or subtracted.
template <bool subtract, std::size_t R, std::size_t C>
[[gnu::always_inline]] inline void tile(std::size_t k, const double* a, std::size_t lda,
                                        const double* b, std::size_t ldb, double* c,
                                        std::size_t ldc) {
    double acc[C][R] = {};
    for (std::size_t t = 0; t < k; ++t) {
        const double* at = a + t * lda;
        const double* bt = b + t * ldb;
        for (std::size_t jj = 0; jj < C; ++jj)
            for (std::size_t ii = 0; ii < R; ++ii) acc[jj][ii] += at[ii] * bt[jj];
    }
    for (std::size_t jj = 0; jj < C; ++jj) {
        double* cj = c + jj * ldc;
        for (std::size_t ii = 0; ii < R; ++ii) {
            if constexpr (subtract) {
                cj[ii] -= acc[jj][ii];
            } else {
                cj[ii] = acc[jj][ii];
            }
        }
    }
}

// Rows [i0, ie) of C columns: R-row tiles, then the rest in halving tiles.
template <bool subtract, std::size_t R, std::size_t C>
[[gnu::always_inline]] inline void sweep_rows(std::size_t i0, std::size_t ie, std::size_t k,
                                              const double* a, std::size_t lda, const double* b,
                                              std::size_t ldb, double* c, std::size_t ldc) {
    for (; i0 + R <= ie; i0 += R) tile<subtract, R, C>(k, a + i0, lda, b, ldb, c + i0, ldc);
    if constexpr (R > 1) sweep_rows<subtract, R / 2, C>(i0, ie, k, a, lda, b, ldb, c, ldc);
}

// The sweeps of `tile`s of R rows, then halving tiles.
template <bool subtract, std::size_t R>
struct TileRows {
    static constexpr std::size_t rows = R;
    static constexpr std::size_t columns = 4;
    template <std::size_t C>
    [[gnu::always_inline]] static void sweep(std::size_t i0, std::size_t ie, std::size_t k,
                                             const double* a, std::size_t lda, const double* b,
                                             std::size_t ldb, double* c, std::size_t ldc) {
        sweep_rows<subtract, R, C>(i0, ie, k, a, lda, b, ldb, c, ldc);
    }
};

// The sweep of a strip of `tail` columns, 0 < tail ≤ C.
template <class Rows, std::size_t C>
[[gnu::always_inline]] inline void sweep_tail(std::size_t tail, std::size_t i0, std::size_t ie,
                                              std::size_t k, const double* a, std::size_t lda,
                                              const double* b, std::size_t ldb, double* c,
                                              std::size_t ldc) {
    if constexpr (C > 1) {
        if (tail < C) return sweep_tail<Rows, C - 1>(tail, i0, ie, k, a, lda, b, ldb, c, ldc);
    }
    Rows::template sweep<C>(i0, ie, k, a, lda, b, ldb, c, ldc);
}

// Blocks of rows, each swept by strips of Rows::columns columns of B and the
// rest: Rows's tiles hold as many independent sums as the vector registers
// do, which is what keeps the adders busy.
template <class Rows>
[[gnu::always_inline]] inline void product_nt(std::size_t m, std::size_t n, std::size_t k,
                                              const double* a, std::size_t lda, const double* b,
                                              std::size_t ldb, double* c, std::size_t ldc,
                                              bool lower, std::size_t row_offset) {
    constexpr std::size_t R = Rows::rows;
    constexpr std::size_t C = Rows::columns;
    const std::size_t n4 = n - n % C;
    // First row whose tile starting at column j0 reaches the needed
    // triangle: global rows i0 + row_offset + R − 1 ≥ j0.
    const auto first_row = [&](std::size_t ib, std::size_t j0) {
        if (!lower || j0 <= row_offset + ib + R - 1) return ib;
        return j0 - row_offset - (R - 1);
    };
    for (std::size_t ib = 0; ib < m; ib += row_block) {
        const std::size_t ie = std::min(m, ib + row_block);
        for (std::size_t j0 = 0; j0 < n4; j0 += C) {
            const std::size_t i0 = first_row(ib, j0);
            if (i0 < ie) Rows::template sweep<C>(i0, ie, k, a, lda, b + j0, ldb, c + j0 * ldc, ldc);
        }
        const std::size_t i0 = first_row(ib, n4);
        if (n4 == n || i0 >= ie) continue;
        sweep_tail<Rows, C - 1>(n - n4, i0, ie, k, a, lda, b + n4, ldb, c + n4 * ldc, ldc);
    }
}

#if DFM_X86_DISPATCH

// A tile of V vectors of four rows by C columns, the last vector's rows
// masked; each entry's sum as in `tile`. Written with intrinsics: GCC 12's
// own vectorization of a 2-row `tile` for AVX2 loads the next row's pair
// beside the one it uses, which past a panel's last row reads outside it.
template <bool subtract, std::size_t V, std::size_t C>
[[gnu::always_inline]] DFM_TARGET_AVX2 inline void tile_avx2(std::size_t k, const double* a,
                                                             std::size_t lda, const double* b,
                                                             std::size_t ldb, double* c,
                                                             std::size_t ldc, __m256i last) {
    __m256d acc[C][V];
    for (std::size_t jj = 0; jj < C; ++jj)
        for (std::size_t v = 0; v < V; ++v) acc[jj][v] = _mm256_setzero_pd();
    for (std::size_t t = 0; t < k; ++t) {
        const double* at = a + t * lda;
        const double* bt = b + t * ldb;
        __m256d av[V];
        for (std::size_t v = 0; v + 1 < V; ++v) av[v] = _mm256_loadu_pd(at + 4 * v);
        av[V - 1] = _mm256_maskload_pd(at + 4 * (V - 1), last);
        for (std::size_t jj = 0; jj < C; ++jj) {
            const __m256d bj = _mm256_set1_pd(bt[jj]);
            for (std::size_t v = 0; v < V; ++v)
                acc[jj][v] = _mm256_add_pd(acc[jj][v], _mm256_mul_pd(av[v], bj));
        }
    }
    const __m256i all = _mm256_set1_epi64x(-1);
    for (std::size_t jj = 0; jj < C; ++jj) {
        double* cj = c + jj * ldc;
        for (std::size_t v = 0; v < V; ++v) {
            const __m256i rows = v + 1 < V ? all : last;
            __m256d out = acc[jj][v];
            if constexpr (subtract) out = _mm256_sub_pd(_mm256_maskload_pd(cj + 4 * v, rows), out);
            _mm256_maskstore_pd(cj + 4 * v, rows, out);
        }
    }
}

// Sixteen registers of four doubles: 8-row tiles of eight accumulators,
// then one tile of the rest. A sweep is a call, not inlined: product_nt,
// which calls it, is compiled for the plain target.
template <bool subtract>
struct Avx2Rows {
    static constexpr std::size_t rows = 8;
    static constexpr std::size_t columns = 4;
    template <std::size_t C>
    DFM_TARGET_AVX2 static void sweep(std::size_t i0, std::size_t ie, std::size_t k,
                                      const double* a, std::size_t lda, const double* b,
                                      std::size_t ldb, double* c, std::size_t ldc) {
        const __m256i all = _mm256_set1_epi64x(-1);
        for (; i0 + 8 <= ie; i0 += 8)
            tile_avx2<subtract, 2, C>(k, a + i0, lda, b, ldb, c + i0, ldc, all);
        const std::size_t rest = ie - i0;
        if (rest == 0) return;
        // Lane l of the last vector is used when l < (rest − 1) % 4 + 1.
        const auto used = static_cast<long long>((rest - 1) % 4 + 1);
        const __m256i mask =
            _mm256_cmpgt_epi64(_mm256_set1_epi64x(used), _mm256_setr_epi64x(0, 1, 2, 3));
        if (rest > 4) {
            tile_avx2<subtract, 2, C>(k, a + i0, lda, b, ldb, c + i0, ldc, mask);
        } else {
            tile_avx2<subtract, 1, C>(k, a + i0, lda, b, ldb, c + i0, ldc, mask);
        }
    }
};

// A tile of V vectors of eight rows by C columns, the last vector's rows
// masked (so a block's last rows take one tile, whatever their count); each
// entry's sum as in `tile`. Written with intrinsics: GCC's own vectorization
// of a 16-row `tile` goes through permutations.
template <bool subtract, std::size_t V, std::size_t C>
[[gnu::always_inline]] DFM_TARGET_AVX512 inline void tile_avx512(std::size_t k, const double* a,
                                                                 std::size_t lda, const double* b,
                                                                 std::size_t ldb, double* c,
                                                                 std::size_t ldc, __mmask8 last) {
    __m512d acc[C][V];
    for (std::size_t jj = 0; jj < C; ++jj)
        for (std::size_t v = 0; v < V; ++v) acc[jj][v] = _mm512_setzero_pd();
    for (std::size_t t = 0; t < k; ++t) {
        const double* at = a + t * lda;
        const double* bt = b + t * ldb;
        __m512d av[V];
        for (std::size_t v = 0; v + 1 < V; ++v) av[v] = _mm512_loadu_pd(at + 8 * v);
        av[V - 1] = _mm512_maskz_loadu_pd(last, at + 8 * (V - 1));
        for (std::size_t jj = 0; jj < C; ++jj) {
            const __m512d bj = _mm512_set1_pd(bt[jj]);
            for (std::size_t v = 0; v < V; ++v)
                acc[jj][v] = _mm512_add_pd(acc[jj][v], _mm512_mul_pd(av[v], bj));
        }
    }
    for (std::size_t jj = 0; jj < C; ++jj) {
        double* cj = c + jj * ldc;
        for (std::size_t v = 0; v < V; ++v) {
            const __mmask8 rows = v + 1 < V ? __mmask8(0xff) : last;
            __m512d out = acc[jj][v];
            if constexpr (subtract)
                out = _mm512_sub_pd(_mm512_maskz_loadu_pd(rows, cj + 8 * v), out);
            _mm512_mask_storeu_pd(cj + 8 * v, rows, out);
        }
    }
}

// 16-row tiles, then one tile of the rest. A sweep is a call, not inlined:
// product_nt, which calls it, is compiled for the plain target.
template <bool subtract>
struct Avx512Rows {
    static constexpr std::size_t rows = 16;
    static constexpr std::size_t columns = 8;
    template <std::size_t C>
    DFM_TARGET_AVX512 static void sweep(std::size_t i0, std::size_t ie, std::size_t k,
                                        const double* a, std::size_t lda, const double* b,
                                        std::size_t ldb, double* c, std::size_t ldc) {
        for (; i0 + 16 <= ie; i0 += 16)
            tile_avx512<subtract, 2, C>(k, a + i0, lda, b, ldb, c + i0, ldc, 0xff);
        const std::size_t rest = ie - i0;
        if (rest == 0) return;
        const auto mask = static_cast<__mmask8>((1u << ((rest - 1) % 8 + 1)) - 1u);
        if (rest > 8) {
            tile_avx512<subtract, 2, C>(k, a + i0, lda, b, ldb, c + i0, ldc, mask);
        } else {
            tile_avx512<subtract, 1, C>(k, a + i0, lda, b, ldb, c + i0, ldc, mask);
        }
    }
};
#endif

[[gnu::always_inline]] inline std::size_t factor_diagonal_body(std::size_t w, double* p,
                                                               std::size_t ld) {
    for (std::size_t j = 0; j < w; ++j) {
        double* pj = p + j * ld;
        const double pivot = pj[j];
        if (!(pivot > 0.0) || !std::isfinite(pivot)) return j;
        const double d = std::sqrt(pivot);
        pj[j] = d;
        const double inverse = 1.0 / d;
        for (std::size_t i = j + 1; i < w; ++i) pj[i] *= inverse;
        for (std::size_t c = j + 1; c < w; ++c) {
            double* pc = p + c * ld;
            const double f = pj[c];
            for (std::size_t i = c; i < w; ++i) pc[i] -= pj[i] * f;
        }
    }
    return w;
}

[[gnu::always_inline]] inline void solve_right_lower_transposed_body(std::size_t m, std::size_t w,
                                                                     const double* l,
                                                                     std::size_t ldl, double* x,
                                                                     std::size_t ldx) {
    // Eight rows at a time, so that the rows' finished entries stay in
    // registers and L1 while each later column reads them.
    constexpr std::size_t chunk = 8;
    std::size_t i0 = 0;
    for (; i0 + chunk <= m; i0 += chunk) {
        for (std::size_t j = 0; j < w; ++j) {
            double acc[chunk];
            double* xj = x + i0 + j * ldx;
            for (std::size_t i = 0; i < chunk; ++i) acc[i] = xj[i];
            for (std::size_t t = 0; t < j; ++t) {
                const double f = l[j + t * ldl];
                const double* xt = x + i0 + t * ldx;
                for (std::size_t i = 0; i < chunk; ++i) acc[i] -= xt[i] * f;
            }
            const double inverse = 1.0 / l[j + j * ldl];
            for (std::size_t i = 0; i < chunk; ++i) xj[i] = acc[i] * inverse;
        }
    }
    for (std::size_t j = 0; j < w; ++j) {
        double* xj = x + j * ldx;
        for (std::size_t t = 0; t < j; ++t) {
            const double f = l[j + t * ldl];
            const double* xt = x + t * ldx;
            for (std::size_t i = i0; i < m; ++i) xj[i] -= xt[i] * f;
        }
        const double inverse = 1.0 / l[j + j * ldl];
        for (std::size_t i = i0; i < m; ++i) xj[i] *= inverse;
    }
}

#if DFM_X86_DISPATCH
DFM_TARGET_AVX2 std::size_t factor_diagonal_avx2(std::size_t w, double* p, std::size_t ld) {
    return factor_diagonal_body(w, p, ld);
}

DFM_TARGET_AVX2 void solve_right_lower_transposed_avx2(std::size_t m, std::size_t w,
                                                       const double* l, std::size_t ldl, double* x,
                                                       std::size_t ldx) {
    solve_right_lower_transposed_body(m, w, l, ldl, x, ldx);
}

// V vectors of eight rows of X ← X L⁻ᵀ, the last vector's rows masked; each
// entry's operations as in the body's. Each row's sum is a chain of
// dependent subtractions: eight rows at a time kept the adder waiting on
// its latency, V independent vectors keep it busy.
template <std::size_t V>
[[gnu::always_inline]] DFM_TARGET_AVX512 inline void solve_rows_avx512(
    std::size_t w, const double* l, std::size_t ldl, double* x, std::size_t ldx, __mmask8 last) {
    const auto rows = [last](std::size_t v) { return v + 1 < V ? __mmask8(0xff) : last; };
    for (std::size_t j = 0; j < w; ++j) {
        double* xj = x + j * ldx;
        __m512d acc[V];
        for (std::size_t v = 0; v < V; ++v) acc[v] = _mm512_maskz_loadu_pd(rows(v), xj + 8 * v);
        for (std::size_t t = 0; t < j; ++t) {
            const __m512d f = _mm512_set1_pd(l[j + t * ldl]);
            const double* xt = x + t * ldx;
            for (std::size_t v = 0; v < V; ++v) {
                const __m512d xv = _mm512_maskz_loadu_pd(rows(v), xt + 8 * v);
                acc[v] = _mm512_sub_pd(acc[v], _mm512_mul_pd(xv, f));
            }
        }
        const __m512d inverse = _mm512_set1_pd(1.0 / l[j + j * ldl]);
        for (std::size_t v = 0; v < V; ++v)
            _mm512_mask_storeu_pd(xj + 8 * v, rows(v), _mm512_mul_pd(acc[v], inverse));
    }
}

DFM_TARGET_AVX512 void solve_right_lower_transposed_avx512(std::size_t m, std::size_t w,
                                                           const double* l, std::size_t ldl,
                                                           double* x, std::size_t ldx) {
    constexpr std::size_t chunk = 64;
    std::size_t i0 = 0;
    for (; i0 + chunk <= m; i0 += chunk) solve_rows_avx512<8>(w, l, ldl, x + i0, ldx, 0xff);
    const std::size_t rest = m - i0;
    if (rest == 0) return;
    const auto last = static_cast<__mmask8>((1u << ((rest - 1) % 8 + 1)) - 1u);
    switch ((rest + 7) / 8) {
        case 1: solve_rows_avx512<1>(w, l, ldl, x + i0, ldx, last); break;
        case 2: solve_rows_avx512<2>(w, l, ldl, x + i0, ldx, last); break;
        case 3: solve_rows_avx512<3>(w, l, ldl, x + i0, ldx, last); break;
        case 4: solve_rows_avx512<4>(w, l, ldl, x + i0, ldx, last); break;
        case 5: solve_rows_avx512<5>(w, l, ldl, x + i0, ldx, last); break;
        case 6: solve_rows_avx512<6>(w, l, ldl, x + i0, ldx, last); break;
        case 7: solve_rows_avx512<7>(w, l, ldl, x + i0, ldx, last); break;
        default: solve_rows_avx512<8>(w, l, ldl, x + i0, ldx, last); break;
    }
}

// The masked forms, all lanes set: GCC 12's unmasked ones pass an
// uninitialised source that -Wmaybe-uninitialized reports.
template <int control>
[[gnu::always_inline]] DFM_TARGET_AVX512 inline __m512d lanes_shuffle(__m512d a, __m512d b) {
    return _mm512_mask_shuffle_f64x2(a, 0xff, a, b, control);
}

// Eight rows by up to eight entries at a time, loaded row by row and
// transposed in registers (the processor's gathers are slower); the last
// rows and entries masked.
DFM_TARGET_AVX512 void transpose_avx512(std::size_t count, std::size_t w, const double* rows,
                                        std::size_t stride, double* out, std::size_t out_stride) {
    for (std::size_t i = 0; i < count; i += 8) {
        const std::size_t height = std::min<std::size_t>(8, count - i);
        const auto stored = static_cast<__mmask8>((1u << height) - 1u);
        for (std::size_t t0 = 0; t0 < w; t0 += 8) {
            const std::size_t width = std::min<std::size_t>(8, w - t0);
            const auto lanes = static_cast<__mmask8>((1u << width) - 1u);
            const double* r = rows + i * stride + t0;
            __m512d x[8];
            for (std::size_t q = 0; q < 8; ++q)
                x[q] =
                    q < height ? _mm512_maskz_loadu_pd(lanes, r + q * stride) : _mm512_setzero_pd();
            // Pairs of rows interleaved, then pairs of pairs, then the halves.
            __m512d y[8];
            for (std::size_t q = 0; q < 8; q += 2) {
                y[q] = _mm512_mask_unpacklo_pd(x[q], 0xff, x[q], x[q + 1]);
                y[q + 1] = _mm512_mask_unpackhi_pd(x[q], 0xff, x[q], x[q + 1]);
            }
            __m512d z[8];
            for (std::size_t h = 0; h < 8; h += 4) {
                z[h] = lanes_shuffle<0x88>(y[h], y[h + 2]);
                z[h + 1] = lanes_shuffle<0xdd>(y[h], y[h + 2]);
                z[h + 2] = lanes_shuffle<0x88>(y[h + 1], y[h + 3]);
                z[h + 3] = lanes_shuffle<0xdd>(y[h + 1], y[h + 3]);
            }
            // z[0..3] hold rows 0-3 of entries {0, 4}, {2, 6}, {1, 5}, {3, 7};
            // z[4..7] the same of rows 4-7.
            constexpr std::size_t source[4] = {0, 2, 1, 3};
            for (std::size_t c = 0; c < 4; ++c) {
                const std::size_t q = source[c];
                if (c < width)
                    _mm512_mask_storeu_pd(out + (t0 + c) * out_stride + i, stored,
                                          lanes_shuffle<0x88>(z[q], z[q + 4]));
                if (c + 4 < width)
                    _mm512_mask_storeu_pd(out + (t0 + c + 4) * out_stride + i, stored,
                                          lanes_shuffle<0xdd>(z[q], z[q + 4]));
            }
        }
    }
}
#endif

}  // namespace

void transpose(simd::Set set, std::size_t count, std::size_t w, const double* rows,
               std::size_t stride, double* out, std::size_t out_stride) {
#if DFM_X86_DISPATCH
    if (set == simd::Set::avx512) return transpose_avx512(count, w, rows, stride, out, out_stride);
#endif
    for (std::size_t i = 0; i < count; ++i)
        for (std::size_t t = 0; t < w; ++t) out[t * out_stride + i] = rows[i * stride + t];
}

void transpose(std::size_t count, std::size_t w, const double* rows, std::size_t stride,
               double* out, std::size_t out_stride) {
    transpose(simd::widest(), count, w, rows, stride, out, out_stride);
}

void multiply_nt(simd::Set set, std::size_t m, std::size_t n, std::size_t k, const double* a,
                 std::size_t lda, const double* b, std::size_t ldb, double* c, std::size_t ldc,
                 bool subtract, bool lower, std::size_t row_offset) {
#if DFM_X86_DISPATCH
    if (set == simd::Set::avx512) {
        if (subtract) {
            product_nt<Avx512Rows<true>>(m, n, k, a, lda, b, ldb, c, ldc, lower, row_offset);
        } else {
            product_nt<Avx512Rows<false>>(m, n, k, a, lda, b, ldb, c, ldc, lower, row_offset);
        }
        return;
    }
    if (set == simd::Set::avx2) {
        if (subtract) {
            product_nt<Avx2Rows<true>>(m, n, k, a, lda, b, ldb, c, ldc, lower, row_offset);
        } else {
            product_nt<Avx2Rows<false>>(m, n, k, a, lda, b, ldb, c, ldc, lower, row_offset);
        }
        return;
    }
#endif
    if (subtract) {
        product_nt<TileRows<true, 4>>(m, n, k, a, lda, b, ldb, c, ldc, lower, row_offset);
    } else {
        product_nt<TileRows<false, 4>>(m, n, k, a, lda, b, ldb, c, ldc, lower, row_offset);
    }
}

void multiply_nt(std::size_t m, std::size_t n, std::size_t k, const double* a, std::size_t lda,
                 const double* b, std::size_t ldb, double* c, std::size_t ldc, bool subtract,
                 bool lower, std::size_t row_offset) {
    multiply_nt(simd::widest(), m, n, k, a, lda, b, ldb, c, ldc, subtract, lower, row_offset);
}

std::size_t factor_diagonal(std::size_t w, double* p, std::size_t ld) {
#if DFM_X86_DISPATCH
    if (simd::available(simd::Set::avx2)) return factor_diagonal_avx2(w, p, ld);
#endif
    return factor_diagonal_body(w, p, ld);
}

void solve_right_lower_transposed(simd::Set set, std::size_t m, std::size_t w, const double* l,
                                  std::size_t ldl, double* x, std::size_t ldx) {
#if DFM_X86_DISPATCH
    if (set == simd::Set::avx512) return solve_right_lower_transposed_avx512(m, w, l, ldl, x, ldx);
    if (set == simd::Set::avx2) return solve_right_lower_transposed_avx2(m, w, l, ldl, x, ldx);
#endif
    solve_right_lower_transposed_body(m, w, l, ldl, x, ldx);
}

void solve_right_lower_transposed(std::size_t m, std::size_t w, const double* l, std::size_t ldl,
                                  double* x, std::size_t ldx) {
    solve_right_lower_transposed(simd::widest(), m, w, l, ldl, x, ldx);
}

std::size_t factor_panel(std::size_t m, std::size_t w, double* p, std::size_t ld) {
    for (std::size_t kb = 0; kb < w; kb += panel_block) {
        const std::size_t ke = std::min(w, kb + panel_block);
        double* diagonal = p + kb + kb * ld;
        const std::size_t done = factor_diagonal(ke - kb, diagonal, ld);
        if (done < ke - kb) return kb + done;
        solve_right_lower_transposed(m - ke, ke - kb, diagonal, ld, p + ke + kb * ld, ld);
        if (ke < w)
            multiply_nt(m - ke, w - ke, ke - kb, p + ke + kb * ld, ld, p + ke + kb * ld, ld,
                        p + ke + ke * ld, ld, true, true);
    }
    return w;
}

}  // namespace dfm::solver::dense
