#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "jobs/worker_pool.hpp"
#include "solver/ordering.hpp"
#include "solver/pbcg.hpp"
#include "solver/preconditioner.hpp"
#include "test_system.hpp"

namespace dfm::solver_bench {

// Times are in milliseconds: the median over the repetitions, and for the
// totals also the fastest (on a shared machine the median carries the noise
// of other work).
struct FactorMeasure {
    solver::OrderingMethod ordering{};
    double graph_ms = 0.0;
    double ordering_ms = 0.0;
    double symbolic_ms = 0.0;
    double numeric_ms = 0.0;
    double setup_ms = 0.0;  // the four above, summed per run
    double setup_min_ms = 0.0;
    double solve_k3_ms = 0.0;  // one forward and back solve for x, y and z
    double solve_k3_min_ms = 0.0;
    std::size_t factor_nonzeros = 0;
    std::size_t stored_values = 0;
    std::size_t supernodes = 0;
    double flops = 0.0;
    double solve_relative_residual = 0.0;
};

FactorMeasure measure_factor(const TestSystem& system, solver::OrderingMethod ordering,
                             jobs::WorkerPool& pool, int repeat);

// One frame of a drag: the previous solution is the mesh itself, the handle
// moves by 1% of the diagonal, the solve starts from the previous solution
// (warm) or from zero (cold).
struct Frame {
    std::vector<double> rhs;
    std::vector<double> previous;
    std::vector<double> reference;  // the new solution, from a refined direct solve
};

Frame make_frame(const TestSystem& system, const mesh::Mesh& mesh, jobs::WorkerPool& pool);

struct SolveMeasure {
    std::string preconditioner;
    bool warm = false;
    double setup_ms = 0.0;
    double solve_ms = 0.0;
    double solve_min_ms = 0.0;
    std::size_t iterations = 0;
    bool converged = false;
    bool stagnated = false;
    double error_estimate = 0.0;     // max over x, y, z of max |M⁻¹ r|, over the diagonal
    double relative_residual = 0.0;  // max over x, y, z
    double true_error = 0.0;         // max |x − reference| over the diagonal
};

SolveMeasure measure_pcg(const TestSystem& system, const Frame& frame,
                         solver::PreconditionerKind kind, bool warm,
                         const solver::PbcgOptions& options, int repeat);

}  // namespace dfm::solver_bench
