#include "solver/dense_kernels.hpp"

#include <algorithm>
#include <cmath>

// Every kernel is also compiled for AVX2 and picked at run time where the
// processor has it: wider vectors, the same multiplications and additions in
// the same order (no fused multiply–add), so the same bits. The choice is an
// ordinary branch rather than an ifunc, which sanitizers' start-up code does
// not survive.
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define DFM_HAS_AVX2_KERNELS 1
#define DFM_TARGET_AVX2 __attribute__((target("avx2")))
#else
#define DFM_HAS_AVX2_KERNELS 0
#endif

namespace dfm::solver::dense {

namespace {

// Rows per cache block: the A rows of one block stay in L2 while every
// 4-column tile of B streams past them.
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

// Tiles of R rows: as many independent sums as the vector registers hold,
// which is what keeps the adders busy.
template <bool subtract, std::size_t R>
[[gnu::always_inline]] inline void product_nt(std::size_t m, std::size_t n, std::size_t k,
                                              const double* a, std::size_t lda, const double* b,
                                              std::size_t ldb, double* c, std::size_t ldc,
                                              bool lower, std::size_t row_offset) {
    const std::size_t n4 = n - n % 4;
    // First row whose tile starting at column j0 reaches the needed
    // triangle: global rows i0 + row_offset + R − 1 ≥ j0.
    const auto first_row = [&](std::size_t ib, std::size_t j0) {
        if (!lower || j0 <= row_offset + ib + R - 1) return ib;
        return j0 - row_offset - (R - 1);
    };
    for (std::size_t ib = 0; ib < m; ib += row_block) {
        const std::size_t ie = std::min(m, ib + row_block);
        for (std::size_t j0 = 0; j0 < n4; j0 += 4) {
            const std::size_t i0 = first_row(ib, j0);
            if (i0 < ie)
                sweep_rows<subtract, R, 4>(i0, ie, k, a, lda, b + j0, ldb, c + j0 * ldc, ldc);
        }
        const std::size_t i0 = first_row(ib, n4);
        if (n4 == n || i0 >= ie) continue;
        const double* bj = b + n4;
        double* cj = c + n4 * ldc;
        switch (n - n4) {
            case 1: sweep_rows<subtract, R, 1>(i0, ie, k, a, lda, bj, ldb, cj, ldc); break;
            case 2: sweep_rows<subtract, R, 2>(i0, ie, k, a, lda, bj, ldb, cj, ldc); break;
            default: sweep_rows<subtract, R, 3>(i0, ie, k, a, lda, bj, ldb, cj, ldc); break;
        }
    }
}

#if DFM_HAS_AVX2_KERNELS
bool avx2_available() {
    static const bool available = [] {
        __builtin_cpu_init();
        return __builtin_cpu_supports("avx2") != 0;
    }();
    return available;
}

// Sixteen registers of four doubles: eight accumulators of an 8×4 tile.
template <bool subtract>
DFM_TARGET_AVX2 void product_nt_avx2(std::size_t m, std::size_t n, std::size_t k, const double* a,
                                     std::size_t lda, const double* b, std::size_t ldb, double* c,
                                     std::size_t ldc, bool lower, std::size_t row_offset) {
    product_nt<subtract, 8>(m, n, k, a, lda, b, ldb, c, ldc, lower, row_offset);
}
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

#if DFM_HAS_AVX2_KERNELS
DFM_TARGET_AVX2 std::size_t factor_diagonal_avx2(std::size_t w, double* p, std::size_t ld) {
    return factor_diagonal_body(w, p, ld);
}

DFM_TARGET_AVX2 void solve_right_lower_transposed_avx2(std::size_t m, std::size_t w,
                                                       const double* l, std::size_t ldl, double* x,
                                                       std::size_t ldx) {
    solve_right_lower_transposed_body(m, w, l, ldl, x, ldx);
}

#endif

}  // namespace

void multiply_nt(std::size_t m, std::size_t n, std::size_t k, const double* a, std::size_t lda,
                 const double* b, std::size_t ldb, double* c, std::size_t ldc, bool subtract,
                 bool lower, std::size_t row_offset) {
#if DFM_HAS_AVX2_KERNELS
    if (avx2_available()) {
        if (subtract) {
            product_nt_avx2<true>(m, n, k, a, lda, b, ldb, c, ldc, lower, row_offset);
        } else {
            product_nt_avx2<false>(m, n, k, a, lda, b, ldb, c, ldc, lower, row_offset);
        }
        return;
    }
#endif
    if (subtract) {
        product_nt<true, 4>(m, n, k, a, lda, b, ldb, c, ldc, lower, row_offset);
    } else {
        product_nt<false, 4>(m, n, k, a, lda, b, ldb, c, ldc, lower, row_offset);
    }
}

std::size_t factor_diagonal(std::size_t w, double* p, std::size_t ld) {
#if DFM_HAS_AVX2_KERNELS
    if (avx2_available()) return factor_diagonal_avx2(w, p, ld);
#endif
    return factor_diagonal_body(w, p, ld);
}

void solve_right_lower_transposed(std::size_t m, std::size_t w, const double* l, std::size_t ldl,
                                  double* x, std::size_t ldx) {
#if DFM_HAS_AVX2_KERNELS
    if (avx2_available()) return solve_right_lower_transposed_avx2(m, w, l, ldl, x, ldx);
#endif
    solve_right_lower_transposed_body(m, w, l, ldl, x, ldx);
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
