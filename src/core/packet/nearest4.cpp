// nearest4.cpp - the kFindHit step of four secondary rays in lanes; the
// contract is in nearest4.h. Each kernel repeats, for four rays of four
// origins, a function of shapes.cpp (hit_sphere, hit_plane, hit_triangle)
// or trace.cpp (bound_mask, nearest_among) with the same operations in the
// same order per lane; where the primary kernels (packet.cpp) read a term
// of the camera, these compute it per lane by the scalar code's expression
// for ray.org. Each scalar branch is a lane mask built from the same
// comparison.
#include "packet/nearest4.h"

#include "packet/frustum.h"

namespace {

// The lanes of `lanes` through the general intersect_t().
void scalar_lanes(const Shape& shape, const f4 org[3], const f4 dir[3], u32 lanes, int object,
                  Hits4& st) {
  for (; lanes; lanes &= lanes - 1) {
    int k = __builtin_ctz(lanes);
    Hit hit;
    hit.t = st.t[k];
    Ray ray{Vec3{org[0][k], org[1][k], org[2][k]}, Vec3{dir[0][k], dir[1][k], dir[2][k]}};
    if (!intersect_t(shape, ray, 0.0f, hit)) continue;
    st.t[k] = hit.t;
    st.id[k] = object;
    st.piece[k] = hit.piece;
    st.local[k] = hit.local;
  }
}

// shapes.cpp's accept() for the lanes of `ok`: piece 0, local 0.
inline void take(Hits4& st, i4 ok, f4 t, int object) {
  st.t = ok ? t : st.t;
  st.id = ok ? i4_of(object) : st.id;
  st.piece = ok ? i4_of(0) : st.piece;
  st.local = ok ? f4_of(0.0f) : st.local;
}

// hit_sphere, tMin = 0: f = org - centre, b = f.d, perp = f - d b, disc =
// r^2 - perp.perp, c = f.f - r^2, q = -(b + sign(b) sqrt(disc)).
void sphere_lanes(const Shape& sh, const f4 org[3], const f4 dir[3], u32 lanes, int object,
                  Hits4& st) {
  f4 zero = f4_of(0.0f);
  f4 fx = org[0] - sh.a.x, fy = org[1] - sh.a.y, fz = org[2] - sh.a.z;
  f4 b = fx * dir[0] + fy * dir[1] + fz * dir[2];
  f4 px = fx - dir[0] * b, py = fy - dir[1] * b, pz = fz - dir[2] * b;
  float r2 = sh.r0 * sh.r0;
  f4 disc = r2 - (px * px + py * py + pz * pz);
  // The scalar code returns at disc < 0; a NaN disc it rejects at accept().
  i4 ok = (disc >= zero) & lanes_of(lanes);
  if (!lane_bits(ok)) return;
  f4 c = (fx * fx + fy * fy + fz * fz) - r2;
  f4 root = lane_sqrt(disc);
  f4 q = -(b + (b >= zero ? root : -root));
  ok &= q != zero;
  f4 t0 = c / q, t1 = q;
  i4 swap = t0 > t1;
  f4 lo = swap ? t1 : t0, hi = swap ? t0 : t1;
  f4 t = lo > zero ? lo : hi;
  ok &= (t > zero) & (t < st.t);
  take(st, ok, t, object);
}

// hit_plane: in float where |cos| >= kPlaneCosFloat, t = a.(b - org) / cos,
// piece 1 when cos < 0; the lanes nearer parallel take its double path
// through the scalar test.
void plane_lanes(const Shape& sh, const f4 org[3], const f4 dir[3], u32 lanes, int object,
                 Hits4& st) {
  Vec3 n = sh.a;
  f4 zero = f4_of(0.0f);
  f4 c = n.x * dir[0] + n.y * dir[1] + n.z * dir[2];
  i4 inFloat = lane_abs(c) >= f4_of(kPlaneCosFloat);
  u32 nearParallel = lanes & ~lane_bits(inFloat);
  f4 num = n.x * (sh.b.x - org[0]) + n.y * (sh.b.y - org[1]) + n.z * (sh.b.z - org[2]);
  f4 t = num / c;
  i4 ok = lanes_of(lanes) & inFloat & (t > zero) & (t < st.t);
  take(st, ok, t, object);
  st.piece = ok ? (i4)(c < zero) & i4_of(1) : st.piece;
  if (nearParallel) scalar_lanes(sh, org, dir, nearParallel, object, st);
}

// Component i (0, 1, 2: lane by lane) of (x, y, z): hit_triangle's at().
inline f4 pick(i4 i, f4 x, f4 y, f4 z) { return i == i4_of(0) ? x : (i == i4_of(1) ? y : z); }

// hit_triangle (Woop et al.): the side test, then the shear with each
// lane's own axis order (kz the direction's largest component, kx and ky
// the next two cyclically, swapped where d[kz] < 0) and the edge functions;
// a lane with an edge function of exactly 0 goes to the scalar test (its
// recomputation in double).
void triangle_lanes(const Shape& sh, const f4 org[3], const f4 dir[3], u32 lanes, int object,
                    Hits4& st) {
  f4 zero = f4_of(0.0f);
  f4 aox = org[0] - sh.a.x, aoy = org[1] - sh.a.y, aoz = org[2] - sh.a.z;
  f4 side = sh.n.x * aox + sh.n.y * aoy + sh.n.z * aoz;
  f4 away = sh.n.x * dir[0] + sh.n.y * dir[1] + sh.n.z * dir[2];
  f4 mx = lane_abs(aox), my = lane_abs(aoy), mz = lane_abs(aoz);
  f4 myz = my > mz ? my : mz;
  f4 m = mx > myz ? mx : myz; // max_abs_bits(ao)
  i4 leaves = side > zero ? away > zero : away < zero;
  lanes &= ~lane_bits(leaves & (lane_abs(side) > sh.sideMargin * m));
  if (!lanes) return;
  f4 ax = lane_abs(dir[0]), ay = lane_abs(dir[1]), az = lane_abs(dir[2]);
  i4 kz = ax > ay ? (ax > az ? i4_of(0) : i4_of(2)) : (ay > az ? i4_of(1) : i4_of(2));
  i4 kx = kz == i4_of(2) ? i4_of(0) : kz + 1;
  i4 ky = kx == i4_of(2) ? i4_of(0) : kx + 1;
  f4 dz = pick(kz, dir[0], dir[1], dir[2]);
  i4 flip = dz < zero, tmp = kx;
  kx = flip ? ky : kx;
  ky = flip ? tmp : ky;
  f4 Sx = pick(kx, dir[0], dir[1], dir[2]) / dz, Sy = pick(ky, dir[0], dir[1], dir[2]) / dz;
  f4 Sz = 1.0f / dz;
  // rel(v, i) = v[i] - org[i], per component, then picked.
  auto rel = [&](Vec3 v, i4 i) { return pick(i, v.x - org[0], v.y - org[1], v.z - org[2]); };
  f4 Az = rel(sh.a, kz), Bz = rel(sh.b, kz), Cz = rel(sh.c, kz);
  f4 Ax = rel(sh.a, kx) - Sx * Az, Ay = rel(sh.a, ky) - Sy * Az;
  f4 Bx = rel(sh.b, kx) - Sx * Bz, By = rel(sh.b, ky) - Sy * Bz;
  f4 Cx = rel(sh.c, kx) - Sx * Cz, Cy = rel(sh.c, ky) - Sy * Cz;
  f4 U = Cx * By - Cy * Bx, V = Ax * Cy - Ay * Cx, W = Bx * Ay - By * Ax;
  u32 exact = lane_bits((U == zero) | (V == zero) | (W == zero)) & lanes;
  lanes &= ~exact;
  if (lanes) {
    i4 outside = ((U < zero) | (V < zero) | (W < zero)) & ((U > zero) | (V > zero) | (W > zero));
    f4 det = U + V + W;
    f4 T = U * Sz * Az + V * Sz * Bz + W * Sz * Cz;
    f4 t = T / det;
    i4 ok = lanes_of(lanes) & ~outside & (det != zero) & (t > zero) & (t < st.t);
    take(st, ok, t, object);
  }
  if (exact) scalar_lanes(sh, org, dir, exact, object, st);
}

// intersect_t() of object i for the lanes of `lanes`.
void object_lanes(const Scene& s, int i, const f4 org[3], const f4 dir[3], u32 lanes, Hits4& st) {
  const Shape& sh = s.objects[i].shape;
  switch (sh.kind) {
  case kSphere:
    sphere_lanes(sh, org, dir, lanes, i, st);
    break;
  case kPlane:
    plane_lanes(sh, org, dir, lanes, i, st);
    break;
  case kTriangle:
    triangle_lanes(sh, org, dir, lanes, i, st);
    break;
  case kCylinder:
  case kCone: {
    FrustumTerms4 f;
    frustum_terms4(sh, org, f);
    FrustumLanes r = frustum_lanes4(sh, f, dir, lanes, st.t, st.piece, st.local);
    st.id = lanes_of(r.hit) ? i4_of(i) : st.id;
    if (r.rest) scalar_lanes(sh, org, dir, r.rest, i, st);
    break;
  }
  default:
    break; // kEmpty: no hit
  }
}

// Bits 0..7 of x to bits 0, 4, ..., 28 (a nibble per object).
inline u32 spread(u32 x) {
  x &= 0xffu;
  x = (x | x << 12) & 0x000f000fu;
  x = (x | x << 6) & 0x03030303u;
  return (x | x << 3) & 0x11111111u;
}

} // namespace

