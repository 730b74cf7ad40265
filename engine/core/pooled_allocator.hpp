#pragma once

#include <cstddef>
#include <new>
#include <type_traits>
#include <utility>
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

// A PooledAllocator under which resize leaves new elements of trivial types
// unwritten, for arrays that are written whole before they are read: the
// factor's values (assembled block by block) and Anderson's history, where
// zeroing a large factor before the factorization overwrites it is a
// visible share of the set-up.
template <class T>
struct UnzeroedPooledAllocator : PooledAllocator<T> {
    UnzeroedPooledAllocator() = default;
    template <class U>
    UnzeroedPooledAllocator(const UnzeroedPooledAllocator<U>&) noexcept {}

    template <class U>
    void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};

template <class T>
using UnzeroedPooledVector = std::vector<T, UnzeroedPooledAllocator<T>>;

}  // namespace dfm
