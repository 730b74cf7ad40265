#include <doctest/doctest.h>

#include <cstdint>
#include <cstring>
#include <vector>

#include "core/simd.hpp"
#include "solver/supernode_kernels.hpp"
#include "solver/test_matrices.hpp"

using namespace dfm::solver;
using dfm::simd::Set;

namespace {

// A supernode of w columns and h rows below, laid out as the solves read it
// (supernode_kernels.hpp), its rows below at scattered rows of the vector.
struct Supernode {
    std::size_t w = 0;
    std::size_t h = 0;
    std::vector<double> l;
    std::vector<std::uint32_t> rows;

    Supernode(std::size_t w, std::size_t h, unsigned seed) : w(w), h(h) {
        l = dfm::test::random_vector(w * w + h * w, seed);
        for (std::size_t j = 0; j < w; ++j) l[j * w + j] = 2.0 + l[j * w + j] * l[j * w + j];
        for (std::size_t t = 0; t < h; ++t)
            rows.push_back(static_cast<std::uint32_t>(w + 1 + 2 * t));
    }
    std::size_t vector_rows() const { return w + 2 * h + 2; }
};

// The vector after the forward or the backward solve of one supernode on
// `set`, from the same start.
std::vector<double> solved(const Supernode& s, Set set, std::size_t k, bool forward) {
    std::vector<double> y = dfm::test::random_vector(s.vector_rows() * k, 7);
    std::vector<double> scratch(supernode::scratch_size(s.w + s.h, k));
    if (forward) {
        supernode::forward(set, s.w + s.h, s.w, s.h, k, s.l.data(), s.rows.data(), y.data(),
                           y.data(), scratch.data());
    } else {
        supernode::backward(set, s.w + s.h, s.w, k, s.l.data(), s.rows.data(), y.data(), y.data(),
                            scratch.data(), nullptr, 0);
    }
    return y;
}

}  // namespace

// The supernode kernels are built for each instruction set (core/simd.hpp)
// and give the same bits on each: every width of block the kernels treat
// apart (the backward solve's narrow rows of 1-4 and 17-32 columns among
// them), with and without rows below, for one to four vectors.
TEST_CASE("solver: the supernode kernels give the same bits on every instruction set") {
    std::size_t compared = 0;
    for (const std::size_t w : {1u, 2u, 3u, 4u, 5u, 7u, 8u, 13u, 17u, 24u, 32u, 33u, 40u}) {
        for (const std::size_t h : {0u, 1u, 5u, 19u}) {
            const Supernode s(w, h, static_cast<unsigned>(100 * w + h));
            for (const std::size_t k : {1u, 2u, 3u, 4u}) {
                for (const bool forward : {true, false}) {
                    CAPTURE(w);
                    CAPTURE(h);
                    CAPTURE(k);
                    CAPTURE(forward);
                    const std::vector<double> plain = solved(s, Set::plain, k, forward);
                    for (const Set set : {Set::avx2, Set::avx512}) {
                        if (!dfm::simd::available(set)) continue;
                        const std::vector<double> wide = solved(s, set, k, forward);
                        CHECK(std::memcmp(plain.data(), wide.data(),
                                          plain.size() * sizeof(double)) == 0);
                        ++compared;
                    }
                }
            }
        }
    }
    MESSAGE("widest set: " << static_cast<int>(dfm::simd::widest()) << ", comparisons "
                           << compared);
}

// A thread's supernodes push only into their own subtree; the supernode
// above pulls the rest afterwards (SparseCholesky::solve). Pushed later by
// supernode::push, the rows below must see what forward's own push gives
// them, bit for bit, on every instruction set.
TEST_CASE("solver: a push made after the forward solve gives the bits of forward's own push") {
    std::size_t compared = 0;
    for (const std::size_t w : {1u, 3u, 4u, 5u, 8u, 17u, 40u}) {
        for (const std::size_t h : {1u, 6u, 19u}) {
            const Supernode s(w, h, static_cast<unsigned>(7 * w + h));
            for (const std::size_t k : {1u, 3u, 4u}) {
                for (const Set set : {Set::plain, Set::avx2, Set::avx512}) {
                    if (!dfm::simd::available(set)) continue;
                    CAPTURE(w);
                    CAPTURE(h);
                    CAPTURE(k);
                    CAPTURE(static_cast<int>(set));
                    const std::vector<double> pushed = solved(s, set, k, true);
                    std::vector<double> y = dfm::test::random_vector(s.vector_rows() * k, 7);
                    std::vector<double> scratch(supernode::scratch_size(s.w + s.h, k));
                    supernode::forward(set, s.w + s.h, s.w, 0, k, s.l.data(), s.rows.data(),
                                       y.data(), y.data(), scratch.data());
                    // Rows below in two parts, as two updates would take them.
                    const std::size_t part = h / 2;
                    const double* below = s.l.data() + w * w;
                    supernode::push(set, part, w, k, below, s.rows.data(), y.data(), y.data(),
                                    scratch.data());
                    supernode::push(set, h - part, w, k, below + part * w, s.rows.data() + part,
                                    y.data(), y.data(), scratch.data());
                    CHECK(std::memcmp(pushed.data(), y.data(), y.size() * sizeof(double)) == 0);
                    ++compared;
                }
            }
        }
    }
    CHECK(compared >= 63);
}
