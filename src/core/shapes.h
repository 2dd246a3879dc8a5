// shapes.h - the closed set of shapes rt64k's scenes use, as tagged structs.
//
// THE INTERSECTION CONTRACT. eps = 2^-24 (float's unit roundoff). For a
// shape, R = Shape::size, the radius of its bounding ball (0 for a plane);
// for a ray, D = the distance from its origin to that ball's centre (for a
// plane, to its stored point b). No bound below involves the world's
// magnitude (where the shape stands), only R and D.
//
// DOMAIN. Builders (make_*) accept:
//   * coordinates |x| <= kMaxCoord = 2^32; sphere radius, frustum height and
//     larger radius in [kMinSize, kMaxCoord] = [2^-32, 2^32];
//   * frustum: radii >= 0, not both 0, height / larger radius in
//     [kMinAspect, kMaxAspect] = [2^-20, 2^20]; a cap of radius 0 (a cone's
//     apex) is dropped; a nonzero finite axis (any length);
//   * plane: a nonzero finite normal (any length), |offset| <= kMaxCoord;
//   * triangle: cross(b - a, c - a), computed in double, with its largest
//     component a normal float (>= 2^-126): not collinear, however thin.
// Anything else (zero, negative, NaN or Inf sizes, zero axis or normal,
// collinear vertices, out of range) gives a shape of kind kEmpty: no ray
// hits it and a scene gives it no bound. No degenerate shape is hit with a
// NaN or an invented normal. Within the domain every square and product the
// solvers form stays far inside float's range.
//
// FOR EVERY RAY with finite origin and unit direction (to float precision):
//   * intersect() reports the nearest hit with  tMin < t < hit.t  (hit.t holds
//     the current nearest distance on entry, kHuge for "none yet"), and then
//     overwrites hit.t, hit.normal and hit.front (and piece, local); otherwise
//     it leaves hit alone.
//   * hit.t and hit.normal are finite and |hit.normal| = 1 (to 1e-6), also
//     for origins far beyond the domain (tested from 1e12 .. 1e38 away);
//     NaN or Inf rays never hit.
//   * hit.normal is the outward normal if hit.front, else its negation;
//     hit.front is true when the ray arrives from outside the solid (or from
//     the side the plane/triangle normal points to). So the normal faces the
//     ray: exactly outside the band (hit.front is exact there), and within
//     4 eps of perpendicular (dot(normal, dir) <= 4 eps) inside it.
//
// ACCURACY, against the exact answer for the stored shape and the very float
// ray (tests/test_shapes_hard.cpp: a long double oracle without tolerances,
// itself checked against __float128; 1e5 rays per class and kind):
//   * THE BAND: rays whose exact answer (hit or miss, the piece hit, the
//     side) flips when the origin moves by at most 2^-16 (R + D), or that
//     cross a piece within 2^-16 (R + D) / |cos| of its boundary (a rim, a
//     side's end, a triangle's edge), or pass within 2^-16 (R + D) of a
//     cone's apex: tangent, rim, edge and apex rays. Float rounding of the
//     ray relative to the shape alone is eps (R + D); inside the band the
//     answer is rounding's to pick (still under the guarantees above).
//   * Outside the band (sphere, frustum, triangle): hit/miss, the piece
//     (frustum side or cap) and hit.front are exact;
//     |t - t_exact| <= 64 eps (R + D) kappa, kappa = 1 / |cos| of the
//     incidence at the exact hit (the crossing's condition number; measured
//     at most 32); the normal is within 64 eps (1 + (R + D) kappa / rho)
//     rad of the exact one, rho the radius of curvature there (frustum
//     side: its radius at the hit; sphere: R; caps, triangles: no term), as
//     a point off by the t error along the surface turns the normal by that
//     over rho (measured at most 6).
//   * Plane: no band (t is continuous in the origin). hit/miss and
//     hit.front exact for |cos| >= 2^-48; |t - t_exact| <= 2^-23 |t_exact| +
//     e (|t_exact| + D) / |cos|, e = 2^-22 for |cos| >= 2^-12 (cos and the
//     distance in float) and 2^-50 below (in double); measured at most 0.5
//     of it.
//   * A cone's apex has no normal: a hit exactly there gets the axis.
// Tested over: frustums of every kind and cap combination with random axes,
// h/r 0.005 .. 200 (ordinary), 1e2 .. 1e4 (long thin), 1e-3 .. 1e-1 (flat),
// at 1e2 .. 1e5 from the world origin (far); every kind at sizes 2^-28 ..
// 2^29 anywhere within 2^31 of the origin, rays from 0.5 .. 4096 R away;
// planes within 1e-13 .. 1 of parallel, 1e5 from the origin.
//
// SPAWNED RAYS must start at spawn_origin() so that they do not find the
// surface they leave (self-intersection, "shadow acne"): see spawn_offset().
//
// LEAVING FOR GOOD: every shape is flat (plane, triangle) or a convex solid
// (sphere, closed frustum), or lies on the boundary of its convex hull (the
// outer side of a frustum with an open cap). A ray from a hit point cannot
// meet the shape again when it leaves a flat shape (to either side), or a
// solid into the open half-space beyond the tangent plane at the hit point,
// i.e. dot(dir, outward normal) > 0: that plane supports the whole solid or
// hull. leaves_for_good() tells which; the tracer then skips the shape for
// that ray instead of relying on spawn_origin() alone.
#pragma once
#include "abi.h"
#include "rtmath.h"

