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
// hit_normal(); each shadow ray's bound test per lane (shadow_mask(),
// trace.h), and where a bound is met its objects through the scalar
// shadow_objects(). Each lane's children then go
// to the scalar tree through trace_children4(). So colour bits, records and
// ray counts are trace_hit's (tests/test_shade4.cpp).
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
// hold anything). When `paths` is set, paths[k] receives the lane's record
// (its count is set here). Rays are counted in ctx.stats as trace_hit
// counts them.
RT64K_HOT_ABI void shade_primary4(TraceContext& ctx, Vec3 org, const f4 dir[3], const Hits4& h,
                                  u32 lanes, PathRecord* paths, Vec3 color[4]);
