#include <doctest/doctest.h>

#include <atomic>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "jobs/scheduler.hpp"
#include "solver/cholesky_schedule.hpp"
#include "solver/elimination_tree.hpp"
#include "solver/sparse_cholesky.hpp"
#include "solver/test_matrices.hpp"
#include "support/procedural_meshes.hpp"

using namespace dfm::solver;

namespace {

constexpr OrderingMethod all_methods[] = {OrderingMethod::identity, OrderingMethod::minimum_degree};

std::vector<double> cholesky_solve(const SparseCholesky& chol, const std::vector<double>& b,
                                   std::size_t k, dfm::jobs::WorkerPool* pool = nullptr) {
    std::vector<double> x(b.size());
    std::vector<double> work(chol.solve_work_size(k, pool != nullptr ? pool->thread_count() : 1));
    chol.solve(b, x, k, work, pool);
    return x;
}

// A copy of `a` with one value changed.
CsrMatrix with_diagonal(CsrMatrix a, std::size_t row, double value) {
    for (std::size_t p = a.row_offsets[row]; p < a.row_offsets[row + 1]; ++p)
        if (a.col_indices[p] == row) a.values[p] = value;
    return a;
}

}  // namespace

TEST_CASE("solver: sparse Cholesky matches a dense solve on random SPD systems") {
    for (const std::size_t n : {1u, 2u, 17u, 150u, 400u}) {
        for (const OrderingMethod method : all_methods) {
            CAPTURE(n);
            CAPTURE(ordering_method_name(method));
            const CsrMatrix a = dfm::test::random_spd(n, 8, n + 100);
            const std::vector<double> b = dfm::test::random_vector(n * 3, n);
            SparseCholesky chol;
            REQUIRE(chol.compute(a, method).is_ok());
            CHECK(chol.is_factored());
            const std::vector<double> x = cholesky_solve(chol, b, 3);
            CHECK(dfm::test::relative_residual(a, x, b, 3) < 1e-12);
            CHECK(dfm::test::relative_difference(x, dfm::test::dense_solve(a, b, 3)) < 1e-12);
        }
    }
}

TEST_CASE("solver: sparse Cholesky handles a dense row and a dense matrix") {
    for (const CsrMatrix& a : {dfm::test::star_matrix(300), dfm::test::complete_matrix(40)}) {
        for (const OrderingMethod method : all_methods) {
            CAPTURE(a.rows);
            CAPTURE(ordering_method_name(method));
            const std::vector<double> b = dfm::test::random_vector(a.rows * 3, 2);
            SparseCholesky chol;
            REQUIRE(chol.compute(a, method).is_ok());
            CHECK(dfm::test::relative_residual(a, cholesky_solve(chol, b, 3), b, 3) < 1e-12);
        }
    }
}

TEST_CASE("solver: sparse Cholesky solves a grid bi-Laplacian to 1e-12") {
    const CsrMatrix a = dfm::test::normal_product(dfm::test::grid_laplacian(22, 19), 0.0);
    const std::vector<double> b = dfm::test::random_vector(a.rows, 5);
    const std::vector<double> reference = dfm::test::dense_solve(a, b, 1);
    for (const OrderingMethod method : all_methods) {
        CAPTURE(ordering_method_name(method));
        SparseCholesky chol;
        REQUIRE(chol.compute(a, method).is_ok());
        const std::vector<double> x = cholesky_solve(chol, b, 1);
        CHECK(dfm::test::relative_residual(a, x, b, 1) < 1e-12);
        CHECK(dfm::test::relative_difference(x, reference) < 1e-10);
    }
}

TEST_CASE("solver: sparse Cholesky solves a sphere mesh's 2-ring system") {
    const CsrMatrix a = dfm::test::normal_product(
        dfm::test::mesh_laplacian(dfm::test::make_icosphere(4), 0.1), 1e-8);
    const std::vector<double> b = dfm::test::random_vector(a.rows * 3, 9);
    SparseCholesky chol;
    REQUIRE(chol.compute(a, OrderingMethod::minimum_degree).is_ok());
    CHECK(dfm::test::relative_residual(a, cholesky_solve(chol, b, 3), b, 3) < 1e-12);
}

