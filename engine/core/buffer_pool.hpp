#pragma once

#include <cstddef>

namespace dfm::buffer_pool {

// Large buffers (the factor's values, the stencils, the normal matrix, the
// analysis's work arrays, Anderson's history) freed by one set-up and kept
// for the next while an SDK context lives. A page of fresh memory costs a
// fault, and on a virtual machine a fault is dear: a large set-up's fresh
// pages can cost more than its arithmetic, so a set-up in pages already
// touched is several times faster. The C library keeps freed memory only below
// thresholds that move with what the process did before, so the engine
// keeps its own.
//
// Every block comes from the aligned `operator new`, so a host's
// replacement of it sees them. Blocks of 32 MiB or more are aligned to
// 2 MiB and advised as transparent huge pages. A fresh block's requested
// pages are made present in one call (MADV_POPULATE_WRITE) rather than
// faulted in one by one as they are first written. Kept and used blocks
// together stay within a quarter above the peak of the bytes in use at
// once: a request the pool cannot serve first frees kept blocks until the
// new one fits. With no holder alive (engine code outside the SDK, or
// after the last context is destroyed) a freed block goes straight back
// to `operator delete`.

inline constexpr std::size_t min_bytes = std::size_t{128} << 10;  // glibc's first mmap threshold
inline constexpr std::size_t huge_bytes = std::size_t{32} << 20;
inline constexpr std::size_t huge_page = std::size_t{2} << 20;
inline constexpr std::size_t max_alignment = 64;

// `bytes` at least min_bytes, `alignment` at most max_alignment. Throws
// std::bad_alloc as operator new does.
void* allocate(std::size_t bytes, std::size_t alignment);
// `bytes` as given to allocate.
void deallocate(void* memory, std::size_t bytes) noexcept;

// A holder keeps freed blocks kept; the last one to go frees them.
void hold() noexcept;
void release() noexcept;

struct Counts {
    std::size_t in_use_bytes = 0;
    std::size_t kept_bytes = 0;
    std::size_t peak_in_use_bytes = 0;
    std::size_t reused = 0;  // allocations served from kept blocks
    std::size_t fresh = 0;   // from operator new
};
Counts counts() noexcept;

// Held for its lifetime (the SDK's context state holds one).
class Hold {
public:
    Hold() noexcept { hold(); }
    ~Hold() { release(); }
    Hold(const Hold&) = delete;
    Hold& operator=(const Hold&) = delete;
};

}  // namespace dfm::buffer_pool
