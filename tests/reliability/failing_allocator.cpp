#include "reliability/failing_allocator.hpp"

#include <atomic>
#include <cstdlib>
#include <new>

namespace {

struct ArmState {
    bool armed = false;
    bool fired = false;
    std::size_t counted = 0;
    std::size_t fail_at = 0;
};

thread_local ArmState arm_state;
std::atomic<std::size_t> live_blocks{0};

// True when this allocation is the armed one: the caller must fail it.
bool take_turn() {
    ArmState& s = arm_state;
    if (!s.armed) return false;
    const bool fail = s.counted == s.fail_at;
    ++s.counted;
    if (fail) s.fired = true;
    return fail;
}

void* allocate(std::size_t size, std::size_t alignment) {
    if (take_turn()) return nullptr;
    if (size == 0) size = 1;
    void* memory = nullptr;
    if (alignment <= alignof(std::max_align_t)) {
        memory = std::malloc(size);
    } else if (posix_memalign(&memory, alignment, size) != 0) {
        memory = nullptr;
    }
    if (memory != nullptr) live_blocks.fetch_add(1, std::memory_order_relaxed);
    return memory;
}

void* allocate_or_throw(std::size_t size, std::size_t alignment) {
    void* memory = allocate(size, alignment);
    if (memory == nullptr) throw std::bad_alloc();
    return memory;
}

void release(void* memory) noexcept {
    if (memory == nullptr) return;
    live_blocks.fetch_sub(1, std::memory_order_relaxed);
    std::free(memory);
}

}  // namespace

namespace dfm::test {

void arm_allocation_failure(std::size_t fail_at) {
    arm_state = ArmState{.armed = true, .fired = false, .counted = 0, .fail_at = fail_at};
}

std::size_t disarm_allocation_failure() {
    arm_state.armed = false;
    return arm_state.counted;
}

bool allocation_failure_fired() {
    return arm_state.fired;
}

void* counted_allocate(std::size_t size, std::size_t alignment) {
    return allocate(size, alignment);
}

void counted_release(void* memory) noexcept {
    release(memory);
}

std::size_t live_allocations() {
    return live_blocks.load(std::memory_order_relaxed);
}

}  // namespace dfm::test

// Every replaceable form of the global allocation functions (C++17 and
// later): plain, array, aligned, nothrow, and the sized deletes.
void* operator new(std::size_t size) {
    return allocate_or_throw(size, 0);
}
void* operator new[](std::size_t size) {
    return allocate_or_throw(size, 0);
}
void* operator new(std::size_t size, std::align_val_t a) {
    return allocate_or_throw(size, static_cast<std::size_t>(a));
}
void* operator new[](std::size_t size, std::align_val_t a) {
    return allocate_or_throw(size, static_cast<std::size_t>(a));
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
    return allocate(size, 0);
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
    return allocate(size, 0);
}
void* operator new(std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept {
    return allocate(size, static_cast<std::size_t>(a));
}
void* operator new[](std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept {
    return allocate(size, static_cast<std::size_t>(a));
}

void operator delete(void* p) noexcept {
    release(p);
}
void operator delete[](void* p) noexcept {
    release(p);
}
void operator delete(void* p, std::size_t) noexcept {
    release(p);
}
void operator delete[](void* p, std::size_t) noexcept {
    release(p);
}
void operator delete(void* p, std::align_val_t) noexcept {
    release(p);
}
void operator delete[](void* p, std::align_val_t) noexcept {
    release(p);
}
void operator delete(void* p, std::size_t, std::align_val_t) noexcept {
    release(p);
}
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept {
    release(p);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
    release(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
    release(p);
}
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept {
    release(p);
}
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept {
    release(p);
}