TEST_CASE("solver: sparse Cholesky reports a non-positive pivot naming the row") {
    const CsrMatrix spd = dfm::test::random_spd(300, 8, 4);
    for (const OrderingMethod method : all_methods) {
        CAPTURE(ordering_method_name(method));
        SparseCholesky chol;
        const dfm::Status st = chol.compute(with_diagonal(spd, 123, -1.0), method);
        CHECK(st.code() == dfm::Errc::numerical);
        CHECK(st.message().find("row 123 ") != std::string::npos);
        CHECK_FALSE(chol.is_factored());
        // The same pattern factors once the matrix is positive definite again.
        CHECK(chol.factorize(spd).is_ok());
        CHECK(chol.is_factored());
    }
    SparseCholesky chol;
    const CsrMatrix with_nan = with_diagonal(spd, 7, std::numeric_limits<double>::quiet_NaN());
    CHECK(chol.compute(with_nan).code() == dfm::Errc::numerical);
    const CsrMatrix zero = with_diagonal(dfm::test::random_spd(1, 0, 1), 0, 0.0);
    CHECK(chol.compute(zero).code() == dfm::Errc::numerical);
}

TEST_CASE("solver: refactoring the same pattern matches a fresh factorization") {
    const CsrMatrix a = dfm::test::normal_product(dfm::test::grid_laplacian(15, 12), 0.0);
    CsrMatrix scaled = a;
    for (double& v : scaled.values) v *= 3.0;
    scaled = with_diagonal(scaled, 5, scaled.diagonal()[5] + 2.0);
    const std::vector<double> b = dfm::test::random_vector(a.rows * 2, 3);

    SparseCholesky reused;
    REQUIRE(reused.compute(a).is_ok());
    const std::vector<std::uint32_t> perm = reused.symbolic().perm;
    REQUIRE(reused.compute(scaled).is_ok());
    CHECK(reused.symbolic().perm == perm);
    SparseCholesky fresh;
    REQUIRE(fresh.compute(scaled).is_ok());
    CHECK(cholesky_solve(reused, b, 2) == cholesky_solve(fresh, b, 2));
}

TEST_CASE("solver: sparse Cholesky rejects what it cannot factor") {
    SparseCholesky chol;
    const CsrMatrix a = dfm::test::random_spd(20, 4, 1);
    SUBCASE("not square") {
        CsrMatrix wide = a;
        wide.cols = 21;
        CHECK(chol.compute(wide).code() == dfm::Errc::invalid_argument);
    }
    SUBCASE("pattern not symmetric") {
        const CsrMatrix b = dfm::test::random_nonsymmetric(20, 4, 1);
        CHECK(chol.compute(b).code() == dfm::Errc::invalid_argument);
    }
    SUBCASE("ordering not a permutation") {
        std::vector<std::uint32_t> perm = identity_ordering(20);
        perm[3] = 4;
        CHECK(chol.analyze(a, perm).code() == dfm::Errc::invalid_argument);
    }
    SUBCASE("another pattern than the analysed one") {
        REQUIRE(chol.analyze(a).is_ok());
        CHECK(chol.factorize(dfm::test::random_spd(20, 4, 2)).code() ==
              dfm::Errc::invalid_argument);
        CHECK_FALSE(chol.is_factored());
    }
}

TEST_CASE("solver: Cholesky solves of 3 and of 7 vectors equal single-vector solves bit for bit") {
    const CsrMatrix a = dfm::test::normal_product(dfm::test::grid_laplacian(72, 72), 1e-3);
    SparseCholesky chol;
    REQUIRE(chol.compute(a).is_ok());
    // The backward solve keeps its sums in registers for supernodes of 1-4,
    // 5-8, 9-12 and 13-16 columns, in vectors of eight for 17-24 and 25-32
    // where the processor has them, and in memory for wider ones: this
    // factor has each kind, with an even and an odd number of rows below.
    const auto kind_of = [](std::size_t w) -> std::size_t {
        if (w <= 16) return (w + 3) / 4 - 1;
        return w <= 24 ? 4 : w <= 32 ? 5 : 6;
    };
    const dfm::solver::CholeskySymbolic& sym = chol.symbolic();
    for (const std::size_t kind : {0u, 1u, 2u, 3u, 4u, 5u, 6u}) {
        for (const std::size_t parity : {0u, 1u}) {
            bool found = false;
            for (std::size_t s = 0; s < sym.supernode_count(); ++s) {
                const std::size_t w = sym.column_begin[s + 1] - sym.column_begin[s];
                const std::size_t h = sym.row_begin[s + 1] - sym.row_begin[s] - w;
                found = found || (kind_of(w) == kind && h > 0 && h % 2 == parity);
            }
            CAPTURE(kind);
            CAPTURE(parity);
            CHECK(found);
        }
    }
    const std::size_t n = a.rows;
    const std::vector<double> b = dfm::test::random_vector(n * 3, 12);
    const std::vector<double> x = cholesky_solve(chol, b, 3);
    for (std::size_t c = 0; c < 3; ++c) {
        std::vector<double> bc(n);
        for (std::size_t i = 0; i < n; ++i) bc[i] = b[i * 3 + c];
        const std::vector<double> xc = cholesky_solve(chol, bc, 1);
        for (std::size_t i = 0; i < n; ++i) REQUIRE(xc[i] == x[i * 3 + c]);
    }
    // And with more vectors than the specialised widths, in place: the
    // general kernels, whose sums are written apart from the specialised
    // ones', give the same bits too.
    const std::vector<double> b7 = dfm::test::random_vector(n * 7, 13);
    std::vector<double> in_place = b7;
    std::vector<double> work(chol.solve_work_size(7));
    chol.solve(in_place, in_place, 7, work);
    CHECK(dfm::test::relative_residual(a, in_place, b7, 7) < 1e-12);
    for (std::size_t c = 0; c < 7; ++c) {
        std::vector<double> bc(n);
        for (std::size_t i = 0; i < n; ++i) bc[i] = b7[i * 7 + c];
        const std::vector<double> xc = cholesky_solve(chol, bc, 1);
        for (std::size_t i = 0; i < n; ++i) REQUIRE(xc[i] == in_place[i * 7 + c]);
    }
}

