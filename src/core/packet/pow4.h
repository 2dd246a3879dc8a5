// pow4.h - rtmath's rt_log2, rt_exp2, rt_pow and rt_exp_nonpositive
// (rtmath.h) in four lanes,
// bit for bit: each lane takes the scalar function's steps, the same float
// and double operations in the same order (the double steps two lanes at a
// time, as SSE2 has them: D4 below), and its branches become selects. For Phong's
// (V.R)^h and Cook-Torrance's D at four shading points at once
// (packet/shade.cpp);
// tests/test_shade4.cpp compares them with the scalar functions over
// millions of seeded and edge inputs.
#pragma once
#include "packet/lanes.h"

typedef double d2 __attribute__((vector_size(16))); // one SSE2 register
typedef long long l2 __attribute__((vector_size(16))); // two 64-bit lanes
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

// The double steps in two halves of two lanes (d2: lanes 0-1, then 2-3), each
// an SSE2 register: a 32-byte double vector (no AVX) was lowered by GCC 12
// to scalar selects and branches, with its halves stored as two 8-byte
// words and reloaded as one 16-byte load (a failed store-to-load forward).
struct D4 {
  d2 lo, hi;
};
inline D4 d4_of(f4 x) { // each lane widened: exact
  return D4{__builtin_ia32_cvtps2pd(x), __builtin_ia32_cvtps2pd(__builtin_ia32_movhlps(x, x))};
}
inline d2 d2_of(double a) { return d2{a, a}; }
// Each lane truncated toward zero to an integer, (i32) as the scalar casts.
inline i4 trunc4(const D4& x) {
  return (i4)__builtin_ia32_punpcklqdq128((l2)__builtin_ia32_cvttpd2dq(x.lo),
                                          (l2)__builtin_ia32_cvttpd2dq(x.hi));
}

// rt_exp2_reduced() of four lanes: x in double, k its rounded integer.
inline f4 rt_exp2_reduced4(const D4& x, i4 k) {
  d2 ln2 = d2_of(0.6931471805599453);
  d2 flo = (x.lo - __builtin_ia32_cvtdq2pd(k)) * ln2;
  d2 fhi = (x.hi - __builtin_ia32_cvtdq2pd(__builtin_ia32_pshufd(k, 0xee))) * ln2;
  f4 f = __builtin_ia32_movlhps(__builtin_ia32_cvtpd2ps(flo), __builtin_ia32_cvtpd2ps(fhi));
  f4 p =
      1.0f +
      f * (1.0f + f * (0.5f + f * (1.0f / 6 +
                                   f * (1.0f / 24 +
                                        f * (1.0f / 120 + f * (1.0f / 720 + f * (1.0f / 5040)))))));
  return p * (f4)(((u4)k + 127u) << 23);
}

// rt_round(double) of each lane: (i32)(x + (x < 0 ? -0.5 : 0.5)), truncated.
inline d2 round_half(d2 x) {
  d2 half = d2_of(0.5);
  return x + (x < d2_of(0.0) ? -half : half);
}

// rt_exp2() (exp2_core of a float): 0 below -126 and for NaN, saturated at 127.
inline f4 rt_exp2_4(f4 xf) {
  D4 x = d4_of(xf);
  d2 top = d2_of(127.0);
  x.lo = x.lo > top ? top : x.lo;
  x.hi = x.hi > top ? top : x.hi;
  i4 k = trunc4(D4{round_half(x.lo), round_half(x.hi)});
  f4 r = rt_exp2_reduced4(x, k);
  return xf > f4_of(-126.0f) ? r : f4_of(0.0f);
}

// rt_exp_nonpositive() (rtmath.h): y = x log2(e) in double, 0 where
// !(y > -126), else rt_exp2_reduced(y, (i32)(y - 0.5)).
inline f4 rt_exp_nonpositive4(f4 xf) {
  D4 y = d4_of(xf);
  d2 log2e = d2_of(1.4426950408889634), half = d2_of(0.5), low = d2_of(-126.0);
  y.lo *= log2e;
  y.hi *= log2e;
  i4 k = trunc4(D4{y.lo - half, y.hi - half});
  f4 r = rt_exp2_reduced4(y, k);
  // y > -126 per lane: the two halves' 64-bit masks narrowed to 32 bits each.
  i4 in = (i4)__builtin_ia32_shufps((f4)(y.lo > low), (f4)(y.hi > low), 0x88);
  return in ? r : f4_of(0.0f);
}

// rt_pow(): 1 where y = 0, else 0 where !(x > 0), else exp2(y log2 x).
inline f4 rt_pow4(f4 x, f4 y) {
  f4 r = rt_exp2_4(y * rt_log2_4(x));
  r = x > f4_of(0.0f) ? r : f4_of(0.0f);
  return y == f4_of(0.0f) ? f4_of(1.0f) : r;
}
