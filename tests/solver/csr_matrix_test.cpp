#include <doctest/doctest.h>

#include <limits>
#include <vector>

#include "jobs/scheduler.hpp"
#include "solver/csr_matrix.hpp"
#include "solver/parallel_kernels.hpp"
#include "solver/test_matrices.hpp"

using namespace dfm::solver;

TEST_CASE("solver: csr_from_triplets sums duplicates and sorts each row") {
    std::vector<Triplet> triplets = {{1, 2, 1.0},  {0, 1, 2.0}, {1, 0, 3.0}, {1, 2, 4.0},
                                     {0, 1, -2.0}, {2, 2, 5.0}, {1, 2, 0.5}};
    const CsrMatrix m = csr_from_triplets(3, 3, triplets);
    CHECK(m.rows == 3);
    CHECK(m.cols == 3);
    CHECK(m.row_offsets == dfm::PooledVector<std::size_t>{0, 1, 3, 4});
    CHECK(m.col_indices == dfm::PooledVector<std::uint32_t>{1, 0, 2, 2});
    // A duplicate that cancels stays stored, as an explicit zero.
    CHECK(m.values == dfm::PooledVector<double>{0.0, 3.0, 5.5, 5.0});
    CHECK(m.nonzeros() == 4);
    CHECK(m.diagonal() == std::vector<double>{0.0, 0.0, 5.0});
}

TEST_CASE("solver: multiply matches the dense product") {
    const CsrMatrix a = dfm::test::random_nonsymmetric(23, 6, 7);
    const std::vector<double> dense = dfm::test::to_dense(a);
    for (const std::size_t k : {1u, 3u}) {
        CAPTURE(k);
        const std::vector<double> x = dfm::test::random_vector(23 * k, 11);
        std::vector<double> y(23 * k);
        a.multiply(x, y, k);
        for (std::size_t i = 0; i < 23; ++i) {
            for (std::size_t c = 0; c < k; ++c) {
                double sum = 0.0;
                for (std::size_t j = 0; j < 23; ++j) sum += dense[i * 23 + j] * x[j * k + c];
                CHECK(y[i * k + c] == doctest::Approx(sum).epsilon(1e-13));
            }
        }
    }
}

TEST_CASE("solver: the parallel product gives CsrMatrix::multiply's bits for every width") {
    const CsrMatrix a = dfm::test::random_nonsymmetric(3000, 9, 31);
    dfm::jobs::Scheduler pool(dfm::jobs::SchedulerConfig::threads(2));
    for (const std::size_t k : {1u, 2u, 3u, 5u}) {
        CAPTURE(k);
        const std::vector<double> x = dfm::test::random_vector(a.cols * k, 32 + k);
        std::vector<double> expected(a.rows * k), serial(a.rows * k), shared(a.rows * k, 7.0);
        a.multiply(x, expected, k);
        kernels::multiply(a, x, serial, k, nullptr);
        kernels::multiply(a, x, shared, k, &pool);
        for (std::size_t i = 0; i < expected.size(); ++i) {
            REQUIRE(serial[i] == expected[i]);
            REQUIRE(shared[i] == expected[i]);
        }
    }
}

TEST_CASE("solver: the residual pass gives the bits of the product, max_abs and dot") {
    const CsrMatrix a = dfm::test::random_nonsymmetric(5000, 9, 41);
    dfm::jobs::Scheduler pool(dfm::jobs::SchedulerConfig::threads(2));
    for (const std::size_t k : {1u, 2u, 3u}) {
        CAPTURE(k);
        const std::size_t size = a.rows * k;
        const std::vector<double> x = dfm::test::random_vector(a.cols * k, 50 + k);
        std::vector<double> b = dfm::test::random_vector(size, 60 + k);
        std::vector<double> expected(size);
        kernels::multiply(a, x, expected, k, nullptr);
        for (std::size_t i = 0; i < size; ++i) expected[i] = b[i] - expected[i];
        std::vector<double> partial(kernels::block_count(a.rows) * 3 * k);
        std::vector<double> largest(k), r2(k), b2(k);
        kernels::max_abs(expected, a.rows, k, largest, partial, nullptr);
        kernels::dot(expected, expected, a.rows, k, r2, partial, nullptr);
        kernels::dot(b, b, a.rows, k, b2, partial, nullptr);
        for (dfm::jobs::WorkerPool* on : {static_cast<dfm::jobs::WorkerPool*>(nullptr),
                                          static_cast<dfm::jobs::WorkerPool*>(&pool)}) {
            CAPTURE(on != nullptr);
            std::vector<double> r(size, 7.0), got_largest(k), got_r2(k), got_b2(k);
            kernels::residual(a, b, x, r, k, got_largest, got_r2, got_b2, partial, on);
            for (std::size_t i = 0; i < size; ++i) REQUIRE(r[i] == expected[i]);
            CHECK(got_largest == largest);
            CHECK(got_r2 == r2);
            CHECK(got_b2 == b2);
        }
    }
    // A NaN in the residual is its largest entry, as max_abs counts it.
    std::vector<double> b = dfm::test::random_vector(a.rows, 70);
    b[4321] = std::numeric_limits<double>::quiet_NaN();
    const std::vector<double> x = dfm::test::random_vector(a.cols, 71);
    std::vector<double> r(a.rows), partial(kernels::block_count(a.rows) * 3), largest(1), r2(1),
        b2(1);
    kernels::residual(a, b, x, r, 1, largest, r2, b2, partial, &pool);
    CHECK(largest[0] == std::numeric_limits<double>::infinity());
}