TEST_CASE(
    "solver: the backward solve's order has each supernode after its parent, subtrees whole") {
    const CsrMatrix a = dfm::test::normal_product(dfm::test::grid_laplacian(40, 30), 1e-6);
    SparseCholesky chol;
    REQUIRE(chol.compute(a).is_ok());
    const CholeskySymbolic& sym = chol.symbolic();
    const std::size_t count = sym.supernode_count();
    REQUIRE(count > 100);
    REQUIRE(sym.backward_order.size() == count);
    REQUIRE(sym.backward_position.size() == count);
    std::vector<bool> seen(count, false);
    std::size_t roots = 0;
    for (std::size_t i = 0; i < count; ++i) {
        const std::uint32_t s = sym.backward_order[i];
        REQUIRE(s < count);
        CHECK_FALSE(seen[s]);
        seen[s] = true;
        CHECK(sym.backward_position[s] == i);
        if (sym.parent[s] == dfm::solver::no_parent) {
            ++roots;
        } else {
            CHECK(seen[sym.parent[s]]);
        }
        // The subtree rooted at s follows it, whole: the supernodes
        // [subtree_begin[s], s] in some order.
        const std::size_t size = s - sym.subtree_begin[s] + 1;
        REQUIRE(i + size <= count);
        for (std::size_t j = i; j < i + size; ++j) {
            CHECK(sym.backward_order[j] >= sym.subtree_begin[s]);
            CHECK(sym.backward_order[j] <= s);
        }
        // Siblings in ascending order: a supernode's next sibling, if any,
        // comes right after its subtree.
        if (i + size < count && sym.parent[sym.backward_order[i + size]] == sym.parent[s])
            CHECK(sym.backward_order[i + size] > s);
    }
    CHECK(roots >= 1);
}

TEST_CASE("solver: Cholesky factor and solve are bit-identical with 1, 2 and 3 threads") {
    // Large enough that the top supernodes are split between threads.
    const CsrMatrix a = dfm::test::normal_product(dfm::test::grid_laplacian(70, 60), 1e-6);
    const std::vector<double> b = dfm::test::random_vector(a.rows * 3, 21);
    std::vector<std::vector<double>> solutions;
    for (const std::size_t threads : {1u, 2u, 3u}) {
        CAPTURE(threads);
        dfm::jobs::Scheduler pool(dfm::jobs::SchedulerConfig::threads(threads));
        SparseCholesky chol;
        REQUIRE(chol.compute(a, OrderingMethod::minimum_degree, &pool).is_ok());
        solutions.push_back(cholesky_solve(chol, b, 3, &pool));
        CHECK(cholesky_solve(chol, b, 3) == solutions.back());
        CHECK(dfm::test::relative_residual(a, solutions.back(), b, 3) < 1e-10);
        const dfm::Status failed = chol.factorize(with_diagonal(a, 1234, -5.0), &pool);
        CHECK(failed.code() == dfm::Errc::numerical);
        CHECK(failed.message().find("row 1234 ") != std::string::npos);
    }
    for (const std::vector<double>& x : solutions) CHECK(x == solutions[0]);
}

