// shapes.h - the closed set of shapes rt64k's scenes use, as tagged structs.
//
// THE INTERSECTION CONTRACT (every shape, no exceptions):
//   * ray.dir has unit length; ray.org is finite.
//   * intersect() reports the nearest hit with  tMin < t < hit.t  (hit.t holds
//     the current nearest distance on entry, kHuge for "none yet"), and then
//     overwrites hit.t, hit.normal and hit.front (and piece, local); otherwise
//     it leaves hit alone.
//   * hit.normal is unit length and faces the incoming ray: dot(normal, dir) <= 0.
//   * hit.front is true when the ray arrives from outside the solid (or from
//     the side the plane/triangle normal points to).
//   * Nothing here returns NaN or Inf: degenerate rays (parallel to a plane,
//     along a cylinder's axis, through a cone's apex) either miss or hit finitely.
// Rays spawned from a hit point must start at spawn_origin() so that they do
// not find the surface they leave (self-intersection, "shadow acne").
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
#include "rtmath.h"

struct Ray {
  Vec3 org, dir;
};

struct Hit {
  float t;
  Vec3 normal;
  bool front;
  u8 piece;     // intersect_t(): which piece of the shape (frustum: side, base, top cap)
  float local;  // intersect_t(): the shape's own parameter of the hit, for hit_normal()
};

enum ShapeKind : u8 { kSphere, kPlane, kCylinder, kCone, kTriangle };

// Cap flags for cylinders and cones.
enum : u8 { kCapBase = 1, kCapTop = 2 };

// One shape. Field meaning by kind:
//   kSphere:   a = centre, r0 = radius.
//   kPlane:    a = unit normal, r0 = offset: the plane is {p : dot(a, p) = r0}.
//   kCylinder, kCone ("frustum"): a = centre of the base disc, b = unit axis
//              from base towards top, r0 = base radius, r1 = top radius
//              (cylinder: r1 = r0; full cone: r1 = 0, the apex), h = height,
//              caps = which discs are closed. Radius varies linearly along the axis.
//              make_cone() also stores constants of the solver: c.x = slope
//              (r1 - r0) / h, c.y = max_abs(a) + h + r0 + r1 (the shape's
//              magnitude, in its rim tolerance).
//   kTriangle: a, b, c = vertices; front side is where cross(b-a, c-a) points.
//              make_triangle() also stores n = cross(b-a, c-a) and
//              sideMargin = kSideRel * max_abs(b-a) * max_abs(c-a) (below).
struct Shape {
  ShapeKind kind;
  u8 caps;
  Vec3 a, b, c;
  float r0, r1, h;
  Vec3 n;
  float sideMargin;
};

// A triangle is skipped before the watertight test when the ray starts on
// one side of its plane and points away from it: dot(n, org - a) and
// dot(n, dir) of one sign, and |dot(n, org - a)| above sideMargin *
// max_abs(org - a). That dot product and n each carry under 10 eps
// (2^-24) of max_abs(b-a) max_abs(c-a) max_abs(org-a); 2^-16 leaves a 25x
// margin, so a ray the test skips starts at least that far off the plane,
// where the watertight test cannot find a hit at t > 0 either. Only for tMin >= 0.
constexpr float kSideRel = 1.0f / 65536;

Shape make_sphere(Vec3 centre, float radius);
Shape make_plane(Vec3 normal, float offset);
Shape make_cylinder(Vec3 base, Vec3 axis, float radius, float height, u8 caps);
Shape make_cone(Vec3 base, Vec3 axis, float baseRadius, float topRadius, float height, u8 caps);
Shape make_triangle(Vec3 a, Vec3 b, Vec3 c);

bool intersect(const Shape& s, const Ray& ray, float tMin, Hit& hit);

// intersect() in two steps, for a tracer that tests several shapes and needs
// one normal: intersect_t() finds the hit as intersect() does (same t, same
// accept/reject) but writes only hit.t, hit.piece and hit.local; then
// hit_normal(), with the same shape and ray, writes hit.normal and hit.front
// exactly as intersect() would have. A shadow ray needs no normal at all.
bool intersect_t(const Shape& s, const Ray& ray, float tMin, Hit& hit);
void hit_normal(const Shape& s, const Ray& ray, Hit& hit);

// A sphere enclosing the shape (radius kHuge for a plane), padded by
// kBoundPad relative so that rounding never culls a real hit.
void shape_bound(const Shape& s, Vec3& centre, float& radius);
constexpr float kBoundPad = 1.0f / 1024;

// Offset of a spawned ray's origin from the surface along the normal, scaled
// by the magnitude of the hit point: float's relative rounding error is 2^-24
// per operation; the quadratic solvers accumulate a few hundred ulps at worst
// (grazing hits on cones, measured by the property tests), so 2^-12 relative
// plus an absolute floor for points near the origin keeps every spawned ray
// off its own surface with margin. At the scenes' scale (|p| < 30) the offset
// is below 0.008, far under a pixel's footprint.
constexpr float kSpawnRel = 1.0f / 4096;
constexpr float kSpawnAbs = 1.0f / 4096;
inline float spawn_offset(Vec3 p) { return kSpawnAbs + kSpawnRel * max_abs(p); }

// True when a ray leaving `hit` (a hit on s, normal facing the incoming ray)
// in direction dir cannot meet s again (LEAVING FOR GOOD above). The outward
// normal is hit.normal when hit.front, else -hit.normal.
inline bool leaves_for_good(const Shape& s, const Hit& hit, Vec3 dir) {
  if (s.kind == kPlane || s.kind == kTriangle) return true;
  float d = dot(dir, hit.normal);
  return hit.front ? d > 0 : d < 0;
}

// Origin for a ray leaving hit point p (with ray-facing unit normal n) in
// direction dir: pushed to the side of the surface that dir goes to.
inline Vec3 spawn_origin(Vec3 p, Vec3 n, Vec3 dir) {
  float off = spawn_offset(p);
  return p + n * (dot(dir, n) >= 0 ? off : -off);
}
