#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "solver/preconditioner.hpp"
#include "solver/test_matrices.hpp"

using namespace dfm::solver;

namespace {

std::vector<double> apply(Preconditioner& m, const std::vector<double>& r, std::size_t k) {
    std::vector<double> z(r.size());
    m.apply(r, z, k);
    return z;
}

CsrMatrix tridiagonal(std::size_t n) {
    std::vector<Triplet> triplets;
    for (std::uint32_t i = 0; i < n; ++i) {
        triplets.push_back({i, i, 2.5 + 0.01 * i});
        if (i > 0) triplets.push_back({i, i - 1, -1.0});
        if (i + 1 < n) triplets.push_back({i, i + 1, -1.0});
    }
    return csr_from_triplets(n, n, triplets);
}

}  // namespace

TEST_CASE("solver: Jacobi applies the inverse diagonal") {
    const CsrMatrix a = dfm::test::random_nonsymmetric(30, 5, 3);
    JacobiPreconditioner m;
    REQUIRE(m.setup(a).is_ok());
    const std::vector<double> r = dfm::test::random_vector(60, 1);
    const std::vector<double> z = apply(m, r, 2);
    const std::vector<double> d = a.diagonal();
    for (std::size_t i = 0; i < 30; ++i)
        for (std::size_t c = 0; c < 2; ++c)
            CHECK(z[i * 2 + c] == doctest::Approx(r[i * 2 + c] / d[i]).epsilon(1e-15));

    std::vector<Triplet> triplets = {{0, 0, 1.0}, {1, 0, 1.0}, {2, 2, 1.0}};
    const dfm::Status st = m.setup(csr_from_triplets(3, 3, triplets));
    CHECK(st.code() == dfm::Errc::numerical);
    CHECK(st.message().find("row 1") != std::string::npos);
}

TEST_CASE("solver: IC(0) is the exact inverse on a tridiagonal matrix") {
    // No fill outside the pattern, so the incomplete factor is complete.
    const CsrMatrix a = tridiagonal(40);
    IncompleteCholeskyPreconditioner m;
    REQUIRE(m.setup(a).is_ok());
    CHECK(m.shift() == 0.0);
    const std::vector<double> r = dfm::test::random_vector(120, 2);
    const std::vector<double> z = apply(m, r, 3);
    CHECK(dfm::test::relative_difference(z, dfm::test::dense_solve(a, r, 3)) < 1e-13);
}

TEST_CASE("solver: IC(0) retries with a diagonal shift when a pivot breaks down") {
    // Symmetric with a positive diagonal but indefinite: the plain factor
    // breaks down at its second pivot.
    std::vector<Triplet> triplets = {{0, 0, 1.0}, {0, 1, 2.0}, {1, 0, 2.0}, {1, 1, 1.0}};
    const CsrMatrix a = csr_from_triplets(2, 2, triplets);
    IncompleteCholeskyPreconditioner m;
    REQUIRE(m.setup(a).is_ok());
    CHECK(m.shift() > 1.0);
    const std::vector<double> z = apply(m, {1.0, 1.0}, 1);
    CHECK(std::isfinite(z[0]));
    CHECK(std::isfinite(z[1]));
}

TEST_CASE("solver: IC(0) rejects a missing or non-positive diagonal") {
    std::vector<Triplet> missing = {{0, 0, 1.0}, {1, 0, 0.5}, {0, 1, 0.5}};
    IncompleteCholeskyPreconditioner m;
    dfm::Status st = m.setup(csr_from_triplets(2, 2, missing));
    CHECK(st.code() == dfm::Errc::numerical);
    CHECK(st.message().find("row 1") != std::string::npos);
    std::vector<Triplet> negative = {{0, 0, -1.0}};
    CHECK(m.setup(csr_from_triplets(1, 1, negative)).code() == dfm::Errc::numerical);
}

TEST_CASE("solver: the Cholesky preconditioner applies the exact inverse") {
    const CsrMatrix a = dfm::test::random_spd(200, 10, 8);
    CholeskyPreconditioner m;
    REQUIRE(m.setup(a).is_ok());
    const std::vector<double> r = dfm::test::random_vector(600, 3);
    CHECK(dfm::test::relative_difference(apply(m, r, 3), dfm::test::dense_solve(a, r, 3)) < 1e-12);
    CHECK(m.factor().is_factored());
    std::vector<Triplet> indefinite = {{0, 0, 1.0}, {0, 1, 2.0}, {1, 0, 2.0}, {1, 1, 1.0}};
    CHECK(m.setup(csr_from_triplets(2, 2, indefinite)).code() == dfm::Errc::numerical);
}

TEST_CASE("solver: make_preconditioner makes each kind") {
    CHECK(std::string(make_preconditioner(PreconditionerKind::jacobi)->name()) == "jacobi");
    CHECK(std::string(make_preconditioner(PreconditionerKind::incomplete_cholesky)->name()) ==
          "incomplete cholesky");
    CHECK(std::string(make_preconditioner(PreconditionerKind::cholesky)->name()) == "cholesky");
}