struct Ray {
  Vec3 org, dir;
};

struct Hit {
  float t;
  Vec3 normal;
  bool front;
  u8 piece;    // intersect_t(): which piece (frustum: side, base, top cap; plane: 1 = front)
  float local; // intersect_t(): the shape's own parameter of the hit (frustum: the root tr)
};

enum ShapeKind : u8 { kSphere, kPlane, kCylinder, kCone, kTriangle, kEmpty };

// The builders' domain (THE INTERSECTION CONTRACT above). 2^32 keeps every
// square and product of the solvers (|org - anchor|^2, r^2, k^2 dy^2 rk^2)
// between 2^-90 and 2^100, far from float's limits (2^-126, 2^128); a
// frustum's slope k = (r1 - r0) / h then stays within 2^20.
constexpr float kMaxCoord = 4294967296.0f;       // 2^32
constexpr float kMinSize = 1.0f / 4294967296.0f; // 2^-32
constexpr float kMinAspect = 1.0f / 1048576;     // height / larger radius >= 2^-20
constexpr float kMaxAspect = 1048576.0f;         // height / larger radius <= 2^20
constexpr float kFloatMin = 1.17549435e-38f;     // smallest normal float, 2^-126
constexpr float kFloatMax = 3.40282347e+38f;

// Cap flags for cylinders and cones.
enum : u8 { kCapBase = 1, kCapTop = 2 };

