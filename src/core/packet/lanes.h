// lanes.h - four float lanes in one SSE2 register (GCC vector extensions).
//
// f4 has the scalar operators lane by lane; a comparison gives a lane mask
// (i4: all ones or zero per lane); `mask ? a : b` selects per lane. Every
// lane computes exactly what the scalar code does: each IEEE operation
// (+ - * /, sqrt, compares) rounds alike in its ss and ps forms, and
// -ffp-contract=off keeps GCC from fusing them. SSE2 only (the x86-64
// baseline): no CPU check is needed.
#pragma once
#include "rtmath.h"

typedef float f4 __attribute__((vector_size(16)));
typedef i32 i4 __attribute__((vector_size(16)));

// The 16 bytes at p, any alignment (one movups): a Vec3 and the float that
// follows it in its struct, say (the scalar kernels' x, y, z lanes).
__attribute__((always_inline)) inline f4 lanes_at(const void* p) {
  f4 r;
  __builtin_memcpy(&r, p, 16);
  return r;
}
inline f4 f4_of(float a) { return f4{a, a, a, a}; }
inline i4 i4_of(i32 a) { return i4{a, a, a, a}; }
inline f4 lane_abs(f4 x) { return (f4)((i4)x & i4_of(0x7fffffff)); }
inline f4 lane_sqrt(f4 x) { return __builtin_ia32_sqrtps(x); }
// Bit k set: lane k of the mask is set.
inline u32 lane_bits(i4 m) { return (u32)__builtin_ia32_movmskps((f4)m); }
// Lane k set where bit k of `bits` is.
inline i4 lanes_of(u32 bits) {
  i4 k = {1, 2, 4, 8};
  return (i4_of((i32)bits) & k) == k; // one bit each: != 0 in one compare
}