void nearest4(const Scene& s, const f4 org[3], const f4 dir[3], const u32 skip[4], u32 lanes,
              Hits4& out) {
  out.t = f4_of(kHuge);
  out.id = i4_of(-1);
  out.piece = i4_of(0);
  out.local = f4_of(0.0f);
  // The lone-solid shortcut: each lane's named object first, one call per
  // object named (the lanes with a hit are done).
  u32 search = lanes, only = 0;
  for (u32 m = lanes; m; m &= m - 1) {
    int k = __builtin_ctz(m);
    if (skip[k] >> kOnlyShift) only |= 1u << k;
  }
  while (only) {
    u32 o = skip[__builtin_ctz(only)] >> kOnlyShift, group = 0;
    for (u32 m = only; m; m &= m - 1) {
      int k = __builtin_ctz(m);
      if (skip[k] >> kOnlyShift == o) group |= 1u << k;
    }
    only &= ~group;
    object_lanes(s, (int)o - 1, org, dir, group, out);
    search &= ~(group & lane_bits(out.id >= i4_of(0)));
  }
  if (!search) return;
  // nearest(): each lane's range (all & ~skip) as a nibble of lanes per
  // object, then bound_mask's test, four lanes a bound.
  u32 all = s.numObjects >= 8 ? 0xffu : (1u << s.numObjects) - 1;
  u32 range = 0;
  for (u32 m = search; m; m &= m - 1) {
    int k = __builtin_ctz(m);
    range |= spread(all & ~skip[k]) << k;
  }
  u32 objects = spread(s.unboundedMask) * 15u;
  f4 zero = f4_of(0.0f);
  for (int i = 0; i < s.numObjects; ++i) {
    if (!(range >> 4 * i & 15) || (s.unboundedMask >> i & 1)) continue;
    f4 fx = org[0] - s.boundX[i], fy = org[1] - s.boundY[i], fz = org[2] - s.boundZ[i];
    f4 b = fx * dir[0] + fy * dir[1] + fz * dir[2];
    f4 c = fx * fx + fy * fy + fz * fz - s.boundR2[i];
    i4 miss = (b * b < c) | (__builtin_ia32_minps(b, c) > zero);
    objects |= (~lane_bits(miss) & 15u) << 4 * i;
  }
  objects &= range;
  u32 foreground = s.numForeground >= 8 ? ~0u : (1u << 4 * s.numForeground) - 1;
  // The foreground in index order, then the background for the lanes that
  // met no foreground object.
  for (u32 m = objects & foreground; m;) {
    int i = __builtin_ctz(m) >> 2;
    object_lanes(s, i, org, dir, m >> 4 * i & 15, out);
    m &= ~(15u << 4 * i);
  }
  u32 none = lane_bits(out.id < i4_of(0)) & search;
  for (u32 m = objects & ~foreground & none * 0x11111111u; m;) {
    int i = __builtin_ctz(m) >> 2;
    object_lanes(s, i, org, dir, m >> 4 * i & 15, out);
    m &= ~(15u << 4 * i);
  }
}
