// test_shapes.cpp - ray/shape intersection under the contract in shapes.h.
//
// Part 1: named hard cases per shape (grazing and tangent rays, rays starting
// on the surface, parallel rays, axis rays, the cone's apex, cap rims, rays
// from inside, triangle edges and vertices, degenerate inputs, far and near
// objects, NaN/Inf inputs).
// Part 2: seeded random property tests, 100,000 rays per shape kind, against
// a double-precision reference written here.
//
// Tolerances (float's unit roundoff eps = 2^-24 = 6e-8; "S" is the magnitude
// of the coordinates in the computation: max(|org|, |p|, |shape anchor|)_inf
// plus the shape's size, since every float rounding error is relative to the
// numbers it rounds):
//   * hit point on the surface: distance <= kSurfTol * S with kSurfTol = 2^-16
//     (256 eps; p = org + t dir carries a few eps * S from the sum and
//     product, plus the solver's error in t projected on the normal, which
//     the quadric solvers keep to tens of eps; measured figure printed).
//   * t against the reference: |t - t_ref| <= kTTol * S * kappa, kTTol =
//     2^-16, kappa = 1 / |cos(incidence)| at the reference hit: the
//     condition number of a ray/surface intersection (a plane at grazing
//     angle turns eps * S in the offset into eps * S / |cos| in t; the same
//     holds for the quadrics' square root).
//   * rays whose reference answer is itself unstable are excluded by a stated,
//     scaled margin and counted: a ray is "near-degenerate" when moving its
//     origin by kPerturb * S = 2^-16 * S along any axis changes the
//     reference's hit/miss, the piece hit (side/cap) or the side it arrives
//     from, or when the crossing of a flat piece or the side lies within
//     kPerturb * S * kappa of the piece's boundary (see Ref::margin). That
//     is the near-tangent, near-edge, near-rim, grazing and origin-on-surface
//     set at the scale of the t tolerance. Their hit points must still lie
//     on the piece's carrier surface (a grazing point may stray past an edge
//     along the ray, never off the plane or quadric).
//   * spawned rays (spawn_origin, two per hit): leaving a convex solid or a
//     flat shape they never hit it again; going into a closed solid they
//     must start inside it and find the far side where the reference does.
//     Counted, not checked, for inward rays: hits in the near-degenerate set
//     (at an edge no single normal moves the origin inside), where the solid
//     is under 4 offsets thick, and next to a cone's apex (below).
//   * the spawn-offset sweep repeats the spawn checks with the offset scaled
//     by 2^-k and prints the smallest scale with no failure at it or above.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "shapes.h"

