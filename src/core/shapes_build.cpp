// shapes_build.cpp - the shape builders (make_*) and bounds: the domain of
// THE INTERSECTION CONTRACT (shapes.h) and each shape's stored constants.
// Run once per object per frame: a cold source (cmake/flags.cmake, -Os).
#include "shapes.h"

namespace {

bool finite3(Vec3 v) { return rt_finite(v.x) && rt_finite(v.y) && rt_finite(v.z); }

// Unit vector along a, scaled by 1 / max_abs(a) first so that neither tiny
// nor huge lengths under- or overflow; false when a is zero, denormal (its
// reciprocal would overflow) or not finite: no direction to take.
bool unit_dir(Vec3 a, Vec3& out) {
  float m = max_abs(a); // rt_max drops a NaN: finite3() catches it
  if (!finite3(a) || !(m >= kFloatMin)) return false;
  a = a * (1.0f / m); // max_abs(a) = 1 (within rounding): |a|^2 in [1, 3]
  out = a * (1.0f / rt_sqrt(dot(a, a)));
  return true;
}

bool in_size_domain(float x) { return x >= kMinSize && x <= kMaxCoord; }
bool in_coord_domain(Vec3 p) { return finite3(p) && max_abs(p) <= kMaxCoord; }

Shape empty_shape() {
  Shape s{};
  s.kind = kEmpty;
  return s;
}

} // namespace

// Each builder returns its one named Shape on every path, so the copy is
// elided and the padding bytes stay zero (tests compare shapes bytewise).
Shape make_sphere(Vec3 centre, float radius) {
  Shape s = empty_shape();
  if (!in_coord_domain(centre) || !in_size_domain(radius)) return s;
  s.kind = kSphere;
  s.a = centre;
  s.r0 = radius;
  s.size = radius;
  return s;
}

Shape make_plane(Vec3 normal, float offset) {
  Shape s = empty_shape();
  Vec3 n;
  if (!unit_dir(normal, n) || !(rt_abs(offset) <= kMaxCoord)) return s;
  s.kind = kPlane;
  s.a = n;
  s.b = n * offset;
  s.r0 = offset;
  return s;
}

Shape make_cone(Vec3 base, Vec3 axis, float baseRadius, float topRadius, float height, u8 caps) {
  Shape s = empty_shape();
  float rMax = rt_max(baseRadius, topRadius);
  Vec3 b;
  if (!in_coord_domain(base) || !unit_dir(axis, b) || !in_size_domain(height) ||
      !in_size_domain(rMax) || !(baseRadius >= 0 && topRadius >= 0) ||
      !(height >= kMinAspect * rMax && height <= kMaxAspect * rMax))
    return s;
  s.b = b;
  s.kind = baseRadius == topRadius ? kCylinder : kCone;
  // A cap of radius 0 (a cone's apex) has no area: no cap.
  s.caps = caps & (kCapBase | kCapTop);
  if (baseRadius == 0) s.caps &= (u8)~kCapBase;
  if (topRadius == 0) s.caps &= (u8)~kCapTop;
  s.a = base;
  s.r0 = baseRadius;
  s.r1 = topRadius;
  s.h = height;
  // Per-shape constants of hit_frustum(), computed once here.
  float slope = (topRadius - baseRadius) / height;
  s.c.x = slope;
  s.c.y = height + rMax;
  s.c.z = rt_abs(slope) > 1 ? 2.0f : 0.5f; // see frustum_frame()
  s.size = rt_sqrt(0.25f * height * height + rMax * rMax);
  return s;
}

Shape make_cylinder(Vec3 base, Vec3 axis, float radius, float height, u8 caps) {
  return make_cone(base, axis, radius, radius, height, caps);
}

Shape make_triangle(Vec3 a, Vec3 b, Vec3 c) {
  Shape s = empty_shape();
  if (!in_coord_domain(a) || !in_coord_domain(b) || !in_coord_domain(c)) return s;
  // n = cross(b - a, c - a) in double: the differences of floats and their
  // products are exact or within 2^-53, so a zero n means collinear vertices
  // and a tiny one still has the right direction.
  double e1x = (double)b.x - a.x, e1y = (double)b.y - a.y, e1z = (double)b.z - a.z;
  double e2x = (double)c.x - a.x, e2y = (double)c.y - a.y, e2z = (double)c.z - a.z;
  Vec3 n = v3((float)(e1y * e2z - e1z * e2y), (float)(e1z * e2x - e1x * e2z),
              (float)(e1x * e2y - e1y * e2x));
  float m = max_abs(n);
  if (!(m >= kFloatMin && m <= kFloatMax)) return s; // no area a float normal can hold
  // Scaled by the power of two that brings max_abs(n) into [1, 2), and
  // sideMargin with it: exact, so hit_triangle()'s side test decides as with
  // the raw cross product, and normalize(n) below neither under-
  // nor overflows for any triangle in the domain.
  float pow2 = rt_from_bits((254u - (rt_bits(m) >> 23)) << 23); // 2^-floor(log2 m)
  s.kind = kTriangle;
  s.a = a;
  s.b = b;
  s.c = c;
  s.n = n * pow2;
  s.sideMargin = kSideRel * max_abs(b - a) * max_abs(c - a) * pow2;
  // The unit normal hit_normal() returns, once here instead of at every hit
  // (the same expression, so the same bits it computed there before).
  Vec3 unit = normalize(s.n);
  s.r0 = unit.x;
  s.r1 = unit.y;
  s.h = unit.z;
  Vec3 centre = (a + b + c) * (1.0f / 3);
  s.size = rt_max(length(a - centre), rt_max(length(b - centre), length(c - centre)));
  return s;
}

// The ball's radius is the builder's Shape::size (the same formulas: for a
// frustum the farthest points are the rims, for a triangle its vertices).
void shape_bound(const Shape& s, Vec3& centre, float& radius) {
  switch (s.kind) {
  case kSphere:
    centre = s.a;
    break;
  case kPlane:
    centre = v3(0.0f);
    radius = kHuge;
    return;
  case kCylinder:
  case kCone:
    centre = s.a + s.b * (0.5f * s.h);
    break; // on the axis at mid-height
  case kTriangle:
    centre = (s.a + s.b + s.c) * (1.0f / 3);
    break;
  case kEmpty:
    centre = v3(0.0f);
    radius = -1; // contains no point; scene_add leaves its bound out
    return;
  }
  radius = s.size + kBoundPad * (s.size + max_abs(centre));
}
