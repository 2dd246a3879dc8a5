// rtmath.cpp - our own transcendental functions (no libm in the exe).
// Formulas: Cody-Waite style reduction by pi/2 and Taylor polynomials
// (Abramowitz & Stegun 4.3.65/4.3.66 for sin/cos), the
// atanh series for log (A&S 4.1.27). Truncation errors are stated per function;
// test_math.cpp measures the total error against libm.
#include "rtmath.h"

namespace {

// Horner's rule: c[0] x^(n-1) + ... + c[n-1], as c[n-1] + x (c[n-2] + x (...
// + x c[0])), the very operations of the nested form written out. One loop
// for every polynomial of this file that is not on the renderer's hot path.
double horner(const double* c, int n, double x) {
  double a = c[0];
  for (int i = 1; i < n; ++i)
    a = c[i] + x * a;
  return a;
}

// sin(r) = r P(r^2) and cos(r) = Q(r^2) for |r| <= pi/4 in double (Taylor,
// highest power first). Truncation after r^13 and r^14: (pi/4)^15/15! <
// 3e-14, far below float's 6e-8.
constexpr double kSinPoly[7] = {
    1.0 / 6227020800.0, -1.0 / 39916800, 1.0 / 362880, -1.0 / 5040, 1.0 / 120, -1.0 / 6, 1};
constexpr double kCosPoly[8] = {-1.0 / 87178291200.0, 1.0 / 479001600, -1.0 / 3628800, 1.0 / 40320,
                                -1.0 / 720,           1.0 / 24,        -0.5,           1};

// sin(x + quadrant * pi/2).
float sin_quadrant(float x, int quadrant) {
  constexpr double kTwoOverPi = 0.63661977236758134;
  // Cody-Waite: pi/2 = kHalfPiHi + kHalfPiLo, Hi with 33 significant bits so
  // k * Hi is exact for |k| < 2^20 and x - k * Hi is exact; the pair carries
  // ~86 bits of pi/2. (One double pi/2 left an error of k * 6e-17 ~ 1e-11 in
  // r, i.e. thousands of ulps for floats near a multiple of pi/2.)
  constexpr double kHalfPiHi = 1.5707963267341256;
  constexpr double kHalfPiLo = 6.077100506506192e-11;
  double xd = x;
  i32 k = rt_round(xd * kTwoOverPi);
  double r = (xd - k * kHalfPiHi) - k * kHalfPiLo;
  // Quadrants 0..3: sin, cos, -sin, -cos (a negation is exact, before or
  // after the rounding to float).
  int q = (k + quadrant) & 3;
  double v = q & 1 ? horner(kCosPoly, 8, r * r) : r * horner(kSinPoly, 7, r * r);
  return (float)(q & 2 ? -v : v);
}

} // namespace

float rt_sin(float x) { return sin_quadrant(x, 0); }
float rt_cos(float x) { return sin_quadrant(x, 1); }

namespace {

float exp2_core(double x) { return rt_exp2_checked(x); }

} // namespace

float rt_exp2(float x) { return exp2_core(x); }
float rt_exp(float x) { return exp2_core(x * 1.4426950408889634); }

float rt_log2(float x) { return rt_log2_inline(x); }

float rt_pow(float x, float y) {
  if (y == 0.0f) return 1.0f;
  if (!(x > 0.0f)) return 0.0f;
  return rt_exp2(y * rt_log2(x));
}