namespace {

constexpr double kEps = 1.0 / 16777216; // 2^-24
constexpr double kSurfTol = 1.0 / 65536;
constexpr double kTTol = 1.0 / 65536;
constexpr double kPerturb = 1.0 / 65536;
// At a cone's apex the quadric is singular: a ray through it has a double
// root there, and the rounding of B^2 - AC (eps * B^2) moves the roots by up
// to sqrt(eps) * S = 2.4e-4 S, falling off as the cone widens (a near-tangent
// root errs by ~eps S^2 / local radius). Hits on rays passing where the cone
// is thinner than kApexNear * S get the bound
// kApexTol = 4 sqrt(eps) instead of kSurfTol, and count as near-degenerate
// in the property tests.
constexpr double kApexNear = 1.0 / 256;
constexpr double kApexTol = 1.0 / 1024;
constexpr double kUnitTol = 1e-6; // | |n| - 1 |: normalize() rounds a few times (test_math)

const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();

// ------------------------------------------------------------ double maths

struct D3 {
  double x, y, z;
};
D3 dv(Vec3 v) { return {v.x, v.y, v.z}; }
Vec3 fv(D3 v) { return v3(float(v.x), float(v.y), float(v.z)); }
D3 operator+(D3 a, D3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
D3 operator-(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 operator-(D3 a) { return {-a.x, -a.y, -a.z}; }
D3 operator*(D3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 cross(D3 a, D3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
double norm(D3 a) { return std::sqrt(dot(a, a)); }
D3 unit(D3 a) { return a * (1.0 / norm(a)); }
double maxabs(D3 a) { return std::max({std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)}); }
bool finite3(Vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
double flen(Vec3 v) { return norm(dv(v)); }

// Any unit vector perpendicular to unit n, and a second completing the frame.
void frame(D3 n, D3& e1, D3& e2) {
  D3 h = std::fabs(n.x) < 0.6 ? D3{1, 0, 0} : D3{0, 1, 0};
  e1 = unit(cross(n, h));
  e2 = cross(n, e1);
}

// ------------------------------------------------------------ float calls

struct Cast {
  bool hit;
  Hit h;
};
constexpr float kSentinelT = 123.25f;
Cast cast(const Shape& s, Vec3 org, Vec3 dir, float tMin = 0.0f, float tMax = kHuge) {
  Hit h;
  h.t = tMax;
  h.normal = v3(-7.0f, 8.0f, -9.0f); // sentinel: must survive a miss
  h.front = true;
  bool ok = intersect(s, Ray{org, dir}, tMin, h);
  return {ok, h};
}
bool untouched(const Cast& c, float tMax) {
  return c.h.t == tMax && c.h.normal.x == -7.0f && c.h.normal.y == 8.0f && c.h.normal.z == -9.0f &&
         c.h.front;
}
// Contract checks every float hit must pass.
void expect_valid_hit(const Cast& c, Vec3 dir, const char* what) {
  ASSERT_TRUE(std::isfinite(c.h.t)) << what;
  ASSERT_TRUE(finite3(c.h.normal)) << what;
  EXPECT_NEAR(flen(c.h.normal), 1.0, kUnitTol) << what;
  EXPECT_LE(dot(c.h.normal, dir), 0.0f) << what;
}
Vec3 at(Vec3 org, Vec3 dir, float t) { return org + dir * t; } // as trace() computes p

// ------------------------------------------------------------ reference

// Distances to segments (2D, 3D), in double.
double seg_dist2d(double px, double py, double ax, double ay, double bx, double by) {
  double dx = bx - ax, dy = by - ay, l2 = dx * dx + dy * dy;
  double t = l2 > 0 ? std::clamp(((px - ax) * dx + (py - ay) * dy) / l2, 0.0, 1.0) : 0.0;
  double ex = px - (ax + t * dx), ey = py - (ay + t * dy);
  return std::sqrt(ex * ex + ey * ey);
}
double seg_dist3d(D3 p, D3 a, D3 b) {
  D3 ab = b - a;
  double t = std::clamp(dot(p - a, ab) / dot(ab, ab), 0.0, 1.0);
  return norm(p - (a + ab * t));
}
// Nearest hit in double. piece: 0 = the surface proper (sphere, plane,
// triangle, lateral side), 1 = base cap, 2 = top cap. n is the outward normal
// (plane/triangle: their own normal).
// margin: over every crossing of a piece's carrier surface (kept or not,
// ahead of the origin or behind it), the smallest distance from the crossing to the
// piece's boundary (triangle edges, cap rims, the side's ends) times |cos| of
// the incidence there. A float crossing point strays along the ray by about
// eps S / |cos|, so margin < C eps S means hit/miss is not decided by the
// geometry but by rounding.
struct Ref {
  bool hit = false;
  double t = 0;
  D3 n{0, 0, 0};
  int piece = -1;
  bool front = false;
  double margin = std::numeric_limits<double>::infinity();
};

void edge_margin(Ref& r, double dist, D3 n, D3 d) {
  r.margin = std::min(r.margin, dist * std::fabs(dot(unit(n), d)));
}

void consider(Ref& r, double t, double tMin, D3 nOut, int piece, D3 d) {
  if (!(t > tMin) || (r.hit && t >= r.t)) return;
  r.hit = true;
  r.t = t;
  r.n = nOut;
  r.piece = piece;
  r.front = dot(nOut, d) < 0;
}

// Roots of a t^2 + 2 b t + c = 0 (stable form); returns how many.
int quadratic(double a, double b, double c, double roots[2]) {
  double disc = b * b - a * c;
  if (disc < 0) return 0;
  double q = -(b + std::copysign(std::sqrt(disc), b));
  int n = 0;
  if (a != 0) roots[n++] = q / a;
  if (q != 0) roots[n++] = c / q;
  return n;
}

Ref ref_intersect(const Shape& s, D3 o, D3 d, double tMin = 0) {
  Ref r;
  switch (s.kind) {
  case kSphere: {
    D3 c = dv(s.a);
    double rad = s.r0;
    D3 f = o - c;
    double a = dot(d, d), b = dot(f, d);
    D3 perp = f - d * (b / a);
    double disc = a * (rad * rad - dot(perp, perp));
    if (disc < 0) break;
    double q = -(b + std::copysign(std::sqrt(disc), b));
    double roots[2] = {q / a, (dot(f, f) - rad * rad) / q};
    for (double t : roots)
      consider(r, t, tMin, unit(o + d * t - c), 0, d);
    break;
  }
  case kPlane: {
    D3 n = dv(s.a);
    double denom = dot(n, d);
    if (denom == 0) break;
    consider(r, (s.r0 - dot(n, o)) / denom, tMin, unit(n), 0, d);
    break;
  }
  case kCylinder:
  case kCone: {
    D3 ax = unit(dv(s.b)), oc = o - dv(s.a);
    double y0 = dot(oc, ax), dy = dot(d, ax), h = s.h, r0 = s.r0, r1 = s.r1;
    D3 v = oc - ax * y0, u = d - ax * dy;
    double k = (r1 - r0) / h, rk = r0 + k * y0;
    double roots[2];
    int n =
        quadratic(dot(u, u) - k * k * dy * dy, dot(u, v) - k * dy * rk, dot(v, v) - rk * rk, roots);
    for (int i = 0; i < n; ++i) {
      double t = roots[i], y = y0 + t * dy;
      D3 g = v + u * t - ax * (k * (r0 + k * y));
      if (dot(g, g) == 0) g = ax; // the apex: same fallback as the float code
      edge_margin(r, std::min(std::fabs(y), std::fabs(y - h)), g, d);
      if (y < 0 || y > h) continue;
      consider(r, t, tMin, unit(g), 0, d);
    }
    if (dy != 0) {
      for (int cap = 0; cap < 2; ++cap) {
        if (!(s.caps & (cap ? kCapTop : kCapBase))) continue;
        double t = ((cap ? h : 0.0) - y0) / dy, rc = cap ? r1 : r0;
        D3 pp = v + u * t;
        edge_margin(r, std::fabs(norm(pp) - rc), ax, d);
        if (dot(pp, pp) <= rc * rc) consider(r, t, tMin, cap ? ax : -ax, cap ? 2 : 1, d);
      }
    }
    break;
  }
  case kTriangle: {
    // Moller-Trumbore in double, no epsilons.
    D3 A = dv(s.a), e1 = dv(s.b) - A, e2 = dv(s.c) - A;
    D3 pv = cross(d, e2);
    double det = dot(e1, pv);
    if (det == 0) break;
    D3 nt = cross(e1, e2);
    double tp = dot(A - o, nt) / dot(d, nt); // where the ray crosses the plane
    D3 q = o + d * tp;
    edge_margin(r,
                std::min({seg_dist3d(q, A, dv(s.b)), seg_dist3d(q, dv(s.b), dv(s.c)),
                          seg_dist3d(q, dv(s.c), A)}),
                nt, d);
    D3 tv = o - A;
    double u = dot(tv, pv) / det;
    if (u < 0 || u > 1) break;
    D3 qv = cross(tv, e1);
    double v = dot(d, qv) / det;
    if (v < 0 || u + v > 1) break;
    consider(r, dot(e2, qv) / det, tMin, unit(cross(e1, e2)), 0, d);
    break;
  }
  case kEmpty: // builders reject degenerate input: nothing to hit or measure
    break;
  }
  return r;
}

// True when the reference's answer is not stable at scale eta: its margin
// (above) is below eta, or moving the origin by eta along any axis changes
// hit/miss, the piece hit or the side it is hit from (the ray is within eta
// of a tangency, edge or rim, or starts within eta of the surface).
// The ray passes through, or within kApexNear * S of, the part of a full
// cone thinner than kApexNear * S (for a needle that part reaches far down
// from the apex): judged at the axis point nearest the ray.
bool near_apex(const Shape& s, D3 o, D3 d, double S) {
  if (s.kind != kCone || s.r1 != 0) return false;
  D3 a = dv(s.a), b = unit(dv(s.b)), w = o - a;
  double db = dot(d, b), denom = dot(d, d) - db * db;
  double y = denom > 1e-12 ? (dot(b, w) * dot(d, d) - db * dot(d, w)) / denom : dot(b, w);
  y = std::clamp(y, 0.0, double(s.h));
  double rho = s.r0 * (1 - y / s.h), dist = norm(cross(a + b * y - o, d));
  return rho < kApexNear * S && dist < rho + kApexNear * S;
}

bool near_degenerate(const Shape& s, D3 o, D3 d, const Ref& base, double eta) {
  if (base.margin < eta) return true;
  if (near_apex(s, o, d, eta / kPerturb)) return true;
  static const D3 kAxes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (const D3& e : kAxes) {
    Ref r = ref_intersect(s, o + e * eta, d);
    if (r.hit != base.hit) return true;
    if (r.hit && (r.piece != base.piece || r.front != base.front)) return true;
  }
  return false;
}

// Distance from p to the shape's surface (all its pieces), in double.
double surface_distance(const Shape& s, D3 p) {
  switch (s.kind) {
  case kSphere:
    return std::fabs(norm(p - dv(s.a)) - s.r0);
  case kPlane:
    return std::fabs(dot(dv(s.a), p) - s.r0) / norm(dv(s.a));
  case kCylinder:
  case kCone: {
    // A surface of revolution: distance in the meridian half-plane (rho, y).
    D3 ax = unit(dv(s.b)), oc = p - dv(s.a);
    double y = dot(oc, ax), rho = norm(oc - ax * y);
    double best = seg_dist2d(rho, y, s.r0, 0, s.r1, s.h);
    if (s.caps & kCapBase) best = std::min(best, seg_dist2d(rho, y, 0, 0, s.r0, 0));
    if (s.caps & kCapTop) best = std::min(best, seg_dist2d(rho, y, 0, s.h, s.r1, s.h));
    return best;
  }
  case kTriangle: {
    D3 A = dv(s.a), B = dv(s.b), C = dv(s.c), n = unit(cross(B - A, C - A));
    double h = dot(p - A, n);
    D3 q = p - n * h; // in the plane: inside when all edge tests agree
    double s0 = dot(cross(B - A, q - A), n), s1 = dot(cross(C - B, q - B), n),
           s2 = dot(cross(A - C, q - C), n);
    if (s0 >= 0 && s1 >= 0 && s2 >= 0) return std::fabs(h);
    return std::min({seg_dist3d(p, A, B), seg_dist3d(p, B, C), seg_dist3d(p, C, A)});
  }
  case kEmpty: // builders reject degenerate input: nothing to hit or measure
    break;
  }
  return 0;
}

// Distance from p to the carrier surface of the nearest piece: the sphere,
// the plane, the triangle's plane, the side's infinite cone or cylinder, a
// cap's plane. A grazing hit's point strays along the ray by eps S / |cos|,
// so it may land beyond a piece's boundary, but never off its carrier.
double carrier_distance(const Shape& s, D3 p) {
  switch (s.kind) {
  case kSphere:
  case kPlane:
    return surface_distance(s, p);
  case kCylinder:
  case kCone: {
    D3 ax = unit(dv(s.b)), oc = p - dv(s.a);
    double y = dot(oc, ax), rho = norm(oc - ax * y);
    double dr = double(s.r1) - s.r0, len = std::sqrt(dr * dr + double(s.h) * s.h);
    // Distance to the line through (r0, 0) and (r1, h) in the (rho, y) plane.
    double best = std::fabs((rho - s.r0) * s.h - y * dr) / len;
    if (s.caps & kCapBase) best = std::min(best, std::fabs(y));
    if (s.caps & kCapTop) best = std::min(best, std::fabs(y - s.h));
    return best;
  }
  case kTriangle: {
    D3 A = dv(s.a), n = unit(cross(dv(s.b) - A, dv(s.c) - A));
    return std::fabs(dot(p - A, n));
  }
  case kEmpty: // builders reject degenerate input: nothing to hit or measure
    break;
  }
  return 0;
}

// Inside the convex solid bounded by the shape (for an open frustum: the
// solid its missing cap would close).
bool inside_solid(const Shape& s, D3 p) {
  if (s.kind == kSphere) return norm(p - dv(s.a)) < s.r0;
  D3 ax = unit(dv(s.b)), oc = p - dv(s.a);
  double y = dot(oc, ax), rho = norm(oc - ax * y);
  return y > 0 && y < s.h && rho < s.r0 + (s.r1 - s.r0) * y / s.h;
}

// ------------------------------------------------------------ random input

using Rng = std::mt19937;
double uni(Rng& g, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(g);
}
double loguni(Rng& g, double lo, double hi) { return std::exp(uni(g, std::log(lo), std::log(hi))); }
D3 rand_unit(Rng& g) {
  std::normal_distribution<double> n;
  for (;;) {
    D3 v{n(g), n(g), n(g)};
    double l = norm(v);
    if (l > 1e-6) return v * (1 / l);
  }
}
D3 rand_ball(Rng& g, double r) { return rand_unit(g) * (r * std::cbrt(uni(g, 0, 1))); }
// Random unit direction on n's side with cos(angle to n) in [cmin, 1].
D3 rand_hemi(Rng& g, D3 n, double cmin) {
  D3 e1, e2;
  frame(n, e1, e2);
  double c = uni(g, cmin, 1), sn = std::sqrt(1 - c * c), ph = uni(g, 0, 2 * M_PI);
  return n * c + e1 * (sn * std::cos(ph)) + e2 * (sn * std::sin(ph));
}
// A float direction of unit length (to float precision), as the contract wants.
Vec3 fdir(D3 d) { return fv(unit(d)); }

enum class Kind { Sphere, Plane, CappedCylinder, OpenFrustum, FullCone, Triangle };
const char* kind_name(Kind k) {
  switch (k) {
  case Kind::Sphere:
    return "sphere";
  case Kind::Plane:
    return "plane";
  case Kind::CappedCylinder:
    return "capped cylinder";
  case Kind::OpenFrustum:
    return "open frustum";
  case Kind::FullCone:
    return "full cone";
  case Kind::Triangle:
    return "triangle";
  }
  return "?";
}

// A shape with where it is and how big: centre of its bounding ball and the
// ball's radius; `anchor` is the stored point the solver subtracts.
struct Sample {
  Shape s;
  D3 centre;
  double extent;
  D3 anchor;
  bool closed; // closed convex solid: a ray from inside always hits
};

Sample random_shape(Kind kind, Rng& g) {
  D3 c{uni(g, -20, 20), uni(g, -20, 20), uni(g, -20, 20)};
  Vec3 fc = fv(c);
  Sample smp{};
  switch (kind) {
  case Kind::Sphere: {
    float r = float(loguni(g, 0.05, 10));
    smp = {make_sphere(fc, r), dv(fc), r, dv(fc), true};
    break;
  }
  case Kind::Plane: {
    D3 n = rand_unit(g);
    float off = float(uni(g, -20, 20));
    Shape s = make_plane(fv(n), off);
    smp = {s, dv(s.a) * off, 1.0, dv(s.a) * off, false};
    break;
  }
  case Kind::CappedCylinder:
  case Kind::OpenFrustum:
  case Kind::FullCone: {
    float r0 = float(loguni(g, 0.05, 10)), h = float(loguni(g, 0.05, 10));
    float r1 = r0;
    u8 caps = kCapBase | kCapTop;
    if (kind == Kind::OpenFrustum) {
      r1 = float(r0 * uni(g, 0.1, 0.9));
      if (uni(g, 0, 1) < 0.3) std::swap(r0, r1); // widening frustum, open at the wide end
      caps = kCapBase;
    } else if (kind == Kind::FullCone) {
      r1 = 0;
      caps = kCapBase;
    }
    Shape s = make_cone(fc, fv(rand_unit(g)), r0, r1, h, caps);
    D3 mid = dv(s.a) + unit(dv(s.b)) * (0.5 * h);
    smp = {s, mid, std::sqrt(0.25 * h * h + double(std::max(r0, r1)) * std::max(r0, r1)), dv(s.a),
           kind != Kind::OpenFrustum};
    break;
  }
  case Kind::Triangle: {
    double L = loguni(g, 0.05, 10);
    for (;;) {
      D3 A = c + rand_ball(g, L), B = c + rand_ball(g, L), C = c + rand_ball(g, L);
      Shape s = make_triangle(fv(A), fv(B), fv(C));
      D3 a = dv(s.a), b = dv(s.b), cc = dv(s.c);
      if (norm(cross(b - a, cc - a)) < 1e-3 * L * L) continue; // keep it a triangle
      D3 cen = (a + b + cc) * (1.0 / 3);
      double ext = std::max({norm(a - cen), norm(b - cen), norm(cc - cen)});
      smp = {s, cen, ext, a, false};
      break;
    }
    break;
  }
  }
  return smp;
}

// A point on the surface and its outward normal (for tangent-constructed rays).
void random_surface_point(const Sample& smp, Rng& g, D3& p, D3& n) {
  const Shape& s = smp.s;
  p = n = D3{0, 0, 0};
  switch (s.kind) {
  case kSphere:
    n = rand_unit(g);
    p = dv(s.a) + n * s.r0;
    return;
  case kPlane: {
    D3 e1, e2, a = unit(dv(s.a));
    frame(a, e1, e2);
    n = a;
    p = a * s.r0 + e1 * uni(g, -10, 10) + e2 * uni(g, -10, 10);
    return;
  }
  case kCylinder:
  case kCone: {
    D3 ax = unit(dv(s.b)), e1, e2;
    frame(ax, e1, e2);
    double ph = uni(g, 0, 2 * M_PI);
    D3 radial = e1 * std::cos(ph) + e2 * std::sin(ph);
    int piece = int(uni(g, 0, 3));
    if (piece == 1 && (s.caps & kCapBase)) {
      p = dv(s.a) + radial * (s.r0 * std::sqrt(uni(g, 0, 1)));
      n = -ax;
    } else if (piece == 2 && (s.caps & kCapTop)) {
      p = dv(s.a) + ax * s.h + radial * (s.r1 * std::sqrt(uni(g, 0, 1)));
      n = ax;
    } else {
      double y = uni(g, 0, s.h), k = (s.r1 - s.r0) / s.h;
      p = dv(s.a) + ax * y + radial * (s.r0 + k * y);
      n = unit(radial - ax * k);
    }
    return;
  }
  case kTriangle: {
    double u = uni(g, 0, 1), v = uni(g, 0, 1);
    if (u + v > 1) u = 1 - u, v = 1 - v;
    D3 A = dv(s.a), B = dv(s.b), C = dv(s.c);
    p = A + (B - A) * u + (C - A) * v;
    n = unit(cross(B - A, C - A));
    return;
  }
  case kEmpty: // builders reject degenerate input: nothing to hit or measure
    break;
  }
}

// A random ray for a shape: mostly aimed at the shape's bounding ball from
// up to 4 extents away (some origins inside), 15% built tangent to the
// surface with a tilt of 10^-2..10^-9 rad (grazing hits and near misses).
void random_ray(const Sample& smp, Rng& g, Vec3& org, Vec3& dir) {
  double u = uni(g, 0, 1);
  if (u < 0.15) {
    D3 p, n, e1, e2;
    random_surface_point(smp, g, p, n);
    frame(n, e1, e2);
    double ph = uni(g, 0, 2 * M_PI), tilt = std::pow(10.0, -uni(g, 2, 9));
    D3 tangent = e1 * std::cos(ph) + e2 * std::sin(ph);
    D3 d = unit(tangent + n * (uni(g, 0, 1) < 0.5 ? tilt : -tilt));
    dir = fdir(d);
    org = fv(p - d * (smp.extent * uni(g, 0.2, 3)));
    return;
  }
  if (smp.s.kind == kPlane) {
    org = fv(D3{uni(g, -30, 30), uni(g, -30, 30), uni(g, -30, 30)});
    dir = fdir(rand_unit(g));
    return;
  }
  D3 o = smp.centre + rand_ball(g, (u < 0.25 ? 0.8 : 4.0) * smp.extent);
  D3 aim = smp.centre + rand_ball(g, 1.2 * smp.extent);
  if (smp.s.kind == kTriangle) {
    D3 A = dv(smp.s.a), B = dv(smp.s.b), C = dv(smp.s.c);
    aim = A + (B - A) * uni(g, -0.2, 1.2) + (C - A) * uni(g, -0.2, 1.2);
  }
  if (norm(aim - o) < 1e-9) aim = aim + D3{1, 0, 0};
  org = fv(o);
  dir = fdir(aim - o);
}

// Scale of the numbers in a computation (see the header comment).
double scale_of(const Sample& smp, Vec3 org, Vec3 p) {
  return std::max({maxabs(dv(org)), maxabs(dv(p)), maxabs(smp.anchor)}) + smp.extent;
}

// S for the named cases: the coordinates' magnitude plus the shape's size.
double named_scale(Vec3 o, Vec3 p, double size) {
  return std::max(maxabs(dv(o)), maxabs(dv(p))) + size;
}

// ============================================================ named cases

// ---- sphere (unit sphere at the origin unless stated)

// closed_convex (shapes.h): spheres and frustums with every disc of nonzero
// radius capped; an open frustum, a plane or a triangle is not.
TEST(Shapes, ClosedConvexSolids) {
  Vec3 o = v3(0, 0, 0), up = v3(0, 1, 0);
  EXPECT_TRUE(closed_convex(make_sphere(o, 1)));
  EXPECT_TRUE(closed_convex(make_cylinder(o, up, 1, 2, kCapBase | kCapTop)));
  EXPECT_FALSE(closed_convex(make_cylinder(o, up, 1, 2, kCapBase)));
  EXPECT_FALSE(closed_convex(make_cylinder(o, up, 1, 2, kCapTop)));
  EXPECT_TRUE(closed_convex(make_cone(o, up, 1, 0, 2, kCapBase)));        // apex: no cap needed
  EXPECT_TRUE(closed_convex(make_cone(o, up, 0, 1, 2, kCapTop)));         // apex at the base
  EXPECT_FALSE(closed_convex(make_cone(o, up, 1.5f, 0.3f, 2, kCapBase))); // open top (scene 1)
  EXPECT_TRUE(closed_convex(make_cone(o, up, 1.5f, 0.3f, 2, kCapBase | kCapTop)));
  EXPECT_FALSE(closed_convex(make_plane(up, 0)));
  EXPECT_FALSE(closed_convex(make_triangle(o, v3(1, 0, 0), v3(0, 0, 1))));
  EXPECT_FALSE(closed_convex(make_sphere(o, -1))); // empty
}

TEST(Sphere, HeadOnHitIsExact) {
  Shape s = make_sphere(v3(0, 0, 0), 1);
  Cast c = cast(s, v3(0, 0, -5), v3(0, 0, 1));
  ASSERT_TRUE(c.hit);
  expect_valid_hit(c, v3(0, 0, 1), "head-on");
  EXPECT_EQ(c.h.t, 4.0f);
  EXPECT_EQ(c.h.normal.z, -1.0f);
  EXPECT_TRUE(c.h.front);
}

TEST(Sphere, TangentRayGrazesFinitely) {
  Shape s = make_sphere(v3(0, 0, 0), 1);
  Vec3 d = v3(1, 0, 0);
  Cast tangent = cast(s, v3(-5, 1, 0), d); // touches at (0, 1, 0)
  if (tangent.hit) {
    expect_valid_hit(tangent, d, "tangent");
    EXPECT_NEAR(tangent.h.t, 5.0f, 1e-3f);
  } else {
    EXPECT_TRUE(untouched(tangent, kHuge));
  }
  // Just inside the silhouette hits at the chord's near end, just outside misses.
  Cast in = cast(s, v3(-5, 1 - 1e-3f, 0), d);
  ASSERT_TRUE(in.hit);
  expect_valid_hit(in, d, "just inside");
  double y = double(1 - 1e-3f);
  EXPECT_NEAR(in.h.t, 5 - std::sqrt(1 - y * y), 2e-5);
  EXPECT_FALSE(cast(s, v3(-5, 1 + 1e-6f, 0), d).hit);
}

TEST(Sphere, RaySpawnedFromHitDoesNotRehit) {
  Shape s = make_sphere(v3(0.5f, -0.25f, 2), 1.5f);
  Rng g(101);
  int checked = 0;
  for (int i = 0; i < 2000; ++i) {
    Vec3 o = fv(D3{0.5, -0.25, 2} + rand_unit(g) * 6),
         d = fdir(D3{0.5, -0.25, 2} + rand_ball(g, 1.4) - dv(o));
    Cast c = cast(s, o, d);
    if (!c.hit) continue;
    Vec3 p = at(o, d, c.h.t), n = c.h.normal;
    float off = spawn_offset(p, spawn_scale(s, c.h));
    Vec3 out = fdir(rand_hemi(g, dv(n), 0.01)), in = fdir(rand_hemi(g, -dv(n), 0.05));
    EXPECT_FALSE(cast(s, spawn_origin(p, n, out, off), out).hit) << "reflected ray re-hit, i=" << i;
    Vec3 o2 = spawn_origin(p, n, in, off);
    Cast far = cast(s, o2, in);
    ASSERT_TRUE(far.hit) << "refracted ray found no far side, i=" << i;
    // The far side: the chord 2 r cos from p, shortened by the offset's share
    // along the ray; exactly, the double reference from the spawned origin.
    double cosIn = dot(dv(in), -dv(n)), chord = 2 * 1.5 * cosIn;
    EXPECT_GT(far.h.t, chord - 2 * off / cosIn) << i;
    Ref r = ref_intersect(s, dv(o2), dv(in));
    EXPECT_NEAR(far.h.t, r.t, 1e-5 / cosIn) << i;
    EXPECT_FALSE(far.h.front);
    ++checked;
  }
  EXPECT_GT(checked, 1000);
}

TEST(Sphere, RaysFromCentreHitAtRadiusFromInside) {
  Shape s = make_sphere(v3(1, 2, 3), 2.5f);
  Rng g(102);
  for (int i = 0; i < 1000; ++i) {
    Vec3 d = fdir(rand_unit(g));
    Cast c = cast(s, v3(1, 2, 3), d);
    ASSERT_TRUE(c.hit);
    expect_valid_hit(c, d, "from centre");
    EXPECT_NEAR(c.h.t, 2.5f, 2e-6f);
    EXPECT_FALSE(c.h.front);
    EXPECT_NEAR(dot(c.h.normal, d), -1.0f, 1e-6f);
  }
}

TEST(Sphere, RayFromInsideOffCentre) {
  Shape s = make_sphere(v3(0, 0, 0), 2);
  Cast c = cast(s, v3(1.5f, 0, 0), v3(-1, 0, 0));
  ASSERT_TRUE(c.hit);
  EXPECT_FLOAT_EQ(c.h.t, 3.5f);
  EXPECT_FALSE(c.h.front);
  EXPECT_EQ(c.h.normal.x, 1.0f); // facing the ray: the inward normal
}

TEST(Sphere, FarAwayAt1e6) {
  Shape s = make_sphere(v3(0, 0, 1e6f), 1);
  Cast c = cast(s, v3(0, 0, 0), v3(0, 0, 1));
  ASSERT_TRUE(c.hit);
  expect_valid_hit(c, v3(0, 0, 1), "far");
  EXPECT_NEAR(c.h.t, 1e6 - 1, 0.125); // float spacing at 1e6 is 0.0625
  EXPECT_NEAR(c.h.normal.z, -1.0f, 1e-6f);
  // And a sphere of radius 1e6 seen from just outside it.
  Shape big = make_sphere(v3(0, -1e6f, 0), 1e6f);
  Cast b = cast(big, v3(0, 10, 0), v3(0, -1, 0));
  ASSERT_TRUE(b.hit);
  EXPECT_NEAR(b.h.t, 10.0, 0.125);
}

TEST(Sphere, VeryCloseTinyT) {
  Shape s = make_sphere(v3(0, 0, 0), 1);
  Vec3 o = v3(0, 0, -1 - 1e-4f);
  Cast c = cast(s, o, v3(0, 0, 1));
  ASSERT_TRUE(c.hit);
  Ref r = ref_intersect(s, dv(o), D3{0, 0, 1});
  EXPECT_NEAR(c.h.t, r.t, 2e-7); // a few eps of |org|^2 in c, divided by q ~ 2
  EXPECT_TRUE(c.h.front);
  // A tiny sphere.
  Shape tiny = make_sphere(v3(0, 0, 1), 1e-4f);
  Cast t = cast(tiny, v3(0, 0, 0), v3(0, 0, 1));
  ASSERT_TRUE(t.hit);
  EXPECT_NEAR(t.h.t, 1 - 1e-4, 1e-7);
  expect_valid_hit(t, v3(0, 0, 1), "tiny sphere");
}

TEST(Sphere, ZeroRadiusIsRejected) {
  // Radius 0 gave a NaN normal ((p - c) / 0); the builder now returns an
  // empty shape, which no ray hits (test_shapes_hard.cpp: every degenerate input).
  Shape s = make_sphere(v3(0, 0, 0), 0);
  EXPECT_EQ(s.kind, kEmpty);
  for (float y : {0.0f, 1e-7f, 1e-30f, -1e-3f}) {
    Cast c = cast(s, v3(-5, y, 0), v3(1, 0, 0));
    EXPECT_FALSE(c.hit);
    EXPECT_TRUE(untouched(c, kHuge));
  }
}

// ---- plane (y = 0 unless stated)

TEST(Plane, ParallelRayMissesAndLeavesHitAlone) {
  Shape s = make_plane(v3(0, 1, 0), 0);
  Cast above = cast(s, v3(0, 1, 0), v3(1, 0, 0));
  EXPECT_FALSE(above.hit);
  EXPECT_TRUE(untouched(above, kHuge));
  Cast inPlane = cast(s, v3(0, 0, 0), v3(0, 0, 1)); // lies in the plane
  EXPECT_FALSE(inPlane.hit);
  EXPECT_TRUE(untouched(inPlane, kHuge));
}

TEST(Plane, NearlyParallelHitsFinitelyOrMisses) {
  Shape s = make_plane(v3(0, 1, 0), 0);
  // dir.y = -1e-20: t = 1e20 < kHuge, a finite far hit; -1e-35 gives 1e35 >
  // kHuge (rejected); -1e-40 (denormal) gives Inf (rejected).
  Cast c = cast(s, v3(0, 1, 0), v3(1, -1e-20f, 0));
  ASSERT_TRUE(c.hit);
  expect_valid_hit(c, v3(1, -1e-20f, 0), "1e-20");
  EXPECT_NEAR(c.h.t / 1e20, 1.0, 1e-6);
  for (float dy : {-1e-35f, -1e-40f, -0.0f}) {
    Cast m = cast(s, v3(0, 1, 0), v3(1, dy, 0));
    EXPECT_FALSE(m.hit) << dy;
    EXPECT_TRUE(untouched(m, kHuge)) << dy;
  }
}

TEST(Plane, GrazingAngleT) {
  Shape s = make_plane(v3(0, 1, 0), 0);
  for (double c : {1e-1, 1e-2, 1e-3, 1e-4, 1e-5}) {
    Vec3 d = fdir(D3{std::sqrt(1 - c * c), -c, 0});
    Cast h = cast(s, v3(3, 2, -1), d);
    ASSERT_TRUE(h.hit) << c;
    expect_valid_hit(h, d, "grazing");
    double tRef = 2.0 / -double(d.y);
    EXPECT_NEAR(h.h.t / tRef, 1.0, 4 * kEps) << c; // one division: correctly rounded
  }
}

TEST(Plane, BackSideHitFacesRay) {
  Shape s = make_plane(v3(0, 1, 0), 0);
  Cast c = cast(s, v3(0, -2, 0), v3(0, 1, 0));
  ASSERT_TRUE(c.hit);
  EXPECT_EQ(c.h.t, 2.0f);
  EXPECT_FALSE(c.h.front);
  EXPECT_EQ(c.h.normal.y, -1.0f);
}

TEST(Plane, RayStartingOnPlaneIsNotAHit) {
  Shape s = make_plane(v3(0, 1, 0), 0);
  // Exactly on the plane: t = 0 is not > tMin = 0.
  EXPECT_FALSE(cast(s, v3(1, 0, 1), fdir(D3{1, 1, 0})).hit);
  EXPECT_FALSE(cast(s, v3(1, 0, 1), fdir(D3{1, -1, 0})).hit);
}

TEST(Plane, SpawnedRayDoesNotRehit) {
  Rng g(103);
  int n = 0;
  for (int i = 0; i < 5000; ++i) {
    Shape s = make_plane(fv(rand_unit(g)), float(uni(g, -20, 20)));
    Vec3 o = fv(D3{uni(g, -30, 30), uni(g, -30, 30), uni(g, -30, 30)}), d = fdir(rand_unit(g));
    Cast c = cast(s, o, d);
    if (!c.hit) continue;
    Vec3 p = at(o, d, c.h.t);
    for (double side : {1.0, -1.0}) {
      Vec3 d2 = fdir(rand_hemi(g, dv(c.h.normal) * side, 0.001));
      EXPECT_FALSE(
          cast(s, spawn_origin(p, c.h.normal, d2, spawn_offset(p, spawn_scale(s, c.h))), d2).hit)
          << i;
    }
    ++n;
  }
  EXPECT_GT(n, 2000);
}

TEST(Plane, FarAndNear) {
  Shape far = make_plane(v3(0, 0, 1), 1e6f);
  Cast c = cast(far, v3(0, 0, 0), v3(0, 0, 1));
  ASSERT_TRUE(c.hit);
  EXPECT_EQ(c.h.t, 1e6f);
  Shape near = make_plane(v3(0, 1, 0), 1e-6f);
  Cast n = cast(near, v3(5, 0, 5), v3(0, 1, 0));
  ASSERT_TRUE(n.hit);
  EXPECT_EQ(n.h.t, 1e-6f);
}

TEST(Plane, ZeroNormalIsRejected) {
  // A zero normal has no direction: the builder returns an empty shape
  // instead of inventing +y (normalize's fallback, before).
  Shape s = make_plane(v3(0, 0, 0), 1);
  EXPECT_EQ(s.kind, kEmpty);
  Cast c = cast(s, v3(0, 5, 0), v3(0, -1, 0));
  EXPECT_FALSE(c.hit);
  EXPECT_TRUE(untouched(c, kHuge));
  // A tiny but nonzero normal keeps its direction.
  Shape tiny = make_plane(v3(0, 1e-30f, 0), 1);
  ASSERT_EQ(tiny.kind, kPlane);
  EXPECT_EQ(tiny.a.y, 1.0f);
}

// ---- cylinder (base at the origin, axis +y, radius 1, height 2, both caps)

Shape unit_cylinder(u8 caps = kCapBase | kCapTop) {
  return make_cylinder(v3(0, 0, 0), v3(0, 1, 0), 1, 2, caps);
}

TEST(Cylinder, PerpendicularThroughAxis) {
  Cast c = cast(unit_cylinder(), v3(-5, 1, 0), v3(1, 0, 0));
  ASSERT_TRUE(c.hit);
  expect_valid_hit(c, v3(1, 0, 0), "perpendicular");
  EXPECT_EQ(c.h.t, 4.0f);
  EXPECT_EQ(c.h.normal.x, -1.0f);
  EXPECT_TRUE(c.h.front);
}

TEST(Cylinder, TangentToSideGrazesFinitely) {
  Shape s = unit_cylinder();
  Vec3 d = v3(1, 0, 0);
  Cast t = cast(s, v3(-5, 1, 1), d);
  if (t.hit) {
    expect_valid_hit(t, d, "tangent");
    EXPECT_NEAR(t.h.t, 5.0f, 1e-3f);
  }
  Cast in = cast(s, v3(-5, 1, 1 - 1e-3f), d);
  ASSERT_TRUE(in.hit);
  double z = double(1 - 1e-3f);
  EXPECT_NEAR(in.h.t, 5 - std::sqrt(1 - z * z), 2e-5);
  EXPECT_FALSE(cast(s, v3(-5, 1, 1 + 1e-6f), d).hit);
}

TEST(Cylinder, RayAlongAxisFromInsideHitsCap) {
  Cast up = cast(unit_cylinder(), v3(0, 1, 0), v3(0, 1, 0));
  ASSERT_TRUE(up.hit);
  expect_valid_hit(up, v3(0, 1, 0), "axis up");
  EXPECT_EQ(up.h.t, 1.0f);
  EXPECT_FALSE(up.h.front);
  EXPECT_EQ(up.h.normal.y, -1.0f);
  Cast down = cast(unit_cylinder(), v3(0.3f, 0.5f, -0.2f), v3(0, -1, 0));
  ASSERT_TRUE(down.hit);
  EXPECT_EQ(down.h.t, 0.5f);
  EXPECT_FALSE(down.h.front);
}

TEST(Cylinder, RayAlongAxisFromOutsideHitsCap) {
  Cast c = cast(unit_cylinder(), v3(0, -5, 0), v3(0, 1, 0));
  ASSERT_TRUE(c.hit);
  EXPECT_EQ(c.h.t, 5.0f);
  EXPECT_EQ(c.h.normal.y, -1.0f);
  EXPECT_TRUE(c.h.front);
}

TEST(Cylinder, ParallelToAxisInOpenTubeMisses) {
  Shape tube = unit_cylinder(0); // A = 0, B = 0: the side is never crossed
  for (Vec3 o : {v3(0, -5, 0), v3(0.5f, -5, 0.3f), v3(0, 1, 0), v3(0.99f, 1, 0)}) {
    Cast c = cast(tube, o, v3(0, 1, 0));
    EXPECT_FALSE(c.hit) << o.x;
    EXPECT_TRUE(untouched(c, kHuge));
  }
}

TEST(Cylinder, ParallelToAxisOutsideMissesOnWallFinite) {
  Shape s = unit_cylinder();
  EXPECT_FALSE(cast(s, v3(2, -5, 0), v3(0, 1, 0)).hit);
  EXPECT_FALSE(cast(s, v3(0, -5, 1.0001f), v3(0, 1, 0)).hit);
  // Exactly on the wall line: disc = 0, the base cap's rim is the only hit.
  Cast on = cast(s, v3(1, -5, 0), v3(0, 1, 0));
  if (on.hit) {
    expect_valid_hit(on, v3(0, 1, 0), "on wall");
    EXPECT_EQ(on.h.t, 5.0f);
  }
}

TEST(Cylinder, CapRimHitExactly) {
  // Aimed at the rim point (1, 2, 0) from the diagonal: side and cap meet there.
  Shape s = unit_cylinder();
  Vec3 d = fdir(D3{-1, -1, 0});
  Cast c = cast(s, v3(3, 4, 0), d);
  ASSERT_TRUE(c.hit);
  expect_valid_hit(c, d, "rim");
  EXPECT_NEAR(c.h.t, 2 * std::sqrt(2.0), 1e-5);
  EXPECT_TRUE(c.h.front);
}

TEST(Cylinder, CapParallelRayInCapPlane) {
  // In the plane of the top cap (dy = 0): the cap is edge-on, the side is hit
  // exactly at its top edge.
  Cast c = cast(unit_cylinder(), v3(-5, 2, 0), v3(1, 0, 0));
  if (c.hit) {
    expect_valid_hit(c, v3(1, 0, 0), "cap plane");
    EXPECT_NEAR(c.h.t, 4.0f, 1e-5f);
  }
  EXPECT_FALSE(cast(unit_cylinder(), v3(-5, 2.001f, 0), v3(1, 0, 0)).hit);
}

TEST(Cylinder, RaysFromInsideHitOnceFromInside) {
  Shape s = make_cylinder(v3(1, -2, 0.5f), fv(unit(D3{0.3, 1, -0.2})), 0.8f, 3, kCapBase | kCapTop);
  D3 mid = dv(s.a) + dv(s.b) * 1.5;
  Rng g(104);
  for (int i = 0; i < 2000; ++i) {
    Vec3 o = fv(mid + rand_ball(g, 0.5)), d = fdir(rand_unit(g));
    Cast c = cast(s, o, d);
    ASSERT_TRUE(c.hit) << i;
    expect_valid_hit(c, d, "inside");
    EXPECT_FALSE(c.h.front) << i;
    Vec3 p = at(o, d, c.h.t);
    EXPECT_LE(surface_distance(s, dv(p)), kSurfTol * named_scale(o, p, 3)) << i;
  }
}

TEST(Cylinder, FarAwayAndTiny) {
  Shape far = make_cylinder(v3(1e6f, -1, 0), v3(0, 1, 0), 1, 2, kCapBase | kCapTop);
  Cast c = cast(far, v3(0, 0, 0), v3(1, 0, 0));
  ASSERT_TRUE(c.hit);
  EXPECT_NEAR(c.h.t, 1e6 - 1, 0.125);
  EXPECT_NEAR(c.h.normal.x, -1.0f, 1e-3f);
  Shape tiny = make_cylinder(v3(0, 0, 1), v3(0, 1, 0), 1e-4f, 1e-4f, kCapBase | kCapTop);
  Cast t = cast(tiny, v3(0, 5e-5f, 0), v3(0, 0, 1));
  ASSERT_TRUE(t.hit);
  expect_valid_hit(t, v3(0, 0, 1), "tiny");
  EXPECT_NEAR(t.h.t, 1 - 1e-4, 1e-7);
}

TEST(Cylinder, DegenerateDimensionsAreRejected) {
  // Zero height (k = 0/0), zero radius, zero axis (was: falls back to +y):
  // empty shapes that no ray hits.
  Shape shapes[] = {make_cylinder(v3(0, 0, 0), v3(0, 1, 0), 1, 0, kCapBase | kCapTop),
                    make_cylinder(v3(0, 0, 0), v3(0, 1, 0), 0, 2, kCapBase | kCapTop),
                    make_cylinder(v3(0, 0, 0), v3(0, 0, 0), 1, 2, kCapBase | kCapTop)};
  Rng g(105);
  for (const Shape& s : shapes) {
    EXPECT_EQ(s.kind, kEmpty);
    for (int i = 0; i < 2000; ++i) {
      Vec3 o = fv(rand_ball(g, 4)), d = fdir(rand_ball(g, 1.2) - dv(o));
      Cast c = cast(s, o, d);
      ASSERT_FALSE(c.hit);
      ASSERT_TRUE(untouched(c, kHuge));
    }
  }
}

// A side's normal, bit for bit, against frustum_outward()'s general steps
// written out here with Vec3 (dot() sums x, y, z as the lanes' dot3() does):
// q = (org - base) + t dir, p_perp = q - axis (q.axis), n = p_perp - axis
// (k sqrt(|p_perp|^2)), n / |n| by 1 / sqrt, turned to face the ray. A
// cylinder (k = +0) takes a shortcut in shapes.cpp (|n|^2 is |p_perp|^2 bit
// for bit there); the cones, which do not, are checked the same way.
// Random axes, also axis-aligned ones of both signs (exact zeros in p_perp
// and in the axis), rays from outside and from inside.
TEST(Frustum, SideNormalIsTheGeneralFormulaBitForBit) {
  Rng g(131);
  const Vec3 aligned[] = {v3(0, 1, 0), v3(0, -1, 0), v3(1, 0, 0), v3(0, 0, -1)};
  int sides[2] = {0, 0}; // cylinders, cones
  for (int i = 0; i < 20000; ++i) {
    bool cone = i % 2 == 1;
    Vec3 axis = i % 3 == 0 ? aligned[(i / 3) % 4] : fdir(rand_unit(g));
    float r0 = (float)uni(g, 0.2, 2), h = (float)uni(g, 0.5, 4);
    float r1 = cone ? (float)uni(g, 0, 1.9) : r0;
    Vec3 base = i % 3 == 0 ? v3(0, 0, 0) : fv(rand_ball(g, 3));
    Shape s = make_cone(base, axis, r0, r1, h, kCapBase | kCapTop);
    ASSERT_EQ(s.kind, r1 == r0 ? kCylinder : kCone) << i;
    D3 mid = dv(s.a) + dv(s.b) * (0.5 * s.h);
    Vec3 o = i % 4 == 0 ? fv(mid + rand_ball(g, 0.1)) : fv(mid + rand_unit(g) * 6.0);
    Vec3 d = fdir(mid + rand_ball(g, 1.5) - dv(o));
    Cast c = cast(s, o, d);
    if (!c.hit || c.h.piece != kPieceSide) continue;
    ++sides[cone];
    Vec3 ax = s.b;
    Vec3 q = (o - s.a) + d * c.h.t;
    Vec3 pPerp = q - ax * dot(q, ax);
    float rho2 = dot(pPerp, pPerp);
    ASSERT_LE(rho2, 1e20f) << i;
    Vec3 n = pPerp - ax * (s.c.x * std::sqrt(rho2));
    float len2 = dot(n, n);
    Vec3 out = len2 > 1e-30f ? n * (1.0f / std::sqrt(len2)) : ax;
    bool front = dot(out, d) < 0;
    Vec3 want = front ? out : -out;
    ASSERT_EQ(c.h.front, front) << i;
    ASSERT_EQ(0, std::memcmp(&c.h.normal, &want, sizeof(Vec3))) << i << (cone ? " cone" : " cylinder");
  }
  EXPECT_GT(sides[0], 3000);
  EXPECT_GT(sides[1], 3000);
}

// ---- cones (full cone: base at origin, axis +y, radius 1, height 2, base cap)

Shape unit_cone() { return make_cone(v3(0, 0, 0), v3(0, 1, 0), 1, 0, 2, kCapBase); }
// The scene's lower cone: a frustum open at its narrow top.
Shape open_frustum() { return make_cone(v3(0, 0, 0), v3(0, 1, 0), 1.5f, 0.32f, 1.75f, kCapBase); }

TEST(Cone, EqualRadiiMakeACylinder) {
  EXPECT_EQ(make_cone(v3(0, 0, 0), v3(0, 1, 0), 1, 1, 2, 0).kind, kCylinder);
  EXPECT_EQ(unit_cone().kind, kCone);
}

TEST(Cone, RayAlongAxisThroughApex) {
  Cast c = cast(unit_cone(), v3(0, 5, 0), v3(0, -1, 0));
  ASSERT_TRUE(c.hit);
  expect_valid_hit(c, v3(0, -1, 0), "apex on axis"); // gradient 0: normal falls back to axis
  EXPECT_EQ(c.h.t, 3.0f);
  EXPECT_TRUE(c.h.front);
}

TEST(Cone, ObliqueRaysThroughApexFinite) {
  Shape s = unit_cone();
  Rng g(106);
  int hits = 0;
  double worst = 0;
  for (int i = 0; i < 5000; ++i) {
    D3 d = rand_unit(g);
    Vec3 o = fv(D3{0, 2, 0} - d * uni(g, 0.5, 5)), fd = fdir(d);
    Cast c = cast(s, o, fd);
    if (!c.hit) {
      ASSERT_TRUE(untouched(c, kHuge));
      continue;
    }
    ++hits;
    expect_valid_hit(c, fd, "through apex");
    Vec3 p = at(o, fd, c.h.t);
    double S = named_scale(o, p, 2), dist = surface_distance(s, dv(p));
    worst = std::max(worst, dist / S);
    EXPECT_LE(dist, kApexTol * S) << i;
  }
  std::printf("[ measured ] rays through a cone's apex: max surface distance / S = %.3g\n", worst);
  EXPECT_GT(hits, 1000);
}

TEST(Cone, RayParallelToSideSingleRoot) {
  // A ray parallel to a generator (A = 0 in the quadratic): one root, C/q.
  Shape s = unit_cone();
  D3 gen = unit(D3{1, -2, 0}); // apex (0,2,0) to rim (1,0,0)
  for (double off : {-0.3, -0.1, 0.05}) {
    D3 o = D3{0, 2, 0} - gen * 3 + D3{0, 0, off};
    Vec3 fo = fv(o), fd = fv(gen);
    Cast c = cast(s, fo, fd);
    Ref r = ref_intersect(s, dv(fo), dv(fd));
    ASSERT_EQ(c.hit, r.hit) << off;
    if (!c.hit) continue;
    expect_valid_hit(c, fd, "parallel to side");
    EXPECT_NEAR(c.h.t, r.t, 1e-5 * (1 + r.t)) << off;
  }
}

TEST(Cone, TangentToSideGrazesFinitely) {
  Shape s = unit_cone(); // radius 0.5 at y = 1
  Vec3 d = v3(1, 0, 0);
  Cast t = cast(s, v3(-5, 1, 0.5f), d);
  if (t.hit) {
    expect_valid_hit(t, d, "tangent");
    EXPECT_NEAR(t.h.t, 5.0f, 1e-3f);
  }
  Cast in = cast(s, v3(-5, 1, 0.5f - 1e-3f), d);
  ASSERT_TRUE(in.hit);
  Ref r = ref_intersect(s, D3{-5, 1, double(0.5f - 1e-3f)}, D3{1, 0, 0});
  EXPECT_NEAR(in.h.t, r.t, 1e-4);
  EXPECT_FALSE(cast(s, v3(-5, 1, 0.5f + 1e-6f), d).hit);
}

TEST(Cone, RaysFromInsideHitOnceFromInside) {
  Shape s = unit_cone();
  Rng g(107);
  for (int i = 0; i < 2000; ++i) {
    Vec3 o = fv(D3{0, 0.5, 0} + rand_ball(g, 0.3)), d = fdir(rand_unit(g));
    Cast c = cast(s, o, d);
    ASSERT_TRUE(c.hit) << i;
    expect_valid_hit(c, d, "inside");
    EXPECT_FALSE(c.h.front) << i;
    Vec3 p = at(o, d, c.h.t);
    EXPECT_LE(surface_distance(s, dv(p)), kSurfTol * named_scale(o, p, 3)) << i;
  }
}

TEST(Cone, BaseCapRimHitExactly) {
  Shape s = unit_cone();
  Vec3 d = fdir(D3{-1, 1, 0}); // from below-outside, into the rim at (1, 0, 0)
  Cast c = cast(s, v3(2, -1, 0), d);
  ASSERT_TRUE(c.hit);
  expect_valid_hit(c, d, "cone rim");
  EXPECT_NEAR(c.h.t, std::sqrt(2.0), 1e-5);
  EXPECT_TRUE(c.h.front);
}

TEST(OpenFrustum, RayDownThroughOpeningHitsBaseFromInside) {
  Cast c = cast(open_frustum(), v3(0, 5, 0), v3(0, -1, 0));
  ASSERT_TRUE(c.hit);
  expect_valid_hit(c, v3(0, -1, 0), "through opening");
  EXPECT_EQ(c.h.t, 5.0f);
  EXPECT_FALSE(c.h.front); // the base cap seen from inside the solid
  EXPECT_EQ(c.h.normal.y, 1.0f);
}

TEST(OpenFrustum, InnerWallSeenThroughOpening) {
  Shape s = open_frustum();
  Rng g(108);
  int inner = 0;
  for (int i = 0; i < 2000; ++i) {
    // Through a point of the opening (radius 0.32 at y = 1.75), steeply down.
    double ph = uni(g, 0, 2 * M_PI), rr = 0.3 * std::sqrt(uni(g, 0, 1));
    D3 p{rr * std::cos(ph), 1.75, rr * std::sin(ph)};
    D3 d = unit(D3{uni(g, -2.5, 2.5), -1, uni(g, -2.5, 2.5)});
    Vec3 o = fv(p - d * 2), fd = fv(d);
    Cast c = cast(s, o, fd);
    ASSERT_TRUE(c.hit) << i; // the base cap closes it below
    expect_valid_hit(c, fd, "opening");
    EXPECT_FALSE(c.h.front) << i;
    Ref r = ref_intersect(s, dv(o), dv(fd));
    EXPECT_NEAR(c.h.t, r.t, 1e-5 * (1 + r.t)) << i;
    inner += r.piece == 0;
  }
  EXPECT_GT(inner, 200); // some of them do land on the inner wall
}

// hit_frustum's cull (shapes.cpp, kCullRim): a ray that the frame solves
// from its point nearest the axis (u.u >= 0.5: more than 45 deg off the
// axis) and that passes farther than max(r0, r1) + 1024 rim from the axis
// line is rejected before the quadratic. Every frustum point lies within
// max(r0, r1) of that line, so such a ray misses exactly. Seeded rays on
// both sides of the frustum's reach: lines at distance max(r0, r1) (1 +
// 2^-10 .. 2) from the axis (beyond the band) must miss, and lines through
// an interior point of the closed solid must hit it from outside, for a
// closed cylinder, a cone with its apex and a closed frustum with random
// axes; the rays in the cull's regime (by its documented rule, in double)
// are counted so that both sides of its reach are exercised. (Since round
// seven the cull also takes the rays solved from a point clamped into the
// slab: the next test.)
TEST(FrustumCull, BeyondTheReachMissesInsideHits) {
  Rng g(4242);
  long beyond = 0, outsideNear = 0;
  for (int kind = 0; kind < 3; ++kind) {
    for (int shape = 0; shape < 20; ++shape) {
      D3 axis = rand_unit(g), base{uni(g, -3, 3), uni(g, -1, 3), uni(g, -3, 3)};
      double r0 = uni(g, 0.3, 1.5), h = uni(g, 0.5, 4);
      double r1 = kind == 0 ? r0 : (kind == 1 ? 0 : r0 * uni(g, 0.3, 0.9));
      Shape s = kind == 0
                    ? make_cylinder(fv(base), fv(axis), float(r0), float(h), kCapBase | kCapTop)
                    : make_cone(fv(base), fv(axis), float(r0), float(r1), float(h),
                                kind == 1 ? kCapBase : kCapBase | kCapTop);
      ASSERT_NE(s.kind, kEmpty);
      D3 a = dv(s.b), b0 = dv(s.a); // the stored axis and base
      double rmax = std::max<double>(s.r0, s.r1), size = h + rmax;
      for (int i = 0; i < 1000; ++i) {
        // Beyond the reach: the line through P along d, n perpendicular to
        // both d and the axis, is rho from the axis line.
        D3 d = rand_unit(g);
        if (i % 2 == 0) { // half of them more than 45 deg off the axis
          D3 e1, e2;
          frame(a, e1, e2);
          double c = uni(g, -0.69, 0.69), ph = uni(g, 0, 2 * M_PI), sn = std::sqrt(1 - c * c);
          d = a * c + e1 * (sn * std::cos(ph)) + e2 * (sn * std::sin(ph));
        }
        D3 n = cross(d, a);
        if (norm(n) < 1e-3) continue;
        n = unit(n);
        double rho = rmax * (1 + loguni(g, 1.0 / 1024, 2));
        D3 p = b0 + a * uni(g, -0.5 * h, 1.5 * h) + n * rho;
        Vec3 o = fv(p - d * (size * uni(g, 2, 6))), fd = fdir(d);
        Cast c = cast(s, o, fd);
        EXPECT_FALSE(c.hit) << "kind " << kind << " shape " << shape << " ray " << i;
        D3 w = dv(o) - b0, dd = dv(fd);
        D3 u = dd - a * dot(dd, a);
        double rim = (maxabs(w) + s.c.y) / 1048576;
        if (dot(u, u) >= 0.5 && rho > rmax + 1024 * rim)
          ++beyond;
        else
          ++outsideNear;
        // Through an interior point of the closed solid: a hit from outside.
        double y = uni(g, 0.05, 0.95) * h, ry = (r0 + (r1 - r0) * y / h) * uni(g, 0, 0.95);
        D3 e1, e2;
        frame(a, e1, e2);
        double ph = uni(g, 0, 2 * M_PI);
        D3 q = b0 + a * y + e1 * (ry * std::cos(ph)) + e2 * (ry * std::sin(ph));
        D3 d2 = rand_unit(g);
        Vec3 o2 = fv(q - d2 * (size * uni(g, 2, 6))), fd2 = fdir(d2);
        Cast c2 = cast(s, o2, fd2);
        EXPECT_TRUE(c2.hit && c2.h.front) << "kind " << kind << " shape " << shape << " ray " << i;
      }
    }
  }
  std::printf("frustum cull: %ld rays beyond the reach in the cull's regime, %ld outside it\n",
              beyond, outsideNear);
  EXPECT_GT(beyond, 15000);
  EXPECT_GT(outsideNear, 15000);
}

// The cull in the slab regime (round seven): a ray the frame solves from
// its point clamped into the slab (u.u < c.z: within 45 deg of the axis, or
// any ray on a flat frustum) is culled on its distance from the axis at
// that point, which is the least distance of the ray's part inside the
// slab, where every hit lies. Seeded rays at that reach's edge, each
// against the double reference (hit or miss, piece, side, t), bands
// excluded as in part 2: near-axis rays through a cap at rc (1 - delta)
// from the axis (cap rims, the wide end of cones and frusta), tangent
// lines rmax (1 - delta) from the axis with their nearest point in the
// slab (grazing the side), rays past a cone's apex, rays from inside, and
// lines rmax (1 + delta) out that must miss; delta = 2^-12 .. 2^-3. A cull
// that dropped a real hit fails it: the reach at min(r0, r1) (cones and
// frusta), at rmax (1 - 2^-10) (grazing), or |v| taken at the ray's own
// origin instead of the clamped point (tested by hand: each fails here).
TEST(FrustumCull, SlabRegimeKeepsEveryHitAtTheReach) {
  Rng g(7007);
  long checked = 0, grazingHits = 0, capRimHits = 0, misses = 0, skipped = 0;
  for (int kind = 0; kind < 6; ++kind) {
    for (int shape = 0; shape < 12; ++shape) {
      D3 axis = rand_unit(g), base{uni(g, -3, 3), uni(g, -1, 3), uni(g, -3, 3)};
      double r0 = uni(g, 0.3, 1.5), h = uni(g, 0.5, 4), r1 = r0;
      u8 caps = kCapBase | kCapTop;
      switch (kind) {
      case 1:
        r1 = 0;
        caps = kCapBase;
        break; // cone, apex on top
      case 2:
        r1 = r0 * uni(g, 0.3, 0.9);
        break; // closed frustum narrowing
      case 3:
        r1 = r0 * uni(g, 1.2, 2.5);
        break; // widening (the wide cap on top)
      case 4:
        h = r0 * uni(g, 0.1, 0.6);
        r1 = r0 * uni(g, 2.2, 3);
        break; // flat side: |k| > 1
      case 5:
        r1 = r0 * uni(g, 0.4, 0.8);
        caps = 0;
        break; // open at both ends
      default:
        break;
      }
      Shape s = kind == 0 ? make_cylinder(fv(base), fv(axis), float(r0), float(h), caps)
                          : make_cone(fv(base), fv(axis), float(r0), float(r1), float(h), caps);
      ASSERT_NE(s.kind, kEmpty);
      D3 a = dv(s.b), b0 = dv(s.a);
      double rmax = std::max<double>(s.r0, s.r1), size = h + rmax;
      D3 e1, e2;
      frame(a, e1, e2);
      for (int i = 0; i < 600; ++i) {
        // A direction within 45 deg of the axis (flat frustum: any), either way along it.
        double c = kind == 4 ? uni(g, -1, 1) : (i % 2 ? 1 : -1) * uni(g, 0.72, 1.0);
        double ph = uni(g, 0, 2 * M_PI), sn = std::sqrt(std::max(0.0, 1 - c * c));
        D3 d = a * c + e1 * (sn * std::cos(ph)) + e2 * (sn * std::sin(ph));
        double delta = loguni(g, 1.0 / 4096, 1.0 / 8);
        D3 q; // a point the ray goes through
        int cls = i % 5;
        double ps = uni(g, 0, 2 * M_PI);
        D3 radial = e1 * std::cos(ps) + e2 * std::sin(ps);
        if (cls == 0) { // through a cap's disc at rc (1 - delta): the rim
          bool top = g() & 1;
          double rc = top ? s.r1 : s.r0;
          if (rc == 0) continue;
          q = b0 + a * (top ? h : 0.0) + radial * (rc * (1 - delta));
          if ((dot(d, a) > 0) == top) d = -d; // arrive from outside the slab
        } else if (cls == 1 || cls == 4) {    // a line rmax (1 -+ delta) from the axis
          D3 n = cross(d, a);
          if (norm(n) < 1e-6) continue;
          n = unit(n);
          double y = uni(g, 0.02, 0.98) * h;
          q = b0 + a * y + n * (rmax * (cls == 1 ? 1 - delta : 1 + delta));
        } else if (cls == 2) { // past a cone's apex (or the narrow end) on the axis
          double y = s.r1 <= s.r0 ? h : 0.0;
          q = b0 + a * y + radial * (rmax * delta);
        } else { // from inside the solid
          double y = uni(g, 0.05, 0.95) * h, ry = (r0 + (r1 - r0) * y / h) * uni(g, 0, 0.95);
          q = b0 + a * y + radial * ry;
        }
        Vec3 o = cls == 3 ? fv(q) : fv(q - d * (size * uni(g, 1.5, 5))), fd = fdir(d);
        Cast cst = cast(s, o, fd);
        Ref r = ref_intersect(s, dv(o), dv(fd));
        double S = maxabs(dv(o) - b0) + maxabs(b0) + size;
        if (near_degenerate(s, dv(o), dv(fd), r, kPerturb * S)) {
          ++skipped;
          continue;
        }
        ++checked;
        ASSERT_EQ(cst.hit, r.hit) << "kind " << kind << " shape " << shape << " ray " << i
                                  << " class " << cls;
        if (!r.hit) {
          ++misses;
          EXPECT_TRUE(untouched(cst, kHuge));
          continue;
        }
        EXPECT_EQ(cst.h.front, r.front) << kind << " " << shape << " " << i;
        double kappa = 1 / std::max(std::fabs(dot(r.n, dv(fd))), 1e-12);
        EXPECT_NEAR(cst.h.t, r.t, kTTol * S * kappa) << kind << " " << shape << " " << i;
        grazingHits += cls == 1;
        capRimHits += cls == 0 && r.piece != 0;
      }
    }
  }
  std::printf("slab-regime cull: %ld rays checked (%ld grazing hits, %ld cap-rim hits, %ld "
              "misses), %ld in the band\n",
              checked, grazingHits, capRimHits, misses, skipped);
  EXPECT_GT(grazingHits, 2000);
  EXPECT_GT(capRimHits, 2000);
  EXPECT_GT(misses, 2000);
}

// A cast at a hard case: a hit is valid and on the surface within kSurfTol of
// the scale of its numbers; a miss leaves the Hit untouched. `i` labels the case.
void expect_on_surface_or_untouched(const Shape& s, Vec3 o, Vec3 fd, const char* what, int i) {
  Cast c = cast(s, o, fd);
  if (c.hit) {
    expect_valid_hit(c, fd, what);
    Vec3 p = at(o, fd, c.h.t);
    EXPECT_LE(surface_distance(s, dv(p)), kSurfTol * named_scale(o, p, 2)) << what << " " << i;
  } else {
    EXPECT_TRUE(untouched(c, kHuge)) << what << " " << i;
  }
}

TEST(OpenFrustum, OpeningRimFinite) {
  Shape s = open_frustum();
  Rng g(109);
  for (int i = 0; i < 2000; ++i) {
    double ph = uni(g, 0, 2 * M_PI);
    D3 rim{0.32 * std::cos(ph), 1.75, 0.32 * std::sin(ph)};
    D3 d = rand_unit(g);
    Vec3 o = fv(rim - d * uni(g, 0.5, 4)), fd = fdir(d);
    expect_on_surface_or_untouched(s, o, fd, "opening rim", i);
  }
}

TEST(Cone, FarAwayAndTiny) {
  Shape far = make_cone(v3(0, 0, 1e6f), v3(0, 0, -1), 1, 0, 2, kCapBase);
  Cast c = cast(far, v3(0, 0, 0), v3(0, 0, 1)); // meets the apex at 1e6 - 2
  ASSERT_TRUE(c.hit);
  EXPECT_NEAR(c.h.t, 1e6 - 2, 0.125);
  Shape tiny = make_cone(v3(0, -5e-5f, 1), v3(0, 1, 0), 1e-4f, 0, 1e-4f, kCapBase);
  Cast t = cast(tiny, v3(0, 0, 0), v3(0, 0, 1)); // radius 5e-5 at y = 0
  ASSERT_TRUE(t.hit);
  expect_valid_hit(t, v3(0, 0, 1), "tiny cone");
  EXPECT_NEAR(t.h.t, 1 - 5e-5, 1e-7);
}

TEST(Cone, DegenerateDimensionsNeverNaN) {
  // Zero height (k = -inf), zero base radius (a needle), top wider than base.
  Shape shapes[] = {make_cone(v3(0, 0, 0), v3(0, 1, 0), 1, 0, 0, kCapBase),
                    make_cone(v3(0, 0, 0), v3(0, 1, 0), 0, 1e-30f, 2, kCapBase | kCapTop),
                    make_cone(v3(0, 0, 0), v3(0, 1, 0), 0.2f, 2, 1, kCapBase | kCapTop)};
  Rng g(110);
  for (const Shape& s : shapes) {
    for (int i = 0; i < 2000; ++i) {
      Vec3 o = fv(rand_ball(g, 4)), d = fdir(rand_ball(g, 1.2) - dv(o));
      Cast c = cast(s, o, d);
      if (c.hit) {
        expect_valid_hit(c, d, "degenerate cone");
      } else {
        ASSERT_TRUE(untouched(c, kHuge));
      }
    }
  }
}

// Rays aimed exactly at a cap's rim that enter the solid through both the
// side and the cap (cos <= -0.001 with each) must hit: a miss, or a hit from
// inside (the far wall), is a crack between the two pieces. The float
// origin is chosen first and the direction aimed from it, so the float ray
// passes the rim point within eps of its length (rounding the origin after
// aiming moved it by eps |origin|, the world's magnitude, up to 1e-6 here:
// enough for a grazing ray to pass outside the solid). A ray that the
// double reference still does not see entering is set aside and counted.
void expect_rim_watertight(const char* name, u8 capsWanted, bool fullCone) {
  Rng g(111);
  long rays = 0, cracks = 0, setAside = 0;
  for (int shape = 0; shape < 200; ++shape) {
    Sample smp = random_shape(fullCone ? Kind::FullCone : Kind::CappedCylinder, g);
    Shape& s = smp.s;
    if (!fullCone && uni(g, 0, 1) < 0.5) { // also frusta with both caps
      s = make_cone(s.a, s.b, s.r0, float(s.r0 * uni(g, 0.2, 0.9)), s.h, kCapBase | kCapTop);
    }
    D3 ax = unit(dv(s.b)), e1, e2;
    frame(ax, e1, e2);
    double k = (double(s.r1) - s.r0) / s.h;
    for (int i = 0; i < 1000; ++i) {
      bool top = (capsWanted & kCapTop) && (i & 1);
      double ph = uni(g, 0, 2 * M_PI), rc = top ? s.r1 : s.r0;
      D3 radial = e1 * std::cos(ph) + e2 * std::sin(ph);
      D3 P = dv(s.a) + ax * (top ? double(s.h) : 0.0) + radial * rc;
      D3 nSide = unit(radial - ax * k), nCap = top ? ax : -ax, d{0, 0, 0};
      D3 along = cross(radial, ax); // the rim's tangent
      bool found = false;
      for (int attempt = 0; attempt < 100 && !found; ++attempt) {
        d = unit(-(nSide * uni(g, 0.05, 1) + nCap * uni(g, 0.05, 1)) + along * uni(g, -1, 1) +
                 rand_unit(g) * 0.3);
        found = dot(d, nSide) < -0.001 && dot(d, nCap) < -0.001;
      }
      if (!found) continue; // a wedge too thin to aim into
      Vec3 o = fv(P - d * (smp.extent * uni(g, 0.1, 3)));
      d = unit(P - dv(o));
      if (!(dot(d, nSide) < -0.001 && dot(d, nCap) < -0.001)) continue;
      Vec3 fd = fdir(d);
      Ref r = ref_intersect(s, dv(o), dv(fd));
      if (!r.hit || !r.front) {
        ++setAside;
        continue;
      }
      Cast c = cast(s, o, fd);
      ++rays;
      if (!c.hit || !c.h.front) {
        if (++cracks <= 5)
          std::printf("  crack: kind %d a=(%.9g,%.9g,%.9g) b=(%.9g,%.9g,%.9g) r0=%.9g r1=%.9g "
                      "h=%.9g caps=%d; org=(%.9g,%.9g,%.9g) dir=(%.9g,%.9g,%.9g) cos side %.3g "
                      "cap %.3g; hit=%d t=%.9g dist=%.9g\n",
                      int(s.kind), s.a.x, s.a.y, s.a.z, s.b.x, s.b.y, s.b.z, s.r0, s.r1, s.h,
                      int(s.caps), o.x, o.y, o.z, fd.x, fd.y, fd.z, dot(d, nSide), dot(d, nCap),
                      int(c.hit), c.h.t, norm(P - dv(o)));
      }
    }
  }
  std::printf("[ measured ] %s: %ld rays aimed at cap rims, %ld passed through (%ld set aside: "
              "the reference sees them miss)\n",
              name, rays, cracks, setAside);
  EXPECT_GT(rays, 150000);
  EXPECT_EQ(cracks, 0);
}

TEST(Cylinder, CapRimNoCrack) {
  expect_rim_watertight("cylinder/frustum", kCapBase | kCapTop, false);
}
TEST(Cone, BaseCapRimNoCrack) { expect_rim_watertight("full cone", kCapBase, true); }

// ---- triangle (a = origin, b = +x, c = +y: normal +z)

Shape unit_triangle() { return make_triangle(v3(0, 0, 0), v3(1, 0, 0), v3(0, 1, 0)); }

TEST(Triangle, InteriorHitBothSides) {
  Cast back = cast(unit_triangle(), v3(0.25f, 0.25f, -1), v3(0, 0, 1));
  ASSERT_TRUE(back.hit);
  EXPECT_EQ(back.h.t, 1.0f);
  EXPECT_FALSE(back.h.front);
  EXPECT_EQ(back.h.normal.z, -1.0f);
  Cast front = cast(unit_triangle(), v3(0.25f, 0.25f, 2), v3(0, 0, -1));
  ASSERT_TRUE(front.hit);
  EXPECT_EQ(front.h.t, 2.0f);
  EXPECT_TRUE(front.h.front);
  EXPECT_EQ(front.h.normal.z, 1.0f);
}

TEST(Triangle, EdgesAndVerticesAreInclusiveHeadOn) {
  // Axis-aligned rays at edge midpoints and vertices: the edge function is
  // exactly 0 there and the test is inclusive.
  Shape s = unit_triangle();
  for (Vec3 p :
       {v3(0.5f, 0, 0), v3(0.5f, 0.5f, 0), v3(0, 0.5f, 0), v3(0, 0, 0), v3(1, 0, 0), v3(0, 1, 0)}) {
    Cast c = cast(s, v3(p.x, p.y, 3), v3(0, 0, -1));
    ASSERT_TRUE(c.hit) << p.x << "," << p.y;
    EXPECT_EQ(c.h.t, 3.0f);
  }
  EXPECT_FALSE(cast(s, v3(0.5f, 0.5f + 1e-6f, 3), v3(0, 0, -1)).hit);
  EXPECT_FALSE(cast(s, v3(-1e-7f, 0.5f, 3), v3(0, 0, -1)).hit);
}

// hit_triangle() as it was before round thirteen, for tMin = 0 and no hit
// yet: edge functions of exactly 0 recomputed in double before the test of
// their signs (shapes.cpp now tests the signs first and recomputes only
// where they do not already say "beside"). The same float operations, so
// the same bits.
bool triangle_before13(const Shape& s, Vec3 org, Vec3 dir, float& t, bool& zero) {
  zero = false;
  Vec3 ao = org - s.a;
  float side = dot(s.n, ao), away = dot(s.n, dir);
  if ((side > 0 ? away > 0 : away < 0) && std::fabs(side) > s.sideMargin * max_abs(ao))
    return false;
  float d[3] = {dir.x, dir.y, dir.z}, o[3] = {org.x, org.y, org.z};
  float a[3] = {s.a.x, s.a.y, s.a.z}, b[3] = {s.b.x, s.b.y, s.b.z}, c[3] = {s.c.x, s.c.y, s.c.z};
  float ax = std::fabs(d[0]), ay = std::fabs(d[1]), az = std::fabs(d[2]);
  int kz = ax > ay ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
  int kx = kz == 2 ? 0 : kz + 1, ky = kx == 2 ? 0 : kx + 1;
  if (d[kz] < 0) std::swap(kx, ky);
  float Sx = d[kx] / d[kz], Sy = d[ky] / d[kz], Sz = 1.0f / d[kz];
  float Az = a[kz] - o[kz], Bz = b[kz] - o[kz], Cz = c[kz] - o[kz];
  float Ax = (a[kx] - o[kx]) - Sx * Az, Ay = (a[ky] - o[ky]) - Sy * Az;
  float Bx = (b[kx] - o[kx]) - Sx * Bz, By = (b[ky] - o[ky]) - Sy * Bz;
  float Cx = (c[kx] - o[kx]) - Sx * Cz, Cy = (c[ky] - o[ky]) - Sy * Cz;
  float U = Cx * By - Cy * Bx, V = Ax * Cy - Ay * Cx, W = Bx * Ay - By * Ax;
  if (U == 0 || V == 0 || W == 0) {
    zero = true;
    U = (float)((double)Cx * By - (double)Cy * Bx);
    V = (float)((double)Ax * Cy - (double)Ay * Cx);
    W = (float)((double)Bx * Ay - (double)By * Ax);
  }
  if ((U < 0 || V < 0 || W < 0) && (U > 0 || V > 0 || W > 0)) return false;
  float det = U + V + W;
  if (det == 0) return false;
  t = (U * Sz * Az + V * Sz * Bz + W * Sz * Cz) / det;
  return t > 0 && t < kHuge;
}

TEST(Triangle, ZeroEdgeFunctionsGiveTheAnswerOfTheRecomputeFirst) {
  // Rays whose float edge functions come out exactly 0 (through vertices,
  // along edges and their extensions beyond the vertices, on dyadic
  // triangles and grid points, axis-aligned and 45-degree directions) and
  // random rays at edges: hit or miss and t, bit for bit, as the order
  // before round thirteen gives them.
  Rng g(1313);
  long rays = 0, zeros = 0, hits = 0;
  const Vec3 dirs[] = {v3(0, 0, -1),
                       v3(0, 0, 1),
                       v3(1, 0, 0),
                       v3(0, -1, 0),
                       normalize(v3(1, 0, -1)),
                       normalize(v3(0, 1, -1)),
                       normalize(v3(-1, -1, -1))};
  for (int tri = 0; tri < 64; ++tri) {
    auto grid = [&](int n) { return (float)std::floor(uni(g, -n, n + 1)) * 0.25f; };
    Vec3 a = v3(grid(8), grid(8), grid(2)), b = v3(grid(8), grid(8), grid(2)),
         c = v3(grid(8), grid(8), grid(2));
    if (tri == 0) a = v3(0, 0, 0), b = v3(1, 0, 0), c = v3(0, 1, 0);
    Shape s = make_triangle(a, b, c);
    if (s.kind != kTriangle) continue;
    for (int i = 0; i < 4000; ++i) {
      Vec3 dir = dirs[i % 7];
      Vec3 p;
      Vec3 org;
      if (i % 2) { // a random ray through a point of an edge's line (double)
        const Vec3* v[3] = {&a, &b, &c};
        D3 e0 = dv(*v[i % 3]), e1 = dv(*v[(i + 1) % 3]);
        D3 q = e0 + (e1 - e0) * uni(g, -0.5, 1.5), d = rand_unit(g);
        dir = fdir(d);
        org = fv(q - d * uni(g, 0.5, 8));
      } else {
        if (i % 3 == 0) { // a grid point: on edges, their extensions and vertices
          p = v3(grid(10), grid(10), grid(3));
        } else { // on an edge's line, inside or beyond its ends
          Vec3 e0 = i % 3 == 1 ? a : b, e1 = i % 3 == 1 ? c : a;
          float u = (float)std::floor(uni(g, -8, 13)) * 0.125f;
          p = e0 + (e1 - e0) * u;
        }
        org = p - dir * 4.0f;
      }
      float tRef = 0;
      bool zero = false;
      bool ref = triangle_before13(s, org, dir, tRef, zero);
      Hit h;
      h.t = kHuge;
      bool got = intersect_t(s, Ray{org, dir}, 0.0f, h);
      ++rays;
      hits += ref;
      zeros += zero;
      ASSERT_EQ(got, ref) << "triangle " << tri << " ray " << i;
      if (ref) {
        ASSERT_EQ(h.t, tRef) << "triangle " << tri << " ray " << i;
      }
    }
  }
  std::printf("[ measured ] %ld rays at edges and vertices: %ld hits, %ld with a float edge "
              "function of 0\n",
              rays, hits, zeros);
  EXPECT_GE(rays, 200000);
  EXPECT_GE(hits, 20000);
  EXPECT_GE(zeros, 10000);
}

TEST(Triangle, ObliqueRaysAtEdgesAndVerticesFinite) {
  Shape s = unit_triangle();
  Rng g(112);
  for (int i = 0; i < 5000; ++i) {
    D3 targets[6] = {
        {uni(g, 0, 1), 0, 0}, {0, uni(g, 0, 1), 0}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0}};
    double u = uni(g, 0, 1);
    targets[5] = {u, 1 - u, 0};
    D3 d = rand_unit(g);
    Vec3 o = fv(targets[i % 6] - d * uni(g, 0.5, 5)), fd = fdir(d);
    expect_on_surface_or_untouched(s, o, fd, "edge/vertex", i);
  }
}

TEST(Triangle, QuadDiagonalHasNoCracks) {
  // Two triangles sharing the diagonal a-c, as scene 2's ground (a, c, b) and
  // (a, d, c); seeded rays at points of the diagonal, crossing the surface,
  // must hit at least one. Checked on the scene's ground quad and on random
  // quads, flat and folded.
  Rng g(113);
  long rays = 0, cracks = 0;
  for (int q = 0; q < 200; ++q) {
    Vec3 a, b, c, d;
    if (q == 0) {
      a = v3(-7, 0, -7), b = v3(7, 0, -7), c = v3(7, 0, 7), d = v3(-7, 0, 7);
    } else {
      D3 cen{uni(g, -20, 20), uni(g, -20, 20), uni(g, -20, 20)};
      double L = loguni(g, 0.05, 10);
      D3 A = cen + rand_ball(g, L), C = cen + rand_ball(g, L), mid = (A + C) * 0.5;
      D3 e = unit(cross(C - A, rand_unit(g))) * (L * uni(g, 0.2, 1));
      D3 fold = unit(cross(C - A, e)) * (q % 2 ? 0.0 : L * uni(g, -0.5, 0.5));
      a = fv(A), c = fv(C), b = fv(mid + e + fold), d = fv(mid - e + fold);
    }
    Shape t1 = make_triangle(a, c, b), t2 = make_triangle(a, d, c);
    D3 A = dv(a), C = dv(c);
    D3 n1 = cross(C - A, dv(b) - A), n2 = cross(dv(d) - A, C - A);
    for (int i = 0; i < 1000; ++i) {
      D3 p = A + (C - A) * uni(g, 0, 1);
      D3 dir = rand_unit(g);
      // On a folded quad a ray that sees one face from the front and the
      // other from the back only touches the ridge (it does not cross the
      // surface): it may miss both. Keep rays that cross, 0.01 clear of that.
      double c1 = dot(dir, unit(n1)), c2 = dot(dir, unit(n2));
      if (!(c1 * c2 > 0 && std::fabs(c1) > 0.01 && std::fabs(c2) > 0.01)) {
        --i;
        continue;
      }
      Vec3 o = fv(p - dir * (norm(C - A) * uni(g, 0.05, 3))), fd = fdir(dir);
      ++rays;
      Cast h1 = cast(t1, o, fd), h2 = cast(t2, o, fd);
      if (!h1.hit && !h2.hit) ++cracks;
    }
  }
  std::printf("[ measured ] quad diagonals: %ld rays, %ld cracks\n", rays, cracks);
  EXPECT_GE(rays, 200000);
  EXPECT_EQ(cracks, 0);
}

TEST(Triangle, FanAroundSharedVertexHasNoHole) {
  // Six triangles around a shared centre vertex; rays aimed at the centre.
  Rng g(114);
  long rays = 0, holes = 0;
  for (int f = 0; f < 50; ++f) {
    D3 cen{uni(g, -20, 20), uni(g, -20, 20), uni(g, -20, 20)}, n = rand_unit(g), e1, e2;
    frame(n, e1, e2);
    double L = loguni(g, 0.05, 10);
    Vec3 fc = fv(cen);
    Shape fan[6];
    for (int k = 0; k < 6; ++k) {
      double a0 = k * M_PI / 3, a1 = (k + 1) * M_PI / 3;
      D3 p0 = cen + (e1 * std::cos(a0) + e2 * std::sin(a0)) * L + n * (L * 0.1 * std::sin(3 * a0));
      D3 p1 = cen + (e1 * std::cos(a1) + e2 * std::sin(a1)) * L + n * (L * 0.1 * std::sin(3 * a1));
      fan[k] = make_triangle(fc, fv(p0), fv(p1));
    }
    for (int i = 0; i < 1000; ++i) {
      D3 d = rand_unit(g);
      if (std::fabs(dot(d, n)) < 0.2) continue; // the fan is not flat: stay clear of edge-on
      Vec3 o = fv(dv(fc) - d * (L * uni(g, 0.1, 3))), fd = fdir(d);
      bool any = false;
      for (const Shape& t : fan)
        any |= cast(t, o, fd).hit;
      ++rays;
      holes += !any;
    }
  }
  std::printf("[ measured ] vertex fans: %ld rays, %ld holes\n", rays, holes);
  EXPECT_EQ(holes, 0);
}

TEST(Triangle, RayInPlaneOrParallelMisses) {
  Shape s = unit_triangle();
  Cast inPlane = cast(s, v3(-1, 0.25f, 0), v3(1, 0, 0)); // edge-on: det = 0
  EXPECT_FALSE(inPlane.hit);
  EXPECT_TRUE(untouched(inPlane, kHuge));
  EXPECT_FALSE(cast(s, v3(-1, 0.25f, 0.5f), v3(1, 0, 0)).hit);
}

TEST(Triangle, DegenerateTrianglesRejectedSliversKept) {
  // Collinear vertices and a point have no area: empty shapes (they were hit
  // with normalize's invented +y normal). A sliver 1e-30 wide has an area
  // and, from the double cross product, its true normal +z.
  Shape shapes[] = {make_triangle(v3(0, 0, 0), v3(1, 0, 0), v3(2, 0, 0)),       // collinear
                    make_triangle(v3(1, 1, 1), v3(1, 1, 1), v3(1, 1, 1)),       // a point
                    make_triangle(v3(0, 0, 0), v3(1, 0, 0), v3(1, 1e-30f, 0))}; // sliver
  EXPECT_EQ(shapes[0].kind, kEmpty);
  EXPECT_EQ(shapes[1].kind, kEmpty);
  ASSERT_EQ(shapes[2].kind, kTriangle);
  Cast onSliver = cast(shapes[2], v3(0.999f, 0, 1), v3(0, 0, -1));
  if (onSliver.hit) {
    EXPECT_EQ(onSliver.h.normal.z, 1.0f);
  }
  Rng g(115);
  for (const Shape& s : shapes) {
    for (int i = 0; i < 2000; ++i) {
      Vec3 o = fv(rand_ball(g, 4)), d = fdir(rand_ball(g, 1.5) - dv(o));
      Cast c = cast(s, o, d);
      if (c.hit) {
        expect_valid_hit(c, d, "degenerate triangle");
      } else {
        ASSERT_TRUE(untouched(c, kHuge));
      }
    }
  }
}

TEST(Triangle, FarAwayAndTiny) {
  Shape far = make_triangle(v3(-1, -1, 1e6f), v3(1, -1, 1e6f), v3(0, 1, 1e6f));
  Cast c = cast(far, v3(0, 0, 0), v3(0, 0, 1));
  ASSERT_TRUE(c.hit);
  EXPECT_EQ(c.h.t, 1e6f);
  Shape tiny = make_triangle(v3(-1e-4f, -1e-4f, 1), v3(1e-4f, -1e-4f, 1), v3(0, 1e-4f, 1));
  Cast t = cast(tiny, v3(0, 0, 0), v3(0, 0, 1));
  ASSERT_TRUE(t.hit);
  EXPECT_EQ(t.h.t, 1.0f);
  Cast near = cast(unit_triangle(), v3(0.2f, 0.2f, 1e-6f), v3(0, 0, -1));
  ASSERT_TRUE(near.hit);
  EXPECT_EQ(near.h.t, 1e-6f);
}

// make_triangle() stores the unit normal hit_normal() returns (r0, r1, h):
// bit for bit the normalize(n) hit_normal() computed at every hit before,
// unit, along the double-precision cross product, and turned to face the
// ray on both sides, head-on and grazing (within 1e-3 of the plane).
TEST(Triangle, StoredUnitNormalIsNormalizeOfN) {
  Rng g(117);
  int hits = 0, grazing = 0;
  for (int i = 0; i < 20000; ++i) {
    double scale = loguni(g, 0x1p-28, 0x1p29);
    D3 centre = rand_ball(g, 0x1p31 * uni(g, 0, 1) * uni(g, 0, 1));
    D3 p[3];
    for (D3& v : p)
      v = centre + rand_unit(g) * scale;
    if (i % 4 == 0)
      p[2] = p[0] + (p[1] - p[0]) * uni(g, 0, 1) + rand_unit(g) * (scale * 1e-6); // sliver
    Shape s = make_triangle(fv(p[0]), fv(p[1]), fv(p[2]));
    if (s.kind != kTriangle) continue;
    Vec3 stored = normalize(s.n);
    ASSERT_EQ(0, std::memcmp(&stored.x, &s.r0, 4)) << i;
    ASSERT_EQ(0, std::memcmp(&stored.y, &s.r1, 4)) << i;
    ASSERT_EQ(0, std::memcmp(&stored.z, &s.h, 4)) << i;
    ASSERT_NEAR(flen(stored), 1.0, 1e-6) << i;
    D3 exact = unit(cross(dv(s.b) - dv(s.a), dv(s.c) - dv(s.a)));
    ASSERT_GT(dot(exact, dv(stored)), 1.0 - 1e-6) << i;
    // Rays through the centroid from both sides, head-on and grazing.
    D3 at = (dv(s.a) + dv(s.b) + dv(s.c)) * (1.0 / 3);
    D3 e1, e2;
    frame(exact, e1, e2);
    for (int side = -1; side <= 1; side += 2) {
      for (double c : {1.0, 1e-3}) {
        D3 d = unit(exact * (-side * c) + e1 * std::sqrt(1 - c * c));
        Vec3 dir = fdir(d), org = fv(at - d * (2 * scale));
        Cast hit = cast(s, org, dir);
        if (!hit.hit) continue;
        ++hits;
        grazing += c < 1;
        bool front = side > 0;
        ASSERT_EQ(hit.h.front, front) << i;
        Vec3 want = front ? stored : -stored;
        ASSERT_EQ(0, std::memcmp(&hit.h.normal, &want, sizeof(Vec3))) << i;
        ASSERT_LE(dot(hit.h.normal, dir), 0.0f) << i;
      }
    }
  }
  EXPECT_GT(hits, 25000);   // 25,534 (slivers are missed by many grazing rays)
  EXPECT_GT(grazing, 9000); // 9,199
}

TEST(Triangle, SpawnedRayDoesNotRehit) {
  Rng g(116);
  int n = 0;
  for (int i = 0; i < 5000; ++i) {
    Sample smp = random_shape(Kind::Triangle, g);
    Vec3 o, d;
    random_ray(smp, g, o, d);
    Cast c = cast(smp.s, o, d);
    if (!c.hit) continue;
    Vec3 p = at(o, d, c.h.t);
    for (double side : {1.0, -1.0}) {
      Vec3 d2 = fdir(rand_hemi(g, dv(c.h.normal) * side, 0.001));
      EXPECT_FALSE(
          cast(smp.s, spawn_origin(p, c.h.normal, d2, spawn_offset(p, spawn_scale(smp.s, c.h))), d2)
              .hit)
          << i;
    }
    ++n;
  }
  EXPECT_GT(n, 1000);
}

// ---- every shape

std::vector<Shape> one_of_each() {
  return {make_sphere(v3(0, 0, 0), 1),
          make_plane(v3(0, 1, 0), 0),
          unit_cylinder(),
          unit_cone(),
          open_frustum(),
          unit_triangle()};
}

TEST(AllShapes, NaNAndInfRaysNeverHit) {
  // Like Embree's verifier: non-finite input on purpose. The contract needs a
  // finite origin and unit direction; with them broken, no hit may be
  // reported and the Hit must stay as it was.
  const Vec3 orgs[] = {v3(kNaN, 0, 0), v3(0, kInf, 0), v3(0, 0.5f, -kInf), v3(0.2f, 0.2f, 5)};
  const Vec3 dirs[] = {v3(kNaN, kNaN, kNaN), v3(0, 0, kNaN), v3(kInf, 0, 0), v3(0, -1, 0)};
  for (const Shape& s : one_of_each())
    for (Vec3 o : orgs)
      for (Vec3 d : dirs) {
        if (finite3(o) && finite3(d)) continue;
        Cast c = cast(s, o, d);
        if (c.hit) { // an Inf direction may still give a finite t; never NaN
          EXPECT_TRUE(std::isfinite(c.h.t) && finite3(c.h.normal)) << int(s.kind);
        } else {
          EXPECT_TRUE(untouched(c, kHuge)) << int(s.kind);
        }
        if (std::isnan(o.x) || std::isnan(d.x) || std::isnan(d.z)) {
          EXPECT_FALSE(c.hit) << int(s.kind);
        }
      }
}

TEST(AllShapes, ZeroDirectionNeverNaN) {
  for (const Shape& s : one_of_each())
    for (Vec3 o : {v3(0.2f, 0.5f, 0.1f), v3(3, 3, 3), v3(0.2f, 0.2f, 0)}) {
      Cast c = cast(s, o, v3(0, 0, 0));
      if (c.hit) {
        EXPECT_TRUE(std::isfinite(c.h.t) && finite3(c.h.normal)) << int(s.kind);
      } else {
        EXPECT_TRUE(untouched(c, kHuge)) << int(s.kind);
      }
    }
}

TEST(AllShapes, IntervalIsOpenAndRespected) {
  // A hit only for tMin < t < hit.t: the same ray with the window moved.
  struct Case {
    Shape s;
    Vec3 o, d;
    float t;
  };
  const Case cases[] = {{make_sphere(v3(0, 0, 0), 1), v3(0, 0, -5), v3(0, 0, 1), 4},
                        {make_plane(v3(0, 1, 0), 0), v3(0, 2, 0), v3(0, -1, 0), 2},
                        {unit_cylinder(), v3(-5, 1, 0), v3(1, 0, 0), 4},
                        {unit_cone(), v3(0, 5, 0), v3(0, -1, 0), 3},
                        {open_frustum(), v3(0, 5, 0), v3(0, -1, 0), 5},
                        {unit_triangle(), v3(0.2f, 0.2f, 3), v3(0, 0, -1), 3}};
  for (const Case& k : cases) {
    Cast first = cast(k.s, k.o, k.d);
    ASSERT_TRUE(first.hit) << int(k.s.kind);
    float t = first.h.t;
    EXPECT_NEAR(t, k.t, 4e-7 * k.t) << int(k.s.kind);
    Cast notNearer = cast(k.s, k.o, k.d, 0, t); // hit.t == t: not nearer, untouched
    EXPECT_FALSE(notNearer.hit) << int(k.s.kind);
    EXPECT_TRUE(untouched(notNearer, t)) << int(k.s.kind);
    EXPECT_FALSE(cast(k.s, k.o, k.d, 0, t * 0.5f).hit) << int(k.s.kind);
    Cast later = cast(k.s, k.o, k.d, t); // t == tMin: excluded; a far side may follow
    if (later.hit) {
      EXPECT_GT(later.h.t, t) << int(k.s.kind);
    }
    Cast window = cast(k.s, k.o, k.d, 0, kSentinelT);
    ASSERT_TRUE(window.hit);
    EXPECT_EQ(window.h.t, t) << int(k.s.kind);
  }
}

// ============================================================ properties

struct SpawnCase {
  Sample smp;
  Vec3 p, n;   // float hit point and ray-facing normal
  float scale; // spawn_scale() of the hit
  bool front, degenerate, apex;
};

struct PropStats {
  long rays = 0, hits = 0, refCompared = 0, excluded = 0, excludedDisagree = 0;
  long mismatchHit = 0, mismatchT = 0, mismatchFront = 0, offSurface = 0, badNormal = 0;
  long spawnOut = 0, spawnOutFail = 0, spawnIn = 0, spawnInFail = 0, spawnSideFail = 0;
  long spawnInEdge = 0, spawnInThin = 0, spawnApex = 0;
  double maxSurf = 0, maxT = 0, maxSurfOverOffset = 0, maxSurfApex = 0;
  long apexHits = 0;
  std::string examples; // the first few failures, for the assertion message
  int noted = 0;
};

void note(PropStats* st, const char* what, const Shape& s, Vec3 o, Vec3 d, const Cast& c,
          const Ref& r) {
  if (!st || st->noted++ >= 8) return;
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "\n  %s: shape kind %d a=(%.9g,%.9g,%.9g) b=(%.9g,%.9g,%.9g) c=(%.9g,%.9g,%.9g) "
                "r0=%.9g r1=%.9g h=%.9g caps=%d; org=(%.9g,%.9g,%.9g) dir=(%.9g,%.9g,%.9g); "
                "float hit=%d t=%.9g front=%d; ref hit=%d t=%.17g piece=%d front=%d",
                what, int(s.kind), s.a.x, s.a.y, s.a.z, s.b.x, s.b.y, s.b.z, s.c.x, s.c.y, s.c.z,
                s.r0, s.r1, s.h, int(s.caps), o.x, o.y, o.z, d.x, d.y, d.z, int(c.hit), c.h.t,
                int(c.h.front), int(r.hit), r.t, r.piece, int(r.front));
  st->examples += buf;
}

// Outcome of a spawned ray: 0 = fine, 1 = re-hit near t = 0 (or a closed
// solid's far side missed).
int check_spawn(const Sample& smp, Vec3 p, float scale, Vec3 n, bool front, Vec3 d2,
                float offsetScale, bool strict, bool edgeHit, bool apexHit, PropStats* st) {
  const Shape& s = smp.s;
  // Next to a cone's apex the side's normal (and so which way is out) is
  // itself rounding noise: such hits are counted, not checked.
  if (apexHit) {
    if (st) ++st->spawnApex;
    return 0;
  }
  D3 outward = dv(front ? n : -n);
  bool leaving = dot(dv(d2), outward) > 0;
  bool flat = s.kind == kPlane || s.kind == kTriangle;
  float off = offsetScale * spawn_offset(p, scale);
  Vec3 o2 = p + n * (dot(d2, n) >= 0 ? off : -off);
  if (offsetScale == 1.0f) { // the shipped function itself
    Vec3 o1 = spawn_origin(p, n, d2, spawn_offset(p, scale));
    EXPECT_TRUE(o1.x == o2.x && o1.y == o2.y && o1.z == o2.z);
  }
  Cast c = cast(s, o2, d2);
  if (flat || leaving) {
    // Flat shapes are never met again; a ray leaving a convex solid's
    // boundary outward never meets the solid again.
    if (st) ++st->spawnOut;
    if (c.hit && st) {
      ++st->spawnOutFail;
      note(st, "spawned ray re-hit", s, o2, d2, c, Ref{});
    }
    return c.hit ? 1 : 0;
  }
  // Going into the solid. From a hit within rounding of an edge or rim, an
  // offset along the normal of one piece need not move the origin inside the
  // other: such hits (the near-degenerate set) are counted, not checked.
  if (st) ++st->spawnIn;
  if (edgeHit) {
    if (st) ++st->spawnInEdge;
    return 0;
  }
  // Where the solid is thinner than a few offsets (next to a small cone's
  // apex, a thin disc's rim), an offset along the normal crosses it: such
  // hits are counted, not checked.
  {
    double S = scale_of(smp, p, p);
    Shape closed = s; // an open frustum: the solid its missing cap would close
    if (closed.kind != kSphere) closed.caps = kCapBase | kCapTop;
    Ref thick = ref_intersect(closed, dv(p), -outward, 1e-4 * S);
    if (!thick.hit || thick.t < 4.0 * spawn_offset(p, scale)) {
      if (st) ++st->spawnInThin;
      return 0;
    }
  }
  if (strict) {
    // The spawned origin must be inside the solid (offset larger than p's error).
    bool inside = inside_solid(s, dv(o2));
    Ref r = ref_intersect(s, dv(o2), dv(d2));
    if (!inside && st) {
      ++st->spawnSideFail;
      note(st, "spawned origin outside the solid", s, o2, d2, c, r);
    }
    double S = scale_of(smp, o2, p);
    if (near_degenerate(s, dv(o2), dv(d2), r, kPerturb * S)) return 0;
    bool ok = c.hit == r.hit;
    if (ok && c.hit) {
      double kappa = 1 / std::max(std::fabs(dot(r.n, dv(d2))), 1e-12);
      ok = std::fabs(c.h.t - r.t) <= kTTol * S * kappa;
    }
    if (smp.closed && !c.hit) ok = false;
    if (!ok && st) {
      ++st->spawnInFail;
      note(st, "spawned ray into the solid", s, o2, d2, c, r);
    }
    return ok ? 0 : 1;
  }
  // Offset sweep (offsets scaled down): the spawned origin must be inside the
  // solid (the offset cleared p's rounding error), and the float ray must not
  // find a surface near t = 0 that the exact answer from the same origin
  // does not have; a closed solid's far side must be found.
  double offNominal = spawn_offset(p, scale);
  Ref r = ref_intersect(s, dv(o2), dv(d2));
  if (near_degenerate(s, dv(o2), dv(d2), r, kPerturb * scale_of(smp, o2, p))) return 0;
  bool fail = !inside_solid(s, dv(o2)) ||
              (c.hit && c.h.t < 16 * offNominal && !(r.hit && r.t < 32 * offNominal)) ||
              (smp.closed && !c.hit);
  if (fail) note(st, "sweep: spawned ray into the solid", s, o2, d2, c, r);
  return fail ? 1 : 0;
}

void run_properties(Kind kind, unsigned seed) {
  Rng g(seed);
  PropStats st;
  std::vector<SpawnCase> keep;
  constexpr int kRays = 100000, kRaysPerShape = 100;
  Sample smp{};
  for (int i = 0; i < kRays; ++i) {
    if (i % kRaysPerShape == 0) smp = random_shape(kind, g);
    const Shape& s = smp.s;
    Vec3 o, d;
    random_ray(smp, g, o, d);
    ++st.rays;
    Cast c = cast(s, o, d);
    Ref r = ref_intersect(s, dv(o), dv(d));
    double S = scale_of(smp, o, c.hit ? at(o, d, c.h.t) : o);
    bool degenerate = near_degenerate(s, dv(o), dv(d), r, kPerturb * S);
    if (!c.hit) {
      ASSERT_TRUE(untouched(c, kHuge)) << "a miss changed the Hit, ray " << i;
    } else {
      ++st.hits;
      ASSERT_TRUE(std::isfinite(c.h.t) && c.h.t > 0 && c.h.t < kHuge) << i;
      ASSERT_TRUE(finite3(c.h.normal)) << i;
      // Facing the ray up to the rounding of a dot product of nearly
      // perpendicular unit vectors (a plane decides its side in double).
      if (!(std::fabs(flen(c.h.normal) - 1) <= kUnitTol) || dot(c.h.normal, d) > 4 * kEps) {
        ++st.badNormal;
        note(&st, "normal not unit or not facing the ray", s, o, d, c, r);
      }
      Vec3 p = at(o, d, c.h.t);
      // On the finite surface; for near-degenerate rays (grazing, at an
      // edge) on the piece's carrier surface.
      double dist = degenerate ? carrier_distance(s, dv(p)) : surface_distance(s, dv(p));
      bool apex = near_apex(s, dv(o), dv(d), S);
      if (apex) {
        ++st.apexHits;
        st.maxSurfApex = std::max(st.maxSurfApex, dist / S);
      } else {
        st.maxSurf = std::max(st.maxSurf, dist / S);
      }
      if (dist > (apex ? kApexTol : kSurfTol) * S) {
        ++st.offSurface;
        note(&st, "hit point off the surface", s, o, d, c, r);
      }
      float scale = spawn_scale(s, c.h);
      if (!apex)
        st.maxSurfOverOffset = std::max(st.maxSurfOverOffset, dist / spawn_offset(p, scale));
      // Spawned rays: one back to the incoming side, one through.
      for (double side : {1.0, -1.0}) {
        Vec3 d2 = fdir(rand_hemi(g, dv(c.h.normal) * side, 1.0 / 1024));
        check_spawn(smp, p, scale, c.h.normal, c.h.front, d2, 1.0f, true, degenerate, apex, &st);
      }
      if (keep.size() < 20000)
        keep.push_back({smp, p, c.h.normal, scale, c.h.front, degenerate, apex});
    }
    // Agreement with the reference, near-degenerate rays excluded and counted.
    bool agree = c.hit == r.hit;
    double tErr = 0, kappa = 1;
    if (agree && c.hit) {
      kappa = 1 / std::max(std::fabs(dot(r.n, dv(d))), 1e-12);
      tErr = std::fabs(c.h.t - r.t) / (S * kappa);
      agree = tErr <= kTTol && c.h.front == r.front;
    }
    if (degenerate) {
      ++st.excluded;
      st.excludedDisagree += !agree;
      continue;
    }
    ++st.refCompared;
    if (c.hit != r.hit) {
      ++st.mismatchHit;
      note(&st, "hit/miss differs from the reference", s, o, d, c, r);
    } else if (c.hit) {
      st.maxT = std::max(st.maxT, tErr);
      if (tErr > kTTol) {
        ++st.mismatchT;
        note(&st, "t differs from the reference", s, o, d, c, r);
      }
      if (c.h.front != r.front) {
        ++st.mismatchFront;
        note(&st, "front differs from the reference", s, o, d, c, r);
      }
    }
  }

  // Smallest spawn offset (as a fraction of shapes.h's) with no failure at
  // it or any larger fraction, on up to 20,000 of the hits, two directions
  // each (outward cos >= 2^-10, inward cos >= 0.1).
  int safeLevel = -1;
  PropStats sweep;
  for (int level = 0; level <= 20; ++level) {
    float frac = std::ldexp(1.0f, -level);
    Rng g2(seed + 1);
    long fails = 0;
    for (const SpawnCase& k : keep) {
      D3 outward = dv(k.front ? k.n : -k.n);
      Vec3 out = fdir(rand_hemi(g2, outward, 1.0 / 1024)), in = fdir(rand_hemi(g2, -outward, 0.1));
      PropStats* log = level == 0 ? &sweep : nullptr;
      fails += check_spawn(k.smp, k.p, k.scale, k.n, k.front, out, frac, false, k.degenerate,
                           k.apex, log);
      fails += check_spawn(k.smp, k.p, k.scale, k.n, k.front, in, frac, false, k.degenerate, k.apex,
                           log);
    }
    if (fails) break;
    safeLevel = level;
  }
  if (safeLevel < 0) st.examples += "\n sweep at 2^0:" + sweep.examples;
  if (st.apexHits) {
    std::printf(
        "[ measured ] %s: %ld hits on rays through its part thinner than 2^-8 S, max surface "
        "distance / S = %.3g (tol %.3g)\n",
        kind_name(kind), st.apexHits, st.maxSurfApex, kApexTol);
  }

  const char* name = kind_name(kind);
  std::printf(
      "[ measured ] %s: %ld rays, %ld hits; vs double reference: %ld compared, %ld "
      "near-degenerate excluded (%ld of them disagreed); max |t - t_ref| / (S kappa) = %.3g "
      "(tol %.3g); max surface distance / S = %.3g (tol %.3g); max surface distance / "
      "spawn_offset = %.3g; spawned rays %ld out + %ld in (not checked: %ld in from "
      "near-degenerate hits, %ld where the solid is < 4 offsets thick, %ld near an apex); "
      "smallest safe spawn offset = 2^-%d of shapes.h's\n",
      name, st.rays, st.hits, st.refCompared, st.excluded, st.excludedDisagree, st.maxT, kTTol,
      st.maxSurf, kSurfTol, st.maxSurfOverOffset, st.spawnOut, st.spawnIn, st.spawnInEdge,
      st.spawnInThin, st.spawnApex, safeLevel);
  std::string key = std::string("shape_") + name;
  for (char& ch : key)
    if (ch == ' ') ch = '_';
  char buf[200];
  std::snprintf(buf, sizeof buf, "excluded=%ld/%ld maxT=%.3g maxSurf=%.3g safeSpawn=2^-%d",
                st.excluded, st.rays, st.maxT, st.maxSurf, safeLevel);
  ::testing::Test::RecordProperty(key, buf);

  SCOPED_TRACE(st.examples);
  EXPECT_EQ(st.rays, kRays);
  EXPECT_GT(st.hits, kRays / 5) << name;
  EXPECT_EQ(st.badNormal, 0) << name;
  EXPECT_EQ(st.offSurface, 0) << name;
  EXPECT_EQ(st.mismatchHit, 0) << name;
  EXPECT_EQ(st.mismatchT, 0) << name;
  EXPECT_EQ(st.mismatchFront, 0) << name;
  // 15% of the rays are built tangent on purpose; most of those are excluded.
  EXPECT_LT(st.excluded, kRays / 4) << name << ": the margin excludes too much to mean anything";
  EXPECT_EQ(st.spawnOutFail, 0) << name << ": a spawned ray re-hit its surface";
  EXPECT_EQ(st.spawnInFail, 0) << name << ": a spawned ray into the solid went wrong";
  EXPECT_EQ(st.spawnSideFail, 0) << name << ": spawn_origin() left p on the wrong side";
  EXPECT_GE(safeLevel, 0) << name << ": shapes.h's own spawn offset fails";
}

TEST(ShapeProperties, Sphere) { run_properties(Kind::Sphere, 1001); }
TEST(ShapeProperties, Plane) { run_properties(Kind::Plane, 1002); }
TEST(ShapeProperties, CappedCylinder) { run_properties(Kind::CappedCylinder, 1003); }
TEST(ShapeProperties, OpenFrustum) { run_properties(Kind::OpenFrustum, 1004); }
TEST(ShapeProperties, FullCone) { run_properties(Kind::FullCone, 1005); }
TEST(ShapeProperties, Triangle) { run_properties(Kind::Triangle, 1006); }

} // namespace

// intersect_pair() (shapes.h, kPairNext) against the two intersect_t() calls
// it stands for, bit for bit: the index found, hit.t, hit.piece and
// hit.local, and a hit left alone on a miss. The pairs: scene 2's stage
// square and random squares (the precondition: same a, n and sideMargin,
// first.b == second.c), in the three axis planes, from 2^-6 to 2^10 wide,
// up to 1e4 from the origin. Rays: through the shared diagonal (where
// both triangles may hit and the second is accepted only nearer), through
// the vertices and the outer edges, grazing (within 1e-7 .. 1e-2 rad of the
// plane), starting on the plane (spawned from it, both sides), random from
// all around, with and without a nearer hit already known, tMin 0 and
// negative (no side test).
namespace {
bool same_float(float a, float b) { return std::memcmp(&a, &b, 4) == 0; }
} // namespace

TEST(Triangle, PairIsTheTwoCallsBitForBit) {
  Rng g(131);
  long rays = 0, both = 0, second = 0, firstHits = 0, mismatches = 0;
  for (int q = 0; q < 120; ++q) {
    Vec3 a, b, c, d;
    if (q == 0) {
      a = v3(-7, 0, -7), b = v3(7, 0, -7), c = v3(7, 0, 7), d = v3(-7, 0, 7);
    } else {
      double w = std::ldexp(1.0, (int)uni(g, -6, 10)) * uni(g, 0.5, 1);
      float side = (float)w;
      D3 cen{uni(g, -1e4, 1e4), uni(g, -1e4, 1e4), uni(g, -1e4, 1e4)};
      if (q % 3 == 0) cen = rand_ball(g, 20);
      Vec3 o = fv(cen);
      int ax = q % 3; // the plane's normal axis
      auto put = [&](float u, float v) {
        Vec3 p = o;
        float* f = &p.x;
        f[(ax + 1) % 3] += u;
        f[(ax + 2) % 3] += v;
        return p;
      };
      a = put(0, 0), b = put(side, 0), c = put(side, side), d = put(0, side);
      if (q % 2) std::swap(b, d); // the other winding
    }
    Shape t1 = make_triangle(a, c, b), t2 = make_triangle(a, d, c);
    if (std::memcmp(&t1.n, &t2.n, sizeof(Vec3)) || !same_float(t1.sideMargin, t2.sideMargin) ||
        std::memcmp(&t1.b, &t2.c, sizeof(Vec3))) {
      continue; // the rounding of the corners broke the precondition: not a pair
    }
    D3 A = dv(a), B = dv(b), C = dv(c), Dd = dv(d);
    D3 n = unit(cross(C - A, B - A));
    double L = norm(C - A);
    for (int i = 0; i < 2500; ++i) {
      int kind = i % 6;
      D3 p, dir;
      switch (kind) {
      case 0:
        p = A + (C - A) * uni(g, -0.01, 1.01);
        break; // the diagonal
      case 1:
        p = (i / 6 % 4 == 0 ? A : i / 6 % 4 == 1 ? B : i / 6 % 4 == 2 ? C : Dd);
        break;
      case 2: { // the outer edges
        D3 e0 = i / 6 % 2 ? A : C, e1 = i / 6 % 4 < 2 ? B : Dd;
        p = e0 + (e1 - e0) * uni(g, 0, 1);
        break;
      }
      default:
        p = A + (B - A) * uni(g, -0.2, 1.2) + (Dd - A) * uni(g, -0.2, 1.2);
        break;
      }
      if (kind == 3) { // grazing
        D3 e1, e2;
        frame(n, e1, e2);
        double ph = uni(g, 0, 2 * M_PI), s = loguni(g, 1e-7, 1e-2) * (i % 2 ? 1 : -1);
        dir = unit((e1 * std::cos(ph) + e2 * std::sin(ph)) + n * s);
      } else {
        dir = rand_unit(g);
      }
      Vec3 fd = fdir(dir), org;
      if (kind == 4) { // starts on the plane (a spawned ray), either way
        org = fv(p + n * (L * std::ldexp(1.0, -(int)uni(g, 10, 30)) * (i % 2 ? 1 : -1)));
      } else {
        org = fv(p - dir * (L * loguni(g, 1e-3, 3)));
      }
      float tMin = i % 7 == 0 ? -1.0f : 0.0f;
      Ray ray{org, fd};
      Hit h2, h1;
      std::memset(&h2, 0x5a, sizeof(Hit));
      h2.t = i % 5 == 0 ? (float)(L * uni(g, 0, 3)) : kHuge; // a nearer hit may be known
      std::memcpy(&h1, &h2, sizeof(Hit));
      int twoCalls = -1;
      if (intersect_t(t1, ray, tMin, h2)) twoCalls = 0;
      bool firstHit = twoCalls == 0;
      if (intersect_t(t2, ray, tMin, h2)) twoCalls = 1;
      int pair = intersect_pair(t1, t2, ray, tMin, h1) - 1;
      ++rays;
      firstHits += firstHit;
      both += firstHit && twoCalls == 1;
      second += twoCalls == 1;
      if (pair != twoCalls || std::memcmp(&h1, &h2, sizeof(Hit))) ++mismatches;
    }
  }
  std::printf("[ measured ] triangle pairs: %ld rays, %ld first hits, %ld second hits, %ld both "
              "(second nearer), %ld mismatches\n",
              rays, firstHits, second, both, mismatches);
  EXPECT_GE(rays, 100000);
  EXPECT_GE(firstHits, 10000);
  EXPECT_GE(second, 10000);
  EXPECT_GE(both, 1); // rays through the diagonal that hit both, the second nearer
  EXPECT_EQ(mismatches, 0);
}

// plane_t() (shapes.h, kInlinePlane: the resumed tree's inline floor test)
// against intersect_t(), bit for bit (found, hit.t, hit.piece, hit.local; a
// miss leaves hit alone): rays going away from the plane (most of the
// floor's tests), towards it, from on it (spawned, both sides), with |cos|
// on both sides of kPlaneCosFloat (the float and the double path) and down
// to 1e-12, exactly parallel, with a nearer hit already known; planes of
// random normal and offset, and scene 1's floor.
TEST(Plane, InlineTestIsIntersectTBitForBit) {
  Rng g(137);
  long rays = 0, hits = 0, nearParallel = 0, mismatches = 0;
  for (int q = 0; q < 100; ++q) {
    Shape pl = q == 0 ? make_plane(v3(0, 1, 0), 0.0f)
                      : make_plane(fdir(rand_unit(g)), (float)uni(g, -100, 100));
    D3 n = dv(pl.a), b = dv(pl.b);
    for (int i = 0; i < 2000; ++i) {
      D3 p = b + rand_ball(g, 50);
      p = p - n * dot(p - b, n); // on the plane
      double h = i % 4 == 0 ? std::ldexp(1.0, -(int)uni(g, 8, 30)) : uni(g, 0.01, 30);
      D3 o = p + n * (i % 2 ? h : -h);
      D3 dir;
      int k = i % 5;
      if (k == 0 || k == 1) { // near parallel, either side of kPlaneCosFloat
        D3 e1, e2;
        frame(n, e1, e2);
        double ph = uni(g, 0, 2 * M_PI);
        double s = (k == 0 ? loguni(g, 1e-12, 1e-3) : uni(g, 0.5, 2) / 4096) * (i % 3 ? 1 : -1);
        if (i % 97 == 0) s = 0;
        dir = e1 * std::cos(ph) + e2 * std::sin(ph) + n * s;
        ++nearParallel;
      } else {
        dir = rand_unit(g);
      }
      Ray ray{fv(o), fdir(dir)};
      Hit h1, h2;
      std::memset(&h1, 0x5a, sizeof(Hit));
      h1.t = i % 3 == 0 ? (float)uni(g, 0, 60) : kHuge;
      std::memcpy(&h2, &h1, sizeof(Hit));
      bool a = intersect_t(pl, ray, 0.0f, h1), c = plane_t(pl, ray, h2);
      ++rays;
      hits += a;
      if (a != c || std::memcmp(&h1, &h2, sizeof(Hit))) ++mismatches;
    }
  }
  std::printf("[ measured ] inline plane: %ld rays, %ld hits, %ld near parallel, %ld mismatches\n",
              rays, hits, nearParallel, mismatches);
  EXPECT_GE(rays, 200000);
  EXPECT_GE(hits, 40000);
  EXPECT_EQ(mismatches, 0);
}
