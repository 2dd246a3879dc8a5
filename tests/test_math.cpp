// test_math.cpp - rtmath's own functions measured against libm (double).
//
// Each function is swept densely over the range rtmath.h documents, plus
// seeded random samples and the known hard spots (floats next to multiples of
// pi/2 for sin/cos, x next to 1 for log2, binade edges). The maximum error is
// asserted against the bound rtmath.h states and printed ("[ measured ]"
// lines, also recorded as test properties in the XML output) for the README.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>

#include "rtmath.h"

namespace {

// Spacing of floats at |r| (the ulp of the float nearest r); denormals 2^-149.
double float_ulp(double r) {
  r = std::fabs(r);
  if (r < 1.17549435e-38) return std::ldexp(1.0, -149);
  int e;
  std::frexp(r, &e); // r = m 2^e, m in [0.5, 1)
  return std::ldexp(1.0, e - 24);
}

// Largest error seen and where.
struct MaxErr {
  double err = 0;
  double at = 0;
  long samples = 0;
  void add(double e, double x) {
    ++samples;
    if (e > err || std::isnan(e)) {
      err = std::isnan(e) ? std::numeric_limits<double>::infinity() : e;
      at = x;
    }
  }
};

void report(const char* name, const char* unit, const MaxErr& m) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%.6g %s (at x = %.9g, %ld samples)", m.err, unit, m.at,
                m.samples);
  ::testing::Test::RecordProperty(std::string(name) + "_max_error", buf);
  std::printf("[ measured ] %s max error %s\n", name, buf);
}

// n evenly spaced points over [lo, hi], both ends included.
template <class F> void sweep(double lo, double hi, long n, F f) {
  for (long i = 0; i <= n; ++i)
    f(lo + (hi - lo) * double(i) / double(n));
}

float next_up(float x, int steps) {
  for (int i = 0; i < steps; ++i)
    x = std::nextafter(x, std::numeric_limits<float>::infinity());
  for (int i = 0; i > steps; --i)
    x = std::nextafter(x, -std::numeric_limits<float>::infinity());
  return x;
}

// ---------------------------------------------------------------- sin, cos

// rtmath.h: within 1 ulp for |x| <= 1e5.
constexpr double kSinCosRange = 1e5;
constexpr double kSinCosUlps = 1.0;

void sincos_sample(float x, MaxErr& s, MaxErr& c) {
  double rs = std::sin(double(x)), rc = std::cos(double(x));
  s.add(std::fabs(double(rt_sin(x)) - rs) / float_ulp(rs), x);
  c.add(std::fabs(double(rt_cos(x)) - rc) / float_ulp(rc), x);
}

TEST(Math, SinCosWithinOneUlpUpTo1e5) {
  MaxErr s, c;
  // Dense: small arguments (the usual case) and the whole range.
  sweep(-10, 10, 1000000, [&](double x) { sincos_sample(float(x), s, c); });
  sweep(-kSinCosRange, kSinCosRange, 1000000, [&](double x) { sincos_sample(float(x), s, c); });
  // Hard spots: every float within 3 ulps of k pi/2, where sin or cos is
  // nearly 0 and an inexact reduction shows as thousands of ulps.
  for (long k = -long(kSinCosRange / 1.5707963267948966); k <= long(kSinCosRange / 1.57079632679);
       ++k) {
    float x = float(double(k) * 1.5707963267948966192);
    if (std::fabs(x) > kSinCosRange) continue;
    for (int d = -3; d <= 3; ++d)
      sincos_sample(next_up(x, d), s, c);
  }
  // Seeded random samples, uniform in x and uniform in log|x|.
  std::mt19937 rng(12345);
  std::uniform_real_distribution<float> uni{float(-kSinCosRange), float(kSinCosRange)};
  std::uniform_real_distribution<double> lg(-20, std::log2(kSinCosRange));
  for (int i = 0; i < 500000; ++i) {
    sincos_sample(uni(rng), s, c);
    float x = float(std::exp2(lg(rng)));
    sincos_sample(i & 1 ? x : -x, s, c);
  }
  report("rt_sin", "ulp", s);
  report("rt_cos", "ulp", c);
  EXPECT_LE(s.err, kSinCosUlps) << "at x = " << s.at;
  EXPECT_LE(c.err, kSinCosUlps) << "at x = " << c.at;
}

