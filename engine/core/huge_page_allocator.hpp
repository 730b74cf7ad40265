#pragma once

#include <cstddef>
#include <new>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace dfm {

// An allocator for the set-up's largest arrays (the factor's values, the
// stencils): a buffer of 32 MiB or more is aligned to 2 MiB and offered to
// the kernel as transparent huge pages. Each page of fresh memory costs a
// fault, and on virtual machines a fault can cost ten microseconds: the
// 104k-vertex factor's 121 MB took about 360 ms of faults in 4 KiB pages on
// the machine of docs/benchmarks.md, about 10 ms in 2 MiB pages once the
// machine had backed them. 32 MiB is glibc's largest threshold for mapping
// a buffer afresh: a smaller one may come from the heap and be reused warm,
// and advice on heap memory would change how glibc trims its heap (measured:
// the 26k set-up's smaller arrays then faulted on every set-up). Smaller
// buffers, and systems without the advice, get ordinary memory. Allocation
// goes through the aligned operator new, so a host's replacement of it sees
// these buffers too.
template <class T>
struct HugePageAllocator {
    using value_type = T;

    static constexpr std::size_t huge_page = std::size_t{2} << 20;
    static constexpr std::size_t threshold = std::size_t{32} << 20;

    HugePageAllocator() = default;
    template <class U>
    HugePageAllocator(const HugePageAllocator<U>&) noexcept {}

    T* allocate(std::size_t n) {
        const std::size_t bytes = n * sizeof(T);
        if (bytes < threshold) return static_cast<T*>(::operator new(bytes, alignment()));
        const std::size_t rounded = (bytes + huge_page - 1) / huge_page * huge_page;
        void* p = ::operator new (rounded, std::align_val_t{huge_page});
#if defined(__linux__) && defined(MADV_HUGEPAGE)
        // Advice only: where the kernel declines, the pages stay small.
        (void)::madvise(p, rounded, MADV_HUGEPAGE);
#endif
        return static_cast<T*>(p);
    }

    void deallocate(T* p, std::size_t n) noexcept {
        if (n * sizeof(T) < threshold) {
            ::operator delete(p, alignment());
        } else {
            ::operator delete (p, std::align_val_t{huge_page});
        }
    }

    template <class U>
    bool operator==(const HugePageAllocator<U>&) const noexcept {
        return true;
    }

private:
    static constexpr std::align_val_t alignment() {
        return std::align_val_t{alignof(T) > alignof(std::max_align_t) ? alignof(T)
                                                                       : alignof(std::max_align_t)};
    }
};

template <class T>
using HugePageVector = std::vector<T, HugePageAllocator<T>>;

}  // namespace dfm
