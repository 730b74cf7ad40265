#pragma once

namespace dfm::cpu {

// What the processor runs, asked once per process. The solver's kernels and
// the local step's pass are compiled for several instruction sets and take
// the widest of these at run time; the answers are false where the engine
// is not built for x86-64 with GCC or Clang.
bool has_avx2();
bool has_avx512f();
// AVX-512 with its 256-bit forms (VL): four-double lanes in 32 registers.
bool has_avx512vl();

}  // namespace dfm::cpu