TEST(Math, SinCosExactValues) {
  EXPECT_EQ(rt_sin(0.0f), 0.0f);
  EXPECT_EQ(rt_cos(0.0f), 1.0f);
  // sin is odd and cos even, bit for bit (the reduction is symmetric).
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> uni(0, 1e4f);
  for (int i = 0; i < 10000; ++i) {
    float x = uni(rng);
    ASSERT_EQ(rt_sin(-x), -rt_sin(x)) << x;
    ASSERT_EQ(rt_cos(-x), rt_cos(x)) << x;
  }
}

// ---------------------------------------------------------------- exp2, exp

// rtmath.h: relative error <= 4e-7 for -126 < x <= 127 (exp: x log2 e in it).
constexpr double kExpRel = 4e-7;

TEST(Math, Exp2RelativeErrorOverNormalRange) {
  MaxErr m;
  auto sample = [&](float x) {
    if (!(x > -126.0f && x <= 127.0f)) return;
    double r = std::exp2(double(x));
    m.add(std::fabs(double(rt_exp2(x)) - r) / r, x);
  };
  sweep(-126, 127, 4000000, [&](double x) { sample(float(x)); });
  sweep(-1, 1, 1000000, [&](double x) { sample(float(x)); });
  // Half-integers, where the reduction switches k.
  for (int k = -126; k <= 127; ++k)
    for (int d = -3; d <= 3; ++d) {
      sample(next_up(float(k) + 0.5f, d));
      sample(next_up(float(k), d));
    }
  std::mt19937 rng(2024);
  std::uniform_real_distribution<float> uni(-126.0f, 127.0f);
  for (int i = 0; i < 1000000; ++i)
    sample(uni(rng));
  report("rt_exp2", "relative", m);
  EXPECT_LE(m.err, kExpRel) << "at x = " << m.at;
}

TEST(Math, ExpRelativeErrorOverNormalRange) {
  MaxErr m;
  constexpr double kLo = -126.0 / 1.4426950408889634, kHi = 127.0 / 1.4426950408889634;
  auto sample = [&](float x) {
    if (!(x > kLo && x <= kHi)) return;
    double r = std::exp(double(x));
    m.add(std::fabs(double(rt_exp(x)) - r) / r, x);
  };
  sweep(kLo, kHi, 4000000, [&](double x) { sample(float(x)); });
  sweep(-1, 1, 1000000, [&](double x) { sample(float(x)); });
  std::mt19937 rng(2025);
  std::uniform_real_distribution<float> uni{float(kLo), float(kHi)};
  for (int i = 0; i < 1000000; ++i)
    sample(uni(rng));
  report("rt_exp", "relative", m);
  EXPECT_LE(m.err, kExpRel) << "at x = " << m.at;
}

TEST(Math, ExpEdgesNeverInfOrNaN) {
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(rt_exp2(0.0f), 1.0f);
  EXPECT_EQ(rt_exp(0.0f), 1.0f);
  EXPECT_EQ(rt_exp2(-126.0f), 0.0f); // underflow returns 0
  EXPECT_EQ(rt_exp2(-1000.0f), 0.0f);
  EXPECT_EQ(rt_exp2(-inf), 0.0f);
  EXPECT_EQ(rt_exp2(nan), 0.0f);
  EXPECT_EQ(rt_exp(-200.0f), 0.0f);
  // Saturation at 2^127: finite, never Inf.
  EXPECT_EQ(rt_exp2(127.0f), std::ldexp(1.0f, 127));
  EXPECT_EQ(rt_exp2(500.0f), std::ldexp(1.0f, 127));
  EXPECT_EQ(rt_exp2(inf), std::ldexp(1.0f, 127));
  EXPECT_EQ(rt_exp(1000.0f), std::ldexp(1.0f, 127));
  // Integers are exact powers of two.
  for (int k = -125; k <= 127; ++k)
    ASSERT_EQ(rt_exp2(float(k)), std::ldexp(1.0f, k)) << k;
}

