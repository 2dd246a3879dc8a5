// primary.cpp - the per-frame terms of primary rays (primary.h). Each line
// repeats, for ray.org = org, an expression of bound_mask (trace.cpp) or of
// hit_sphere / hit_plane / hit_triangle (shapes.cpp), operation for
// operation, so the values are the ones those functions compute per ray
// (frustums: frustum_terms(), packet/frustum.cpp).
#include "packet/primary.h"

namespace {

float max_abs_bits(Vec3 a) {
  return rt_max(__builtin_fabsf(a.x), rt_max(__builtin_fabsf(a.y), __builtin_fabsf(a.z)));
}

} // namespace

void primary_terms(const Scene& s, Vec3 org, PrimaryTerms& p) {
  p.org = org;
  p.sideFar = 0;
  for (int i = 0; i < kMaxObjects; ++i) {
    // bound_mask: f = org - centre, c = f.f - R^2.
    float fx = org.x - s.boundX[i], fy = org.y - s.boundY[i], fz = org.z - s.boundZ[i];
    p.fx[i] = fx;
    p.fy[i] = fy;
    p.fz[i] = fz;
    p.c[i] = fx * fx + fy * fy + fz * fz - s.boundR2[i];
    bool bounded = !(s.unboundedMask >> i & 1);
    for (int k = 0; k < 4; ++k) {
      p.splat[i][0][k] = fx;
      p.splat[i][1][k] = fy;
      p.splat[i][2][k] = fz;
      p.splat[i][3][k] = bounded ? p.c[i] : -1.0f;
      p.away[i][k] = bounded && p.c[i] > 0 ? -1 : 0;
    }
    p.shapeC[i] = p.r2[i] = p.side[i] = 0;
    for (int v = 0; v < 3; ++v)
      p.vert[i][v][0] = p.vert[i][v][1] = p.vert[i][v][2] = 0;
    if (i >= s.numObjects) continue;
    const Shape& sh = s.objects[i].shape;
    if (sh.kind == kSphere) {
      // hit_sphere: f = org - a (the bound's f: same centre), c = f.f - r^2.
      Vec3 f = org - sh.a;
      float r2 = sh.r0 * sh.r0;
      p.r2[i] = r2;
      p.shapeC[i] = dot(f, f) - r2;
    } else if (sh.kind == kPlane) {
      p.shapeC[i] = dot(sh.a, sh.b - org); // hit_plane's numerator (float path)
    } else if (sh.kind == kTriangle) {
      // hit_triangle: the side test's origin terms and A3, B3, C3.
      Vec3 ao = org - sh.a;
      float side = dot(sh.n, ao);
      p.side[i] = side;
      if (__builtin_fabsf(side) > sh.sideMargin * max_abs_bits(ao)) p.sideFar |= 1u << i;
      Vec3 rel[3] = {sh.a - org, sh.b - org, sh.c - org};
      for (int v = 0; v < 3; ++v) {
        p.vert[i][v][0] = rel[v].x;
        p.vert[i][v][1] = rel[v].y;
        p.vert[i][v][2] = rel[v].z;
      }
    } else if (sh.kind == kCylinder || sh.kind == kCone) {
      frustum_terms(sh, org, p.frustum[i]);
    }
  }
}