// One shape. Field meaning by kind:
//   kSphere:   a = centre, r0 = radius.
//   kPlane:    a = unit normal, r0 = offset, b = r0 a (rounded): the plane is
//              {p : dot(a, p - b) = 0}, through b.
//   kCylinder, kCone ("frustum"): a = centre of the base disc, b = unit axis
//              from base towards top, r0 = base radius, r1 = top radius
//              (cylinder: r1 = r0; full cone: r1 = 0, the apex), h = height,
//              caps = which discs are closed. Radius varies linearly along the axis.
//              make_cone() also stores constants of the solver: c.x = slope
//              k = (r1 - r0) / h, c.y = h + max(r0, r1) (the shape's size in
//              its rim tolerance), c.z = 2 when |k| > 1 (a flat side: the
//              solve is always centred within the slab and the side's ends
//              are tested radially), else 0.5 (the least u.u of a ray that
//              is solved from its point nearest the axis; shapes.cpp).
//   kTriangle: a, b, c = vertices; front side is where cross(b-a, c-a) points.
//              make_triangle() also stores n = cross(b-a, c-a) and
//              sideMargin = kSideRel * max_abs(b-a) * max_abs(c-a) (below),
//              both times the power of two that puts max_abs(n) in [1, 2);
//              and r0, r1, h = x, y, z of normalize(n), the unit normal
//              hit_normal() returns (stored: no square root and division per
//              hit; docs/tracer-speed.md, round eight).
//   kEmpty:    no fields; no ray hits it.
// size (every kind): R of the contract, the radius of the shape's bounding
// ball (0 for a plane); it scales the spawn offset.
struct Shape {
  ShapeKind kind;
  u8 caps;
  Vec3 a, b, c;
  float r0, r1, h;
  Vec3 n;
  float sideMargin;
  float size;
};

// A triangle is skipped before the watertight test when the ray starts on
// one side of its plane and points away from it: dot(n, org - a) and
// dot(n, dir) of one sign, and |dot(n, org - a)| above sideMargin *
// max_abs(org - a). That dot product and n each carry under 10 eps
// (2^-24) of max_abs(b-a) max_abs(c-a) max_abs(org-a); 2^-16 leaves a 25x
// margin, so a ray the test skips starts at least that far off the plane,
// where the watertight test cannot find a hit at t > 0 either. Only for tMin >= 0.
constexpr float kSideRel = 1.0f / 65536;

// hit_plane() computes the cosine a.dir in float where |cos| >= this, in
// double nearer parallel (shapes.cpp gives the error analysis).
constexpr float kPlaneCosFloat = 1.0f / 4096;

// hit_frustum()'s constants (shapes.cpp explains both), here because the
// packet kernel of primary rays (packet/frustum.h) repeats that solver:
// the pieces' overlap at a rim is kRimRel (|org - base|_max + h + max(r0,
// r1)), and a ray whose least distance from the axis exceeds max(r0, r1) +
// kCullRim rim is rejected before the quadratic.
constexpr float kRimRel = 1.0f / 1048576;
constexpr float kCullRim = 1024.0f;
// Pieces of a frustum, in Hit::piece.
enum : u8 { kPieceSide, kPieceBase, kPieceTop };

Shape make_sphere(Vec3 centre, float radius);
Shape make_plane(Vec3 normal, float offset);
Shape make_cylinder(Vec3 base, Vec3 axis, float radius, float height, u8 caps);
Shape make_cone(Vec3 base, Vec3 axis, float baseRadius, float topRadius, float height, u8 caps);
Shape make_triangle(Vec3 a, Vec3 b, Vec3 c);

RT64K_HOT_ABI bool intersect(const Shape& s, const Ray& ray, float tMin, Hit& hit);

// intersect() in two steps, for a tracer that tests several shapes and needs
// one normal: intersect_t() finds the hit as intersect() does (same t, same
// accept/reject) but writes only hit.t, hit.piece and hit.local; then
// hit_normal(), with the same shape and ray, writes hit.normal and hit.front
// exactly as intersect() would have. A shadow ray needs no normal at all.
RT64K_HOT_ABI bool intersect_t(const Shape& s, const Ray& ray, float tMin, Hit& hit);
RT64K_HOT_ABI void hit_normal(const Shape& s, const Ray& ray, Hit& hit);

// A plane's normal at a hit of intersect_t(): the side the ray came from
// is its piece (1: against the normal). Inline: the resumed tree of the
// packet tracer shades the floor's hits with it (trace.cpp).
__attribute__((always_inline)) inline void plane_normal(const Shape& s, Hit& hit) {
  hit.front = hit.piece != 0;
  hit.normal = hit.front ? s.a : -s.a;
}

