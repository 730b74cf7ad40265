#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "jobs/scheduler.hpp"
#include "solver/pbcg.hpp"
#include "solver/test_matrices.hpp"

using namespace dfm::solver;

namespace {

constexpr PreconditionerKind all_kinds[] = {PreconditionerKind::jacobi,
                                            PreconditionerKind::incomplete_cholesky,
                                            PreconditionerKind::cholesky};

struct Outcome {
    std::vector<double> x;
    PbcgResult result;
};

Outcome run(const CsrMatrix& a, Preconditioner& m, const std::vector<double>& b,
            std::vector<double> x, std::size_t k, const PbcgOptions& options) {
    PbcgWorkspace work(a.rows, k);
    Outcome out;
    REQUIRE(pbcg_solve(a, m, b, x, k, options, work, out.result).is_ok());
    out.x = std::move(x);
    REQUIRE(out.result.columns.size() == k);
    return out;
}

std::unique_ptr<Preconditioner> prepared(PreconditionerKind kind, const CsrMatrix& a,
                                         dfm::jobs::WorkerPool* pool = nullptr) {
    std::unique_ptr<Preconditioner> m = make_preconditioner(kind, pool);
    REQUIRE(m->setup(a).is_ok());
    return m;
}

double max_error(const std::vector<double>& x, const std::vector<double>& exact) {
    double e = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) e = std::max(e, std::abs(x[i] - exact[i]));
    return e;
}

// A bi-Laplacian on a grid, the shape of the editing system.
CsrMatrix grid_system(std::size_t side) {
    return dfm::test::normal_product(dfm::test::grid_laplacian(side, side), 1e-6);
}

}  // namespace

TEST_CASE("solver: PCG matches a dense solve on random SPD systems, each preconditioner") {
    const CsrMatrix a = dfm::test::random_spd(120, 8, 31);
    const std::vector<double> b = dfm::test::random_vector(360, 32);
    const std::vector<double> reference = dfm::test::dense_solve(a, b, 3);
    for (const PreconditionerKind kind : all_kinds) {
        auto m = prepared(kind, a);
        CAPTURE(m->name());
        PbcgOptions options;
        options.tolerance = 1e-13;
        const Outcome out = run(a, *m, b, std::vector<double>(360, 0.0), 3, options);
        CHECK(out.result.converged);
        CHECK(dfm::test::relative_difference(out.x, reference) < 1e-10);
        for (const PbcgColumnResult& column : out.result.columns) {
            CHECK(column.converged);
            CHECK_FALSE(column.breakdown);
            CHECK(column.error_estimate <= 1e-13);
            CHECK(column.relative_residual < 1e-10);
        }
        if (kind == PreconditionerKind::cholesky) CHECK(out.result.iterations <= 2);
    }
}

TEST_CASE("solver: a warm start at the solution takes no iteration and is converged") {
    const CsrMatrix a = grid_system(20);
    const std::vector<double> b = dfm::test::random_vector(a.rows * 3, 6);
    auto chol = prepared(PreconditionerKind::cholesky, a);
    std::vector<double> exact(b.size());
    chol->apply(b, exact, 3);
    for (const PreconditionerKind kind : all_kinds) {
        auto m = prepared(kind, a);
        CAPTURE(m->name());
        PbcgOptions options;
        // The factor's solution is exact up to rounding; of its residual,
        // IC(0) makes an error estimate of about 1e-9 on this system
        // (condition about 1e8), Jacobi 1e-12, the factor itself 1e-14.
        options.tolerance = 1e-8;
        const Outcome out = run(a, *m, b, exact, 3, options);
        CHECK(out.result.converged);
        CHECK(out.result.iterations == 0);
        CHECK(out.x == exact);
    }
}

