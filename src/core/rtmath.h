// rtmath.h - freestanding scalar and vector maths for rt64k.
//
// Contract: no C runtime, no standard library, no heap. Every function here is
// usable from the CRT-free Win32 exe and from the Linux tool and tests alike.
// The core is compiled with RT64K_FP_FLAGS (see CMakeLists.txt): IEEE floats,
// no fast-math, no FP contraction, no errno, so sqrt is one SSE instruction.
//
// Accuracy of each function over its documented range is measured against
// libm by tests/test_math.cpp; the figures quoted here are those limits.
#pragma once

typedef unsigned char u8;
typedef unsigned short u16;
typedef unsigned int u32;
typedef int i32;
typedef unsigned long long u64;

constexpr float kPi = 3.14159265358979f;
constexpr float kTwoPi = 6.28318530717959f;
constexpr float kHuge = 1e30f; // "no hit yet" distance; far above any scene's scale

// |x| by clearing the sign bit (one andps, no branch); -0 gives +0.
inline float rt_abs(float x) { return __builtin_fabsf(x); }
inline float rt_min(float a, float b) { return a < b ? a : b; }
inline float rt_max(float a, float b) { return a > b ? a : b; }
inline float rt_clamp(float x, float lo, float hi) { return x < lo ? lo : (x > hi ? hi : x); }
inline bool rt_finite(float x) { return x - x == 0.0f; } // false for NaN and +-Inf

// Correctly rounded (one sqrtss); negative input gives NaN, so callers clamp.
inline float rt_sqrt(float x) { return __builtin_sqrtf(x); }

inline u32 rt_bits(float x) { return __builtin_bit_cast(u32, x); }
inline float rt_from_bits(u32 b) { return __builtin_bit_cast(float, b); }

// Round to nearest integer (ties away from zero); valid for |x| < 2^31.
inline i32 rt_round(float x) { return (i32)(x + (x < 0 ? -0.5f : 0.5f)); }
inline i32 rt_round(double x) { return (i32)(x + (x < 0 ? -0.5 : 0.5)); }
// Largest integer <= x; valid for |x| < 2^31.
inline float rt_floor(float x) {
  float t = (float)(i32)x;
  return t > x ? t - 1.0f : t;
}

// sin and cos of x in radians. Reduction by pi/2 (Cody-Waite, two parts) and
// the polynomials run in double, so the result is within 1 ulp of float for
// |x| <= 1e5, also next to multiples of pi/2 (measured in test_math: see
// README). Scenes and the synth use |x| < 1e4.
float rt_sin(float x);
float rt_cos(float x);
// 2^x, e^x: relative error <= 4e-7 for -126 < x <= 127 (rt_exp: for
// -126 < x log2(e) <= 127, i.e. -87.33 < x <= 88.02); below, 0; above,
// saturates at 2^127 (never Inf).
float rt_exp2(float x);
float rt_exp(float x);

// 2^x = e^f 2^k for a double x and an integer k with x - k in [-1/2, 1/2]:
// the steps of rt_exp2 and rt_exp after the range checks. x stays double so
// that rt_exp's x * log2(e) keeps its low bits: in float that product's
// rounding alone gave |x| * 6e-8 relative error.
inline float rt_exp2_reduced(double x, i32 k) {
  float f = (float)((x - k) * 0.6931471805599453); // |f| <= ln2/2
  // e^f, Taylor to f^7: truncation (ln2/2)^8/8! = 5e-9.
  float p =
      1 + f * (1 + f * (0.5f + f * (1.0f / 6 +
                                    f * (1.0f / 24 + f * (1.0f / 120 +
                                                          f * (1.0f / 720 + f * (1.0f / 5040)))))));
  return p * rt_from_bits((u32)(k + 127) << 23);
}

// rt_exp(x) for x <= 0 (or NaN), bit for bit, inline: for a hot caller
// (Cook-Torrance's D) that should not save its registers around a call
// (docs/tracer-speed.md, round seven, third wave). With x <= 0 the product
// y = x log2(e) is <= 0: rt_exp2's saturation at 127 never applies, and
// rt_round(y) is (i32)(y - 0.5) (for y = +0 or -0, rt_round adds +0.5 and
// this -0.5: both truncate to 0). Below -126 (and NaN, -Inf), 0 as rt_exp.
__attribute__((always_inline)) inline float rt_exp_nonpositive(float x) {
  double y = x * 1.4426950408889634;
  if (!(y > -126.0)) return 0.0f;
  return rt_exp2_reduced(y, (i32)(y - 0.5));
}