TEST_CASE("solver: a schedule covers every supernode once and splits the heavy subtrees") {
    // Weighed by work (the factorization's) and by stored values (the
    // solves'): every supernode in one thread's subtrees or in the top, a
    // subtree whole, none heavier than a quarter of the whole but a single
    // supernode, and the top's supernodes ascending.
    const CsrMatrix a = dfm::test::normal_product(dfm::test::grid_laplacian(70, 60), 1e-6);
    SparseCholesky chol;
    REQUIRE(chol.analyze(a, OrderingMethod::minimum_degree).is_ok());
    const CholeskySymbolic& sym = chol.symbolic();
    const std::vector<double> values = solve_weights(sym);
    double stored = 0.0;
    for (const double v : values) stored += v;
    CHECK(stored == static_cast<double>(sym.stored_values));
    const std::vector<double> work(sym.work.begin(), sym.work.end());
    for (const std::vector<double>* weight : {&work, &values}) {
        const CholeskySchedule schedule = make_cholesky_schedule(sym, *weight, 2);
        REQUIRE(schedule.subtrees.size() == 2);
        double total = 0.0;
        for (const double w : *weight) total += w;
        std::vector<int> owners(sym.supernode_count(), 0);
        for (const std::vector<std::uint32_t>& roots : schedule.subtrees) {
            for (const std::uint32_t root : roots) {
                double subtree = 0.0;
                for (std::uint32_t s = sym.subtree_begin[root]; s <= root; ++s) {
                    ++owners[s];
                    subtree += (*weight)[s];
                }
                CHECK((subtree <= total / 4.0 || sym.subtree_begin[root] == root));
            }
        }
        for (std::size_t p = 0; p < schedule.top.size(); ++p) {
            ++owners[schedule.top[p]];
            if (p > 0) CHECK(schedule.top[p - 1] < schedule.top[p]);
        }
        for (const int owner : owners) CHECK(owner == 1);
        CHECK(!schedule.top.empty());
    }
}

TEST_CASE("solver: a raised stop flag ends analyze and factorize, a lowered one changes nothing") {
    const CsrMatrix a = dfm::test::normal_product(dfm::test::grid_laplacian(70, 60), 1e-6);
    const std::vector<double> b = dfm::test::random_vector(a.rows * 3, 22);
    for (const std::size_t threads : {1u, 3u}) {
        CAPTURE(threads);
        dfm::jobs::Scheduler pool(dfm::jobs::SchedulerConfig::threads(threads));
        SparseCholesky plain;
        REQUIRE(plain.compute(a, OrderingMethod::minimum_degree, &pool).is_ok());
        const std::vector<double> reference = cholesky_solve(plain, b, 3, &pool);

        std::atomic<bool> stop{false};
        SparseCholesky watched;
        watched.set_stop(&stop);
        REQUIRE(watched.compute(a, OrderingMethod::minimum_degree, &pool).is_ok());
        CHECK_FALSE(watched.stopped());
        CHECK(cholesky_solve(watched, b, 3, &pool) == reference);

        // Raised after the analysis: the numeric phase stops before its first supernode.
        stop = true;
        const dfm::Status numeric = watched.factorize(a, &pool);
        CHECK(numeric.code() == dfm::Errc::cancelled);
        CHECK(watched.stopped());
        CHECK_FALSE(watched.is_factored());
        // Lowered again, the same analysis factors to the same bits.
        stop = false;
        REQUIRE(watched.factorize(a, &pool).is_ok());
        CHECK_FALSE(watched.stopped());
        CHECK(cholesky_solve(watched, b, 3, &pool) == reference);

        // Raised before the analysis: no ordering is computed.
        stop = true;
        SparseCholesky fresh;
        fresh.set_stop(&stop);
        CHECK(fresh.compute(a, OrderingMethod::minimum_degree, &pool).code() ==
              dfm::Errc::cancelled);
        CHECK(fresh.stopped());
        CHECK_FALSE(fresh.is_factored());
        CHECK(fresh.times().ordering_ms == 0.0);
    }
}

TEST_CASE("solver: the factor's memory grows with the system and covers its values") {
    SparseCholesky small, large;
    const CsrMatrix a = dfm::test::normal_product(dfm::test::grid_laplacian(20, 20), 1e-6);
    const CsrMatrix b = dfm::test::normal_product(dfm::test::grid_laplacian(60, 60), 1e-6);
    REQUIRE(small.compute(a).is_ok());
    REQUIRE(large.compute(b).is_ok());
    CHECK(small.memory_bytes() >= small.symbolic().stored_values * sizeof(double));
    CHECK(large.memory_bytes() >= large.symbolic().stored_values * sizeof(double));
    CHECK(large.memory_bytes() > 4 * small.memory_bytes());
}
