#pragma once

// Whether the engine builds kernels for several x86-64 instruction sets
// (GCC's and Clang's target attribute) to pick among at run time.
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define DFM_X86_DISPATCH 1
#else
#define DFM_X86_DISPATCH 0
#endif

namespace dfm::cpu {

// What the processor runs, asked once per process. The solver's kernels and
// the local step's pass are compiled for several instruction sets and take
// the widest of these at run time; the answers are false without
// DFM_X86_DISPATCH.
bool has_avx2();
bool has_avx512f();
// AVX-512 with its 256-bit forms (VL): four-double lanes in 32 registers.
bool has_avx512vl();

}  // namespace dfm::cpu
