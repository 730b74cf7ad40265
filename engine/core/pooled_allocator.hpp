#pragma once

#include <cstddef>
#include <new>
#include <vector>

#include "core/buffer_pool.hpp"

namespace dfm {

// A standard allocator whose buffers of buffer_pool::min_bytes and more go
// through the buffer pool (buffer_pool.hpp: kept between set-ups, huge pages
// from 32 MiB); smaller ones come from the aligned operator new directly.
template <class T>
struct PooledAllocator {
    using value_type = T;
    static_assert(alignof(T) <= buffer_pool::max_alignment);

    PooledAllocator() = default;
    template <class U>
    PooledAllocator(const PooledAllocator<U>&) noexcept {}

    T* allocate(std::size_t n) {
        const std::size_t bytes = n * sizeof(T);
        if (bytes < buffer_pool::min_bytes) {
            return static_cast<T*>(::operator new(bytes, alignment()));
        }
        return static_cast<T*>(buffer_pool::allocate(bytes, alignof(T)));
    }

    void deallocate(T* p, std::size_t n) noexcept {
        const std::size_t bytes = n * sizeof(T);
        if (bytes < buffer_pool::min_bytes) {
            ::operator delete(p, alignment());
        } else {
            buffer_pool::deallocate(p, bytes);
        }
    }

    template <class U>
    bool operator==(const PooledAllocator<U>&) const noexcept {
        return true;
    }

private:
    static constexpr std::align_val_t alignment() {
        return std::align_val_t{alignof(T) > alignof(std::max_align_t) ? alignof(T)
                                                                       : alignof(std::max_align_t)};
    }
};

template <class T>
using PooledVector = std::vector<T, PooledAllocator<T>>;

}  // namespace dfm