// 2^x with rt_exp2's range checks: 0 below -126 (and NaN), saturated at
// 127 (no Inf). rt_exp2 and rt_exp are this, out of line.
inline float rt_exp2_checked(double x) {
  if (!(x > -126.0)) return 0.0f; // underflow (and NaN) -> 0: a light term that vanishes
  if (x > 127.0) x = 127.0;       // saturate: 2^127 is finite; no Inf leaves this function
  return rt_exp2_reduced(x, rt_round(x));
}

// log2(x) for normal x > 0: |error| <= 2e-7 max(1, |log2 x|) (absolute near
// x = 1, relative elsewhere). Zero, negative, denormal or NaN x returns -126.
// rt_log2 is rt_log2_inline out of line.
float rt_log2(float x);
inline float rt_log2_inline(float x) {
  if (!(x >= 1.17549435e-38f)) return -126.0f; // zero, negative, denormal, NaN
  u32 b = rt_bits(x);
  i32 e = (i32)((b >> 23) & 255) - 127;
  float m = rt_from_bits((b & 0x7fffffu) | 0x3f800000u); // [1, 2)
  if (m > 1.41421356f) {
    m *= 0.5f;
    ++e;
  }
  // log(m) = 2 atanh(s), s = (m-1)/(m+1), |s| <= 0.1716; series to s^9:
  // truncation 2 s^11/11 < 7e-10.
  float s = (m - 1.0f) / (m + 1.0f), s2 = s * s;
  float ln = 2 * s * (1 + s2 * (1.0f / 3 + s2 * (1.0f / 5 + s2 * (1.0f / 7 + s2 * (1.0f / 9)))));
  return (float)e + ln * 1.44269504088896f;
}
// x^y for x >= 0; pow(0, y > 0) = 0. Used by Phong's (V.R)^h. For x > 0 and
// z = y log2(x) in (-126, 127]: relative error <= 4e-7 (1 + |z|), the error
// of log2 amplified by y.
float rt_pow(float x, float y);
// rt_pow bit for bit, inline: the same steps (rt_log2, the float product,
// rt_exp2's checks) without its three calls, for Phong's light loop in
// trace_tree, which saved its values around them (docs/tracer-speed.md,
// rounds ten and eleven).
inline float rt_pow_inline(float x, float y) {
  if (y == 0.0f) return 1.0f;
  if (!(x > 0.0f)) return 0.0f;
  return rt_exp2_checked(y * rt_log2_inline(x));
}

struct Vec3 {
  float x, y, z;
};

inline Vec3 v3(float x, float y, float z) { return Vec3{x, y, z}; }
inline Vec3 v3(float s) { return Vec3{s, s, s}; }
inline Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator-(Vec3 a) { return {-a.x, -a.y, -a.z}; }
inline Vec3 operator*(Vec3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
inline Vec3 operator*(float s, Vec3 a) { return {a.x * s, a.y * s, a.z * s}; }
inline Vec3 operator*(Vec3 a, Vec3 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
inline Vec3& operator+=(Vec3& a, Vec3 b) { return a = a + b; }
inline float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(Vec3 a) { return rt_sqrt(dot(a, a)); }
inline float max_abs(Vec3 a) { return rt_max(rt_abs(a.x), rt_max(rt_abs(a.y), rt_abs(a.z))); }
inline float comp(Vec3 a, int i) { return i == 0 ? a.x : (i == 1 ? a.y : a.z); }

// Unit vector along a. A zero-length (or denormal-length) input returns
// `fallback`, so no NaN comes out of a degenerate configuration.
inline Vec3 normalize(Vec3 a, Vec3 fallback = Vec3{0, 1, 0}) {
  float len2 = dot(a, a);
  if (!(len2 > 1e-30f)) return fallback; // 1e-30: far below any real length^2, above denormals
  return a * (1.0f / rt_sqrt(len2));
}

inline Vec3 lerp(Vec3 a, Vec3 b, float t) { return a + (b - a) * t; }
inline float lerp(float a, float b, float t) { return a + (b - a) * t; }
// Cubic smoothstep of t clamped to [0, 1]: 0 and 1 with zero slope at the ends.
inline float smooth01(float t) {
  t = rt_clamp(t, 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

// sin(2 pi p) for p in turns, |p| < 2^23; |error| <= 1e-3 (parabola through
// 0, +-1/4, +-1/2 plus one refinement step; measured in test_synth). The
// synth's oscillators run on it: a cheap per-sample sine, not a precise one
// (that is rt_sin). Its result never leaves [-1, 1].
inline float rt_sin_turns(float p) {
  p -= rt_floor(p + 0.5f);                        // [-1/2, 1/2)
  float s = 8.0f * p * (1.0f - 2.0f * rt_abs(p)); // |s| <= 1
  return s * (0.776f + 0.224f * rt_abs(s));
}
