#pragma once

#include <cstddef>
#include <vector>

namespace dfm {

// The bytes a vector's buffer holds: its capacity, not its size, since that
// is what it takes from the allocator.
template <class T, class A>
std::size_t capacity_bytes(const std::vector<T, A>& v) {
    return v.capacity() * sizeof(T);
}

template <class... Vectors>
std::size_t capacity_bytes(const Vectors&... vectors) {
    return (capacity_bytes(vectors) + ...);
}

}  // namespace dfm
