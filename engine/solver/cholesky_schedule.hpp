#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "solver/cholesky_symbolic.hpp"

namespace dfm::solver {

// How the factor's supernodes are shared between threads: whole subtrees
// for each thread, balanced by estimated work, then the supernodes above
// them in order. Subtrees are independent, so which thread does one changes
// nothing in the result.
struct CholeskySchedule {
    std::vector<std::vector<std::uint32_t>> subtrees;  // subtree roots, per thread, ascending
    std::vector<std::uint32_t> top;                    // the rest, ascending
};

// Splits subtrees from the top while one holds more than a 2 × threads-th of
// the work, then deals them out longest first to the least loaded thread.
CholeskySchedule make_cholesky_schedule(const CholeskySymbolic& sym, std::size_t threads);

}  // namespace dfm::solver