// rt_exp_nonpositive (Cook-Torrance's inline exp) is rt_exp bit for bit for
// every x <= 0, NaN and -Inf: over the negative floats by a stride of bit
// patterns, densely where the reduction's k changes (y = x log2(e) next to
// -(j + 1/2)) and at the underflow edge (y next to -126), and the specials.
TEST(Math, ExpNonpositiveIsRtExpBitForBit) {
  int checked = 0, mismatches = 0;
  float firstBad = 0;
  auto check = [&](float x) {
    ++checked;
    if (rt_bits(rt_exp_nonpositive(x)) != rt_bits(rt_exp(x)) && mismatches++ == 0) firstBad = x;
  };
  for (u64 b = 0x80000000u; b <= 0xff800000u; b += 1021)
    check(rt_from_bits((u32)b));
  constexpr double kLog2e = 1.4426950408889634;
  for (int j = 0; j <= 126; ++j) {
    u32 mid = rt_bits(float(-(j + 0.5) / kLog2e));
    for (u32 d = 0; d <= 512; ++d) {
      check(rt_from_bits(mid - 256 + d));
    }
  }
  u32 edge = rt_bits(float(-126.0 / kLog2e));
  for (u32 d = 0; d <= 4096; ++d)
    check(rt_from_bits(edge - 2048 + d));
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (float x : {0.0f, -0.0f, -1e-45f, -1e-38f, -1e-20f, -1.0f, -87.0f, -88.0f, -1e30f, -inf, nan})
    check(x);
  EXPECT_EQ(mismatches, 0) << "first at x = " << firstBad;
  EXPECT_GT(checked, 2000000);
  EXPECT_EQ(rt_exp_nonpositive(-0.0f), 1.0f);
  EXPECT_EQ(rt_exp_nonpositive(-100.0f), 0.0f);
}

// rt_pow_inline (rtmath.h), which Phong's light loop calls, gives rt_pow's
// bits: Phong's range (x in [0, 1] a little beyond, the scenes' exponents)
// densely, every 8191st float x with exponents from 2^-10 to 2^10, the edges
// where y log2(x) crosses -126, 127 and the half-integers of rt_round, and
// zeros, denormals, negatives, Inf and NaN for both arguments.
TEST(Math, PowInlineIsRtPowBitForBit) {
  int checked = 0, mismatches = 0;
  float badX = 0, badY = 0;
  auto check = [&](float x, float y) {
    ++checked;
    if (rt_bits(rt_pow_inline(x, y)) != rt_bits(rt_pow(x, y)) && mismatches++ == 0) {
      badX = x;
      badY = y;
    }
  };
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (float y : {40.0f, 60.0f, 120.0f, 200.0f, 1.0f, 2.5f})
    for (u32 b = rt_bits(0.25f); b <= rt_bits(1.0001f); b += 7)
      check(rt_from_bits(b), y);
  for (int e = -10; e <= 10; ++e)
    for (u64 b = 0; b <= 0x7f800000u; b += 8191)
      check(rt_from_bits((u32)b), std::ldexp(1.0f + 0.37f * (float)(e & 3), e));
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0, 1);
  for (int i = 0; i < 200000; ++i) {
    float y = std::ldexp(u(rng) + 0.5f, (int)(rng() % 24) - 8);
    // x where y log2(x) is near -126, 127 or a half-integer.
    float target = i % 3 == 0 ? -126.0f : i % 3 == 1 ? 127.0f : -(float)(rng() % 120) - 0.5f;
    float x = (float)std::exp2((double)target / y);
    u32 b = rt_bits(x);
    for (u32 d = 0; d < 8; ++d)
      check(rt_from_bits(b - 4 + d), y);
  }
  for (float x : {0.0f, -0.0f, 1e-45f, 1e-39f, -1.0f, 1.0f, 2.0f, inf, nan})
    for (float y : {0.0f, -0.0f, 1.0f, 200.0f, -3.0f, 1e-30f, inf, nan})
      check(x, y);
  EXPECT_EQ(mismatches, 0) << "first at x = " << badX << ", y = " << badY;
  EXPECT_GT(checked, 5000000);
  EXPECT_EQ(rt_pow_inline(0.5f, 2.0f), rt_pow(0.5f, 2.0f));
  EXPECT_EQ(rt_pow_inline(0.0f, 40.0f), 0.0f);
  EXPECT_EQ(rt_pow_inline(0.3f, 0.0f), 1.0f);
}

