#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include <sys/mman.h>
#include <unistd.h>

#include "solver/dense_kernels.hpp"

using namespace dfm::solver;

namespace {

// A's rows in m, B's in n, both k wide, C m×n, each with its own leading
// dimension and values of every magnitude the factor meets.
struct Product {
    std::size_t m, n, k, lda, ldb, ldc;
    std::vector<double> a, b, c;
};

Product random_product(std::mt19937& rng, std::size_t m, std::size_t n, std::size_t k) {
    std::uniform_real_distribution<double> value(-1.0, 1.0);
    std::uniform_int_distribution<int> exponent(-30, 30);
    Product p{m, n, k, m + 3, n + 1, m + 5, {}, {}, {}};
    const auto fill = [&](std::vector<double>& v, std::size_t size) {
        v.resize(size);
        for (double& x : v) x = std::ldexp(value(rng), exponent(rng));
    };
    fill(p.a, p.lda * k);
    fill(p.b, p.ldb * k);
    fill(p.c, p.ldc * n);
    return p;
}

std::vector<double> run(dfm::simd::Set set, const Product& p, bool subtract, bool lower,
                        std::size_t offset) {
    std::vector<double> c = p.c;
    dense::multiply_nt(set, p.m, p.n, p.k, p.a.data(), p.lda, p.b.data(), p.ldb, c.data(), p.ldc,
                       subtract, lower, offset);
    return c;
}

bool same_bits(const std::vector<double>& x, const std::vector<double>& y) {
    return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(double)) == 0;
}

// The entries a `lower` product must compute: global row i + offset ≥ j.
bool same_needed_bits(const Product& p, std::size_t offset, const std::vector<double>& x,
                      const std::vector<double>& y) {
    for (std::size_t j = 0; j < p.n; ++j)
        for (std::size_t i = 0; i < p.m; ++i) {
            if (i + offset < j) continue;
            const std::size_t at = i + j * p.ldc;
            if (std::memcmp(&x[at], &y[at], sizeof(double)) != 0) return false;
        }
    return true;
}

}  // namespace

TEST_CASE("solver: the dense product gives the same bits on every instruction set") {
    const dfm::simd::Set wide[] = {dfm::simd::Set::avx2, dfm::simd::Set::avx512};
    std::mt19937 rng(12);
    std::uniform_int_distribution<std::size_t> size(1, 150);
    std::size_t compared = 0;
    for (int trial = 0; trial < 60; ++trial) {
        // Sizes past the row block (96) and the tiles' tails of every length.
        const Product p = random_product(rng, size(rng), size(rng) % 40 + 1, size(rng) % 70 + 1);
        const std::size_t offset = size(rng) % 20;
        for (const bool subtract : {false, true}) {
            const std::vector<double> full = run(dfm::simd::Set::plain, p, subtract, false, 0);
            const std::vector<double> lower = run(dfm::simd::Set::plain, p, subtract, true, offset);
            for (dfm::simd::Set set : wide) {
                if (!dfm::simd::available(set)) continue;
                CHECK(same_bits(run(set, p, subtract, false, 0), full));
                CHECK(same_needed_bits(p, offset, run(set, p, subtract, true, offset), lower));
                ++compared;
            }
        }
    }
    MESSAGE("compared ", compared, " products with the plain kernel's");
}

