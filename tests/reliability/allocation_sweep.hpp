#pragma once

#include <cstddef>
#include <functional>

#include "dualform/dualform.h"

namespace dfm::test {

// One step of a sweep: set up fresh objects, make the call under test with
// the k-th allocation failing (ArmedAllocationFailure around that call
// only), check the outcome, then destroy everything. Returns the armed
// call's result.
using SweepStep = std::function<dfm_result(std::size_t fail_at)>;

// Runs `step` for k = 0, 1, 2, ... until k is past the call's last
// allocation, checking at every k that a failing call said
// DFM_ERROR_OUT_OF_MEMORY and that the step as a whole leaked nothing.
// Returns the number of allocation points exercised. A first step with k
// past every allocation warms what lives for the whole process (the handle
// registry), so it does not count as a leak.
std::size_t sweep_allocation_failures(const SweepStep& step);

// Host allocator hooks over the counted, failable allocation, so the C
// API's own objects take part in the sweep too.
dfm_allocator failable_host_allocator();

}  // namespace dfm::test