// ---------------------------------------------------------------- log2

// rtmath.h: |error| <= 2e-7 max(1, |log2 x|) for normal x > 0.
constexpr double kLog2Err = 2e-7;

TEST(Math, Log2ErrorOverAllNormalFloats) {
  MaxErr m;
  auto sample = [&](float x) {
    double r = std::log2(double(x));
    m.add(std::fabs(double(rt_log2(x)) - r) / std::max(1.0, std::fabs(r)), x);
  };
  // Every binade, 16384 mantissas each (4.2M samples).
  for (int e = -126; e <= 127; ++e)
    for (int i = 0; i < 16384; ++i)
      sample(std::ldexp(1.0f + float(i) / 16384.0f, e));
  // Next to 1 (where log2 -> 0) and next to sqrt(2) (the mantissa fold).
  for (float c : {1.0f, 1.41421356f}) {
    float up = c, down = c;
    for (int d = 0; d < 20000; ++d) {
      sample(up = next_up(up, 1));
      sample(down = next_up(down, -1));
    }
  }
  std::mt19937 rng(99);
  std::uniform_real_distribution<float> mant(1.0f, 2.0f);
  std::uniform_int_distribution<int> ex(-126, 127);
  for (int i = 0; i < 1000000; ++i)
    sample(std::ldexp(mant(rng), ex(rng)));
  report("rt_log2", "abs/max(1,|log2 x|)", m);
  EXPECT_LE(m.err, kLog2Err) << "at x = " << m.at;
}

TEST(Math, Log2EdgesAndExactPowers) {
  EXPECT_EQ(rt_log2(1.0f), 0.0f);
  for (int k = -126; k <= 127; ++k)
    ASSERT_EQ(rt_log2(std::ldexp(1.0f, k)), float(k)) << k;
  // Outside the domain: the documented -126, never NaN or -Inf.
  EXPECT_EQ(rt_log2(0.0f), -126.0f);
  EXPECT_EQ(rt_log2(-1.0f), -126.0f);
  EXPECT_EQ(rt_log2(1e-40f), -126.0f); // denormal
  EXPECT_EQ(rt_log2(std::numeric_limits<float>::quiet_NaN()), -126.0f);
}

// ---------------------------------------------------------------- pow

// rtmath.h: relative error <= 4e-7 (1 + |z|), z = y log2 x in (-126, 127].
constexpr double kPowRel = 4e-7;

TEST(Math, PowRelativeErrorScaledByExponent) {
  MaxErr m;
  double worstPlain = 0; // plain relative error, for the record
  auto sample = [&](float x, float y) {
    double z = double(y) * std::log2(double(x));
    if (!(z > -126 && z <= 127)) return;
    double r = std::pow(double(x), double(y));
    double rel = std::fabs(double(rt_pow(x, y)) - r) / r;
    worstPlain = std::max(worstPlain, rel);
    m.add(rel / (1 + std::fabs(z)), x);
  };
  // Phong's use: x = V.R in (0, 1], y = shininess in [1, 256]; also x > 1
  // and fractional y.
  for (int i = 1; i <= 2000; ++i)
    for (int j = 0; j <= 1000; ++j)
      sample(float(i) / 2000.0f * 4.0f, float(j) * 0.256f);
  std::mt19937 rng(4242);
  std::uniform_real_distribution<float> ux(0.0f, 1.0f), uy(0.0f, 256.0f);
  std::uniform_int_distribution<int> near1(1, 24);
  for (int i = 0; i < 1000000; ++i) {
    float x = ux(rng);
    if (i % 4 == 0) x = 1.0f - std::ldexp(ux(rng), -near1(rng)); // highlights: V.R -> 1
    sample(x, uy(rng));
  }
  report("rt_pow", "relative/(1+|y log2 x|)", m);
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.4g", worstPlain);
  RecordProperty("rt_pow_max_plain_relative_error", buf);
  std::printf("[ measured ] rt_pow max plain relative error %s (same samples)\n", buf);
  EXPECT_LE(m.err, kPowRel) << "at x = " << m.at;
}

