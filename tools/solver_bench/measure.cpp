#include "measure.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "solver/cholesky_symbolic.hpp"
#include "solver/pbcg.hpp"
#include "solver/sparse_cholesky.hpp"
#include "solver/symmetric_graph.hpp"

namespace dfm::solver_bench {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

double fastest(const std::vector<double>& v) {
    return v.empty() ? 0.0 : *std::min_element(v.begin(), v.end());
}

double relative_residual(const solver::CsrMatrix& a, const std::vector<double>& x,
                         const std::vector<double>& b) {
    std::vector<double> ax(b.size());
    a.multiply(x, ax, 3);
    double r = 0.0;
    double n = 0.0;
    for (std::size_t i = 0; i < b.size(); ++i) {
        r += (b[i] - ax[i]) * (b[i] - ax[i]);
        n += b[i] * b[i];
    }
    return std::sqrt(r / n);
}

}  // namespace

FactorMeasure measure_factor(const TestSystem& system, solver::OrderingMethod ordering,
                             jobs::WorkerPool& pool, int repeat) {
    const solver::CsrMatrix& a = system.matrix;
    FactorMeasure out;
    out.ordering = ordering;
    std::vector<double> graph, order, symbolic, numeric, setup, solve;
    std::vector<double> b(a.rows * 3);
    for (std::size_t i = 0; i < b.size(); ++i) b[i] = std::sin(0.1 * static_cast<double>(i));
    std::vector<double> x(b.size());
    std::vector<double> work;
    for (int r = 0; r < repeat; ++r) {
        solver::SparseCholesky chol;
        const Clock::time_point t0 = Clock::now();
        const solver::SymmetricGraph g = solver::symmetric_graph(a);
        const Clock::time_point t1 = Clock::now();
        const std::vector<std::uint32_t> perm = solver::fill_reducing_ordering(g, ordering);
        const Clock::time_point t2 = Clock::now();
        if (!chol.analyze(a, perm)) return out;
        const Clock::time_point t3 = Clock::now();
        if (!chol.factorize(a, &pool)) return out;
        const Clock::time_point t4 = Clock::now();
        graph.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
        order.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
        symbolic.push_back(std::chrono::duration<double, std::milli>(t3 - t2).count());
        numeric.push_back(std::chrono::duration<double, std::milli>(t4 - t3).count());
        setup.push_back(std::chrono::duration<double, std::milli>(t4 - t0).count());
        work.resize(chol.solve_work_size(3, pool.thread_count()));
        for (int s = 0; s < 3; ++s) {
            const Clock::time_point t5 = Clock::now();
            chol.solve(b, x, 3, work, &pool);
            solve.push_back(ms_since(t5));
        }
        const solver::CholeskySymbolic& info = chol.symbolic();
        out.factor_nonzeros = info.factor_nonzeros;
        out.stored_values = info.stored_values;
        out.supernodes = info.supernode_count();
        out.flops = info.flops;
    }
    out.graph_ms = median(graph);
    out.ordering_ms = median(order);
    out.symbolic_ms = median(symbolic);
    out.numeric_ms = median(numeric);
    out.setup_ms = median(setup);
    out.setup_min_ms = fastest(setup);
    out.solve_k3_ms = median(solve);
    out.solve_k3_min_ms = fastest(solve);
    out.solve_relative_residual = relative_residual(a, x, b);
    return out;
}

Frame make_frame(const TestSystem& system, const mesh::Mesh& mesh, jobs::WorkerPool& pool) {
    const solver::CsrMatrix& a = system.matrix;
    const std::size_t n = a.rows;
    Frame frame;
    frame.previous.resize(n * 3);
    for (std::size_t i = 0; i < n; ++i)
        for (int c = 0; c < 3; ++c) frame.previous[i * 3 + c] = mesh.positions[i][c];
    frame.rhs.resize(n * 3);
    a.multiply(frame.previous, frame.rhs, 3);
    const double step = 0.01 * system.diagonal;
    for (const std::size_t v : system.moving) frame.rhs[v * 3] += system.handle_weight[v] * step;

    // The reference: a direct solve refined until rounding stops it.
    solver::CholeskyPreconditioner m(solver::OrderingMethod::minimum_degree, &pool);
    frame.reference = frame.previous;
    if (!m.setup(a)) return frame;
    solver::PbcgWorkspace work(n, 3);
    solver::PbcgResult result;
    solver::PbcgOptions options;
    options.tolerance = 0.0;
    options.max_iterations = 10;
    options.stagnation_limit = 2;
    options.pool = &pool;
    (void)solver::pbcg_solve(a, m, frame.rhs, frame.reference, 3, options, work, result);
    return frame;
}

SolveMeasure measure_pcg(const TestSystem& system, const Frame& frame,
                         solver::PreconditionerKind kind, bool warm,
                         const solver::PbcgOptions& options, int repeat) {
    const solver::CsrMatrix& a = system.matrix;
    const std::size_t n = a.rows;
    SolveMeasure out;
    out.warm = warm;
    std::unique_ptr<solver::Preconditioner> m = solver::make_preconditioner(kind, options.pool);
    out.preconditioner = m->name();
    const Clock::time_point t0 = Clock::now();
    if (!m->setup(a)) return out;
    out.setup_ms = ms_since(t0);

    solver::PbcgWorkspace work(n, 3);
    solver::PbcgResult result;
    std::vector<double> x;
    std::vector<double> times;
    for (int r = 0; r < repeat; ++r) {
        x = warm ? frame.previous : std::vector<double>(n * 3, 0.0);
        const Clock::time_point t1 = Clock::now();
        if (!solver::pbcg_solve(a, *m, frame.rhs, x, 3, options, work, result)) return out;
        times.push_back(ms_since(t1));
    }
    out.solve_ms = median(times);
    out.solve_min_ms = fastest(times);
    out.iterations = result.iterations;
    out.converged = result.converged;
    for (const solver::PbcgColumnResult& column : result.columns) {
        out.stagnated = out.stagnated || column.stagnated;
        out.error_estimate = std::max(out.error_estimate, column.error_estimate / system.diagonal);
        out.relative_residual = std::max(out.relative_residual, column.relative_residual);
    }
    for (std::size_t i = 0; i < x.size(); ++i)
        out.true_error =
            std::max(out.true_error, std::abs(x[i] - frame.reference[i]) / system.diagonal);
    return out;
}

}  // namespace dfm::solver_bench
