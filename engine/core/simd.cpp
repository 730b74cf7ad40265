#include "core/simd.hpp"

namespace dfm::simd {

Set widest() {
    static const Set found = [] {
#if DFM_X86_DISPATCH
        __builtin_cpu_init();
        if (__builtin_cpu_supports("avx512f") != 0 && __builtin_cpu_supports("avx512vl") != 0) {
            return Set::avx512;
        }
        if (__builtin_cpu_supports("avx2") != 0) return Set::avx2;
#endif
        return Set::plain;
    }();
    return found;
}

bool available(Set set) {
    return set <= widest();
}

}  // namespace dfm::simd