TEST(Math, PowEdges) {
  EXPECT_EQ(rt_pow(0.0f, 2.0f), 0.0f);
  EXPECT_EQ(rt_pow(0.0f, 0.0f), 1.0f);
  EXPECT_EQ(rt_pow(0.5f, 0.0f), 1.0f);
  EXPECT_EQ(rt_pow(-0.5f, 3.0f), 0.0f); // x < 0 is outside the domain: 0, not NaN
  for (float y : {1.0f, 7.5f, 140.0f, 1000.0f})
    EXPECT_EQ(rt_pow(1.0f, y), 1.0f) << y;
  EXPECT_EQ(rt_pow(1e-30f, 200.0f), 0.0f); // underflow -> 0, never NaN
  EXPECT_TRUE(std::isfinite(rt_pow(3e38f, 100.0f)));
}

// ---------------------------------------------------------------- sqrt

// rtmath.h: correctly rounded, i.e. within 0.5 ulp, over all floats >= 0.
TEST(Math, SqrtCorrectlyRounded) {
  MaxErr m;
  auto sample = [&](float x) {
    double r = std::sqrt(double(x));
    m.add(std::fabs(double(rt_sqrt(x)) - r) / float_ulp(r), x);
  };
  for (int e = -149; e <= 127; ++e)
    for (int i = 0; i < 8192; ++i) {
      float x = std::ldexp(1.0f + float(i) / 8192.0f, e);
      if (std::isfinite(x)) sample(x);
    }
  std::mt19937 rng(5);
  std::uniform_int_distribution<u32> bits(0, 0x7f7fffffu); // every finite float >= 0
  for (int i = 0; i < 1000000; ++i)
    sample(rt_from_bits(bits(rng)));
  report("rt_sqrt", "ulp", m);
  EXPECT_LE(m.err, 0.5) << "at x = " << m.at;
  EXPECT_EQ(rt_sqrt(0.0f), 0.0f);
  EXPECT_EQ(rt_sqrt(1.0f), 1.0f);
  EXPECT_TRUE(std::isnan(rt_sqrt(-1.0f))); // documented: callers clamp
}

// ---------------------------------------------------------------- vectors

TEST(Math, NormalizeIsUnitAndDegenerateFallsBack) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> uni(-1.0f, 1.0f);
  std::uniform_int_distribution<int> ex(-40, 40);
  double worst = 0;
  for (int i = 0; i < 200000; ++i) {
    float s = std::ldexp(1.0f, ex(rng));
    Vec3 a = v3(uni(rng) * s, uni(rng) * s, uni(rng) * s);
    if (!(double(a.x) * a.x + double(a.y) * a.y + double(a.z) * a.z > 1e-30)) continue;
    Vec3 n = normalize(a);
    double len = std::sqrt(double(n.x) * n.x + double(n.y) * n.y + double(n.z) * n.z);
    worst = std::max(worst, std::fabs(len - 1));
  }
  std::printf("[ measured ] normalize max | |n| - 1 | %.3g\n", worst);
  EXPECT_LE(worst, 4e-7); // a few float roundings of a unit vector
  Vec3 fb = normalize(v3(0, 0, 0), v3(0, 0, 1));
  EXPECT_EQ(fb.z, 1.0f);
  Vec3 den = normalize(v3(1e-20f, 0, 0)); // length^2 1e-40 is denormal: fallback
  EXPECT_EQ(den.y, 1.0f);
  Vec3 nanv = normalize(v3(std::numeric_limits<float>::quiet_NaN(), 0, 0));
  EXPECT_EQ(nanv.y, 1.0f);
}

TEST(Math, RoundFloorFinite) {
  EXPECT_EQ(rt_round(2.5f), 3);
  EXPECT_EQ(rt_round(-2.5f), -3);
  EXPECT_EQ(rt_round(-0.4f), 0);
  EXPECT_EQ(rt_floor(-0.5f), -1.0f);
  EXPECT_EQ(rt_floor(3.0f), 3.0f);
  EXPECT_TRUE(rt_finite(1e38f));
  EXPECT_FALSE(rt_finite(std::numeric_limits<float>::infinity()));
  EXPECT_FALSE(rt_finite(std::numeric_limits<float>::quiet_NaN()));
}

} // namespace
