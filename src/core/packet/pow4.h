// pow4.h - rtmath's rt_log2, rt_exp2, rt_pow and rt_exp_nonpositive
// (rtmath.h) in four lanes,
// bit for bit: each lane takes the scalar function's steps, the same float
// and double operations in the same order (the double steps two lanes at a
// time, as SSE2 has them), and its branches become selects. For Phong's
// (V.R)^h and Cook-Torrance's D at four shading points at once
// (packet/shade.cpp);
// tests/test_shade4.cpp compares them with the scalar functions over
// millions of seeded and edge inputs.
#pragma once
#include "packet/lanes.h"

typedef double d4 __attribute__((vector_size(32))); // two SSE2 registers
typedef u32 u4 __attribute__((vector_size(16)));

// rt_log2(): -126 for zero, negative, denormal or NaN x.
inline f4 rt_log2_4(f4 x) {
  i4 b = (i4)x;
  i4 e = ((b >> 23) & i4_of(255)) - i4_of(127);
  f4 m = (f4)((b & i4_of(0x7fffff)) | i4_of(0x3f800000)); // [1, 2)
  i4 big = m > f4_of(1.41421356f);
  m = big ? m * 0.5f : m;
  e = big ? e + 1 : e;
  f4 s = (m - 1.0f) / (m + 1.0f), s2 = s * s;
  f4 ln = 2.0f * s * (1.0f + s2 * (1.0f / 3 + s2 * (1.0f / 5 + s2 * (1.0f / 7 + s2 * (1.0f / 9)))));
  f4 r = __builtin_convertvector(e, f4) + ln * 1.44269504088896f;
  return x >= f4_of(1.17549435e-38f) ? r : f4_of(-126.0f);
}

// rt_exp2_reduced() of four lanes: x in double, k its rounded integer.
inline f4 rt_exp2_reduced4(const d4& x, i4 k) {
  f4 f = __builtin_convertvector((x - __builtin_convertvector(k, d4)) * 0.6931471805599453, f4);
  f4 p =
      1.0f +
      f * (1.0f + f * (0.5f + f * (1.0f / 6 +
                                   f * (1.0f / 24 +
                                        f * (1.0f / 120 + f * (1.0f / 720 + f * (1.0f / 5040)))))));
  return p * (f4)(((u4)k + 127u) << 23);
}

// rt_exp2() (exp2_core of a float): 0 below -126 and for NaN, saturated at 127.
inline f4 rt_exp2_4(f4 xf) {
  d4 x = __builtin_convertvector(xf, d4);
  d4 top = {127.0, 127.0, 127.0, 127.0}, zero = {0, 0, 0, 0};
  d4 half = {0.5, 0.5, 0.5, 0.5};
  x = x > top ? top : x;
  // rt_round(double): (i32)(x + (x < 0 ? -0.5 : 0.5)), truncated.
  i4 k = __builtin_convertvector(x + (x < zero ? -half : half), i4);
  f4 r = rt_exp2_reduced4(x, k);
  return xf > f4_of(-126.0f) ? r : f4_of(0.0f);
}

// rt_exp_nonpositive() (rtmath.h): y = x log2(e) in double, 0 where
// !(y > -126), else rt_exp2_reduced(y, (i32)(y - 0.5)).
inline f4 rt_exp_nonpositive4(f4 xf) {
  d4 y = __builtin_convertvector(xf, d4) * 1.4426950408889634;
  d4 half = {0.5, 0.5, 0.5, 0.5}, low = {-126.0, -126.0, -126.0, -126.0};
  i4 k = __builtin_convertvector(y - half, i4);
  f4 r = rt_exp2_reduced4(y, k);
  i4 in = __builtin_convertvector(y > low, i4); // -1 (true) or 0 per lane
  return in ? r : f4_of(0.0f);
}

// rt_pow(): 1 where y = 0, else 0 where !(x > 0), else exp2(y log2 x).
inline f4 rt_pow4(f4 x, f4 y) {
  f4 r = rt_exp2_4(y * rt_log2_4(x));
  r = x > f4_of(0.0f) ? r : f4_of(0.0f);
  return y == f4_of(0.0f) ? f4_of(1.0f) : r;
}
