// shapes.cpp - ray/shape intersection under the contract in shapes.h.
#include "shapes.h"
#include "packet/lanes.h" // f4, i4, lanes_at (header only: no packet code)

namespace {

// |x| by clearing the sign bit (one andps); equals rt_abs(x) but for the sign
// of a zero, which no caller here can tell apart.
inline float abs_bits(float x) { return __builtin_fabsf(x); }
inline float max_abs_bits(Vec3 a) {
  return rt_max(abs_bits(a.x), rt_max(abs_bits(a.y), abs_bits(a.z)));
}

// A Vec3's x, y, z four floats wide (lane 3 unused): each + - * on them is
// one packed SSE instruction, which rounds as the scalar one does, and
// dot3() sums the products (x + y) + z as dot() does, so the same
// expressions give the same bits as with Vec3 (round thirteen,
// docs/tracer-speed.md).

// x, y, z of a Shape's a or b, or of a Ray's org, read as 16 bytes of the
// struct: the fourth lane is the float that follows in it.
static_assert(__builtin_offsetof(Shape, b) + 16 <= sizeof(Shape), "b is followed by c");
static_assert(__builtin_offsetof(Ray, org) == 0 && sizeof(Ray) == 24, "org, then dir");
__attribute__((always_inline)) inline f4 shape_a(const Shape& s) {
  return lanes_at((const char*)&s + __builtin_offsetof(Shape, a));
}
__attribute__((always_inline)) inline f4 shape_b(const Shape& s) {
  return lanes_at((const char*)&s + __builtin_offsetof(Shape, b));
}
__attribute__((always_inline)) inline f4 org_lanes(const Ray& ray) { return lanes_at(&ray); }
// A Ray's dir from its last 16 bytes (org.z, dir): no read past the Ray.
__attribute__((always_inline)) inline f4 dir_lanes(const Ray& ray) {
  return __builtin_shuffle(lanes_at((const char*)&ray + 8), i4{1, 2, 3, 0});
}
__attribute__((always_inline)) inline float dot3(f4 a, f4 b) {
  f4 p = a * b;
  // y and z brought to lane 0 by pshufd (a copy and a shuffle in one).
  f4 y = (f4)__builtin_ia32_pshufd((i4)p, 0x55), z = (f4)__builtin_ia32_pshufd((i4)p, 0xaa);
  return p[0] + y[0] + z[0];
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

// Sphere, after Haines et al., "Precision Improvements for Ray/Sphere
// Intersection" (Ray Tracing Gems ch. 7): discriminant r^2 - |f - (f.d)d|^2
// and roots q = -(b + sign(b) sqrt(disc)), t0 = c/q, t1 = q (a = 1).
bool hit_sphere(const Shape& s, const Ray& ray, float tMin, Hit& hit) {
  f4 dir = dir_lanes(ray);
  f4 f = org_lanes(ray) - shape_a(s);
  float b = dot3(f, dir);
  f4 perp = f - dir * b;
  float r2 = s.r0 * s.r0;
  float disc = r2 - dot3(perp, perp);
  if (disc < 0) return false;
  float c = dot3(f, f) - r2;
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

// Plane {p : a.(p - b) = 0}, b its point offset * a. The numerator is the
// origin's distance to the plane from q = b - org: rounding eps |q|, the
// ray's distance, not |org| or |offset| (r0 - a.org carried eps of both).
// cos = a.dir: in float, its rounding (< 3 eps) is at most 2^-20 of it for
// |cos| >= kPlaneCosFloat = 2^-12, well inside t's own condition (a
// direction rounded by eps moves t by eps / |cos| relative). Nearer
// parallel, cos in double: the products of floats are exact and the sums
// round at 2^-53, so the sign is right for |cos| >= 2^-50 and t good to
// ~2^-52 / |cos| relative (float's cos had the wrong sign below 6e-8 and t
// off by 100% near 1e-7; issue 10 class 4). Such rays, within 0.014 deg of
// the plane, meet it at t > 4096 times their distance: rare in a frame.
// (kPlaneCosFloat is in shapes.h: the packet kernels switch at it too.)

inline double plane_cos(const Shape& s, const Ray& ray) {
  return (double)s.a.x * ray.dir.x + (double)s.a.y * ray.dir.y + (double)s.a.z * ray.dir.z;
}

// Hit::piece records the side the ray comes from (1: against the normal,
// the front), decided by the same cos as t: float's cos alone has the wrong
// sign for |cos| below ~6e-8.
bool hit_plane(const Shape& s, const Ray& ray, float tMin, Hit& hit) {
  f4 a = shape_a(s);
  float c = dot3(a, dir_lanes(ray)), t;
  bool front;
  if (abs_bits(c) >= kPlaneCosFloat) {
    return plane_accept(dot3(a, shape_b(s) - org_lanes(ray)) / c, c, tMin, hit);
  } else {
    double cd = plane_cos(s, ray);
    if (cd == 0) return false; // parallel: no intersection (or the whole plane, ignored)
    double num = (double)s.a.x * ((double)s.b.x - ray.org.x) +
                 (double)s.a.y * ((double)s.b.y - ray.org.y) +
                 (double)s.a.z * ((double)s.b.z - ray.org.z);
    t = (float)(num / cd); // beyond float's range +-Inf: rejected by hit.t (<= kHuge)
    front = cd < 0;
  }
  return accept(t, tMin, front ? 1 : 0, 0.0f, hit);
}

// FRUSTUM (finite cylinder or cone). In the frame of the axis, with
// v = perpendicular part of the ray point at t = tc, u = perpendicular part
// of dir, y(t) = y0 + (t - tc) dy the axial coordinate and
// r(y) = r0 + k y (k = (r1 - r0)/h):
//   |v + tr u|^2 = (r0 + k y(tc + tr))^2
// gives A tr^2 + 2 B tr + C = 0 with
//   A = u.u - k^2 dy^2,  B = u.v - k dy rk,  C = v.v - rk^2,  rk = r0 + k y0.
// Roots by q = -(B + sign(B) sqrt(B^2 - AC)), tr = q/A and C/q, which stays
// exact when A -> 0 (ray parallel to a cone's side or to a cylinder's axis).
//
// The centre tc is the ray's point nearest the axis line, t_axis =
// -(vw.u)/(u.u) (vw: the origin's offset from the axis). For a ray at 45 deg
// or more from the axis (u.u >= 1/2, so |dy| <= |u|) any side hit lies
// within max(r0, r1) of the axis, hence within max(r0, r1) / |u| of t_axis
// along the ray and within max(r0, r1) of y(t_axis) along the axis: at tc =
// t_axis, |v| and |y0 - y(hit)| are of the shape's size. A ray nearer the
// axis has t_axis ill-conditioned, far out or undefined (u = 0); it is
// clamped into the slab -rim <= y <= h + rim, where the ray runs at most
// (h + 2 rim) / |dy| <= 1.5 (h + 2 rim) and |v| is no larger than at any
// side hit (|v + tr u| is convex in tr). So is every ray on a flat side
// (|k| > 1): there the two nappes of the double cone lie within 2 r / |k|
// of each other, a ray crosses both close together, and B^2 - AC cancels
// unless y0 stays within the slab, where rk = r0 + k y0 is of the size of
// the radii. Either way A, B, C have the size of the shape, whatever the
// ray's distance and wherever it crosses the axis (the remedy Haines et al.
// apply to spheres). The point nearest the base centre, used before, left
// |v| and y0 of the size of h on long thin frustums: for h/r = 1e2..1e4,
// C = v.v - rk^2 lost every digit of the radius (issue 10 class 1). What
// remains is the rounding of the ray's position relative to the base,
// eps |org - base|. (The slab is widened by rim so that a ray that passes
// just outside it, within the pieces' overlap, is still solved at its own
// nearest point, not one far along.)
//
// Where a piece ends, pieces overlap by `rim` = kRimRel (|org - base|_max +
// h + max(r0, r1)): the magnitudes in the computation, so the overlap
// follows the shape's size and the ray's distance, not where the shape
// stands in the world (|base| in it made a unit cylinder at 1e5 10% fatter
// at its caps; issue 10 class 3). Without it, rounding put a ray aimed at a
// rim outside both pieces: 10-15% of such rays passed through the closed
// solid (tests/test_shapes.cpp, *CapRimNoCrack). Cracks show at 2^-24 and
// vanish from 2^-23 on; 2^-20 keeps an 8x margin and stays 16x inside the
// band of the tests (2^-16 of the shape's size plus the ray's distance).
// The side's end is tested where it is well conditioned: along the axis
// (y in [-rim, h + rim]) and, for a flat side (|k| > 1: Shape::c.z = 2), also
// radially (|v + tr u| in [min r - rim, max r + rim]): a flat side is
// crossed at y known to eps |org - base| but at a radius known only to
// |k| times that, so a rim slack along the axis overhung a flat ring's rim
// radially by |k| rim (rays through its hole hit the side; class 2).
// Caps take |p_perp| <= rc + rim.
// (kRimRel and the pieces kPieceSide, kPieceBase, kPieceTop are in shapes.h:
// the packet kernel of primary rays repeats this solver.)

// The ray in the axis frame (above).
struct FrustumFrame {
  f4 v, u;
  float tc, y0, dy, k, uu, rim;
};

__attribute__((always_inline)) inline FrustumFrame frustum_frame(const Shape& s, const Ray& ray) {
  FrustumFrame f;
  f4 axis = shape_b(s);
  f4 dir = dir_lanes(ray);
  f4 w = org_lanes(ray) - shape_a(s);
  float yw = dot3(w, axis);
  f.dy = dot3(dir, axis);
  f4 vw = w - axis * yw;
  f.u = dir - axis * f.dy;
  f.uu = dot3(f.u, f.u);
  f4 aw = (f4)((i4)w & i4{0x7fffffff, 0x7fffffff, 0x7fffffff, 0x7fffffff});
  f.rim = kRimRel * (rt_max(aw[0], rt_max(aw[1], aw[2])) + s.c.y);
  float tc = -dot3(vw, f.u) / f.uu;
  if (!(f.uu >= s.c.z)) {
    // Near the axis (|dy| > 0.7: the slab is short), or a flat side (c.z =
    // 2, always). Written so that a NaN t_axis (u = 0) ends at the slab's
    // lower end: rt_max(NaN, lo) is lo.
    float ta = (-f.rim - yw) / f.dy, tb = (s.h + f.rim - yw) / f.dy;
    tc = rt_min(rt_max(tc, rt_min(ta, tb)), rt_max(ta, tb));
  }
  f.tc = tc;
  f.v = vw + f.u * tc;
  f.y0 = yw + f.dy * tc;
  f.k = s.c.x;
  return f;
}

// Every hit lies on the ray's part inside the slab -rim <= y <= h + rim
// (side hits are kept only there, the caps are at y = 0 and h), and |v| at
// the frame's centre tc is the least distance from the axis of that part:
// for a ray solved from its point nearest the axis (u.u >= c.z) it is its
// distance from the axis line; for a ray near the axis or on a flat side,
// tc is that nearest point clamped into the slab's interval along the ray,
// the least of the convex |v + tr u| there (a ray along the axis, u = 0, is
// |v| from the axis everywhere). Both carry rounding of eps (|org - base| +
// h), far below the pad. Every point of the frustum lies within max(r0, r1)
// of the axis line, its pieces' overlap (rim) and the band of THE
// INTERSECTION CONTRACT add at most 2^-16 of the scale, so a ray whose |v|
// exceeds max(r0, r1) + kCullRim rim is an exact miss outside the band: it
// is rejected before the quadratic and the caps, with the answer the solver
// would give (tests/test_shapes.cpp, FrustumCull.*; test_shapes_hard.cpp).
// 1024 rim = 2^-10 (|org - base|_max + h + max(r0, r1)), 64x the band. At
// 44 s it rejects 27 % of the glass cylinders' tests in an adaptive frame
// (36 % in a full one) among rays solved from their nearest point; taken to
// the clamped rays too (round seven: most shadow rays run within 45 deg of
// the cylinders' axes to the lights above), it saves 0.8 % of that frame.
// (kCullRim is in shapes.h, beside kRimRel.)

bool hit_frustum(const Shape& s, const Ray& ray, float tMin, Hit& hit) {
  FrustumFrame f = frustum_frame(s, ray);
  f4 v = f.v, u = f.u;
  float vv = dot3(v, v);
  float reach = rt_max(s.r0, s.r1) + kCullRim * f.rim;
  if (vv > reach * reach) return false;
  float tc = f.tc, y0 = f.y0, dy = f.dy, k = f.k;
  float rk = s.r0 + k * y0;
  float A = f.uu - k * k * dy * dy;
  float B = dot3(u, v) - k * dy * rk;
  float C = vv - rk * rk;
  bool found = false;
  float disc = B * B - A * C;
  if (disc >= 0) {
    float q = -(B + (B >= 0 ? rt_sqrt(disc) : -rt_sqrt(disc)));
    // The two roots q/A and C/q in turn (in registers, no array).
    float tr = A != 0 ? q / A : kHuge, next = q != 0 ? C / q : kHuge;
    for (int root = 0; root < 2; ++root, tr = next) {
      float t = tc + tr;
      if (!(t > tMin && t < hit.t)) continue;
      float y = y0 + tr * dy, rim = f.rim;
      if (y < -rim || y > s.h + rim) continue;
      if (s.c.z > 1) { // flat side: its ends radially
        f4 pPerp = v + u * tr;
        float rho2 = dot3(pPerp, pPerp), lo = rt_min(s.r0, s.r1) - rim,
              hi = rt_max(s.r0, s.r1) + rim;
        if (rho2 < lo * abs_bits(lo) || rho2 > hi * hi) continue;
      }
      found |= accept(t, tMin, kPieceSide, tr, hit);
    }
  }
  // Caps: discs at y = 0 (normal -axis) and y = h (normal +axis), each
  // written out (a loop over the two cost ~12 instructions a test in its
  // counter and selects: round seven, docs/tracer-speed.md).
  auto cap = [&](float yc, float rc, u8 piece) __attribute__((always_inline)) {
    float tr = (yc - y0) / dy, t = tc + tr;
    if (!(t > tMin && t < hit.t)) return;
    f4 pPerp = v + u * tr;
    float rr = rc + f.rim;
    if (dot3(pPerp, pPerp) > rr * rr) return;
    found |= accept(t, tMin, piece, tr, hit);
  };
  if (dy != 0) {
    if (s.caps & kCapBase) cap(0.0f, s.r0, kPieceBase);
    if (s.caps & kCapTop) cap(s.h, s.r1, kPieceTop);
  }
  return found;
}

// Outward normal of the side: the gradient of |p_perp|^2 - r(y)^2 on the
// surface, p_perp - k r(y) axis, with r(y) taken as |p_perp| (equal there),
// i.e. the direction of p_perp - k |p_perp| axis: it depends on the azimuth
// alone, also next to a cone's apex where r(y) = r0 + k y is a difference of
// rounded numbers that may even come out negative (the mirror nappe, whose
// normal points the other way). p_perp is the perpendicular part of the hit
// point relative to the base, (org - base) + t dir: rounding eps
// (|org - base| + t), as the solve's own. Within the domain |p_perp|^2 <=
// 2^67 and the normal's square <= 2^107; a hit from beyond it is rescaled
// first. At the apex itself p_perp = 0 and the surface has no normal: the
// fallback is the axis (the apex's end). Returns the outward unit normal.
Vec3 frustum_outward(const Shape& s, const Ray& ray, const Hit& hit) {
  Vec3 axis = s.b;
  if (hit.piece != kPieceSide) return hit.piece == kPieceTop ? axis : -axis;
  // Four floats wide, as the solver (normalize() written out).
  f4 ax = shape_b(s);
  f4 q = (org_lanes(ray) - shape_a(s)) + dir_lanes(ray) * hit.t;
  f4 pPerp = q - ax * dot3(q, ax);
  float rho2 = dot3(pPerp, pPerp);
  if (!(rho2 <= 1e20f)) { // only from beyond the domain: keep |n|^2 from overflowing
    pPerp = pPerp * (1.0f / max_abs(Vec3{pPerp[0], pPerp[1], pPerp[2]}));
    rho2 = dot3(pPerp, pPerp);
  }
  f4 n;
  float len2;
  if (s.kind == kCylinder) {
    // Slope c.x = +0 (make_cone(): r1 == r0), so c.x sqrt(rho2) is +0 for
    // every rho2 this reaches (a NaN ends at the fallback both ways): n is
    // pPerp less the same zeros, each of its squares pPerp's, and
    // dot3(n, n) is rho2 bit for bit. So the same n and len2 without the
    // first square root and the second sum on the normal's chain of
    // latencies (a cylinder's normal: sqrt, div, mul instead of sqrt, mul,
    // mul, sub, dot3, sqrt, div, mul).
    n = pPerp - ax * 0.0f;
    len2 = rho2;
  } else {
    n = pPerp - ax * (s.c.x * rt_sqrt(rho2));
    len2 = dot3(n, n);
  }
  if (!(len2 > 1e-30f)) return axis; // normalize()'s fallback
  n = n * (1.0f / rt_sqrt(len2));
  return Vec3{n[0], n[1], n[2]};
}

// Watertight ray/triangle test: Woop, Benthin, Wald, "Watertight Ray/Triangle
// Intersection", JCGT 2(1), 2013. Shear so the ray is +z, then 2D edge
// functions U, V, W; a point on a shared edge gets the same edge function in
// both triangles, so the ground quad's diagonal has no cracks. Edge functions
// that come out exactly 0 are recomputed in double, as the paper does.
// The side test (below): true when the ray starts off the triangle's plane
// and moves away from it. Reads a, n and sideMargin only.
__attribute__((always_inline)) inline bool tri_away(const Shape& s, const Ray& ray, float tMin) {
  static_assert(__builtin_offsetof(Shape, n) + 16 <= sizeof(Shape), "n is followed by more");
  f4 n = lanes_at((const char*)&s + __builtin_offsetof(Shape, n));
  f4 ao = org_lanes(ray) - shape_a(s);
  float side = dot3(n, ao), away = dot3(n, dir_lanes(ray));
  return tMin >= 0 && (side > 0 ? away > 0 : away < 0) &&
         abs_bits(side) > s.sideMargin * max_abs_bits(Vec3{ao[0], ao[1], ao[2]});
}

// Components indexed by kx, ky, kz: loads from the vectors themselves (their
// bytes, at 4 i), not branches; each difference is the one s.a - ray.org
// etc. would give in that component.
static_assert(sizeof(Vec3) == 12, "x, y, z at bytes 0, 4, 8");
__attribute__((always_inline)) inline float at(const Vec3& v, int i) {
  float f;
  __builtin_memcpy(&f, (const char*)&v + 4 * i, 4);
  return f;
}

// The ray's shear (Woop et al.): the axes and S, shared by every triangle
// the ray is tested against.
struct Shear {
  int kx, ky, kz;
  float Sx, Sy, Sz;
};
__attribute__((always_inline)) inline Shear shear_of(const Ray& ray) {
  Shear h;
  float ax = abs_bits(ray.dir.x), ay = abs_bits(ray.dir.y), az = abs_bits(ray.dir.z);
  int kz = ax > ay ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
  int kx = kz == 2 ? 0 : kz + 1;
  int ky = kx == 2 ? 0 : kx + 1;
  float dz = at(ray.dir, kz);
  if (dz < 0) {
    int tmp = kx;
    kx = ky;
    ky = tmp;
  }
  h.kx = kx;
  h.ky = ky;
  h.kz = kz;
  h.Sx = at(ray.dir, kx) / dz;
  h.Sy = at(ray.dir, ky) / dz;
  h.Sz = 1.0f / dz;
  return h;
}

// A vertex relative to the ray's origin, sheared: x, y in the plane
// across the ray, z along kz.
struct Sheared {
  float x, y, z;
};
__attribute__((always_inline)) inline Sheared sheared(const Vec3& v, const Ray& ray,
                                                      const Shear& h) {
  float z = at(v, h.kz) - at(ray.org, h.kz);
  return Sheared{(at(v, h.kx) - at(ray.org, h.kx)) - h.Sx * z,
                 (at(v, h.ky) - at(ray.org, h.ky)) - h.Sy * z, z};
}

// The watertight test's second half for sheared vertices A, B, C: edge
// functions, their signs and zeros, t. Edge functions of both signs: the ray
// passes beside the triangle. A float edge function that is not 0 has the
// exact one's sign (the two products round monotonically: the larger to no
// less than the smaller), and so has its recompute in double (exact
// products, one rounding), but for an exact value under 2^-150, which rounds
// to a float 0: a difference of products of floats that small needs a
// factor under ~2^-52 at the domain's sizes (<= 2^33): a ray that close to
// the triangle's edges, in the band of THE INTERSECTION CONTRACT (2^-16 of R
// >= 2^-32). So two of opposite signs answer "beside" whatever the third,
// recomputed or not: that test comes first, and the zeros are looked for
// only on the rays that pass it (a miss leaves 12 instructions sooner; round
// thirteen).
__attribute__((always_inline)) inline bool tri_edges(Sheared A, Sheared B, Sheared C, float Sz,
                                                     float tMin, Hit& hit) {
  float Ax = A.x, Ay = A.y, Bx = B.x, By = B.y, Cx = C.x, Cy = C.y;
  float U = Cx * By - Cy * Bx, V = Ax * Cy - Ay * Cx, W = Bx * Ay - By * Ax;
  auto beside = [](float a, float b, float c) __attribute__((always_inline)) {
    return (a < 0 || b < 0 || c < 0) && (a > 0 || b > 0 || c > 0);
  };
  if (beside(U, V, W)) return false;
  if (U == 0 || V == 0 || W == 0) {
    U = (float)((double)Cx * By - (double)Cy * Bx);
    V = (float)((double)Ax * Cy - (double)Ay * Cx);
    W = (float)((double)Bx * Ay - (double)By * Ax);
    if (beside(U, V, W)) return false;
  }
  float det = U + V + W;
  if (det == 0) return false; // ray in the triangle's plane: edge-on, no area seen
  float T = U * Sz * A.z + V * Sz * B.z + W * Sz * C.z;
  float t = T / det;
  return accept(t, tMin, 0, 0.0f, hit);
}

// Watertight ray/triangle test: Woop, Benthin, Wald, "Watertight Ray/Triangle
// Intersection", JCGT 2(1), 2013. Shear so the ray is +z, then 2D edge
// functions U, V, W; a point on a shared edge gets the same edge function in
// both triangles, so the ground quad's diagonal has no cracks. Edge functions
// that come out exactly 0 are recomputed in double, as the paper does.
bool hit_triangle(const Shape& s, const Ray& ray, float tMin, Hit& hit) {
  if (tri_away(s, ray, tMin)) return false; // starts off the plane and moves away (kSideRel)
  Shear h = shear_of(ray);
  return tri_edges(sheared(s.a, ray, h), sheared(s.b, ray, h), sheared(s.c, ray, h), h.Sz, tMin,
                   hit);
}

} // namespace

bool intersect_t(const Shape& s, const Ray& ray, float tMin, Hit& hit) {
  switch (s.kind) {
  case kSphere:
    return hit_sphere(s, ray, tMin, hit);
  case kPlane:
    return hit_plane(s, ray, tMin, hit);
  case kCylinder:
  case kCone:
    return hit_frustum(s, ray, tMin, hit);
  case kTriangle:
    return hit_triangle(s, ray, tMin, hit);
  case kEmpty:
    return false;
  }
  return false;
}

// Two triangles of a pair (kPairNext, shapes.h) as two intersect_t() calls
// in index order would test them: the side test, the shear and the shared
// vertices are the same operations on the same floats for both (first.a ==
// second.a, first.n == second.n, first.sideMargin == second.sideMargin,
// first.b == second.c, bit for bit), so they are done once; each
// triangle's edge functions and t are its own call's, in its order, and the
// second is accepted against the first's hit.t. Returns 0 (no hit), 1 (the
// first's hit) or 2 (the second's).
int intersect_pair(const Shape& first, const Shape& second, const Ray& ray, float tMin, Hit& hit) {
  if (tri_away(first, ray, tMin)) return 0;
  Shear h = shear_of(ray);
  Sheared A = sheared(first.a, ray, h), B = sheared(first.b, ray, h);
  int found = tri_edges(A, B, sheared(first.c, ray, h), h.Sz, tMin, hit);
  if (tri_edges(A, sheared(second.b, ray, h), B, h.Sz, tMin, hit)) found = 2;
  return found;
}

// The outward normal of each kind, then one face_ray() for all (a copy per kind
// cost ~200 bytes of the exe).
void hit_normal(const Shape& s, const Ray& ray, Hit& hit) {
  Vec3 outward;
  switch (s.kind) {
  case kSphere:
    outward = sphere_outward(s, ray, hit);
    break;
  case kPlane:
    plane_normal(s, hit);
    return;
  case kCylinder:
  case kCone:
    outward = frustum_outward(s, ray, hit);
    break;
  case kTriangle:
    outward = Vec3{s.r0, s.r1, s.h}; // normalize(n), stored by make_triangle()
    break;
  default: // kEmpty
    return;
  }
  face_ray(outward, ray, hit);
}

bool intersect(const Shape& s, const Ray& ray, float tMin, Hit& hit) {
  if (!intersect_t(s, ray, tMin, hit)) return false;
  hit_normal(s, ray, hit);
  return true;
}
