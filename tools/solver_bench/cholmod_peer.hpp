#pragma once

#include <cstddef>

#include "test_system.hpp"

// The anchor the solver is measured against: CHOLMOD's supernodal Cholesky
// (SuiteSparse) on exactly the same matrix and fill-reducing ordering, timed
// as measure_factor times ours. Built into solver_bench only when CMake
// finds CHOLMOD; the library never links it.
namespace dfm::solver_bench {

struct CholmodMeasure {
    double symbolic_ms = 0.0;  // cholmod_analyze_p with our minimum-degree permutation
    double numeric_ms = 0.0;   // cholmod_factorize
    double solve_k3_ms = 0.0;  // cholmod_solve for x, y and z together
    double solve_k3_min_ms = 0.0;
    std::size_t factor_nonzeros = 0;
    double solve_relative_residual = 0.0;
    bool ok = false;
};

CholmodMeasure measure_cholmod(const TestSystem& system, int repeat);

}  // namespace dfm::solver_bench