TEST_CASE("solver: a slightly wrong warm start is not converged until the error is small") {
    const std::size_t side = 30;
    const CsrMatrix a = grid_system(side);
    const std::vector<double> b = dfm::test::random_vector(a.rows * 3, 7);
    auto m = prepared(PreconditionerKind::cholesky, a);
    std::vector<double> exact(b.size());
    m->apply(b, exact, 3);
    // A smooth error: its residual is tiny relative to b, which fools a stop
    // relative to the residual, but it is far above the tolerance. The
    // tolerance stays well above what rounding allows for this conditioning.
    double size = 0.0;
    for (const double v : exact) size = std::max(size, std::abs(v));
    const double offset = 1e-5 * size;
    std::vector<double> start = exact;
    for (std::size_t y = 0; y < side; ++y)
        for (std::size_t x = 0; x < side; ++x)
            for (std::size_t c = 0; c < 3; ++c)
                start[(y * side + x) * 3 + c] += offset *
                                                 std::sin(3.14159 * (x + 1.0) / (side + 1.0)) *
                                                 std::sin(3.14159 * (y + 1.0) / (side + 1.0));
    REQUIRE(dfm::test::relative_residual(a, start, b, 3) < 1e-6);
    REQUIRE(max_error(start, exact) > 0.9 * offset);

    PbcgOptions options;
    options.tolerance = 1e-8 * size;
    options.max_iterations = 0;
    const Outcome capped = run(a, *m, b, start, 3, options);
    CHECK_FALSE(capped.result.converged);
    CHECK(capped.result.columns[0].error_estimate > 0.9 * offset);

    options.max_iterations = 100;
    const Outcome out = run(a, *m, b, start, 3, options);
    CHECK(out.result.converged);
    CHECK(out.result.iterations >= 1);
    CHECK(max_error(out.x, exact) <= options.tolerance);
}

TEST_CASE("solver: b = 0 converges to x = 0 without NaN") {
    const CsrMatrix a = grid_system(10);
    const std::vector<double> zero(a.rows * 3, 0.0);
    for (const PreconditionerKind kind : all_kinds) {
        auto m = prepared(kind, a);
        CAPTURE(m->name());
        PbcgOptions options;
        options.tolerance = 1e-12;
        options.max_iterations = 5000;
        const Outcome from_zero = run(a, *m, zero, zero, 3, options);
        CHECK(from_zero.result.converged);
        CHECK(from_zero.result.iterations == 0);
        CHECK(from_zero.x == zero);
        CHECK(from_zero.result.columns[0].relative_residual == 0.0);

        const Outcome from_random =
            run(a, *m, zero, dfm::test::random_vector(zero.size(), 8), 3, options);
        CHECK(from_random.result.converged);
        for (const double v : from_random.x) CHECK(std::isfinite(v));
        for (const PbcgColumnResult& column : from_random.result.columns)
            CHECK(std::isfinite(column.relative_residual));
    }
}

TEST_CASE("solver: a breakdown is reported, never NaN") {
    // Jacobi's M⁻¹ = diag(1, −1) makes ρ = rᵀ M⁻¹ r = 0 for r = (1, −1).
    std::vector<Triplet> triplets = {{0, 0, 1.0}, {1, 1, -1.0}};
    const CsrMatrix a = csr_from_triplets(2, 2, triplets);
    JacobiPreconditioner m;
    REQUIRE(m.setup(a).is_ok());
    const Outcome out = run(a, m, {1.0, -1.0}, {0.0, 0.0}, 1, PbcgOptions{});
    CHECK_FALSE(out.result.converged);
    CHECK(out.result.columns[0].breakdown);
    CHECK(out.result.iterations == 0);
    CHECK(out.x == std::vector<double>{0.0, 0.0});
    CHECK(std::isfinite(out.result.columns[0].error_estimate));
    CHECK(out.result.columns[0].relative_residual == 1.0);
}

TEST_CASE("solver: the iteration cap stops an unconverged solve") {
    const CsrMatrix a = grid_system(20);
    JacobiPreconditioner m;
    REQUIRE(m.setup(a).is_ok());
    PbcgOptions options;
    options.tolerance = 1e-14;
    options.max_iterations = 5;
    const std::vector<double> b = dfm::test::random_vector(a.rows, 9);
    const Outcome out = run(a, m, b, std::vector<double>(a.rows, 0.0), 1, options);
    CHECK_FALSE(out.result.converged);
    CHECK(out.result.iterations == 5);
    CHECK_FALSE(out.result.columns[0].breakdown);
    CHECK(out.result.columns[0].relative_residual ==
          doctest::Approx(dfm::test::relative_residual(a, out.x, b, 1)).epsilon(1e-6));
}

TEST_CASE("solver: a tolerance below the rounding floor stagnates instead of looping") {
    const CsrMatrix a = grid_system(25);
    const std::vector<double> b = dfm::test::random_vector(a.rows * 3, 14);
    auto m = prepared(PreconditionerKind::cholesky, a);
    PbcgOptions options;
    options.tolerance = 0.0;
    options.max_iterations = 40;
    // The default for an exact preconditioner stops it.
    const Outcome stopped = run(a, *m, b, std::vector<double>(b.size(), 0.0), 3, options);
    CHECK_FALSE(stopped.result.converged);
    CHECK(stopped.result.iterations < 15);
    for (const PbcgColumnResult& column : stopped.result.columns) {
        CHECK(column.stagnated);
        CHECK_FALSE(column.breakdown);
        CHECK(column.relative_residual < 1e-12);
    }
    options.stagnation_limit = options.max_iterations + 1;
    const Outcome capped = run(a, *m, b, std::vector<double>(b.size(), 0.0), 3, options);
    CHECK(capped.result.iterations == 40);
    CHECK_FALSE(capped.result.columns[0].stagnated);
    CHECK_FALSE(make_preconditioner(PreconditionerKind::jacobi)->is_exact());
    CHECK_FALSE(make_preconditioner(PreconditionerKind::incomplete_cholesky)->is_exact());
    CHECK(m->is_exact());
}

