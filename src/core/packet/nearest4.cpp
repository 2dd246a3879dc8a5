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
__attribute__((always_inline)) inline void
sphere_lanes(const Shape& sh, const f4 org[3], const f4 dir[3], u32 lanes, int object, Hits4& st) {
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
__attribute__((always_inline)) inline void
plane_lanes(const Shape& sh, const f4 org[3], const f4 dir[3], u32 lanes, int object, Hits4& st) {
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

// hit_triangle's shear of the four directions: kz the largest component, kx
// and ky the next two cyclically, swapped where d[kz] < 0; Sx = d[kx] /
// d[kz], Sy = d[ky] / d[kz], Sz = 1 / d[kz]. It depends on the direction
// alone, so a packet's triangles share it (the same values the scalar test
// computes for each). Where every lane of `live` has one order, it is held
// as indices (k); else per lane (i).
struct Shear {
  bool uniform;
  int kx, ky, kz;
  i4 ix, iy, iz;
  f4 Sx, Sy, Sz;
};

void shear_of(const f4 dir[3], u32 live, Shear& o) {
  f4 ax = lane_abs(dir[0]), ay = lane_abs(dir[1]), az = lane_abs(dir[2]);
  i4 kz = ax > ay ? (ax > az ? i4_of(0) : i4_of(2)) : (ay > az ? i4_of(1) : i4_of(2));
  f4 dz = pick(kz, dir[0], dir[1], dir[2]);
  i4 flip = dz < f4_of(0.0f);
  i4 code = kz + (flip & i4_of(4));
  i32 c0 = code[__builtin_ctz(live)];
  o.uniform = (lane_bits(code == i4_of(c0)) & live) == live;
  if (o.uniform) {
    o.kz = c0 & 3;
    o.kx = o.kz == 2 ? 0 : o.kz + 1;
    o.ky = o.kx == 2 ? 0 : o.kx + 1;
    if (c0 & 4) {
      int tmp = o.kx;
      o.kx = o.ky;
      o.ky = tmp;
    }
    o.Sx = dir[o.kx] / dz;
    o.Sy = dir[o.ky] / dz;
  } else {
    i4 kx = kz == i4_of(2) ? i4_of(0) : kz + 1;
    i4 ky = kx == i4_of(2) ? i4_of(0) : kx + 1;
    o.iz = kz;
    o.ix = flip ? ky : kx;
    o.iy = flip ? kx : ky;
    o.Sx = pick(o.ix, dir[0], dir[1], dir[2]) / dz;
    o.Sy = pick(o.iy, dir[0], dir[1], dir[2]) / dz;
  }
  o.Sz = 1.0f / dz;
}

inline float comp3(Vec3 v, int i) {
  float f;
  __builtin_memcpy(&f, (const char*)&v + 4 * i, 4);
  return f;
}

// hit_triangle (Woop et al.) with the packet's shear: the side test, the
// sheared vertices and the edge functions; a lane with an edge function of
// exactly 0 goes to the scalar test (its recomputation in double).
void triangle_lanes(const Shape& sh, const f4 org[3], const f4 dir[3], const Shear& o, u32 lanes,
                    int object, Hits4& st) {
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
  // rel(v, i) = v[i] - org[i].
  f4 aX, aY, aZ, bX, bY, bZ, cX, cY, cZ;
  if (o.uniform) {
    f4 ox = org[o.kx], oy = org[o.ky], oz = org[o.kz];
    aX = comp3(sh.a, o.kx) - ox, aY = comp3(sh.a, o.ky) - oy, aZ = comp3(sh.a, o.kz) - oz;
    bX = comp3(sh.b, o.kx) - ox, bY = comp3(sh.b, o.ky) - oy, bZ = comp3(sh.b, o.kz) - oz;
    cX = comp3(sh.c, o.kx) - ox, cY = comp3(sh.c, o.ky) - oy, cZ = comp3(sh.c, o.kz) - oz;
  } else {
    auto rel = [&](Vec3 v, i4 i) { return pick(i, v.x - org[0], v.y - org[1], v.z - org[2]); };
    aX = rel(sh.a, o.ix), aY = rel(sh.a, o.iy), aZ = rel(sh.a, o.iz);
    bX = rel(sh.b, o.ix), bY = rel(sh.b, o.iy), bZ = rel(sh.b, o.iz);
    cX = rel(sh.c, o.ix), cY = rel(sh.c, o.iy), cZ = rel(sh.c, o.iz);
  }
  f4 Sx = o.Sx, Sy = o.Sy, Sz = o.Sz;
  f4 Ax = aX - Sx * aZ, Ay = aY - Sy * aZ;
  f4 Bx = bX - Sx * bZ, By = bY - Sy * bZ;
  f4 Cx = cX - Sx * cZ, Cy = cY - Sy * cZ;
  f4 U = Cx * By - Cy * Bx, V = Ax * Cy - Ay * Cx, W = Bx * Ay - By * Ax;
  u32 exact = lane_bits((U == zero) | (V == zero) | (W == zero)) & lanes;
  lanes &= ~exact;
  if (lanes) {
    i4 outside = ((U < zero) | (V < zero) | (W < zero)) & ((U > zero) | (V > zero) | (W > zero));
    f4 det = U + V + W;
    f4 T = U * Sz * aZ + V * Sz * bZ + W * Sz * cZ;
    f4 t = T / det;
    i4 ok = lanes_of(lanes) & ~outside & (det != zero) & (t > zero) & (t < st.t);
    take(st, ok, t, object);
  }
  if (exact) scalar_lanes(sh, org, dir, exact, object, st);
}

// intersect_t() of object i for the lanes of `lanes`; `shear` is set by
// the first triangle of the packet (for the lanes of `live`).
__attribute__((always_inline)) inline void object_lanes(const Scene& s, int i, const f4 org[3],
                                                        const f4 dir[3], u32 lanes, u32 live,
                                                        Shear& shear, bool& sheared, Hits4& st) {
  const Shape& sh = s.objects[i].shape;
  switch (sh.kind) {
  case kSphere:
    sphere_lanes(sh, org, dir, lanes, i, st);
    break;
  case kPlane:
    plane_lanes(sh, org, dir, lanes, i, st);
    break;
  case kTriangle:
    if (!sheared) {
      shear_of(dir, live, shear);
      sheared = true;
    }
    triangle_lanes(sh, org, dir, shear, lanes, i, st);
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

// The lone solid i for the lanes of `lanes` (out of line: rare for the
// first children, which are mostly reflected rays).
__attribute__((noinline)) void only_lanes(const Scene& s, int i, const f4 org[3], const f4 dir[3],
                                          u32 lanes, Hits4& st) {
  Shear shear;
  bool sheared = false;
  object_lanes(s, i, org, dir, lanes, lanes, shear, sheared, st);
}

// bound_mask's test of slot i (its terms in lane i & 3 of bx, by, bz, r2)
// for the four rays: lane k's bit of nibble i set in `objects` where its ray
// may meet the bound (an unbounded object: always) and does not skip the
// object (bit i of skip[k]).
template <int i>
__attribute__((always_inline)) inline void bound_slot(const Scene& s, f4 bx, f4 by, f4 bz, f4 r2,
                                                      const f4 org[3], const f4 dir[3], i4 skip,
                                                      u32& objects) {
  constexpr int j = i & 3;
  i4 out = skip << (31 - i); // the sign: bit i
  if (!(s.unboundedMask >> i & 1)) {
    f4 fx = org[0] - shade4::lane_splat<j>(bx), fy = org[1] - shade4::lane_splat<j>(by);
    f4 fz = org[2] - shade4::lane_splat<j>(bz);
    f4 b = fx * dir[0] + fy * dir[1] + fz * dir[2];
    f4 c = fx * fx + fy * fy + fz * fz - shade4::lane_splat<j>(r2);
    out |= (b * b < c) | (__builtin_ia32_minps(b, c) > f4_of(0.0f));
  }
  objects |= (~lane_bits(out) & 15u) << 4 * i;
}

// The slots g .. g + 3 below s.numObjects.
template <int g>
__attribute__((always_inline)) inline void bound_group(const Scene& s, const f4 org[3],
                                                       const f4 dir[3], i4 skip, u32& objects) {
  f4 bx = *(const f4*)(s.boundX + g), by = *(const f4*)(s.boundY + g);
  f4 bz = *(const f4*)(s.boundZ + g), r2 = *(const f4*)(s.boundR2 + g);
  int n = s.numObjects - g;
  bound_slot<g>(s, bx, by, bz, r2, org, dir, skip, objects);
  if (n > 1) bound_slot<g + 1>(s, bx, by, bz, r2, org, dir, skip, objects);
  if (n > 2) bound_slot<g + 2>(s, bx, by, bz, r2, org, dir, skip, objects);
  if (n > 3) bound_slot<g + 3>(s, bx, by, bz, r2, org, dir, skip, objects);
}

} // namespace

void nearest4(const Scene& s, const f4 org[3], const f4 dir[3], const u32 skip[4], u32 lanes,
              Hits4& out) {
  static_assert(kMaxObjects == 8, "two groups of four slots");
  out.t = f4_of(kHuge);
  out.id = i4_of(-1);
  out.piece = i4_of(0);
  out.local = f4_of(0.0f);
  i4 skips = *(const i4*)skip;
  // The lone-solid shortcut: each lane's named object first, one pass per
  // object named (the lanes with a hit are done).
  u32 search = lanes;
  u32 only = lane_bits((skips >> kOnlyShift) != i4_of(0)) & lanes;
  while (only) {
    u32 o = skip[__builtin_ctz(only)] >> kOnlyShift;
    u32 group = lane_bits((skips >> kOnlyShift) == i4_of((i32)o)) & only;
    only &= ~group;
    only_lanes(s, (int)o - 1, org, dir, group, out);
    search &= ~(group & lane_bits(out.id >= i4_of(0)));
  }
  if (!search) return;
  // nearest(): bound_mask's test, four lanes a bound, each lane less the
  // objects it skips; a nibble of lanes per object.
  u32 objects = 0;
  if (s.numObjects > 0) bound_group<0>(s, org, dir, skips, objects);
  if (s.numObjects > 4) bound_group<4>(s, org, dir, skips, objects);
  objects &= search * 0x11111111u;
  u32 foreground = s.numForeground >= 8 ? ~0u : (1u << 4 * s.numForeground) - 1;
  // The foreground in index order, then the background for the lanes that
  // met no foreground object.
  Shear shear;
  bool sheared = false;
  for (u32 m = objects & foreground;;) {
    if (!m) {
      u32 none = lane_bits(out.id < i4_of(0)) & search;
      m = objects & ~foreground & none * 0x11111111u;
      objects = foreground; // the background's turn: next time, done
      if (!m) break;
    }
    int i = __builtin_ctz(m) >> 2;
    object_lanes(s, i, org, dir, m >> 4 * i & 15, search, shear, sheared, out);
    m &= ~(15u << 4 * i);
  }
}
