// shapes.cpp - ray/shape intersection under the contract in shapes.h.
#include "shapes.h"

Shape make_sphere(Vec3 centre, float radius) {
  Shape s{};
  s.kind = kSphere;
  s.a = centre;
  s.r0 = radius;
  return s;
}

Shape make_plane(Vec3 normal, float offset) {
  Shape s{};
  s.kind = kPlane;
  s.a = normalize(normal);
  s.r0 = offset;
  return s;
}

Shape make_cone(Vec3 base, Vec3 axis, float baseRadius, float topRadius, float height, u8 caps) {
  Shape s{};
  s.kind = baseRadius == topRadius ? kCylinder : kCone;
  s.caps = caps;
  s.a = base;
  s.b = normalize(axis);
  s.r0 = baseRadius;
  s.r1 = topRadius;
  s.h = height;
  // Per-shape constants of hit_frustum(), computed once here.
  s.c.x = (topRadius - baseRadius) / height;
  s.c.y = max_abs(base) + height + baseRadius + topRadius;
  return s;
}

Shape make_cylinder(Vec3 base, Vec3 axis, float radius, float height, u8 caps) {
  return make_cone(base, axis, radius, radius, height, caps);
}

Shape make_triangle(Vec3 a, Vec3 b, Vec3 c) {
  Shape s{};
  s.kind = kTriangle;
  s.a = a;
  s.b = b;
  s.c = c;
  s.n = cross(b - a, c - a);
  s.sideMargin = kSideRel * max_abs(b - a) * max_abs(c - a);
  return s;
}

