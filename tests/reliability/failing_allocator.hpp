#pragma once

#include <cstddef>

// The global operator new of the reliability tests, replaced so a test can
// make one chosen allocation fail. Arming is per thread: only allocations
// made by the thread that armed count, so the context's workers and doctest
// itself run undisturbed.
namespace dfm::test {

// From now on, this thread's allocations are counted from 0 and the one
// numbered `fail_at` throws std::bad_alloc (or returns NULL for the nothrow
// forms). Later ones succeed again.
void arm_allocation_failure(std::size_t fail_at);

// Stops counting on this thread; returns how many allocations it counted
// since arming, the failed one included.
std::size_t disarm_allocation_failure();

// Whether the armed failure happened since arming.
bool allocation_failure_fired();

// The same counted, failable allocation for other allocators to build on
// (the C API's host allocator hooks): NULL for the armed allocation.
void* counted_allocate(std::size_t size, std::size_t alignment);
void counted_release(void* memory) noexcept;

// Blocks from every thread allocated through operator new or
// counted_allocate and not yet
// freed: equal before and after a sequence means it leaked nothing.
std::size_t live_allocations();

// Arms for the lifetime of the object, so an early return from a CHECK
// cannot leave the thread armed.
class ArmedAllocationFailure {
public:
    explicit ArmedAllocationFailure(std::size_t fail_at) { arm_allocation_failure(fail_at); }
    ~ArmedAllocationFailure() { disarm_allocation_failure(); }
    ArmedAllocationFailure(const ArmedAllocationFailure&) = delete;
    ArmedAllocationFailure& operator=(const ArmedAllocationFailure&) = delete;
};

}  // namespace dfm::test
