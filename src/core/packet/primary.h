// primary.h - what every primary ray of a frame shares.
//
// Primary rays all start at the camera, so every term of the bound and
// shape tests that depends on the origin and the scene alone is computed
// once per frame here instead of once per ray. Each term is computed with
// the very operations, in the same order, that the per-ray code of
// trace.cpp (bound_mask) and shapes.cpp (hit_sphere, hit_plane,
// hit_triangle) applies to ray.org, so a tracer that reads it finds
// bit-identical hits (packet/packet.h; tests/test_packet.cpp).
// Cylinders and cones get frustum_frame()'s origin terms (packet/frustum.h).
#pragma once
#include "abi.h"
#include "packet/frustum.h"
#include "scene.h"

struct PrimaryTerms {
  Vec3 org; // the camera: every primary ray's origin
  // Per bounding sphere i (Scene::boundX...; unused slots too, as in
  // bound_mask): f = org - centre and c = |f|^2 - R^2.
  alignas(16) float fx[kMaxObjects];
  alignas(16) float fy[kMaxObjects];
  alignas(16) float fz[kMaxObjects];
  alignas(16) float c[kMaxObjects];
  // The same four terms per object, each repeated in four lanes, for
  // packets of four rays: splat[i] = {fx x4, fy x4, fz x4, c x4}, but c =
  // -1 for an unbounded object (Scene::unboundedMask), which no ray may
  // miss: b^2 < -1 never holds. away[i]: four lanes of all ones where c > 0
  // (the camera outside a bound, where a ray pointing away misses it), else
  // (and unbounded) 0.
  alignas(16) float splat[kMaxObjects][4][4];
  alignas(16) i32 away[kMaxObjects][4];
  // Per shape i. Sphere: shapeC = |f|^2 - r^2 with the f above (a sphere's
  // bound has its centre), r2 = r^2. Plane: shapeC = normal.(point - org).
  // Triangle: vert = its vertices a, b, c minus org; side = n.(org - a);
  // bit i of sideFar set when |side| > sideMargin * max|org - a|
  // (hit_triangle's kSideRel test: a ray pointing away from the plane
  // then misses).
  float shapeC[kMaxObjects];
  float r2[kMaxObjects];
  float side[kMaxObjects];
  float vert[kMaxObjects][3][3]; // [object][vertex][x, y, z]
  u32 sideFar;
  // Cylinder or cone: frustum_terms(shape, org) (set for those kinds only).
  FrustumTerms frustum[kMaxObjects];
};

// The terms of `scene` for rays from `org`.
RT64K_HOT_ABI void primary_terms(const Scene& scene, Vec3 org, PrimaryTerms& out);