namespace {

// |x| by clearing the sign bit (one andps); equals rt_abs(x) but for the sign
// of a zero, which no caller here can tell apart.
inline float abs_bits(float x) { return __builtin_fabsf(x); }
inline float max_abs_bits(Vec3 a) {
  return rt_max(abs_bits(a.x), rt_max(abs_bits(a.y), abs_bits(a.z)));
}

// Accepts t when it is the new nearest: records t and which piece it is on.
// The normal waits for hit_normal(): only the nearest hit needs one.
bool accept(float t, float tMin, u8 piece, float local, Hit& hit) {
  if (!(t > tMin && t < hit.t)) return false;
  hit.t = t;
  hit.piece = piece;
  hit.local = local;
  return true;
}

// Writes the outward normal turned to face the ray, and hit.front.
void face(Vec3 outward, const Ray& ray, Hit& hit) {
  bool front = dot(outward, ray.dir) < 0;
  hit.normal = front ? outward : -outward;
  hit.front = front;
}

// Sphere, after Haines et al., "Precision Improvements for Ray/Sphere
// Intersection" (Ray Tracing Gems ch. 7): discriminant r^2 - |f - (f.d)d|^2
// and roots q = -(b + sign(b) sqrt(disc)), t0 = c/q, t1 = q (a = 1).
bool hit_sphere(const Shape& s, const Ray& ray, float tMin, Hit& hit) {
  Vec3 f = ray.org - s.a;
  float b = dot(f, ray.dir);
  Vec3 perp = f - ray.dir * b;
  float r2 = s.r0 * s.r0;
  float disc = r2 - dot(perp, perp);
  if (disc < 0) return false;
  float c = dot(f, f) - r2;
  float q = -(b + (b >= 0 ? rt_sqrt(disc) : -rt_sqrt(disc)));
  // q == 0 only when b == 0 and disc == 0: a tangent ray through the centre's
  // foot point from the centre itself (f = 0 and r = 0); no hit worth keeping.
  if (q == 0) return false;
  float t0 = c / q, t1 = q;
  if (t0 > t1) {
    float tmp = t0;
    t0 = t1;
    t1 = tmp;
  }
  float t = t0 > tMin ? t0 : t1;
  return accept(t, tMin, 0, 0.0f, hit);
}

void sphere_normal(const Shape& s, const Ray& ray, Hit& hit) {
  Vec3 p = ray.org + ray.dir * hit.t;
  face(normalize((p - s.a) * (1.0f / s.r0), ray.dir * -1.0f), ray, hit);
}

bool hit_plane(const Shape& s, const Ray& ray, float tMin, Hit& hit) {
  float denom = dot(s.a, ray.dir);
  if (denom == 0) return false;  // parallel: no intersection (or the whole plane, ignored)
  float t = (s.r0 - dot(s.a, ray.org)) / denom;
  return accept(t, tMin, 0, 0.0f, hit);  // t may be +-Inf for tiny denom: rejected by hit.t
}

// Where a cap meets the side, the two pieces overlap by `rim` = kRimRel times
// the magnitudes in the computation (|org - base|, |base|, t, h, radii),
// since rounding errors are relative to those: the side takes
// y in [-rim, h + rim], a cap takes |p_perp| <= rc + rim. Without it, rounding
// put a ray aimed at a rim outside both pieces: 10-15% of such rays passed
// through the closed solid (tests/test_shapes.cpp, *CapRimNoCrack). Cracks
// show at 2^-24 and vanish from 2^-23 on; 2^-20 keeps an 8x margin and stays
// 256x below kSpawnRel, so a ray spawned off a cap does not meet the side's
// overlap.
constexpr float kRimRel = 1.0f / 1048576;

// Finite cylinder / cone frustum. In the frame of the axis, with
// v = perpendicular part of (org - base), u = perpendicular part of dir,
// y(t) = y0 + t dy the axial coordinate and r(y) = r0 + k y (k = (r1-r0)/h):
//   |v + t u|^2 = (r0 + k y(t))^2
// gives A t^2 + 2 B t + C = 0 with
//   A = u.u - k^2 dy^2,  B = u.v - k dy rk,  C = v.v - rk^2,  rk = r0 + k y0.
// Roots by q = -(B + sign(B) sqrt(B^2 - AC)), t = q/A and C/q, which stays
// exact when A -> 0 (ray parallel to a cone's side or to a cylinder's axis).
// The quadratic is solved from the ray's point nearest the base centre,
// t = tc (roots tr, t = tc + tr): its coefficients then have the size of the
// shape, not of the distance to it, so B^2 - AC keeps its digits (the
// remedy Haines et al. apply to spheres). Solved from the ray's origin, a
// cylinder of radius 1 at 1e6 units, or of radius 1e-4 at 1 unit, lost all
// of them (tests/test_shapes.cpp, Cylinder.FarAwayAndTiny).
// Pieces of a frustum, in Hit::piece; Hit::local is the root tr (t = tc + tr).
enum : u8 { kPieceSide, kPieceBase, kPieceTop };

// The ray in the axis frame, shared by hit_frustum() and frustum_normal() so
// that the normal is computed from the very values the hit was.
struct FrustumFrame {
  Vec3 oc0, v, u;
  float tc, y0, dy, k;
};

inline FrustumFrame frustum_frame(const Shape& s, const Ray& ray) {
  FrustumFrame f;
  Vec3 axis = s.b;
  f.oc0 = ray.org - s.a;
  f.tc = -dot(f.oc0, ray.dir);
  Vec3 oc = f.oc0 + ray.dir * f.tc;
  f.y0 = dot(oc, axis);
  f.dy = dot(ray.dir, axis);
  f.v = oc - axis * f.y0;
  f.u = ray.dir - axis * f.dy;
  f.k = s.c.x;
  return f;
}

bool hit_frustum(const Shape& s, const Ray& ray, float tMin, Hit& hit) {
  FrustumFrame f = frustum_frame(s, ray);
  Vec3 oc0 = f.oc0, v = f.v, u = f.u;
  float tc = f.tc, y0 = f.y0, dy = f.dy, k = f.k;
  float rk = s.r0 + k * y0;
  float A = dot(u, u) - k * k * dy * dy;
  float B = dot(u, v) - k * dy * rk;
  float C = dot(v, v) - rk * rk;
  bool found = false;
  float scale = max_abs_bits(oc0) + s.c.y;
  float disc = B * B - A * C;
  if (disc >= 0) {
    float q = -(B + (B >= 0 ? rt_sqrt(disc) : -rt_sqrt(disc)));
    float roots[2] = {A != 0 ? q / A : kHuge, q != 0 ? C / q : kHuge};
    for (float tr : roots) {
      float t = tc + tr;
      if (!(t > tMin && t < hit.t)) continue;
      float y = y0 + tr * dy, rim = kRimRel * (scale + abs_bits(tr));
      if (y < -rim || y > s.h + rim) continue;
      found |= accept(t, tMin, kPieceSide, tr, hit);
    }
  }
  // Caps: discs at y = 0 (normal -axis) and y = h (normal +axis).
  if (s.caps && dy != 0) {
    for (int cap = 0; cap < 2; ++cap) {
      if (!(s.caps & (cap ? kCapTop : kCapBase))) continue;
      float yc = cap ? s.h : 0.0f, rc = cap ? s.r1 : s.r0;
      float tr = (yc - y0) / dy, t = tc + tr;
      if (!(t > tMin && t < hit.t)) continue;
      Vec3 pPerp = v + u * tr;
      float rr = rc + kRimRel * (scale + abs_bits(tr));
      if (dot(pPerp, pPerp) > rr * rr) continue;
      found |= accept(t, tMin, cap ? kPieceTop : kPieceBase, tr, hit);
    }
  }
  return found;
}

void frustum_normal(const Shape& s, const Ray& ray, Hit& hit) {
  Vec3 axis = s.b;
  if (hit.piece != kPieceSide) {
    face(hit.piece == kPieceTop ? axis : -axis, ray, hit);
    return;
  }
  FrustumFrame f = frustum_frame(s, ray);
  float tr = hit.local, y = f.y0 + tr * f.dy;
  // Outward normal: gradient of |p_perp|^2 - r(y)^2, i.e. p_perp - k r(y) axis.
  // At a cone's apex p_perp = 0 and r = 0: the gradient vanishes, so the
  // fallback is the axis direction (the apex's cap side).
  Vec3 pPerp = f.v + f.u * tr;
  face(normalize(pPerp - axis * (f.k * (s.r0 + f.k * y)), axis), ray, hit);
}

// Watertight ray/triangle test: Woop, Benthin, Wald, "Watertight Ray/Triangle
// Intersection", JCGT 2(1), 2013. Shear so the ray is +z, then 2D edge
// functions U, V, W; a point on a shared edge gets the same edge function in
// both triangles, so the ground quad's diagonal has no cracks. Edge functions
// that come out exactly 0 are recomputed in double, as the paper does.
bool hit_triangle(const Shape& s, const Ray& ray, float tMin, Hit& hit) {
  Vec3 ao = ray.org - s.a;
  float side = dot(s.n, ao), away = dot(s.n, ray.dir);
  if (tMin >= 0 && (side > 0 ? away > 0 : away < 0) &&
      abs_bits(side) > s.sideMargin * max_abs_bits(ao))
    return false;  // starts off the plane and moves away from it (kSideRel)
  // Components indexed by kx, ky, kz from arrays: loads, not branches.
  const float d[3] = {ray.dir.x, ray.dir.y, ray.dir.z};
  float ax = abs_bits(d[0]), ay = abs_bits(d[1]), az = abs_bits(d[2]);
  int kz = ax > ay ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
  int kx = kz == 2 ? 0 : kz + 1;
  int ky = kx == 2 ? 0 : kx + 1;
  float dz = d[kz];
  if (dz < 0) {
    int tmp = kx;
    kx = ky;
    ky = tmp;
  }
  float Sx = d[kx] / dz, Sy = d[ky] / dz, Sz = 1.0f / dz;
  Vec3 A3 = s.a - ray.org, B3 = s.b - ray.org, C3 = s.c - ray.org;
  const float A[3] = {A3.x, A3.y, A3.z}, B[3] = {B3.x, B3.y, B3.z}, C[3] = {C3.x, C3.y, C3.z};
  float Ax = A[kx] - Sx * A[kz], Ay = A[ky] - Sy * A[kz];
  float Bx = B[kx] - Sx * B[kz], By = B[ky] - Sy * B[kz];
  float Cx = C[kx] - Sx * C[kz], Cy = C[ky] - Sy * C[kz];
  float U = Cx * By - Cy * Bx, V = Ax * Cy - Ay * Cx, W = Bx * Ay - By * Ax;
  if (U == 0 || V == 0 || W == 0) {
    U = (float)((double)Cx * By - (double)Cy * Bx);
    V = (float)((double)Ax * Cy - (double)Ay * Cx);
    W = (float)((double)Bx * Ay - (double)By * Ax);
  }
  if ((U < 0 || V < 0 || W < 0) && (U > 0 || V > 0 || W > 0)) return false;
  float det = U + V + W;
  if (det == 0) return false;  // ray in the triangle's plane: edge-on, no area seen
  float T = U * Sz * A[kz] + V * Sz * B[kz] + W * Sz * C[kz];
  float t = T / det;
  return accept(t, tMin, 0, 0.0f, hit);
}

}  // namespace