// `values` copied to the end of pages followed by one that cannot be
// read: a kernel that reads past an operand's last entry faults.
class GuardedCopy {
public:
    explicit GuardedCopy(const std::vector<double>& values) {
        const std::size_t page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
        const std::size_t bytes = values.size() * sizeof(double);
        size_ = (bytes + page - 1) / page * page + page;
        void* mapped =
            ::mmap(nullptr, size_, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        REQUIRE(mapped != MAP_FAILED);
        base_ = static_cast<char*>(mapped);
        REQUIRE(::mprotect(base_ + size_ - page, page, PROT_NONE) == 0);
        data_ = reinterpret_cast<double*>(base_ + size_ - page - bytes);
        std::memcpy(data_, values.data(), bytes);
    }
    ~GuardedCopy() { ::munmap(base_, size_); }
    GuardedCopy(const GuardedCopy&) = delete;
    GuardedCopy& operator=(const GuardedCopy&) = delete;
    double* data() { return data_; }

private:
    char* base_ = nullptr;
    std::size_t size_ = 0;
    double* data_ = nullptr;
};

TEST_CASE("solver: the dense product reads nothing past its operands' last rows") {
    // The factor's updates multiply a panel by its own first rows, and the
    // panel may end where the memory does. A and B hold exactly their k
    // rows here (leading dimension m and n), the last one against a page
    // that cannot be read.
    std::mt19937 rng(5);
    for (dfm::simd::Set set :
         {dfm::simd::Set::plain, dfm::simd::Set::avx2, dfm::simd::Set::avx512}) {
        if (!dfm::simd::available(set)) continue;
        for (std::size_t m = 1; m <= 19; ++m)
            for (std::size_t n : {std::size_t{1}, std::size_t{3}, std::size_t{5}, std::size_t{9}})
                for (const bool subtract : {false, true}) {
                    Product p = random_product(rng, m, n, 7);
                    p.lda = m;
                    p.ldb = n;
                    p.a.resize(m * p.k);
                    p.b.resize(n * p.k);
                    GuardedCopy a(p.a);
                    GuardedCopy b(p.b);
                    GuardedCopy c(p.c);
                    dense::multiply_nt(set, m, n, p.k, a.data(), m, b.data(), n, c.data(), p.ldc,
                                       subtract, false, 0);
                    const std::vector<double> expected = run(set, p, subtract, false, 0);
                    CHECK(std::memcmp(c.data(), expected.data(), p.c.size() * sizeof(double)) == 0);
                }
    }
}

TEST_CASE("solver: the dense product's entries are the sums in ascending order") {
    std::mt19937 rng(7);
    const Product p = random_product(rng, 37, 11, 23);
    for (dfm::simd::Set set :
         {dfm::simd::Set::plain, dfm::simd::Set::avx2, dfm::simd::Set::avx512}) {
        if (!dfm::simd::available(set)) continue;
        const std::vector<double> c = run(set, p, true, false, 0);
        for (std::size_t j = 0; j < p.n; ++j)
            for (std::size_t i = 0; i < p.m; ++i) {
                double sum = 0.0;
                for (std::size_t t = 0; t < p.k; ++t) {
                    const double product = p.a[i + t * p.lda] * p.b[j + t * p.ldb];
                    sum += product;
                }
                const double expected = p.c[i + j * p.ldc] - sum;
                CHECK(std::memcmp(&c[i + j * p.ldc], &expected, sizeof(double)) == 0);
            }
    }
}

TEST_CASE("solver: the triangular solve of the rows below gives the same bits on every set") {
    std::mt19937 rng(31);
    std::uniform_int_distribution<std::size_t> size(1, 150);
    std::uniform_real_distribution<double> value(-1.0, 1.0);
    std::size_t compared = 0;
    for (int trial = 0; trial < 60; ++trial) {
        // Row counts past the 64-row chunk and tails of every length.
        const std::size_t m = size(rng), w = size(rng) % 40 + 1;
        const std::size_t ldl = w + 2, ldx = m + 3;
        std::vector<double> l(ldl * w), x(ldx * w);
        // Diagonally dominant, so that the check of the plain solve below
        // measures its rounding, not L's condition.
        for (double& v : l) v = value(rng) / static_cast<double>(w);
        for (std::size_t j = 0; j < w; ++j) l[j + j * ldl] = 1.0 + std::abs(l[j + j * ldl]);
        for (double& v : x) v = std::ldexp(value(rng), static_cast<int>(size(rng) % 41) - 20);
        std::vector<double> plain = x;
        dense::solve_right_lower_transposed(dfm::simd::Set::plain, m, w, l.data(), ldl,
                                            plain.data(), ldx);
        // The plain kernel solves X Lᵀ = B: check it before comparing with it.
        double worst = 0.0;
        for (std::size_t i = 0; i < m; ++i)
            for (std::size_t j = 0; j < w; ++j) {
                double b = 0.0, scale = 0.0;
                for (std::size_t t = 0; t <= j; ++t) {
                    b += plain[i + t * ldx] * l[j + t * ldl];
                    scale += std::abs(plain[i + t * ldx] * l[j + t * ldl]);
                }
                worst = std::max(worst, std::abs(b - x[i + j * ldx]) / scale);
            }
        CHECK(worst < 1e-12);
        for (dfm::simd::Set set : {dfm::simd::Set::avx2, dfm::simd::Set::avx512}) {
            if (!dfm::simd::available(set)) continue;
            std::vector<double> wide = x;
            dense::solve_right_lower_transposed(set, m, w, l.data(), ldl, wide.data(), ldx);
            CHECK(same_bits(wide, plain));
            ++compared;
        }
    }
    MESSAGE("compared ", compared, " solves with the plain kernel's");
}

TEST_CASE("solver: the transpose moves every entry and writes nothing else, on every set") {
    std::mt19937 rng(5);
    std::uniform_int_distribution<std::size_t> size(1, 40);
    std::size_t compared = 0;
    for (int trial = 0; trial < 80; ++trial) {
        // Rows and entries past the eight of a register's block, and tails of
        // every length.
        const std::size_t count = size(rng), w = size(rng);
        const std::size_t stride = w + size(rng) % 5, out_stride = count + size(rng) % 5;
        std::vector<double> rows(count * stride);
        for (std::size_t i = 0; i < rows.size(); ++i) rows[i] = static_cast<double>(i) + 0.5;
        for (dfm::simd::Set set :
             {dfm::simd::Set::plain, dfm::simd::Set::avx2, dfm::simd::Set::avx512}) {
            if (!dfm::simd::available(set)) continue;
            std::vector<double> out(w * out_stride, -1.0);
            dense::transpose(set, count, w, rows.data(), stride, out.data(), out_stride);
            bool moved = true, untouched = true;
            for (std::size_t t = 0; t < w; ++t)
                for (std::size_t i = 0; i < out_stride; ++i) {
                    const double got = out[t * out_stride + i];
                    if (i < count) {
                        moved = moved && got == rows[i * stride + t];
                    } else {
                        untouched = untouched && got == -1.0;
                    }
                }
            CHECK(moved);
            CHECK(untouched);
            ++compared;
        }
    }
    MESSAGE("compared ", compared, " transposes");
}
