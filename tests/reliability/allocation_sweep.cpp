#include "reliability/allocation_sweep.hpp"

#include <cstring>
#include <limits>

#include <doctest/doctest.h>

#include "reliability/failing_allocator.hpp"

namespace dfm::test {

namespace {

void* host_alloc(void*, std::size_t size, std::size_t alignment) {
    return counted_allocate(size, alignment);
}

void host_free(void*, void* memory, std::size_t) {
    counted_release(memory);
}

}  // namespace

dfm_allocator failable_host_allocator() {
    return dfm_allocator{host_alloc, host_free, nullptr};
}

std::size_t sweep_allocation_failures(const SweepStep& step) {
    REQUIRE(step(std::numeric_limits<std::size_t>::max()) == DFM_OK);
    for (std::size_t k = 0;; ++k) {
        const std::size_t live_before = live_allocations();
        const dfm_result result = step(k);
        CHECK_MESSAGE(live_allocations() == live_before,
                      "leaked when allocation " << k << " failed");
        if (!allocation_failure_fired()) {
            CHECK_MESSAGE(result == DFM_OK,
                          "allocation " << k << " was never made, yet " << dfm_result_name(result));
            return k;
        }
        // A call may survive a failed allocation (a fallback); if it fails,
        // it says why.
        if (result == DFM_OK) continue;
        CHECK_MESSAGE(result == DFM_ERROR_OUT_OF_MEMORY,
                      "allocation " << k << " failed: " << dfm_result_name(result) << ": "
                                    << dfm_last_error_message());
        CHECK(std::strstr(dfm_last_error_message(), "out of memory") != nullptr);
    }
}

}  // namespace dfm::test