TEST_CASE("solver: k = 3 gives the same bits as three k = 1 solves") {
    const CsrMatrix a = grid_system(15);
    const std::size_t n = a.rows;
    const std::vector<double> b = dfm::test::random_vector(n * 3, 10);
    for (const PreconditionerKind kind : all_kinds) {
        auto m = prepared(kind, a);
        CAPTURE(m->name());
        PbcgOptions options;
        options.tolerance = 1e-9;
        options.max_iterations = 200;
        const Outcome together = run(a, *m, b, std::vector<double>(n * 3, 0.0), 3, options);
        for (std::size_t c = 0; c < 3; ++c) {
            std::vector<double> bc(n);
            for (std::size_t i = 0; i < n; ++i) bc[i] = b[i * 3 + c];
            const Outcome alone = run(a, *m, bc, std::vector<double>(n, 0.0), 1, options);
            CHECK(alone.result.columns[0].iterations == together.result.columns[c].iterations);
            CHECK(alone.result.columns[0].converged == together.result.columns[c].converged);
            for (std::size_t i = 0; i < n; ++i) REQUIRE(alone.x[i] == together.x[i * 3 + c]);
        }
    }
}

TEST_CASE("solver: PBCG is bit-identical with 1 and 2 threads") {
    // Several row blocks, so the parallel kernels really split.
    const CsrMatrix a = grid_system(80);
    const std::vector<double> b = dfm::test::random_vector(a.rows * 3, 11);
    for (const PreconditionerKind kind : all_kinds) {
        std::vector<Outcome> outcomes;
        for (const std::size_t threads : {0u, 1u, 2u}) {
            dfm::jobs::Scheduler pool(
                dfm::jobs::SchedulerConfig::threads(std::max<std::size_t>(threads, 1)));
            dfm::jobs::WorkerPool* used = threads == 0 ? nullptr : &pool;
            auto m = prepared(kind, a, used);
            CAPTURE(m->name());
            PbcgOptions options;
            options.tolerance = 1e-9;
            options.max_iterations = 60;
            options.pool = used;
            outcomes.push_back(run(a, *m, b, std::vector<double>(b.size(), 0.0), 3, options));
        }
        for (const Outcome& o : outcomes) {
            CHECK(o.x == outcomes[0].x);
            CHECK(o.result.iterations == outcomes[0].result.iterations);
            CHECK(o.result.columns[2].error_estimate ==
                  outcomes[0].result.columns[2].error_estimate);
        }
    }
}

TEST_CASE("solver: PBCG rejects bad arguments") {
    const CsrMatrix a = dfm::test::random_spd(10, 3, 1);
    JacobiPreconditioner m;
    REQUIRE(m.setup(a).is_ok());
    std::vector<double> b(30, 1.0);
    std::vector<double> x(30, 0.0);
    PbcgWorkspace work(10, 3);
    PbcgResult result;
    PbcgOptions options;
    CHECK(pbcg_solve(a, m, b, x, 0, options, work, result).code() == dfm::Errc::invalid_argument);
    CHECK(pbcg_solve(a, m, std::span(b).first(20), x, 3, options, work, result).code() ==
          dfm::Errc::invalid_argument);
    PbcgWorkspace small(10, 2);
    CHECK(pbcg_solve(a, m, b, x, 3, options, small, result).code() == dfm::Errc::invalid_argument);
    options.tolerance = -1.0;
    CHECK(pbcg_solve(a, m, b, x, 3, options, work, result).code() == dfm::Errc::invalid_argument);
    options.tolerance = std::numeric_limits<double>::quiet_NaN();
    CHECK(pbcg_solve(a, m, b, x, 3, options, work, result).code() == dfm::Errc::invalid_argument);
    options.tolerance = 1e-10;
    JacobiPreconditioner unset;
    CHECK(pbcg_solve(a, unset, b, x, 3, options, work, result).code() ==
          dfm::Errc::invalid_argument);
    CHECK(pbcg_solve(a, m, b, x, 2, options, work, result).is_ok());
}
