// shade.h - the shading point of four primary hits at once (SSE2 lanes).
//
// trace_hit() (trace.h) shades a primary ray's hit (the root node of its ray
// tree: the spawn of its reflected and refracted rays, the light loop with
// a shadow ray per light, its PathRecord node), then traces the rays it
// spawned. shade_primary4() does the root of four such rays in four lanes,
// each lane with its own object and material: the same float operations in
// the same order per lane as trace_tree's (packet/lanes.h: a four-lane copy
// of a formula rounds like the scalar one), Phong's power through
// rt_pow4() and Cook-Torrance's exp through rt_exp_nonpositive4()
// (packet/pow4.h). The normals of a packet whose lanes all see one object
// are computed in lanes, a packet of mixed objects' per lane by the scalar
// hit_normal(); the shadow rays' bound tests four lanes a bound
// (shadow_mask4(), below), and where a lane's ray meets a bound its objects
// through the scalar shadow_objects() (a lone sphere, cylinder or cone as
// the one candidate: in lanes). Each lane's children then go to the scalar
// tree through trace_children4(); where two or more lanes' refracted
// children go into the lone solid their primary rays hit, those children,
// their reflected children inside it and their refracted children out of it
// are shaded four lanes at a time first (the second level, shade.cpp's
// second4()), and the tree takes them up in its own order. So colour bits,
// records and ray counts are trace_hit's (tests/test_shade4.cpp,
// tests/test_shade4_second.cpp).
#pragma once
#include "packet/lanes.h"
#include "trace.h"

// The first hits of four primary rays as the packet tracer's nearest-hit
// search leaves them, in lanes: lane k sees object id[k] (-1: nothing) at
// t[k], with intersect_t()'s piece[k] and local[k].
struct Hits4 {
  f4 t;
  i4 id, piece;
  f4 local;
};

// For the lanes k of `lanes` (bits; each h.id[k] >= 0), the primary ray
// from org along unit (dir[0][k], dir[1][k], dir[2][k]) hitting object
// h.id[k] (Hit t, piece and local from h): color[k] = trace_hit(ctx, ray,
// id, hit, 1, 1). All four lanes of h are read (those outside `lanes` may
// hold anything). When `paths` is set (four records), paths[k] receives
// lane k's record (its count is set here); the records of the lanes outside
// `lanes` are overwritten too (the first node's store goes to all four
// lanes, no per-lane test), for the caller to write after this call. Rays are counted in ctx.stats as trace_hit
// counts them.
RT64K_HOT_ABI void shade_primary4(TraceContext& ctx, Vec3 org, const f4 dir[3], const Hits4& h,
                                  u32 lanes, PathRecord* paths, Vec3 color[4]);

// shadow_mask() (trace.h) of four shadow rays to light l at once, four
// lanes a bound: lane k is shadow_mask(s, l, (Lx[k], Ly[k], Lz[k]),
// dist[k], range[k]) bit for bit, each lane taking shadow_mask's operations
// in its order. Every range[k] holds foreground objects only (as trace_tree's
// shadow ranges do): the slots from s.numForeground on are not tested.
__attribute__((always_inline)) inline i4 shadow_mask4(const Scene& s, int l, f4 Lx, f4 Ly, f4 Lz,
                                                      f4 dist, i4 range);

namespace shade4 {

// Lane j of v in every lane (pshufd: one instruction, its source kept).
template <int j> inline f4 lane_splat(f4 v) { return (f4)__builtin_ia32_pshufd((i4)v, j * 0x55); }
template <int j> inline i4 lane_splat(i4 v) { return __builtin_ia32_pshufd(v, j * 0x55); }

// The bound in slot g + j: its bit set in each lane of `objs` whose ray may
// meet it. fx, fy, fz, c, r: slots g..g + 3 of the light's Scene::lightFX,
// lightFY, lightFZ, lightC and of boundR; cpos: c > 0. Without anyIn every
// lane of cpos is set (the light outside all four bounds, as in every bench
// frame), so shadow_mask's `(c > 0) &` is left out.
template <int g, int j, bool anyIn>
__attribute__((always_inline)) inline void bound4(f4 fx, f4 fy, f4 fz, f4 c, f4 r, i4 cpos, f4 Lx,
                                                  f4 Ly, f4 Lz, f4 dist, i4& objs) {
  f4 zero = f4_of(0.0f);
  f4 beta = lane_splat<j>(fx) * Lx + lane_splat<j>(fy) * Ly + lane_splat<j>(fz) * Lz;
  i4 far = (beta < zero) | (beta - lane_splat<j>(r) >= dist);
  if (anyIn) far &= lane_splat<j>(cpos);
  i4 miss = (beta * beta < lane_splat<j>(c)) | far;
  objs |= ~miss & i4_of(1 << (g + j));
}

// The slots g..g + n - 1 (n <= 4 of them tested) by bound4().
template <int g, bool anyIn>
__attribute__((always_inline)) inline void slots4(f4 fx, f4 fy, f4 fz, f4 c, f4 r, i4 cpos, int n,
                                                  f4 Lx, f4 Ly, f4 Lz, f4 dist, i4& objs) {
  bound4<g, 0, anyIn>(fx, fy, fz, c, r, cpos, Lx, Ly, Lz, dist, objs);
  if (n > 1) bound4<g, 1, anyIn>(fx, fy, fz, c, r, cpos, Lx, Ly, Lz, dist, objs);
  if (n > 2) bound4<g, 2, anyIn>(fx, fy, fz, c, r, cpos, Lx, Ly, Lz, dist, objs);
  if (n > 3) bound4<g, 3, anyIn>(fx, fy, fz, c, r, cpos, Lx, Ly, Lz, dist, objs);
}

// The foreground slots g..g + 3 (those below s.numForeground) by bound4().
template <int g>
__attribute__((always_inline)) inline void group4(const Scene& s, int l, f4 Lx, f4 Ly, f4 Lz,
                                                  f4 dist, i4& objs) {
  f4 fx = *(const f4*)(s.lightFX[l] + g), fy = *(const f4*)(s.lightFY[l] + g);
  f4 fz = *(const f4*)(s.lightFZ[l] + g), c = *(const f4*)(s.lightC[l] + g);
  f4 r = *(const f4*)(s.boundR + g);
  i4 cpos = c > f4_of(0.0f);
  int n = s.numForeground - g;
  if (lane_bits(cpos) == 15)
    slots4<g, false>(fx, fy, fz, c, r, cpos, n, Lx, Ly, Lz, dist, objs);
  else
    slots4<g, true>(fx, fy, fz, c, r, cpos, n, Lx, Ly, Lz, dist, objs);
}

} // namespace shade4

inline i4 shadow_mask4(const Scene& s, int l, f4 Lx, f4 Ly, f4 Lz, f4 dist, i4 range) {
  static_assert(kMaxObjects == 8, "two groups of four slots");
  i4 objs = i4_of(0);
  shade4::group4<0>(s, l, Lx, Ly, Lz, dist, objs);
  if (s.numForeground > 4) shade4::group4<4>(s, l, Lx, Ly, Lz, dist, objs);
  return (objs | i4_of((i32)s.unboundedMask)) & range;
}
