// frustum.cpp - hit_frustum() (shapes.cpp) for four primary rays; the
// contract is in frustum.h. Each line repeats a line of frustum_frame() or
// hit_frustum() for four lanes (or, in frustum_terms(), for ray.org = org),
// operation for operation: SSE2's packed + - * / and sqrt round as the
// scalar ones, -ffp-contract=off keeps them unfused, and each branch of
// the scalar test is a lane mask here, with the same comparison (a NaN
// falls the same way).
#include "packet/frustum.h"

void frustum_terms(const Shape& s, Vec3 org, FrustumTerms& f) {
  // frustum_frame(): w, yw, vw and rim.
  Vec3 axis = s.b;
  Vec3 w = org - s.a;
  float yw = dot(w, axis);
  Vec3 vw = w - axis * yw;
  float rim = kRimRel * (max_abs(w) + s.c.y);
  f.vw[0] = vw.x;
  f.vw[1] = vw.y;
  f.vw[2] = vw.z;
  f.yw = yw;
  // hit_frustum(): the cull's reach, the side's ends, the caps' rr.
  float reach = rt_max(s.r0, s.r1) + kCullRim * rim;
  f.reach2 = reach * reach;
  f.yLo = -rim;
  f.yHi = s.h + rim;
  float rr0 = s.r0 + rim, rr1 = s.r1 + rim;
  f.rr[0] = rr0 * rr0;
  f.rr[1] = rr1 * rr1;
}

// Frustum terms in lanes (frustum_terms4) or shared by the four rays
// (frustum_terms): each term is read as a float or as four lanes, with the
// same operations.
namespace {

template <class Terms>
__attribute__((always_inline)) inline FrustumLanes frustum_kernel(const Shape& s, const Terms& f,
                                                                  const f4 dir[3], u32 lanes,
                                                                  f4& tNear, i4& piece, f4& local) {
  FrustumLanes out{0, lanes};
  if (s.c.z > 1) return out; // a flat side: the scalar test for every lane
  // frustum_frame()
  Vec3 axis = s.b;
  f4 zero = f4_of(0.0f);
  f4 dy = dir[0] * axis.x + dir[1] * axis.y + dir[2] * axis.z;
  f4 ux = dir[0] - axis.x * dy, uy = dir[1] - axis.y * dy, uz = dir[2] - axis.z * dy;
  f4 uu = ux * ux + uy * uy + uz * uz;
  // !(uu >= c.z): the centre clamped into the slab; those lanes go back.
  out.rest = lanes & ~lane_bits(uu >= f4_of(s.c.z));
  lanes &= ~out.rest;
  if (!lanes) return out;
  f4 tc = -(f.vw[0] * ux + f.vw[1] * uy + f.vw[2] * uz) / uu;
  f4 vx = f.vw[0] + ux * tc, vy = f.vw[1] + uy * tc, vz = f.vw[2] + uz * tc;
  f4 y0 = f.yw + dy * tc;
  // hit_frustum(): the cull, then the quadratic.
  f4 vv = vx * vx + vy * vy + vz * vz;
  lanes &= ~lane_bits(vv > f.reach2);
  if (!lanes) return out;
  i4 live = lanes_of(lanes), hit = i4_of(0);
  float k = s.c.x;
  f4 rk = s.r0 + k * y0;
  f4 A = uu - k * k * dy * dy;
  f4 B = (ux * vx + uy * vy + uz * vz) - k * dy * rk;
  f4 C = vv - rk * rk;
  f4 disc = B * B - A * C;
  i4 solved = live & (disc >= zero);
  if (lane_bits(solved)) {
    f4 root = lane_sqrt(disc);
    f4 q = -(B + (B >= zero ? root : -root));
    f4 huge = f4_of(kHuge);
    // The roots q/A and C/q in turn; the second is tested against the first
    // one's t where that was accepted, as hit.t is.
    f4 tr = A != zero ? q / A : huge, next = q != zero ? C / q : huge;
    for (int r = 0; r < 2; ++r, tr = next) {
      f4 t = tc + tr, y = y0 + tr * dy;
      i4 ok = solved & (t > zero) & (t < tNear) & ~((y < f.yLo) | (y > f.yHi));
      tNear = ok ? t : tNear;
      piece = ok ? i4_of(kPieceSide) : piece;
      local = ok ? tr : local;
      hit |= ok;
    }
  }
  // The caps, for the lanes with dy != 0.
  i4 capped = live & (dy != zero);
  auto cap = [&](float yc, auto rr2, int pieceCap) __attribute__((always_inline)) {
    f4 tr = (yc - y0) / dy, t = tc + tr;
    f4 px = vx + ux * tr, py = vy + uy * tr, pz = vz + uz * tr;
    i4 ok = capped & (t > zero) & (t < tNear) & ~(px * px + py * py + pz * pz > rr2);
    tNear = ok ? t : tNear;
    piece = ok ? i4_of(pieceCap) : piece;
    local = ok ? tr : local;
    hit |= ok;
  };
  if (s.caps & kCapBase) cap(0.0f, f.rr[0], kPieceBase);
  if (s.caps & kCapTop) cap(s.h, f.rr[1], kPieceTop);
  out.hit = lane_bits(hit);
  return out;
}

} // namespace

FrustumLanes frustum_lanes(const Shape& s, const FrustumTerms& f, const f4 dir[3], u32 lanes,
                           f4& tNear, i4& piece, f4& local) {
  return frustum_kernel(s, f, dir, lanes, tNear, piece, local);
}

void frustum_terms4(const Shape& s, const f4 org[3], FrustumTerms4& f) {
  // frustum_terms() lane by lane.
  Vec3 axis = s.b;
  f4 wx = org[0] - s.a.x, wy = org[1] - s.a.y, wz = org[2] - s.a.z;
  f4 yw = wx * axis.x + wy * axis.y + wz * axis.z;
  f.vw[0] = wx - axis.x * yw;
  f.vw[1] = wy - axis.y * yw;
  f.vw[2] = wz - axis.z * yw;
  f.yw = yw;
  // max_abs(w) = rt_max(|x|, rt_max(|y|, |z|)), rt_max(a, b) = a > b ? a : b.
  f4 ax = lane_abs(wx), ay = lane_abs(wy), az = lane_abs(wz);
  f4 myz = ay > az ? ay : az;
  f4 m = ax > myz ? ax : myz;
  f4 rim = kRimRel * (m + s.c.y);
  f4 reach = rt_max(s.r0, s.r1) + kCullRim * rim;
  f.reach2 = reach * reach;
  f.yLo = -rim;
  f.yHi = s.h + rim;
  f4 rr0 = s.r0 + rim, rr1 = s.r1 + rim;
  f.rr[0] = rr0 * rr0;
  f.rr[1] = rr1 * rr1;
}

FrustumLanes frustum_lanes4(const Shape& s, const FrustumTerms4& f, const f4 dir[3], u32 lanes,
                            f4& tNear, i4& piece, f4& local) {
  return frustum_kernel(s, f, dir, lanes, tNear, piece, local);
}
