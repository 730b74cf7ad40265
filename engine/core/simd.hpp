#pragma once

#include <cstddef>

// The instruction sets the engine's kernels are built for and pick among at
// run time, and the vectors of doubles they compute in: one home, so that
// each name means one thing in every file. Every set computes every entry
// with the same multiplications and additions in the same order (no fused
// multiply–add: the engine builds with -ffp-contract=off), so each gives
// the same bits; the tests compare them. The choice is an ordinary branch
// rather than an ifunc, which sanitizers' start-up code does not survive.

// Whether the engine builds kernels for several x86-64 instruction sets
// (GCC's and Clang's target attribute).
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define DFM_X86_DISPATCH 1
#else
#define DFM_X86_DISPATCH 0
#endif

#if DFM_X86_DISPATCH
// AVX2: sixteen registers of four doubles.
#define DFM_TARGET_AVX2 __attribute__((target("avx2")))
// AVX-512 with its 128- and 256-bit forms (F and VL): thirty-two registers
// of eight doubles, and the narrower vectors in all thirty-two.
#define DFM_TARGET_AVX512 __attribute__((target("avx512f,avx512vl")))
#endif

namespace dfm::simd {

// Ordered: a processor that runs one set runs every set before it.
enum class Set { plain, avx2, avx512 };

// The widest set the processor runs and the engine builds (asked once per
// process; plain without DFM_X86_DISPATCH).
Set widest();
// Whether the processor runs `set` and the engine builds it.
bool available(Set set);

// Vectors of doubles (GCC's vector extension): element-wise products and
// sums round as scalar ones do. Two doubles fill one SSE2 register, which
// every x86-64 processor has; four one AVX2 register (two SSE2 registers in
// a plain build); eight one AVX-512 register, used only in code built for it.
using Doubles2 = double __attribute__((vector_size(2 * sizeof(double))));
using Doubles4 = double __attribute__((vector_size(4 * sizeof(double))));
using Doubles8 = double __attribute__((vector_size(8 * sizeof(double))));

// The doubles of a vector type.
template <class V>
inline constexpr std::size_t lanes = sizeof(V) / sizeof(double);

}  // namespace dfm::simd
