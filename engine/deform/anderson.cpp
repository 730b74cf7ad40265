#include "deform/anderson.hpp"

#include <algorithm>
#include <cmath>

namespace dfm::deform {

namespace {

// The inner products of G columns (`columns`, `stride` apart) with u and
// with v, each summed in ascending order from 0.0. A single sum is a chain
// of dependent additions, which left the adder waiting on its latency for
// each of the step's 2m sums; taken together in one pass they are 2G
// independent chains, each with the same additions in the same order.
template <std::size_t G>
void column_dots(const double* columns, std::size_t stride, std::size_t n, const double* u,
                 const double* v, double* with_u, double* with_v) {
    double su[G] = {}, sv[G] = {};
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t a = 0; a < G; ++a) {
            const double c = columns[a * stride + i];
            su[a] += c * u[i];
            sv[a] += c * v[i];
        }
    }
    for (std::size_t a = 0; a < G; ++a) {
        with_u[a] = su[a];
        with_v[a] = sv[a];
    }
}

// column_dots over `count` columns, four at a time.
void column_dots(const double* columns, std::size_t stride, std::size_t count, std::size_t n,
                 const double* u, const double* v, double* with_u, double* with_v) {
    std::size_t a = 0;
    for (; a + 4 <= count; a += 4)
        column_dots<4>(columns + a * stride, stride, n, u, v, with_u + a, with_v + a);
    const double* rest = columns + a * stride;
    switch (count - a) {
        case 1: column_dots<1>(rest, stride, n, u, v, with_u + a, with_v + a); break;
        case 2: column_dots<2>(rest, stride, n, u, v, with_u + a, with_v + a); break;
        case 3: column_dots<3>(rest, stride, n, u, v, with_u + a, with_v + a); break;
        default: break;
    }
}

// Solves the small symmetric system G γ = rhs in place (rhs becomes γ) by
// Gaussian elimination with partial pivoting. False when it is singular.
bool solve_small(std::vector<double>& g, std::vector<double>& rhs, std::size_t m) {
    for (std::size_t k = 0; k < m; ++k) {
        std::size_t pivot = k;
        for (std::size_t i = k + 1; i < m; ++i) {
            if (std::abs(g[i * m + k]) > std::abs(g[pivot * m + k])) pivot = i;
        }
        if (!(std::abs(g[pivot * m + k]) > 0.0)) return false;
        if (pivot != k) {
            for (std::size_t j = 0; j < m; ++j) std::swap(g[k * m + j], g[pivot * m + j]);
            std::swap(rhs[k], rhs[pivot]);
        }
        for (std::size_t i = k + 1; i < m; ++i) {
            const double factor = g[i * m + k] / g[k * m + k];
            for (std::size_t j = k; j < m; ++j) g[i * m + j] -= factor * g[k * m + j];
            rhs[i] -= factor * rhs[k];
        }
    }
    for (std::size_t k = m; k-- > 0;) {
        double s = rhs[k];
        for (std::size_t j = k + 1; j < m; ++j) s -= g[k * m + j] * rhs[j];
        rhs[k] = s / g[k * m + k];
    }
    return true;
}

}  // namespace

void AndersonAccelerator::reset(std::size_t size, std::size_t memory) {
    size_ = size;
    memory_ = memory;
    restart();
    previous_f_.resize(size);
    previous_g_.resize(size);
    delta_f_.resize(size * memory);
    delta_g_.resize(size * memory);
    f_.resize(size);
    gram_.assign(memory * memory, 0.0);
    products_.assign(memory * memory, 0.0);
    gamma_.assign(memory, 0.0);
    column_products_.assign(memory, 0.0);
}

void AndersonAccelerator::step(std::span<const double> x, std::span<const double> g,
                               std::span<double> next) {
    for (std::size_t i = 0; i < size_; ++i) f_[i] = g[i] - x[i];
    std::copy(g.begin(), g.end(), next.begin());
    if (memory_ == 0 || !has_previous_) {
        std::copy(f_.begin(), f_.end(), previous_f_.begin());
        std::copy(g.begin(), g.end(), previous_g_.begin());
        has_previous_ = true;
        return;
    }
    // The newest differences overwrite the oldest of `memory_` columns; the
    // least-squares fit does not care about their order. Only the new
    // column's inner products are computed: the rest of the Gram matrix is
    // kept from earlier steps.
    const std::size_t slot = next_slot_;
    double* df = &delta_f_[slot * size_];
    double* dg = &delta_g_[slot * size_];
    for (std::size_t i = 0; i < size_; ++i) {
        df[i] = f_[i] - previous_f_[i];
        dg[i] = g[i] - previous_g_[i];
    }
    next_slot_ = (next_slot_ + 1) % memory_;
    count_ = std::min(count_ + 1, memory_);
    std::copy(f_.begin(), f_.end(), previous_f_.begin());
    std::copy(g.begin(), g.end(), previous_g_.begin());
    // The new column's inner products, and ΔFᵀ f for γ below.
    const std::size_t m = count_;
    column_dots(delta_f_.data(), size_, m, size_, df, f_.data(), column_products_.data(),
                gamma_.data());
    for (std::size_t a = 0; a < m; ++a)
        products_[a * memory_ + slot] = products_[slot * memory_ + a] = column_products_[a];

    // γ = argmin |f - ΔF γ|, by the normal equations with a little Tikhonov
    // damping so that nearly dependent columns stay harmless.
    double trace = 0.0;
    for (std::size_t a = 0; a < m; ++a) {
        for (std::size_t b = 0; b < m; ++b) gram_[a * m + b] = products_[a * memory_ + b];
        trace += gram_[a * m + a];
    }
    for (std::size_t a = 0; a < m; ++a) gram_[a * m + a] += 1e-12 * trace;
    if (!(trace > 0.0) || !solve_small(gram_, gamma_, m)) {
        restart();
        return;
    }
    // next −= ΔG γ, each entry's terms subtracted in column order, all
    // columns in one pass over next.
    for (std::size_t i = 0; i < size_; ++i) {
        double value = next[i];
        for (std::size_t a = 0; a < m; ++a) value -= gamma_[a] * delta_g_[a * size_ + i];
        next[i] = value;
    }
}

}  // namespace dfm::deform
