// nearest4.h - the first hits of four secondary rays at once (SSE2 lanes).
//
// trace_tree (trace.cpp) finds a waiting ray's first hit by its kFindHit
// step: hit.t = kHuge; where the ray's skip names a lone solid (bits from
// kOnlyShift), that object's intersect_t() first; else, or where that finds
// nothing, nearest() over the objects of the scene less the skipped ones
// (the bound test, then the foreground objects in index order, then the
// background ones for a ray that met no foreground object). find_hit()
// (trace.h) is that step for one ray. nearest4() does it for four rays of
// four origins, in lanes: the bound test, spheres, planes and triangles as
// four-lane copies of bound_mask, hit_sphere, hit_plane and hit_triangle
// (the same float operations in the same order per lane: packet/lanes.h),
// cylinders and cones through frustum_lanes4() (packet/frustum.h), and the
// cases the kernels leave out through the scalar intersect_t() per lane
// (a plane within kPlaneCosFloat of parallel, a triangle edge function of
// exactly 0, a frustum's clamped or flat-sided lanes). So lane k's object,
// t, piece and local are find_hit()'s, bit for bit
// (tests/test_nearest4.cpp).
#pragma once
#include "packet/shade.h"

// For the lanes k of `lanes` (bits 0..3): the ray from (org[0][k],
// org[1][k], org[2][k]) along the unit (dir[0][k], dir[1][k], dir[2][k])
// with trace_tree's skip[k] (object bits and the lone solid from
// kOnlyShift): out.id[k] = find_hit()'s object (-1: none) and, for a hit,
// out.t[k], out.piece[k], out.local[k] its hit.t, piece and local. A lane
// that hits nothing gets t = kHuge, piece 0, local 0. Lanes outside `lanes`
// get id -1 and may hold any ray (they are not tested).
RT64K_HOT_ABI void nearest4(const Scene& s, const f4 org[3], const f4 dir[3], const u32 skip[4],
                            u32 lanes, Hits4& out);
