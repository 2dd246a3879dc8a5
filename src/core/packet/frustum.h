// frustum.h - cylinders and cones for four primary rays at once.
//
// hit_frustum() (shapes.cpp) for four rays from one origin, in SSE2 lanes:
// frustum_frame(), the cull, the quadratic and its two roots, the two caps
// and accept(), with the same operations in the same order per lane, so a
// lane gets the bits the scalar test gives (t, piece, local). What depends
// on the origin and the shape alone (frustum_frame's w = org - base, yw,
// vw and rim, and the bounds built from rim) is computed once per frame by
// frustum_terms(), by the very expressions the scalar test applies to
// ray.org. Two cases are not mirrored and are handed back for the scalar
// test: a flat side (|k| > 1, Shape::c.z = 2: every lane), and a lane that
// frustum_frame() solves from its clamped centre (u.u < c.z: the ray within
// 45 deg of the axis). tests/test_frustum4.cpp checks it against
// intersect_t() bit for bit.
#pragma once
#include "abi.h"
#include "packet/lanes.h"
#include "shapes.h"

// A frustum's terms for rays from one origin org (frustum_frame() and
// hit_frustum() for ray.org = org; rim = kRimRel (max_abs(w) + c.y)).
struct FrustumTerms {
  float vw[3];    // w - axis yw, w = org - base: the origin off the axis
  float yw;       // w.axis: the origin along the axis
  float reach2;   // (max(r0, r1) + kCullRim rim)^2: the cull's bound on v.v
  float yLo, yHi; // -rim, h + rim: the side's ends along the axis
  float rr[2];    // (r0 + rim)^2, (r1 + rim)^2: the base and top caps' radii, squared
};

void frustum_terms(const Shape& s, Vec3 org, FrustumTerms& out);

// Lanes (bits 0..3) of a frustum test: `hit` accepted a hit, `rest` need
// the scalar test.
struct FrustumLanes {
  u32 hit, rest;
};

// hit_frustum(s, Ray{org, dir of lane k}, 0, hit) for the lanes of `lanes`
// (s a kCylinder or kCone, f = frustum_terms(s, org)), dir[c][k] component
// c of lane k's unit direction. Lane k's current nearest distance is t[k]
// (hit.t on entry); where the scalar test would accept a hit, t[k],
// piece[k] and local[k] get its hit.t, hit.piece and hit.local. The lanes
// the kernel does not mirror are left alone and returned in `rest`.
RT64K_HOT_ABI FrustumLanes frustum_lanes(const Shape& s, const FrustumTerms& f, const f4 dir[3],
                                         u32 lanes, f4& t, i4& piece, f4& local);

// The same terms for four rays of four origins (the second level's rays
// into a lone cylinder or cone, packet/shade.cpp): lane k holds what frustum_terms(s, (org[0][k],
// org[1][k], org[2][k])) gives, by the same operations.
struct FrustumTerms4 {
  f4 vw[3];
  f4 yw;
  f4 reach2;
  f4 yLo, yHi;
  f4 rr[2];
};

void frustum_terms4(const Shape& s, const f4 org[3], FrustumTerms4& out);

// frustum_lanes() for rays of four origins: lane k is hit_frustum(s,
// Ray{origin of lane k, dir of lane k}, 0, hit), f = frustum_terms4(s,
// org); the same lanes are handed back.
RT64K_HOT_ABI FrustumLanes frustum_lanes4(const Shape& s, const FrustumTerms4& f, const f4 dir[3],
                                          u32 lanes, f4& t, i4& piece, f4& local);