bool intersect_t(const Shape& s, const Ray& ray, float tMin, Hit& hit) {
  switch (s.kind) {
  case kSphere: return hit_sphere(s, ray, tMin, hit);
  case kPlane: return hit_plane(s, ray, tMin, hit);
  case kCylinder:
  case kCone: return hit_frustum(s, ray, tMin, hit);
  case kTriangle: return hit_triangle(s, ray, tMin, hit);
  }
  return false;
}

void hit_normal(const Shape& s, const Ray& ray, Hit& hit) {
  switch (s.kind) {
  case kSphere: sphere_normal(s, ray, hit); return;
  case kPlane: face(s.a, ray, hit); return;
  case kCylinder:
  case kCone: frustum_normal(s, ray, hit); return;
  case kTriangle: face(normalize(s.n), ray, hit); return;
  }
}

bool intersect(const Shape& s, const Ray& ray, float tMin, Hit& hit) {
  if (!intersect_t(s, ray, tMin, hit)) return false;
  hit_normal(s, ray, hit);
  return true;
}

void shape_bound(const Shape& s, Vec3& centre, float& radius) {
  switch (s.kind) {
  case kSphere:
    centre = s.a;
    radius = s.r0;
    break;
  case kPlane:
    centre = v3(0.0f);
    radius = kHuge;
    return;
  case kCylinder:
  case kCone: {
    // Centre on the axis at mid-height; the farthest points are the rims.
    centre = s.a + s.b * (0.5f * s.h);
    float half2 = 0.25f * s.h * s.h;
    radius = rt_sqrt(half2 + rt_max(s.r0 * s.r0, s.r1 * s.r1));
    break;
  }
  case kTriangle: {
    centre = (s.a + s.b + s.c) * (1.0f / 3);
    radius = rt_max(length(s.a - centre), rt_max(length(s.b - centre), length(s.c - centre)));
    break;
  }
  }
  radius += kBoundPad * (radius + max_abs(centre));
}
