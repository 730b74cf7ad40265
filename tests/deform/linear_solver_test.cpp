#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "deform/linear_solver.hpp"
#include "solver/test_matrices.hpp"

using namespace dfm;

namespace {

// A bi-Laplacian, conditioned like an edit's normal matrix, and the
// complete factor of it.
struct System {
    solver::CsrMatrix n = test::normal_product(test::grid_laplacian(24, 24), 1e-4);
    deform::LinearSolver solver;

    System() { REQUIRE(solver.setup(n, solver::PreconditionerKind::cholesky).is_ok()); }

    std::vector<double> rhs(std::uint64_t seed) const {
        test::Random random(seed);
        std::vector<double> b(3 * n.rows);
        for (double& v : b) v = random.uniform(-1.0, 1.0);
        return b;
    }

    // max |x − N⁻¹ b| against a dense solve.
    double error(const std::vector<double>& b, const std::vector<double>& x) const {
        const std::vector<double> exact = test::dense_solve(n, b, 3);
        double worst = 0.0;
        for (std::size_t i = 0; i < x.size(); ++i)
            worst = std::max(worst, std::abs(x[i] - exact[i]));
        return worst;
    }
};

}  // namespace

TEST_CASE(
    "deform: with the complete factor, a verified solve is confirmed by its residual once "
    "measured") {
    System s;
    constexpr double tolerance = 1e-6;
    std::size_t iterations = 0;

    // The first verified solve has nothing to go by: a Krylov solve.
    const std::vector<double> b0 = s.rhs(1);
    std::vector<double> x0(b0.size(), 0.0);
    REQUIRE(s.solver.solve(b0, x0, tolerance, deform::LinearSolver::Accuracy::one_step, iterations)
                .is_ok());
    REQUIRE(s.solver.solve(b0, x0, tolerance, deform::LinearSolver::Accuracy::verified, iterations)
                .is_ok());
    CHECK_FALSE(s.solver.confirmed_by_residual());
    CHECK(s.solver.converged());

    // Later ones, one step of the factor away from their solution, are
    // confirmed by one product with N, and are within the tolerance.
    for (std::uint64_t seed = 2; seed < 6; ++seed) {
        const std::vector<double> b = s.rhs(seed);
        std::vector<double> x(b.size(), 0.0);
        REQUIRE(
            s.solver.solve(b, x, tolerance, deform::LinearSolver::Accuracy::one_step, iterations)
                .is_ok());
        const std::vector<double> step = x;
        REQUIRE(
            s.solver.solve(b, x, tolerance, deform::LinearSolver::Accuracy::verified, iterations)
                .is_ok());
        CHECK(s.solver.confirmed_by_residual());
        CHECK(s.solver.converged());
        CHECK(iterations == 0);
        CHECK(x == step);
        CHECK(s.error(b, x) <= tolerance);
        const double reported = s.solver.relative_residual();
        CHECK(reported == doctest::Approx(test::relative_residual(s.n, x, b, 3)).epsilon(1e-6));
        CHECK(reported < 1e-10);
    }
}

TEST_CASE(
    "deform: a start off its solution is not confirmed by its residual, the Krylov solve mends "
    "it") {
    System s;
    constexpr double tolerance = 1e-6;
    std::size_t iterations = 0;
    const std::vector<double> b0 = s.rhs(7);
    std::vector<double> x0(b0.size(), 0.0);
    REQUIRE(s.solver.solve(b0, x0, tolerance, deform::LinearSolver::Accuracy::verified, iterations)
                .is_ok());

    const std::vector<double> b = s.rhs(8);
    std::vector<double> x(b.size(), 0.0);
    REQUIRE(s.solver.solve(b, x, tolerance, deform::LinearSolver::Accuracy::one_step, iterations)
                .is_ok());
    // Off by 100 tolerances in one entry: its residual is small beside b,
    // but what the factor's measure makes of it is over the tolerance.
    x[3 * 100 + 1] += 100.0 * tolerance;
    REQUIRE(s.error(b, x) > tolerance);
    REQUIRE(s.solver.solve(b, x, tolerance, deform::LinearSolver::Accuracy::verified, iterations)
                .is_ok());
    CHECK_FALSE(s.solver.confirmed_by_residual());
    CHECK(iterations >= 1);
    CHECK(s.solver.converged());
    CHECK(s.error(b, x) <= tolerance);
}
