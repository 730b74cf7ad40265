#include <doctest/doctest.h>

#include <algorithm>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "solver/cholesky_symbolic.hpp"
#include "solver/elimination_tree.hpp"
#include "solver/ordering.hpp"
#include "solver/symmetric_graph.hpp"
#include "solver/test_matrices.hpp"
#include "support/procedural_meshes.hpp"

using namespace dfm::solver;

namespace {

constexpr OrderingMethod all_methods[] = {OrderingMethod::identity, OrderingMethod::minimum_degree};

// Nonzeros of L for A under `perm`.
std::size_t factor_nonzeros(const CsrMatrix& a, const std::vector<std::uint32_t>& perm) {
    CholeskySymbolic sym;
    REQUIRE(analyze_cholesky(a, perm, sym).is_ok());
    return sym.factor_nonzeros;
}

// A block-diagonal matrix: several random SPD blocks and isolated unknowns.
CsrMatrix disconnected_matrix() {
    std::vector<Triplet> triplets;
    std::uint32_t base = 0;
    for (const std::size_t size : {40u, 1u, 300u, 1u, 1u, 7u}) {
        const CsrMatrix block = dfm::test::random_spd(size, 6, size);
        for (std::size_t i = 0; i < block.rows; ++i)
            for (std::size_t p = block.row_offsets[i]; p < block.row_offsets[i + 1]; ++p)
                triplets.push_back({base + static_cast<std::uint32_t>(i),
                                    base + block.col_indices[p], block.values[p]});
        base += static_cast<std::uint32_t>(size);
    }
    return csr_from_triplets(base, base, triplets);
}

// Empty, tiny, random, grid, disconnected, mesh, star and dense patterns.
std::vector<CsrMatrix> ordered_matrices() {
    return {
        CsrMatrix{0, 0, {0}, {}, {}},
        dfm::test::random_spd(1, 0, 1),
        dfm::test::random_spd(2, 2, 1),
        dfm::test::random_spd(500, 12, 3),
        dfm::test::normal_product(dfm::test::grid_laplacian(37, 23), 0.0),
        disconnected_matrix(),
        dfm::test::normal_product(
            dfm::test::mesh_laplacian(dfm::test::make_limb(12, 30, 0.5, 4.0), 0.01), 0.0),
        dfm::test::star_matrix(400),
        dfm::test::complete_matrix(30),
    };
}

}  // namespace

TEST_CASE("solver: every ordering is a permutation") {
    for (const CsrMatrix& a : ordered_matrices()) {
        for (const OrderingMethod method : all_methods) {
            CAPTURE(a.rows);
            CAPTURE(ordering_method_name(method));
            const std::vector<std::uint32_t> perm = fill_reducing_ordering(a, method);
            CHECK(is_permutation(perm, a.rows));
            CHECK(perm == fill_reducing_ordering(a, method));  // deterministic
        }
    }
    CHECK_FALSE(is_permutation(std::vector<std::uint32_t>{0, 0}, 2));
    CHECK_FALSE(is_permutation(std::vector<std::uint32_t>{0, 2}, 2));
    CHECK_FALSE(is_permutation(std::vector<std::uint32_t>{0}, 2));
}

TEST_CASE("solver: minimum degree gives the same order in 32-bit and 64-bit list positions") {
    for (const CsrMatrix& a : ordered_matrices()) {
        CAPTURE(a.rows);
        const SymmetricGraph g = symmetric_graph(a);
        const std::vector<std::uint32_t> narrow = minimum_degree_ordering(g);
        CHECK(is_permutation(narrow, a.rows));
        CHECK(narrow == minimum_degree_ordering_64(g));
    }
}

TEST_CASE("solver: minimum degree needs far less fill than the identity") {
    SUBCASE("grid bi-Laplacian") {
        const CsrMatrix a = dfm::test::normal_product(dfm::test::grid_laplacian(40, 40), 0.0);
        const std::size_t identity = factor_nonzeros(a, identity_ordering(a.rows));
        const std::size_t degree =
            factor_nonzeros(a, fill_reducing_ordering(a, OrderingMethod::minimum_degree));
        CAPTURE(identity);
        CAPTURE(degree);
        CHECK(degree < identity * 6 / 10);
    }
    SUBCASE("sphere mesh bi-Laplacian, vertices in subdivision order") {
        const CsrMatrix a = dfm::test::normal_product(
            dfm::test::mesh_laplacian(dfm::test::make_icosphere(4), 0.01), 0.0);
        const std::size_t identity = factor_nonzeros(a, identity_ordering(a.rows));
        const std::size_t degree =
            factor_nonzeros(a, fill_reducing_ordering(a, OrderingMethod::minimum_degree));
        CAPTURE(identity);
        CAPTURE(degree);
        CHECK(degree < identity / 3);
    }
}

