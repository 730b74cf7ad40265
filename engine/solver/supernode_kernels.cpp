#include "solver/supernode_kernels.hpp"

#include <cstring>

// Compiled also for AVX2 and picked at run time, as the dense kernels are:
// the same multiplications and additions in the same order, so the same
// bits on either path.
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define DFM_HAS_AVX2_KERNELS 1
#define DFM_TARGET_AVX2 __attribute__((target("avx2")))
#else
#define DFM_HAS_AVX2_KERNELS 0
#endif

namespace dfm::solver::supernode {

namespace {

// Four doubles: one AVX2 register where compiled for it, two SSE registers
// otherwise. Element-wise products and sums round as scalar ones do.
using Lanes = double __attribute__((vector_size(32)));

// Lanes pass by reference: by value they would change the calling
// convention between the AVX2 and the plain builds.
[[gnu::always_inline]] inline void load(Lanes& v, const double* p) {
    std::memcpy(&v, p, sizeof v);
}

// s0 + … over t of a[t] b[t], t < n, in four partial sums (t mod 4)
// combined as (s0 + s1) + (s2 + s3).
[[gnu::always_inline]] inline double dot4(std::size_t n, const double* a, const double* b) {
    const std::size_t n4 = n - n % 4;
    Lanes sum = {0.0, 0.0, 0.0, 0.0};
    for (std::size_t t = 0; t < n4; t += 4) {
        Lanes av, bv;
        load(av, a + t);
        load(bv, b + t);
        sum += av * bv;
    }
    for (std::size_t t = n4; t < n; ++t) sum[t - n4] += a[t] * b[t];
    return (sum[0] + sum[1]) + (sum[2] + sum[3]);
}

// The own entries, interleaved, into one column per vector, and back.
template <std::size_t K>
[[gnu::always_inline]] inline void split_columns(std::size_t w, std::size_t k, const double* own,
                                                 double* s) {
    const std::size_t kk = K != 0 ? K : k;
    for (std::size_t j = 0; j < w; ++j)
        for (std::size_t c = 0; c < kk; ++c) s[c * w + j] = own[j * kk + c];
}

template <std::size_t K>
[[gnu::always_inline]] inline void join_columns(std::size_t w, std::size_t k, const double* s,
                                                double* own) {
    const std::size_t kk = K != 0 ? K : k;
    for (std::size_t j = 0; j < w; ++j)
        for (std::size_t c = 0; c < kk; ++c) own[j * kk + c] = s[c * w + j];
}

// GCC 12 takes the registers built from gathered rows below for
// uninitialized (a false positive on vector-typed arrays in AVX2 clones).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

// y[rows[t] K + c] −= Σ_j l[t + j ld] s[c w + j], term by term, j ascending;
// eight rows at a time, two registers per vector, so that each column of L
// is read once for all K vectors.
template <std::size_t K>
[[gnu::always_inline]] inline void push_rows(std::size_t h, std::size_t w, const double* l,
                                             std::size_t ld, const double* s,
                                             const std::uint32_t* rows, double* y) {
    constexpr std::size_t block = 8;
    std::size_t t0 = 0;
    for (; t0 + block <= h; t0 += block) {
        const std::uint32_t* r = rows + t0;
        Lanes top[K], bottom[K];
        for (std::size_t c = 0; c < K; ++c) {
            top[c] = Lanes{y[r[0] * K + c], y[r[1] * K + c], y[r[2] * K + c], y[r[3] * K + c]};
            bottom[c] = Lanes{y[r[4] * K + c], y[r[5] * K + c], y[r[6] * K + c], y[r[7] * K + c]};
        }
        for (std::size_t j = 0; j < w; ++j) {
            const double* lj = l + t0 + j * ld;
            Lanes l0, l1;
            load(l0, lj);
            load(l1, lj + 4);
            for (std::size_t c = 0; c < K; ++c) {
                const double f = s[c * w + j];
                top[c] -= l0 * f;
                bottom[c] -= l1 * f;
            }
        }
        for (std::size_t c = 0; c < K; ++c)
            for (std::size_t lane = 0; lane < 4; ++lane) {
                y[r[lane] * K + c] = top[c][lane];
                y[r[lane + 4] * K + c] = bottom[c][lane];
            }
    }
    for (std::size_t t = t0; t < h; ++t) {
        double* yt = y + static_cast<std::size_t>(rows[t]) * K;
        double acc[K];
        for (std::size_t c = 0; c < K; ++c) acc[c] = yt[c];
        for (std::size_t j = 0; j < w; ++j) {
            const double lt = l[t + j * ld];
            for (std::size_t c = 0; c < K; ++c) acc[c] -= lt * s[c * w + j];
        }
        for (std::size_t c = 0; c < K; ++c) yt[c] = acc[c];
    }
}

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

// K = 0: any k, one vector at a time.
void push_rows_any(std::size_t h, std::size_t w, std::size_t k, const double* l, std::size_t ld,
                   const double* s, const std::uint32_t* rows, double* y) {
    for (std::size_t t = 0; t < h; ++t) {
        double* yt = y + static_cast<std::size_t>(rows[t]) * k;
        for (std::size_t c = 0; c < k; ++c) {
            double acc = yt[c];
            for (std::size_t j = 0; j < w; ++j) acc -= l[t + j * ld] * s[c * w + j];
            yt[c] = acc;
        }
    }
}

// s[c w + j] −= Σ_t l[t + j ld] below[c h + t] for every own column j, the
// sum as dot4 makes it; four columns at a time, so that each load of the
// rows' values serves four columns and each column is read once for all K.
template <std::size_t K>
[[gnu::always_inline]] inline void pull_rows(std::size_t h, std::size_t w, const double* l,
                                             std::size_t ld, const double* below, double* s) {
    const std::size_t h4 = h - h % 4;
    constexpr std::size_t columns = 4;
    std::size_t j0 = 0;
    for (; j0 + columns <= w; j0 += columns) {
        Lanes sum[columns][K] = {};
        for (std::size_t t = 0; t < h4; t += 4) {
            Lanes yv[K];
            for (std::size_t c = 0; c < K; ++c) load(yv[c], below + c * h + t);
            for (std::size_t jj = 0; jj < columns; ++jj) {
                Lanes lv;
                load(lv, l + t + (j0 + jj) * ld);
                for (std::size_t c = 0; c < K; ++c) sum[jj][c] += lv * yv[c];
            }
        }
        for (std::size_t jj = 0; jj < columns; ++jj) {
            const double* lj = l + (j0 + jj) * ld;
            for (std::size_t c = 0; c < K; ++c) {
                Lanes total = sum[jj][c];
                for (std::size_t t = h4; t < h; ++t) total[t - h4] += lj[t] * below[c * h + t];
                s[c * w + j0 + jj] -= (total[0] + total[1]) + (total[2] + total[3]);
            }
        }
    }
    for (; j0 < w; ++j0)
        for (std::size_t c = 0; c < K; ++c) s[c * w + j0] -= dot4(h, l + j0 * ld, below + c * h);
}

template <std::size_t K>
[[gnu::always_inline]] inline void forward_body(std::size_t m, std::size_t w, std::size_t push,
                                                std::size_t k, const double* l,
                                                const std::uint32_t* rows, double* own, double* y,
                                                double* scratch) {
    const std::size_t kk = K != 0 ? K : k;
    double* s = scratch;
    split_columns<K>(w, kk, own, s);
    for (std::size_t j = 0; j < w; ++j) {
        const double* lj = l + j * m;
        for (std::size_t c = 0; c < kk; ++c) {
            double* sc = s + c * w;
            const double f = sc[j] /= lj[j];
            for (std::size_t i = j + 1; i < w; ++i) sc[i] -= lj[i] * f;
        }
    }
    join_columns<K>(w, kk, s, own);
    if (push == 0) return;
    if constexpr (K != 0) {
        push_rows<K>(push, w, l + w, m, s, rows, y);
    } else {
        push_rows_any(push, w, kk, l + w, m, s, rows, y);
    }
}

template <std::size_t K>
[[gnu::always_inline]] inline void backward_body(std::size_t m, std::size_t w, std::size_t k,
                                                 const double* l, const std::uint32_t* rows,
                                                 double* own, const double* y, double* scratch) {
    const std::size_t kk = K != 0 ? K : k;
    const std::size_t h = m - w;
    double* s = scratch;
    double* below = scratch + w * kk;
    split_columns<K>(w, kk, own, s);
    if (h > 0) {
        for (std::size_t t = 0; t < h; ++t) {
            const double* yt = y + static_cast<std::size_t>(rows[t]) * kk;
            for (std::size_t c = 0; c < kk; ++c) below[c * h + t] = yt[c];
        }
        if constexpr (K != 0) {
            pull_rows<K>(h, w, l + w, m, below, s);
        } else {
            for (std::size_t j = 0; j < w; ++j)
                for (std::size_t c = 0; c < kk; ++c)
                    s[c * w + j] -= dot4(h, l + w + j * m, below + c * h);
        }
    }
    // The K chains of subtractions side by side, so that their latencies
    // overlap.
    for (std::size_t j = w; j-- > 0;) {
        const double* lj = l + j * m;
        if constexpr (K != 0) {
            double v[K];
            for (std::size_t c = 0; c < K; ++c) v[c] = s[c * w + j];
            for (std::size_t i = j + 1; i < w; ++i) {
                const double f = lj[i];
                for (std::size_t c = 0; c < K; ++c) v[c] -= f * s[c * w + i];
            }
            for (std::size_t c = 0; c < K; ++c) s[c * w + j] = v[c] / lj[j];
        } else {
            for (std::size_t c = 0; c < kk; ++c) {
                double* sc = s + c * w;
                double v = sc[j];
                for (std::size_t i = j + 1; i < w; ++i) v -= lj[i] * sc[i];
                sc[j] = v / lj[j];
            }
        }
    }
    join_columns<K>(w, kk, s, own);
}

#if DFM_HAS_AVX2_KERNELS
bool avx2_available() {
    static const bool available = [] {
        __builtin_cpu_init();
        return __builtin_cpu_supports("avx2") != 0;
    }();
    return available;
}

template <std::size_t K>
DFM_TARGET_AVX2 void forward_avx2(std::size_t m, std::size_t w, std::size_t push, std::size_t k,
                                  const double* l, const std::uint32_t* rows, double* own,
                                  double* y, double* scratch) {
    forward_body<K>(m, w, push, k, l, rows, own, y, scratch);
}

template <std::size_t K>
DFM_TARGET_AVX2 void backward_avx2(std::size_t m, std::size_t w, std::size_t k, const double* l,
                                   const std::uint32_t* rows, double* own, const double* y,
                                   double* scratch) {
    backward_body<K>(m, w, k, l, rows, own, y, scratch);
}
#endif

template <std::size_t K>
void forward_for(std::size_t m, std::size_t w, std::size_t push, std::size_t k, const double* l,
                 const std::uint32_t* rows, double* own, double* y, double* scratch) {
#if DFM_HAS_AVX2_KERNELS
    if (avx2_available()) return forward_avx2<K>(m, w, push, k, l, rows, own, y, scratch);
#endif
    forward_body<K>(m, w, push, k, l, rows, own, y, scratch);
}

template <std::size_t K>
void backward_for(std::size_t m, std::size_t w, std::size_t k, const double* l,
                  const std::uint32_t* rows, double* own, const double* y, double* scratch) {
#if DFM_HAS_AVX2_KERNELS
    if (avx2_available()) return backward_avx2<K>(m, w, k, l, rows, own, y, scratch);
#endif
    backward_body<K>(m, w, k, l, rows, own, y, scratch);
}

}  // namespace

void forward(std::size_t m, std::size_t w, std::size_t push, std::size_t k, const double* l,
             const std::uint32_t* rows, double* own, double* y, double* scratch) {
    switch (k) {
        case 1: return forward_for<1>(m, w, push, k, l, rows, own, y, scratch);
        case 2: return forward_for<2>(m, w, push, k, l, rows, own, y, scratch);
        case 3: return forward_for<3>(m, w, push, k, l, rows, own, y, scratch);
        default: return forward_for<0>(m, w, push, k, l, rows, own, y, scratch);
    }
}

void backward(std::size_t m, std::size_t w, std::size_t k, const double* l,
              const std::uint32_t* rows, double* own, const double* y, double* scratch) {
    switch (k) {
        case 1: return backward_for<1>(m, w, k, l, rows, own, y, scratch);
        case 2: return backward_for<2>(m, w, k, l, rows, own, y, scratch);
        case 3: return backward_for<3>(m, w, k, l, rows, own, y, scratch);
        default: return backward_for<0>(m, w, k, l, rows, own, y, scratch);
    }
}

}  // namespace dfm::solver::supernode