// A triangle pair: a triangle whose caps hold kPairNext shares its vertex a,
// its n and sideMargin, bit for bit, with the scene's next object, a
// triangle whose c is this one's b (two halves of a quad, the diagonal a-b
// between them; scenes.cpp's stage). intersect_pair() tests both as two
// intersect_t() calls in index order would, the same bits, with one side
// test and one shear: a tracer that would test both may call it instead.
enum : u8 { kPairNext = 4 };
RT64K_HOT_ABI int intersect_pair(const Shape& first, const Shape& second, const Ray& ray,
                                 float tMin, Hit& hit);

// A plane whose caps hold kInlinePlane (scene 1's floor) is tested by the
// resumed tree with plane_t() inline: hit_plane()'s float path (shapes.cpp)
// written out with tMin = 0, the same operations in the same order (dot()
// sums x, y, z as dot3() does), so the same bits; nearer parallel it calls
// intersect_t() for the double path. Most of its tests are misses (rays
// going up from the floor), which then cost no call.
enum : u8 { kInlinePlane = 8 };
// A plane's hit at t, its cos c from the float path: accept() written out,
// the side (c < 0) taken only on a hit, since most tests are misses
// (hit_plane() in shapes.cpp and plane_t() below).
__attribute__((always_inline)) inline bool plane_accept(float t, float c, float tMin, Hit& hit) {
  if (!(t > tMin)) return false;
  if (!(t < hit.t)) return false;
  hit.t = t;
  hit.piece = c < 0 ? 1 : 0;
  hit.local = 0.0f;
  return true;
}
__attribute__((always_inline)) inline bool plane_t(const Shape& s, const Ray& ray, Hit& hit) {
  float c = dot(s.a, ray.dir);
  if (!(__builtin_fabsf(c) >= kPlaneCosFloat)) return intersect_t(s, ray, 0.0f, hit);
  return plane_accept(dot(s.a, s.b - ray.org) / c, c, 0.0f, hit);
}

// Writes the outward normal turned to face the ray, and hit.front.
__attribute__((always_inline)) inline void face_ray(Vec3 outward, const Ray& ray, Hit& hit) {
  bool front = dot(outward, ray.dir) < 0;
  hit.normal = front ? outward : -outward;
  hit.front = front;
}

// The normal from the hit point relative to the centre, m = (org - centre)
// + t dir: it has the sphere's size and carries eps (|org - centre| + t) of
// rounding, not the float spacing of the hit point's world coordinates
// (p - centre, as before, lost the normal when r fell below it: zero-length
// or invented normals, issue 10 class 6). |m| = r up to that rounding; where
// it comes out shorter than r / 2 (r below eps times the ray's distance,
// hits that are all in the band) or longer than 2 r (a ray from beyond the
// domain, where |m|^2 may overflow), m is rebuilt from Haines's stable terms:
// f + t d = perp + (t + b) d and t + b = -+sqrt(disc) for the near and far
// root, so m = perp -+ sqrt(disc) d, |m|^2 = |perp|^2 + disc = r^2: never
// zero, so the normal is always the sphere's own. Returns the outward unit
// normal (hit_normal() turns it to face the ray). Inline: trace_tree shades
// the scalar tree's hits on spheres (most of scene 1's) with it and calls no
// hit_normal() for them (docs/tracer-speed.md, rounds ten and eleven).
inline Vec3 sphere_outward(const Shape& s, const Ray& ray, const Hit& hit) {
  Vec3 f = ray.org - s.a;
  Vec3 m = f + ray.dir * hit.t;
  float len2 = dot(m, m), r2 = s.r0 * s.r0;
  if (!(len2 >= 0.25f * r2 && len2 <= 4.0f * r2)) { // also a ray from beyond the domain
    float b = dot(f, ray.dir);
    Vec3 perp = f - ray.dir * b;
    float root = rt_sqrt(rt_max(r2 - dot(perp, perp), 0.0f));
    m = perp + ray.dir * (hit.t < -b ? -root : root);
    len2 = dot(m, m);
  }
  return m * (1.0f / rt_sqrt(len2));
}