TEST_CASE("solver: symmetric_graph symmetrises the pattern and drops the diagonal") {
    std::vector<Triplet> triplets = {{0, 0, 1.0}, {0, 2, 1.0}, {1, 1, 1.0}, {2, 1, 1.0},
                                     {2, 2, 1.0}, {3, 0, 1.0}, {0, 3, 1.0}};
    const CsrMatrix a = csr_from_triplets(4, 4, triplets);
    CHECK_FALSE(has_symmetric_pattern(a));
    const SymmetricGraph g = symmetric_graph(a);
    CHECK(g.size() == 4);
    CHECK(std::vector<std::uint32_t>(g.of(0).begin(), g.of(0).end()) ==
          std::vector<std::uint32_t>{2, 3});
    CHECK(std::vector<std::uint32_t>(g.of(1).begin(), g.of(1).end()) ==
          std::vector<std::uint32_t>{2});
    CHECK(std::vector<std::uint32_t>(g.of(2).begin(), g.of(2).end()) ==
          std::vector<std::uint32_t>{0, 1});
    CHECK(std::vector<std::uint32_t>(g.of(3).begin(), g.of(3).end()) ==
          std::vector<std::uint32_t>{0});
    CHECK(has_symmetric_pattern(dfm::test::random_spd(50, 5, 2)));
}

TEST_CASE("solver: has_symmetric_pattern finds every entry without its twin") {
    std::mt19937 rng(17);
    std::size_t asymmetric = 0;
    for (int trial = 0; trial < 200; ++trial) {
        const std::size_t n = rng() % 12 + 1;
        // A symmetric pattern, with or without diagonal entries, then on most
        // trials one entry added or removed on one side only.
        std::set<std::pair<std::uint32_t, std::uint32_t>> entries;
        for (std::size_t k = rng() % (2 * n * n / 3 + 1); k > 0; --k) {
            const auto i = static_cast<std::uint32_t>(rng() % n);
            const auto j = static_cast<std::uint32_t>(rng() % n);
            entries.insert({i, j});
            entries.insert({j, i});
        }
        if (rng() % 4 != 0) {
            const std::pair<std::uint32_t, std::uint32_t> e{static_cast<std::uint32_t>(rng() % n),
                                                            static_cast<std::uint32_t>(rng() % n)};
            if (entries.count(e) != 0) {
                entries.erase(e);
            } else {
                entries.insert(e);
            }
        }
        std::vector<Triplet> triplets;
        for (const auto& [i, j] : entries) triplets.push_back({i, j, 1.0});
        const CsrMatrix a = csr_from_triplets(n, n, triplets);
        bool symmetric = true;
        for (const auto& [i, j] : entries) symmetric = symmetric && entries.count({j, i}) != 0;
        CAPTURE(n);
        CHECK(has_symmetric_pattern(a) == symmetric);
        asymmetric += symmetric ? 0 : 1;
    }
    CHECK(asymmetric > 50);
}

TEST_CASE("solver: elimination tree and column counts match a dense symbolic factorization") {
    for (const std::uint64_t seed : {1u, 2u, 3u}) {
        const CsrMatrix a = dfm::test::random_spd(60, 4, seed);
        std::vector<std::uint32_t> perm = fill_reducing_ordering(a, OrderingMethod::minimum_degree);
        if (seed == 3) perm = identity_ordering(a.rows);
        // Postorder first: the column counts need it.
        const std::vector<std::uint32_t> tree =
            elimination_tree(permuted_columns(a, perm, inverse_permutation(perm)));
        const std::vector<std::uint32_t> post = tree_postorder(tree);
        CHECK(is_permutation(post, a.rows));
        std::vector<std::uint32_t> order(a.rows);
        for (std::size_t k = 0; k < a.rows; ++k) order[k] = perm[post[k]];
        const std::vector<std::uint32_t> inverse = inverse_permutation(order);
        const PermutedColumns pattern = permuted_columns(a, order, inverse);
        const std::vector<std::uint32_t> parent = elimination_tree(pattern);
        const std::vector<std::uint32_t> counts = factor_column_counts(pattern, parent);
        CHECK(renumbered_columns(permuted_columns(a, perm, inverse_permutation(perm)), post,
                                 inverse_permutation(post))
                  .rows == pattern.rows);

        // Boolean Gaussian elimination on the permuted pattern.
        const std::size_t n = a.rows;
        std::vector<char> filled(n * n, 0);
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t p = a.row_offsets[i]; p < a.row_offsets[i + 1]; ++p)
                filled[inverse[i] * n + inverse[a.col_indices[p]]] = 1;
        for (std::size_t j = 0; j < n; ++j)
            for (std::size_t i = j + 1; i < n; ++i)
                if (filled[i * n + j])
                    for (std::size_t l = j + 1; l < n; ++l)
                        if (filled[l * n + j]) filled[i * n + l] = filled[l * n + i] = 1;
        for (std::size_t j = 0; j < n; ++j) {
            std::uint32_t count = 1;
            std::uint32_t first_below = no_parent;
            for (std::size_t i = n; i-- > j + 1;) {
                if (!filled[i * n + j]) continue;
                ++count;
                first_below = static_cast<std::uint32_t>(i);
            }
            CAPTURE(j);
            CHECK(counts[j] == count);
            CHECK(parent[j] == first_below);
            if (parent[j] != no_parent) CHECK(parent[j] > j);
        }
    }
}
