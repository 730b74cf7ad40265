#include <cstddef>

#include "solver/sparse_cholesky.hpp"

namespace dfm::solver {

namespace {

// The vectors' count: fixed at compile time for the common cases (K > 0),
// read at run time otherwise (K == 0).
template <std::size_t K>
struct Width {
    std::size_t runtime;
    constexpr std::size_t operator()() const { return K > 0 ? K : runtime; }
};

// L y = y over one supernode: its diagonal block, then its rows below, four
// columns at a time.
template <std::size_t K>
void forward_supernode(const CholeskySymbolic& sym, const double* l, std::uint32_t s, double* y,
                       Width<K> width) {
    const std::size_t k = width();
    const std::size_t first = sym.column_begin[s];
    const std::size_t w = sym.column_begin[s + 1] - first;
    const std::size_t m = sym.row_begin[s + 1] - sym.row_begin[s];
    const std::uint32_t* rows = &sym.rows[sym.row_begin[s]];
    double* yf = y + first * k;
    for (std::size_t j = 0; j < w; ++j) {
        const double* lj = l + j * m;
        double* yj = yf + j * k;
        for (std::size_t c = 0; c < k; ++c) yj[c] /= lj[j];
        for (std::size_t i = j + 1; i < w; ++i)
            for (std::size_t c = 0; c < k; ++c) yf[i * k + c] -= lj[i] * yj[c];
    }
    std::size_t j = 0;
    for (; j + 4 <= w; j += 4) {
        const double* l0 = l + j * m;
        const double* l1 = l0 + m;
        const double* l2 = l1 + m;
        const double* l3 = l2 + m;
        const double* y0 = yf + j * k;
        for (std::size_t t = w; t < m; ++t) {
            double* yt = y + static_cast<std::size_t>(rows[t]) * k;
            for (std::size_t c = 0; c < k; ++c)
                yt[c] -= l0[t] * y0[c] + l1[t] * y0[k + c] + l2[t] * y0[2 * k + c] +
                         l3[t] * y0[3 * k + c];
        }
    }
    for (; j < w; ++j) {
        const double* lj = l + j * m;
        const double* yj = yf + j * k;
        for (std::size_t t = w; t < m; ++t) {
            double* yt = y + static_cast<std::size_t>(rows[t]) * k;
            for (std::size_t c = 0; c < k; ++c) yt[c] -= lj[t] * yj[c];
        }
    }
}

// Lᵀ y = y over one supernode: its rows below first, then its diagonal block.
template <std::size_t K>
void backward_supernode(const CholeskySymbolic& sym, const double* l, std::uint32_t s, double* y,
                        Width<K> width) {
    const std::size_t k = width();
    const std::size_t first = sym.column_begin[s];
    const std::size_t w = sym.column_begin[s + 1] - first;
    const std::size_t m = sym.row_begin[s + 1] - sym.row_begin[s];
    const std::uint32_t* rows = &sym.rows[sym.row_begin[s]];
    double* yf = y + first * k;
    std::size_t j = 0;
    for (; j + 4 <= w; j += 4) {
        const double* l0 = l + j * m;
        const double* l1 = l0 + m;
        const double* l2 = l1 + m;
        const double* l3 = l2 + m;
        double* y0 = yf + j * k;
        for (std::size_t t = w; t < m; ++t) {
            const double* yt = y + static_cast<std::size_t>(rows[t]) * k;
            for (std::size_t c = 0; c < k; ++c) {
                y0[c] -= l0[t] * yt[c];
                y0[k + c] -= l1[t] * yt[c];
                y0[2 * k + c] -= l2[t] * yt[c];
                y0[3 * k + c] -= l3[t] * yt[c];
            }
        }
    }
    for (; j < w; ++j) {
        const double* lj = l + j * m;
        double* yj = yf + j * k;
        for (std::size_t t = w; t < m; ++t) {
            const double* yt = y + static_cast<std::size_t>(rows[t]) * k;
            for (std::size_t c = 0; c < k; ++c) yj[c] -= lj[t] * yt[c];
        }
    }
    for (std::size_t j = w; j-- > 0;) {
        const double* lj = l + j * m;
        double* yj = yf + j * k;
        for (std::size_t i = j + 1; i < w; ++i)
            for (std::size_t c = 0; c < k; ++c) yj[c] -= lj[i] * yf[i * k + c];
        for (std::size_t c = 0; c < k; ++c) yj[c] /= lj[j];
    }
}

template <std::size_t K>
void solve_permuted(const CholeskySymbolic& sym, std::span<const double> values, double* y,
                    Width<K> width) {
    const std::uint32_t s_count = static_cast<std::uint32_t>(sym.supernode_count());
    for (std::uint32_t s = 0; s < s_count; ++s)
        forward_supernode(sym, &values[sym.value_begin[s]], s, y, width);
    for (std::uint32_t s = s_count; s-- > 0;)
        backward_supernode(sym, &values[sym.value_begin[s]], s, y, width);
}

}  // namespace

void SparseCholesky::solve(std::span<const double> b, std::span<double> x, std::size_t k,
                           std::span<double> work) const {
    const CholeskySymbolic& sym = symbolic_;
    const std::size_t n = sym.n;
    double* y = work.data();
    for (std::size_t i = 0; i < n; ++i) {
        const double* from = &b[static_cast<std::size_t>(sym.perm[i]) * k];
        for (std::size_t c = 0; c < k; ++c) y[i * k + c] = from[c];
    }
    switch (k) {
        case 1: solve_permuted(sym, values_, y, Width<1>{1}); break;
        case 2: solve_permuted(sym, values_, y, Width<2>{2}); break;
        case 3: solve_permuted(sym, values_, y, Width<3>{3}); break;
        case 4: solve_permuted(sym, values_, y, Width<4>{4}); break;
        default: solve_permuted(sym, values_, y, Width<0>{k}); break;
    }
    for (std::size_t i = 0; i < n; ++i) {
        double* to = &x[static_cast<std::size_t>(sym.perm[i]) * k];
        for (std::size_t c = 0; c < k; ++c) to[c] = y[i * k + c];
    }
}

}  // namespace dfm::solver