// A sphere enclosing the shape (radius kHuge for a plane), padded by
// kBoundPad relative so that rounding never culls a real hit.
void shape_bound(const Shape& s, Vec3& centre, float& radius);
constexpr float kBoundPad = 1.0f / 1024;

// Offset of a spawned ray's origin from the surface along the normal. The
// hit point p = org + dir t, as the tracer computes it, is off the surface
// by (a) its rounding to float coordinates, at most eps sqrt(3) max_abs(p),
// which the offset's own addition repeats, and (b) the solver's error along
// the normal, a few eps (R + D) (THE INTERSECTION CONTRACT; D <= t + R). So
// the offset is kSpawnPos max_abs(p) (8 eps: 2.3x the 2 sqrt(3) eps of (a))
// plus kSpawnRel (R + t), with `scale` = R + t from spawn_scale(): relative
// to what the error scales with, the shape's size and the ray's length, and
// to the world's magnitude only through the rounding of p itself. Measured
// over every hit of tests/test_shapes_hard.cpp, band included: a hit point
// lies at most 0.15 of this offset off its surface. At the scenes' scale
// (max_abs(p) < 30, R + t < 40) it is below 6e-4; glass of radius 1 at 1e5
// from the origin gets 0.05 (the old 2^-12 max_abs(p) gave 24, more than
// the radius: refraction rays started outside the solid, issue 10 class 5).
constexpr float kSpawnPos = 1.0f / 2097152; // 2^-21 = 8 eps
constexpr float kSpawnRel = 1.0f / 65536;   // 2^-16
inline float spawn_offset(Vec3 p, float scale) {
  return kSpawnPos * max_abs(p) + kSpawnRel * scale;
}
// The scale of a hit's error: the shape's size plus the ray's length to it.
inline float spawn_scale(const Shape& s, const Hit& hit) { return s.size + hit.t; }

// True when a ray leaving `hit` (a hit on s, normal facing the incoming ray)
// in direction dir cannot meet s again (LEAVING FOR GOOD above). The outward
// normal is hit.normal when hit.front, else -hit.normal.
inline bool leaves_for_good(const Shape& s, const Hit& hit, Vec3 dir) {
  if (s.kind == kPlane || s.kind == kTriangle) return true;
  float d = dot(dir, hit.normal);
  return hit.front ? d > 0 : d < 0;
}
// leaves_for_good() given d = dot(dir, hit.normal), for a caller that has it
// already (spawn_origin_dot() needs the same product).
inline bool leaves_for_good_dot(const Shape& s, const Hit& hit, float d) {
  if (s.kind == kPlane || s.kind == kTriangle) return true;
  return hit.front ? d > 0 : d < 0;
}

// True for a closed convex solid: a sphere, or a frustum whose every disc of
// nonzero radius is capped (a cone's apex needs none). A ray from a point
// inside it leaves it exactly once.
inline bool closed_convex(const Shape& s) {
  if (s.kind == kSphere) return true;
  if (s.kind != kCylinder && s.kind != kCone) return false;
  return (s.r0 == 0 || (s.caps & kCapBase)) && (s.r1 == 0 || (s.caps & kCapTop));
}

// Origin for a ray leaving hit point p (with ray-facing unit normal n) in
// direction dir: pushed by `offset` (spawn_offset() of the hit, computed
// once per hit) to the side of the surface that dir goes to.
inline Vec3 spawn_origin(Vec3 p, Vec3 n, Vec3 dir, float offset) {
  return p + n * (dot(dir, n) >= 0 ? offset : -offset);
}
// spawn_origin() given d = dot(dir, n).
inline Vec3 spawn_origin_dot(Vec3 p, Vec3 n, float d, float offset) {
  return p + n * (d >= 0 ? offset : -offset);
}
