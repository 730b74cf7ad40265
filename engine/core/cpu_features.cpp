#include "core/cpu_features.hpp"

namespace dfm::cpu {

namespace {

struct Features {
    bool avx2 = false;
    bool avx512f = false;
    bool avx512vl = false;
};

const Features& features() {
    static const Features found = [] {
        Features f;
#if DFM_X86_DISPATCH
        __builtin_cpu_init();
        f.avx2 = __builtin_cpu_supports("avx2") != 0;
        f.avx512f = __builtin_cpu_supports("avx512f") != 0;
        f.avx512vl = f.avx512f && __builtin_cpu_supports("avx512vl") != 0;
#endif
        return f;
    }();
    return found;
}

}  // namespace

bool has_avx2() {
    return features().avx2;
}

bool has_avx512f() {
    return features().avx512f;
}

bool has_avx512vl() {
    return features().avx512vl;
}

}  // namespace dfm::cpu
