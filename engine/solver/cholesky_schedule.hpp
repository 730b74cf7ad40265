#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "solver/cholesky_symbolic.hpp"

namespace dfm::solver {

// How the factor's supernodes are shared between threads: whole subtrees
// for each thread, balanced by a weight per supernode, then the supernodes
// above them in order. Subtrees are independent, so which thread does one
// changes nothing in the result.
struct CholeskySchedule {
    std::vector<std::vector<std::uint32_t>> subtrees;  // subtree roots, per thread, ascending
    std::vector<std::uint32_t> top;                    // the rest, ascending
};

// Splits subtrees from the top while one holds more than a 2 × threads-th of
// the weight, then deals them out heaviest first to the least loaded thread.
// The factorization weighs a supernode by its work (CholeskySymbolic::work);
// the triangular solves, which read each value once, by its stored values
// (solve_weights).
CholeskySchedule make_cholesky_schedule(const CholeskySymbolic& sym, std::span<const double> weight,
                                        std::size_t threads);

// Each supernode's stored values.
std::vector<double> solve_weights(const CholeskySymbolic& sym);

}  // namespace dfm::solver
