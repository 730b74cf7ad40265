#include "solver/supernode_kernels.hpp"

#include <algorithm>
#include <cstring>

#include "core/simd.hpp"

// Compiled also for AVX2 and for AVX-512 (whose 32 registers hold more sums,
// and eight doubles each where the backward solve pulls rows of 17 to 32
// columns) and picked at run time, as the dense kernels are (core/simd.hpp):
// the same bits on every path.

namespace dfm::solver::supernode {

namespace {

using simd::Doubles4;
using simd::Doubles8;

// Vectors pass by reference: by value they would change the calling
// convention between the AVX2 and the plain builds.
[[gnu::always_inline]] inline void load(Doubles4& v, const double* p) {
    std::memcpy(&v, p, sizeof v);
}

// s0 + … over t of a[t] b[t], t < n, in four partial sums (t mod 4)
// combined as (s0 + s1) + (s2 + s3).
[[gnu::always_inline]] inline double dot4(std::size_t n, const double* a, const double* b) {
    const std::size_t n4 = n - n % 4;
    Doubles4 sum = {0.0, 0.0, 0.0, 0.0};
    for (std::size_t t = 0; t < n4; t += 4) {
        Doubles4 av, bv;
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

// The products a[q] b[q] of the last `count` (1 to 3) terms in lanes q,
// −0 in the others: added to a sum, −0 changes no lane, not even a −0.
// Each lane is named by a constant, so that the sums stay in registers
// (indexed at run time, they went through the stack, and the forward
// solve waited on those stores).
[[gnu::always_inline]] inline void tail_products(std::size_t count, const double* a,
                                                 const double* b, Doubles4& out) {
    switch (count) {
        case 1: out = Doubles4{a[0] * b[0], -0.0, -0.0, -0.0}; break;
        case 2: out = Doubles4{a[0] * b[0], a[1] * b[1], -0.0, -0.0}; break;
        default: out = Doubles4{a[0] * b[0], a[1] * b[1], a[2] * b[2], -0.0}; break;
    }
}

// out[c] = dot4(n, a, s + c w) for every vector c, each row of L read once
// for all K.
template <std::size_t K>
[[gnu::always_inline]] inline void dots(std::size_t n, const double* a, const double* s,
                                        std::size_t w, double* out) {
    const std::size_t n4 = n - n % 4;
    Doubles4 sum[K];
    for (std::size_t c = 0; c < K; ++c) sum[c] = Doubles4{0.0, 0.0, 0.0, 0.0};
    for (std::size_t t = 0; t < n4; t += 4) {
        Doubles4 av;
        load(av, a + t);
        for (std::size_t c = 0; c < K; ++c) {
            Doubles4 bv;
            load(bv, s + c * w + t);
            sum[c] += av * bv;
        }
    }
    if (n4 < n) {
        for (std::size_t c = 0; c < K; ++c) {
            Doubles4 tail;
            tail_products(n - n4, a + n4, s + c * w + n4, tail);
            sum[c] += tail;
        }
    }
    for (std::size_t c = 0; c < K; ++c) out[c] = (sum[c][0] + sum[c][1]) + (sum[c][2] + sum[c][3]);
}

// y[rows[t] k + c] −= dot4(w, row t of L below, s + c w), t < h: row by
// row, so that L streams in order.
template <std::size_t K>
[[gnu::always_inline]] inline void push_rows(std::size_t h, std::size_t w, std::size_t k,
                                             const double* below, const double* s,
                                             const std::uint32_t* rows, double* y) {
    for (std::size_t t = 0; t < h; ++t) {
        double* yt = y + static_cast<std::size_t>(rows[t]) * (K != 0 ? K : k);
        if constexpr (K != 0) {
            double d[K];
            dots<K>(w, below + t * w, s, w, d);
            for (std::size_t c = 0; c < K; ++c) yt[c] -= d[c];
        } else {
            for (std::size_t c = 0; c < k; ++c) yt[c] -= dot4(w, below + t * w, s + c * w);
        }
    }
}

// The first n (1 to 4) of `from`, lanes past them zero.
[[gnu::always_inline]] inline void load_first(std::size_t n, const double* from, Doubles4& v) {
    switch (n) {
        case 1: v = Doubles4{from[0], 0.0, 0.0, 0.0}; break;
        case 2: v = Doubles4{from[0], from[1], 0.0, 0.0}; break;
        case 3: v = Doubles4{from[0], from[1], from[2], 0.0}; break;
        default: load(v, from); break;
    }
}

[[gnu::always_inline]] inline void load_first(std::size_t n, const double* from, Doubles8& v) {
    Doubles4 low, high = {0.0, 0.0, 0.0, 0.0};
    load_first(std::min<std::size_t>(n, 4), from, low);
    if (n > 4) load_first(n - 4, from + 4, high);
    v = __builtin_shufflevector(low, high, 0, 1, 2, 3, 4, 5, 6, 7);
}

// The row's entries from column L q on, q < C, L lanes to a vector: `w`
// of them in all, lanes past the row's end zero. Those lanes' sums are
// never read.
template <class V, std::size_t C>
[[gnu::always_inline]] inline void load_row(std::size_t w, const double* row, V (&lv)[C]) {
    constexpr std::size_t L = simd::lanes<V>;
    for (std::size_t q = 0; q + 1 < C; ++q) std::memcpy(&lv[q], row + L * q, sizeof(V));
    load_first(w - L * (C - 1), row + L * (C - 1), lv[C - 1]);
}

// Lines fetched a few at a time as the rows below are pulled. The backward
// solve takes each supernode before its children, which lie below it in
// memory, where the hardware prefetcher does not follow; fetched all at
// once before a supernode, the next one's lines queued behind each other
// and the narrow supernodes' backward pass fell well behind the forward
// one, which spreading the fetches over the rows closes. Kept as offsets,
// so that no pointer is formed past the bytes given.
class Ahead {
public:
    Ahead(const char* begin, std::size_t bytes, std::size_t rows)
        : begin_(begin),
          bytes_(bytes),
          per_row_((bytes / 64 + rows) / std::max<std::size_t>(rows, 1)) {}

    void row() {
        for (std::size_t line = 0; line < per_row_ && at_ < bytes_; ++line, at_ += 64)
            __builtin_prefetch(begin_ + at_);
    }
    void rest() {
        for (; at_ < bytes_; at_ += 64) __builtin_prefetch(begin_ + at_);
    }

private:
    const char* begin_;
    std::size_t bytes_;
    std::size_t per_row_;
    std::size_t at_ = 0;
};

// pull_rows for a supernode of at most L C columns (L lanes of V), the two
// arrays of sums in registers: through memory, each row's sums waited on the
// stores of the row before last. Each sum takes the same products in the
// same order, so the same bits.
template <class V, std::size_t K, std::size_t C>
[[gnu::always_inline]] inline void pull_narrow_rows(std::size_t h, std::size_t w,
                                                    const double* below, const std::uint32_t* rows,
                                                    const double* y, double* s, Ahead& ahead) {
    constexpr std::size_t L = simd::lanes<V>;
    V acc[2][K][C];
    for (auto& parity : acc)
        for (auto& vector : parity)
            for (V& lanes : vector) lanes = V{};
    const auto add_row = [&](std::size_t t, V(&a)[K][C]) {
        V lv[C] = {};
        load_row<V, C>(w, below + t * w, lv);
        const double* yt = y + static_cast<std::size_t>(rows[t]) * K;
        for (std::size_t c = 0; c < K; ++c)
            for (std::size_t q = 0; q < C; ++q) a[c][q] += lv[q] * yt[c];
    };
    std::size_t t = 0;
    for (; t + 1 < h; t += 2) {
        ahead.row();
        ahead.row();
        add_row(t, acc[0]);
        add_row(t + 1, acc[1]);
    }
    if (t < h) add_row(t, acc[0]);
    for (std::size_t c = 0; c < K; ++c) {
        for (std::size_t q = 0; q < C; ++q) {
            const V sum = acc[0][c][q] + acc[1][c][q];
            for (std::size_t lane = 0; lane < L && L * q + lane < w; ++lane)
                s[c * w + L * q + lane] -= sum[lane];
        }
    }
}

// s[c w + j] −= Σ_t L(w + t, j) y[rows[t] k + c], that sum in two partial
// sums over t (even t, odd t, each in ascending order) added together. The
// rows are taken one after the other, each whole, into two arrays of sums
// after s in the scratch: L streams in order. (Taken a few columns at a
// time over all rows, it was read with a stride of w doubles, which the
// processor does not prefetch over so few rows.)
// Supernodes of up to `max_chunks` chunks of four columns keep the sums in
// registers (16 columns where the kernels have 32 vector registers, 8 where
// they have 16: more spilled and were slower). With `eight_lanes`, those of
// 17 to 32 columns keep them in vectors of eight (24 of the 32 registers),
// which shortens the backward pass for them; supernodes of 5-16 columns
// were slower in vectors of eight.
template <std::size_t K, std::size_t max_chunks, bool eight_lanes>
[[gnu::always_inline]] inline void pull_rows(std::size_t h, std::size_t w, std::size_t k,
                                             const double* below, const std::uint32_t* rows,
                                             const double* y, double* s, Ahead& ahead) {
    if constexpr (K != 0) {
        switch ((w + 3) / 4) {
            case 1: return pull_narrow_rows<Doubles4, K, 1>(h, w, below, rows, y, s, ahead);
            case 2: return pull_narrow_rows<Doubles4, K, 2>(h, w, below, rows, y, s, ahead);
            case 3:
                if constexpr (max_chunks >= 4)
                    return pull_narrow_rows<Doubles4, K, 3>(h, w, below, rows, y, s, ahead);
                break;
            case 4:
                if constexpr (max_chunks >= 4)
                    return pull_narrow_rows<Doubles4, K, 4>(h, w, below, rows, y, s, ahead);
                break;
            case 5:
            case 6:
                if constexpr (eight_lanes)
                    return pull_narrow_rows<Doubles8, K, 3>(h, w, below, rows, y, s, ahead);
                break;
            case 7:
            case 8:
                if constexpr (eight_lanes)
                    return pull_narrow_rows<Doubles8, K, 4>(h, w, below, rows, y, s, ahead);
                break;
            default: break;
        }
    }
    const std::size_t kk = K != 0 ? K : k;
    double* acc[2] = {s + kk * w, s + 2 * kk * w};
    for (std::size_t i = 0; i < 2 * kk * w; ++i) acc[0][i] = 0.0;
    const std::size_t w4 = w - w % 4;
    for (std::size_t t = 0; t < h; ++t) {
        ahead.row();
        const double* row = below + t * w;
        const double* yt = y + static_cast<std::size_t>(rows[t]) * kk;
        double* a = acc[t % 2];
        if constexpr (K != 0) {
            for (std::size_t j = 0; j < w4; j += 4) {
                Doubles4 lv;
                load(lv, row + j);
                for (std::size_t c = 0; c < K; ++c) {
                    Doubles4 av;
                    load(av, a + c * w + j);
                    av += lv * yt[c];
                    std::memcpy(a + c * w + j, &av, sizeof av);
                }
            }
            for (std::size_t j = w4; j < w; ++j)
                for (std::size_t c = 0; c < K; ++c) a[c * w + j] += row[j] * yt[c];
        } else {
            for (std::size_t c = 0; c < kk; ++c)
                for (std::size_t j = 0; j < w; ++j) a[c * w + j] += row[j] * yt[c];
        }
    }
    for (std::size_t i = 0; i < kk * w; ++i) s[i] -= acc[0][i] + acc[1][i];
}

template <std::size_t K>
[[gnu::always_inline]] inline void forward_body(std::size_t m, std::size_t w, std::size_t push,
                                                std::size_t k, const double* l,
                                                const std::uint32_t* rows, double* own, double* y,
                                                double* scratch) {
    (void)m;
    const std::size_t kk = K != 0 ? K : k;
    double* s = scratch;
    split_columns<K>(w, kk, own, s);
    for (std::size_t j = 0; j < w; ++j) {
        const double* lj = l + j * w;
        if constexpr (K != 0) {
            double f[K];
            for (std::size_t c = 0; c < K; ++c) f[c] = s[c * w + j] /= lj[j];
            for (std::size_t i = j + 1; i < w; ++i)
                for (std::size_t c = 0; c < K; ++c) s[c * w + i] -= lj[i] * f[c];
        } else {
            for (std::size_t c = 0; c < kk; ++c) {
                double* sc = s + c * w;
                const double f = sc[j] /= lj[j];
                for (std::size_t i = j + 1; i < w; ++i) sc[i] -= lj[i] * f;
            }
        }
    }
    join_columns<K>(w, kk, s, own);
    if (push > 0) push_rows<K>(push, w, kk, l + w * w, s, rows, y);
}

// The backward solve reads the diagonal block's columns in descending
// order, one stretch ascending each, which the hardware prefetcher does not
// follow from one column to the one before it: in a wide block, the column
// two ahead is fetched while this one is worked on. A block of 16 columns
// is 2 KiB, which comes in with the supernode's first lines, fetched while
// the supernode before it was solved.
constexpr std::size_t prefetch_columns_wider_than = 16;
constexpr std::size_t prefetch_columns_ahead = 2;

template <std::size_t K, std::size_t max_chunks, bool eight_lanes>
[[gnu::always_inline]] inline void backward_body(std::size_t m, std::size_t w, std::size_t k,
                                                 const double* l, const std::uint32_t* rows,
                                                 double* own, const double* y, double* scratch,
                                                 const char* ahead_begin, std::size_t ahead_bytes) {
    const std::size_t kk = K != 0 ? K : k;
    const std::size_t h = m - w;
    double* s = scratch;
    Ahead ahead(ahead_begin, ahead_bytes, h);
    split_columns<K>(w, kk, own, s);
    if (h > 0) pull_rows<K, max_chunks, eight_lanes>(h, w, kk, l + w * w, rows, y, s, ahead);
    ahead.rest();
    // Column i of the diagonal block above the diagonal is row i of L left
    // of it (SparseCholesky's layout): once y_i is known, the entries before
    // it subtract their terms, all K vectors in one pass over that column.
    for (std::size_t i = w; i-- > 0;) {
        const double* li = l + i * w;
        if (w > prefetch_columns_wider_than && i >= prefetch_columns_ahead) {
            const std::size_t next_column = i - prefetch_columns_ahead;
            const auto* column = reinterpret_cast<const char*>(l + next_column * w);
            for (std::size_t byte = 0; byte < next_column * sizeof(double); byte += 64)
                __builtin_prefetch(column + byte);
        }
        if constexpr (K != 0) {
            double x[K];
            for (std::size_t c = 0; c < K; ++c) x[c] = s[c * w + i] /= li[i];
            for (std::size_t j = 0; j < i; ++j)
                for (std::size_t c = 0; c < K; ++c) s[c * w + j] -= li[j] * x[c];
        } else {
            for (std::size_t c = 0; c < kk; ++c) {
                double* sc = s + c * w;
                const double x = sc[i] /= li[i];
                for (std::size_t j = 0; j < i; ++j) sc[j] -= li[j] * x;
            }
        }
    }
    join_columns<K>(w, kk, s, own);
}

template <std::size_t K>
[[gnu::always_inline]] inline void push_body(std::size_t h, std::size_t w, std::size_t k,
                                             const double* below, const std::uint32_t* rows,
                                             const double* own, double* y, double* scratch) {
    split_columns<K>(w, k, own, scratch);
    push_rows<K>(h, w, k, below, scratch, rows, y);
}

#if DFM_X86_DISPATCH
template <std::size_t K>
DFM_TARGET_AVX2 void push_avx2(std::size_t h, std::size_t w, std::size_t k, const double* below,
                               const std::uint32_t* rows, const double* own, double* y,
                               double* scratch) {
    push_body<K>(h, w, k, below, rows, own, y, scratch);
}

template <std::size_t K>
DFM_TARGET_AVX512 void push_avx512(std::size_t h, std::size_t w, std::size_t k, const double* below,
                                   const std::uint32_t* rows, const double* own, double* y,
                                   double* scratch) {
    push_body<K>(h, w, k, below, rows, own, y, scratch);
}

template <std::size_t K>
DFM_TARGET_AVX2 void forward_avx2(std::size_t m, std::size_t w, std::size_t push, std::size_t k,
                                  const double* l, const std::uint32_t* rows, double* own,
                                  double* y, double* scratch) {
    forward_body<K>(m, w, push, k, l, rows, own, y, scratch);
}

template <std::size_t K>
DFM_TARGET_AVX512 void forward_avx512(std::size_t m, std::size_t w, std::size_t push, std::size_t k,
                                      const double* l, const std::uint32_t* rows, double* own,
                                      double* y, double* scratch) {
    forward_body<K>(m, w, push, k, l, rows, own, y, scratch);
}

template <std::size_t K>
DFM_TARGET_AVX2 void backward_avx2(std::size_t m, std::size_t w, std::size_t k, const double* l,
                                   const std::uint32_t* rows, double* own, const double* y,
                                   double* scratch, const char* ahead, std::size_t ahead_bytes) {
    backward_body<K, 2, false>(m, w, k, l, rows, own, y, scratch, ahead, ahead_bytes);
}

template <std::size_t K>
DFM_TARGET_AVX512 void backward_avx512(std::size_t m, std::size_t w, std::size_t k, const double* l,
                                       const std::uint32_t* rows, double* own, const double* y,
                                       double* scratch, const char* ahead,
                                       std::size_t ahead_bytes) {
    backward_body<K, 4, true>(m, w, k, l, rows, own, y, scratch, ahead, ahead_bytes);
}
#endif

template <std::size_t K>
void forward_for(simd::Set set, std::size_t m, std::size_t w, std::size_t push, std::size_t k,
                 const double* l, const std::uint32_t* rows, double* own, double* y,
                 double* scratch) {
#if DFM_X86_DISPATCH
    if (set == simd::Set::avx512) return forward_avx512<K>(m, w, push, k, l, rows, own, y, scratch);
    if (set == simd::Set::avx2) return forward_avx2<K>(m, w, push, k, l, rows, own, y, scratch);
#endif
    forward_body<K>(m, w, push, k, l, rows, own, y, scratch);
}

template <std::size_t K>
void push_for(simd::Set set, std::size_t h, std::size_t w, std::size_t k, const double* below,
              const std::uint32_t* rows, const double* own, double* y, double* scratch) {
#if DFM_X86_DISPATCH
    if (set == simd::Set::avx512) return push_avx512<K>(h, w, k, below, rows, own, y, scratch);
    if (set == simd::Set::avx2) return push_avx2<K>(h, w, k, below, rows, own, y, scratch);
#endif
    push_body<K>(h, w, k, below, rows, own, y, scratch);
}

template <std::size_t K>
void backward_for(simd::Set set, std::size_t m, std::size_t w, std::size_t k, const double* l,
                  const std::uint32_t* rows, double* own, const double* y, double* scratch,
                  const char* ahead, std::size_t ahead_bytes) {
#if DFM_X86_DISPATCH
    if (set == simd::Set::avx512)
        return backward_avx512<K>(m, w, k, l, rows, own, y, scratch, ahead, ahead_bytes);
    if (set == simd::Set::avx2)
        return backward_avx2<K>(m, w, k, l, rows, own, y, scratch, ahead, ahead_bytes);
#endif
    backward_body<K, 2, false>(m, w, k, l, rows, own, y, scratch, ahead, ahead_bytes);
}

}  // namespace

void push(simd::Set set, std::size_t h, std::size_t w, std::size_t k, const double* below,
          const std::uint32_t* rows, const double* own, double* y, double* scratch) {
    switch (k) {
        case 1: return push_for<1>(set, h, w, k, below, rows, own, y, scratch);
        case 2: return push_for<2>(set, h, w, k, below, rows, own, y, scratch);
        case 3: return push_for<3>(set, h, w, k, below, rows, own, y, scratch);
        default: return push_for<0>(set, h, w, k, below, rows, own, y, scratch);
    }
}

void push(std::size_t h, std::size_t w, std::size_t k, const double* below,
          const std::uint32_t* rows, const double* own, double* y, double* scratch) {
    push(simd::widest(), h, w, k, below, rows, own, y, scratch);
}

void forward(simd::Set set, std::size_t m, std::size_t w, std::size_t push, std::size_t k,
             const double* l, const std::uint32_t* rows, double* own, double* y, double* scratch) {
    switch (k) {
        case 1: return forward_for<1>(set, m, w, push, k, l, rows, own, y, scratch);
        case 2: return forward_for<2>(set, m, w, push, k, l, rows, own, y, scratch);
        case 3: return forward_for<3>(set, m, w, push, k, l, rows, own, y, scratch);
        default: return forward_for<0>(set, m, w, push, k, l, rows, own, y, scratch);
    }
}

void forward(std::size_t m, std::size_t w, std::size_t push, std::size_t k, const double* l,
             const std::uint32_t* rows, double* own, double* y, double* scratch) {
    forward(simd::widest(), m, w, push, k, l, rows, own, y, scratch);
}

void backward(simd::Set set, std::size_t m, std::size_t w, std::size_t k, const double* l,
              const std::uint32_t* rows, double* own, const double* y, double* scratch,
              const char* ahead, std::size_t ahead_bytes) {
    switch (k) {
        case 1: return backward_for<1>(set, m, w, k, l, rows, own, y, scratch, ahead, ahead_bytes);
        case 2: return backward_for<2>(set, m, w, k, l, rows, own, y, scratch, ahead, ahead_bytes);
        case 3: return backward_for<3>(set, m, w, k, l, rows, own, y, scratch, ahead, ahead_bytes);
        default: return backward_for<0>(set, m, w, k, l, rows, own, y, scratch, ahead, ahead_bytes);
    }
}

void backward(std::size_t m, std::size_t w, std::size_t k, const double* l,
              const std::uint32_t* rows, double* own, const double* y, double* scratch,
              const char* ahead, std::size_t ahead_bytes) {
    backward(simd::widest(), m, w, k, l, rows, own, y, scratch, ahead, ahead_bytes);
}

}  // namespace dfm::solver::supernode
