// shade.cpp - four primary shading points at once; the contract is in
// shade.h. Every expression below repeats trace_tree's (trace.cpp) for the
// root node (depth 1, weight 1, nothing passed through glass yet), lane by
// lane, in the same order: where trace_tree multiplies by the weight 1 or
// adds to a sum of 0, so does this code, so that no rounding differs. The
// second level (second4(), shade_child4()) does the same for nodes of depth
// 2 and 3 with each lane's own weight, origin and skip bits.
#include "packet/shade.h"

#include "packet/frustum.h"
#include "packet/pow4.h"

namespace {

// Hit::piece of a frustum's hit (shapes.cpp's enum, which the header does
// not export): the side, the base cap, the top cap. test_shade4's caps and
// sides check them.
constexpr i32 kFrustumSide = 0, kFrustumTop = 2;

// Three float lanes: a Vec3 in each of four lanes.
struct V4 {
  f4 x, y, z;
};
inline V4 operator+(V4 a, V4 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline V4 operator-(V4 a, V4 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline V4 operator*(V4 a, f4 s) { return {a.x * s, a.y * s, a.z * s}; }
inline V4 operator*(V4 a, V4 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
inline f4 dot(V4 a, V4 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline V4 splat(Vec3 v) { return {f4_of(v.x), f4_of(v.y), f4_of(v.z)}; }
inline f4 max4(f4 a, f4 b) { return a > b ? a : b; } // rt_max
inline Vec3 lane(V4 v, int k) { return Vec3{v.x[k], v.y[k], v.z[k]}; }
inline V4 select(i4 m, V4 a, V4 b) { return {m ? a.x : b.x, m ? a.y : b.y, m ? a.z : b.z}; }

// leaves_for_good_dot() (shapes.h) with the hit's front side given.
inline bool leaves(const Shape& sh, bool front, float d) {
  if (sh.kind == kPlane || sh.kind == kTriangle) return true;
  return front ? d > 0 : d < 0;
}

// Four floats from p, unaligned.
inline f4 load4(const float* p) {
  f4 r;
  __builtin_memcpy(&r, p, 16);
  return r;
}

// The columns a, b, c, d as rows: out[k] = {a[k], b[k], c[k], d[k]} (a 4x4
// transpose, its own inverse).
inline void rows(f4 a, f4 b, f4 c, f4 d, f4 out[4]) {
  f4 ab0 = __builtin_ia32_unpcklps(a, b), cd0 = __builtin_ia32_unpcklps(c, d);
  f4 ab1 = __builtin_ia32_unpckhps(a, b), cd1 = __builtin_ia32_unpckhps(c, d);
  out[0] = __builtin_ia32_movlhps(ab0, cd0);
  out[1] = __builtin_ia32_movhlps(cd0, ab0);
  out[2] = __builtin_ia32_movlhps(ab1, cd1);
  out[3] = __builtin_ia32_movhlps(cd1, ab1);
}

// The rows r[k] (four floats from row pointer k) as columns: out[c][k] = r[k][c].
inline void columns(const float* const r[4], f4 out[4]) {
  rows(load4(r[0]), load4(r[1]), load4(r[2]), load4(r[3]), out);
}

// Each lane's waiting ray (origin o, direction d, weight w, skip bits) as
// the first 32 bytes of its Pending (Ray, weight, skip): two rows of four
// floats, lane k's lo[k] (org, dir.x) and hi[k] (dir.y, dir.z, weight,
// skip), stored by put() with its pastGlass: three stores a lane.
static_assert(sizeof(Ray) == 24 && __builtin_offsetof(Pending, weight) == 24 &&
                  __builtin_offsetof(Pending, skip) == 28,
              "Pending starts with its ray, weight and skip");
struct PendingRows {
  f4 lo[4], hi[4];
  PendingRows(V4 o, V4 d, f4 w, i4 skip) {
    rows(o.x, o.y, o.z, d.x, lo);
    rows(d.y, d.z, w, (f4)skip, hi);
  }
  void put(int k, Pending& p, bool glass) const {
    __builtin_memcpy(&p, &lo[k], 16);
    __builtin_memcpy((char*)&p + 16, &hi[k], 16);
    p.pastGlass = glass;
  }
};

// Four lanes' rays as Rays: rr[k].ray is lane k's (org, dir), each from
// one transposed pair of rows (two stores a lane, no scalar gather).
struct alignas(16) RayRow {
  Ray ray;
  float pad[2];
};
static_assert(sizeof(RayRow) == 32, "a Ray in two rows");
__attribute__((always_inline)) inline void ray_rows(const V4& o, const V4& d, RayRow rr[4]) {
  f4 lo[4], hi[4];
  rows(o.x, o.y, o.z, d.x, lo);
  rows(d.y, d.z, d.z, d.z, hi);
#pragma GCC unroll 4
  for (int k = 0; k < 4; ++k) {
    __builtin_memcpy(&rr[k], &lo[k], 16);
    __builtin_memcpy((char*)&rr[k] + 16, &hi[k], 16);
  }
}

// A V4 stored lane by lane: v[c][k] is component c of lane k.
struct Lanes3 {
  alignas(16) float v[3][4];
  void set(V4 a) {
    *(f4*)v[0] = a.x;
    *(f4*)v[1] = a.y;
    *(f4*)v[2] = a.z;
  }
  Vec3 lane(int k) const { return Vec3{v[0][k], v[1][k], v[2][k]}; }
};

// hit_sphere() (shapes.cpp) of sphere sh, tMin 0, in lanes, its operations
// in its order: f = org - centre, b = f.d, perp = f - d b, disc = r^2 -
// perp.perp (< 0: a miss; NaN goes on, for the caller's upper bound to
// refuse), c = f.f - r^2, q = -(b + sign(b) sqrt(disc)) (0: a miss), t0 =
// c / q and t1 = q ordered, t = t0 where > 0, else t1. Returns the lanes
// that pass all but the caller's upper bound on t.
__attribute__((always_inline)) inline i4 sphere_t4(const Shape& sh, const V4& org, const V4& dir,
                                                   f4& t) {
  f4 zero = f4_of(0.0f);
  V4 f = org - splat(sh.a);
  f4 b = dot(f, dir);
  V4 perp = f - dir * b;
  float r2 = sh.r0 * sh.r0;
  f4 disc = f4_of(r2) - dot(perp, perp);
  f4 c = dot(f, f) - f4_of(r2);
  f4 root = lane_sqrt(disc);
  f4 q = -(b + (b >= zero ? root : -root));
  f4 t0 = c / q, t1 = q;
  i4 swap = t0 > t1;
  f4 lo = swap ? t1 : t0, hi = swap ? t0 : t1;
  t = lo > zero ? lo : hi;
  return ~(disc < zero) & (q != zero) & (t > zero);
}

// The lanes of `mine` (their shadow rays to light li, from org along L to
// dist: each one's one candidate object j, a sphere, cylinder or cone, not
// crossed untested): shadow_test() (trace.cpp) of that one object in lanes:
// hit_sphere() (tMin 0, hit.t = dist) with its operations in its order, or
// hit_frustum() by frustum_lanes4() (packet/frustum.h), then where it hits,
// a transparent solid multiplies v3(1) by colour * transmit (that product,
// bit for bit), code 1, an opaque one gives code 3 and no light; a miss
// code 0. tv, shadowed and the codes in bits are set for them. Returns the
// lanes done (a frustum's lanes that frustum_lanes4() does not mirror are
// left to the caller's scalar test).
__attribute__((noinline)) u32 solid_shadows4(const Scene& s, int j, u32 mine, const V4& org,
                                             const V4& L, f4 dist, int li, V4& tv, u32& shadowed,
                                             u32 bits[4]) {
  const Object& o = s.objects[j];
  const Shape& sh = o.shape;
  f4 zero = f4_of(0.0f);
  u32 hit, rest = 0;
  if (sh.kind != kSphere) {
    // A cylinder or cone: hit_frustum() in lanes (frustum_lanes4()), the
    // lanes it does not mirror left to the caller.
    f4 o3[3] = {org.x, org.y, org.z}, d3[3] = {L.x, L.y, L.z};
    FrustumTerms4 terms;
    frustum_terms4(sh, o3, terms);
    f4 t = dist, local = zero;
    i4 piece = i4_of(0);
    FrustumLanes fl = frustum_lanes4(sh, terms, d3, mine, t, piece, local);
    hit = fl.hit & mine;
    rest = fl.rest & mine;
  } else {
    f4 t;
    i4 ok = sphere_t4(sh, org, L, t);
    hit = lane_bits(ok & (t < dist)) & mine;
  }
  if (!hit) return mine & ~rest;
  u32 code = o.mat.transmit <= 0 ? 3 : 1;
  V4 ct = code == 3 ? V4{zero, zero, zero} : splat(o.mat.color * o.mat.transmit);
  tv = select(lanes_of(hit), ct, tv);
  if (code == 3) shadowed |= hit;
  *(i4*)bits |= lanes_of(hit) & i4_of((i32)(code << (5 + 3 * li)));
  return mine & ~rest;
}

// Phong's specular term where the kSpecExp cut leaves it, r_S (V.R)^h: out
// of line, as few lanes need it (its double lanes would make the caller
// align its frame to 32 bytes).
__attribute__((noinline)) f4 phong_spec(f4 VdotR, f4 shininess, f4 specular, i4 cut) {
  return cut ? f4_of(0.0f) : specular * rt_pow4(VdotR, shininess);
}

// cook_torrance() (trace.cpp) in lanes past its kSpecExp test (cook_torrance4()):
// h = L - I again, m2 = roughness^2 and the lanes cut given.
__attribute__((noinline)) f4 cook_torrance4_rest(const V4& N, const V4& I, const V4& L, f4 m2,
                                                 f4 f0, i4 cut) {
  f4 zero = f4_of(0.0f), one = f4_of(1.0f);
  V4 h = L - I;
  f4 hh = dot(h, h);
  V4 H = select(hh > f4_of(1e-30f), h * (1.0f / lane_sqrt(hh)), N); // normalize(h, N)
  f4 nH = dot(N, H);
  f4 NdotH = nH < zero ? zero : (nH > one ? one : nH); // rt_clamp(., 0, 1)
  f4 NdotV = max4(-dot(N, I), f4_of(kCosEps));
  f4 NdotL = max4(dot(N, L), zero);
  f4 VdotH = max4(-dot(I, H), 0.5f * (NdotV + NdotL));
  f4 x = 1.0f - VdotH, x2 = x * x;
  f4 F = f0 + x2 * x2 * x * (1.0f - f0);
  f4 mn = NdotV < NdotL ? NdotV : NdotL;
  f4 g = 2.0f * NdotH * mn / VdotH;
  f4 G = one < g ? one : g; // rt_min(1, g)
  f4 c2 = NdotH * NdotH;
  f4 D = rt_exp_nonpositive4((c2 - 1.0f) / (c2 * m2)) / (kPi * m2 * c2 * c2);
  D = c2 > f4_of(kCos2Min) ? D : zero;
  f4 r = F * D * G / NdotV;
  return cut ? zero : r;
}

// cook_torrance() (trace.cpp) in lanes: F D G / (N.V), 0 where the
// kSpecExp test cuts it (or N.h <= 0). I is the incident direction. The
// test inline (most calls cut every lane), the rest out of line.
__attribute__((always_inline)) inline f4 cook_torrance4(const V4& N, const V4& I, const V4& L,
                                                        f4 roughness, f4 f0) {
  f4 zero = f4_of(0.0f);
  V4 h = L - I;
  f4 nh = dot(N, h), m2 = roughness * roughness;
  i4 cut = ~(nh > zero) | (dot(h, h) - nh * nh > kSpecExp * m2 * (nh * nh));
  if (!(~lane_bits(cut) & 15)) return zero;
  return cook_torrance4_rest(N, I, L, m2, f0, cut);
}

// The lanes of `cand` whose shadow ray's one candidate (objects[k], the
// first such lane's) is a sphere, cylinder or cone, less the lanes
// exiting(j) names (inside that solid j, towards a light outside its bound:
// the caller's own test), by solid_shadows4() in lanes. Returns the lanes
// of `cand` left to the scalar test.
template <class Exiting>
__attribute__((always_inline)) inline u32
one_solid_shadows4(const Scene& s, int li, u32 cand, const u32* objects, Exiting exiting,
                   const V4& lightOrg, const V4& L, const float* dist, V4& tv, u32& shadowed,
                   u32* bits) {
  u32 m0 = objects[__builtin_ctz(cand)];
  int j = __builtin_ctz(m0 | 1u << 31);
  if (!(m0 & (m0 - 1)) && s.objects[j].shape.kind != kPlane &&
      s.objects[j].shape.kind != kTriangle && s.objects[j].shape.kind != kEmpty) {
    u32 mine = lane_bits(*(const i4*)objects == i4_of((i32)m0)) & cand & ~exiting(j);
    if (mine)
      cand &= ~solid_shadows4(s, j, mine, lightOrg, L, *(const f4*)dist, li, tv, shadowed, bits);
  }
  return cand;
}

// The shadow rays of the lanes `cand` whose bound tests left candidates
// (objects[k]), one lane at a time through the scalar shadow_objects(): lane
// k's ray from lightOrg's lane k along L over dist[k], exits(k) the solid it
// leaves (0: none). Their transmittance goes into tv, their codes into bits
// (code 3, no light: into shadowed).
template <class Exits>
__attribute__((always_inline)) inline void
shadow_objects4(const Scene& s, int li, u32 cand, const V4& lightOrg, const V4& L,
                const float* dist, const u32* objects, Exits exits, V4& tv, u32& shadowed,
                u32* bits) {
  RayRow rr[4];
  ray_rows(lightOrg, L, rr);
  Lanes3 through;
  through.set(tv);
  for (u32 q = cand; q; q &= q - 1) {
    int k = __builtin_ctz(q);
    int code = 0;
    Vec3 tr = shadow_objects(s, rr[k].ray, dist[k], objects[k], code, exits(k));
    through.v[0][k] = tr.x;
    through.v[1][k] = tr.y;
    through.v[2][k] = tr.z;
    shadowed |= (u32)(code == 3) << k;
    bits[k] |= (u32)code << (5 + 3 * li);
  }
  tv = V4{*(f4*)through.v[0], *(f4*)through.v[1], *(f4*)through.v[2]};
}

// One light's term unshadowed in four lanes: trace_tree's light loop up to
// its shadow ray, for the primary shading point and the second level alike.
// Returns the lanes of `live` that face the light (N.L > 0); dist and L are
// the way to the light from lightOrg, and only where some lane faces it,
// spec the specular factor and term the light's colour term (trace_tree's
// `lit`), Phong or Cook-Torrance.
__attribute__((always_inline)) inline u32
light_term4(const Scene& s, const Light& light, const V4& lightOrg, const V4& N, const V4& D,
            i4 live, const V4& mc, f4 diffuse, f4 specular, f4 shininess, f4 roughness, f4 f0,
            float dist[4], V4& L, f4& spec, V4& term) {
  f4 zero = f4_of(0.0f);
  V4 toLight = splat(light.pos) - lightOrg;
  *(f4*)dist = lane_sqrt(dot(toLight, toLight));
  L = toLight * (1.0f / max4(*(f4*)dist, f4_of(1e-20f)));
  f4 NdotL = dot(N, L);
  u32 lit = lane_bits((NdotL > zero) & live);
  if (!lit) return 0;
  spec = zero;
  if (s.model == kPhong) {
    // V.R = -(I.R), R = N (2 N.L) - L.
    f4 VdotR = max4(-dot(D, N * (2.0f * NdotL) - L), zero);
    i4 cut = shininess * (1.0f - VdotR) > f4_of(kSpecExp);
    if (lit & ~lane_bits(cut)) spec = phong_spec(VdotR, shininess, specular, cut);
    term = (mc * (diffuse * NdotL) + V4{spec, spec, spec}) * splat(light.color);
  } else {
    spec = specular * cook_torrance4(N, D, L, roughness, f0) * NdotL;
    term = mc * (diffuse * NdotL + spec) * splat(light.color);
  }
  return lit;
}

// The waiting rays *src[k] (depth `depth`, each past glass or not as
// pastGlass says) of the lanes `have`, which all hit object `id` (t, piece
// and local found ahead in dst[k]->hit): each lane's node shaded as
// trace_tree shades it (the normal, the spawn of its children, the light
// loop with its weight's cuts), stored in *dst[k]: its colour, record node,
// whether it records, its children. Every lane's pointers are read (those
// outside `have` repeat a lane of `have`'s: second4()); only the lanes of
// `have` are written.
//
// On a sphere the hits are found here: hit_sphere() (shapes.cpp, tMin 0,
// as the lone-solid test calls it) in lanes, its operations in its order;
// where a lane's ray misses, nothing is done and false returned (the tree
// searches again). Elsewhere the caller found them; true.
template <int depth, bool sphere>
__attribute__((noinline)) bool shade_child4(TraceContext& ctx, const Pending* const src[4],
                                            PreNode* const dst[4], u32 have, bool pastGlass, int id,
                                            int maxDepth) {
  const Scene& s = *ctx.scene;
  const Object& o = s.objects[id];
  const Material& mt = o.mat;
  const Shape& sh = o.shape;
  // Each lane's ray and weight as columns: org, dir.x; dir.y, dir.z,
  // weight, skip.
  f4 a[4], b[4];
  rows(load4(&src[0]->ray.org.x), load4(&src[1]->ray.org.x), load4(&src[2]->ray.org.x),
       load4(&src[3]->ray.org.x), a);
  rows(load4(&src[0]->ray.dir.y), load4(&src[1]->ray.dir.y), load4(&src[2]->ray.dir.y),
       load4(&src[3]->ray.dir.y), b);
  V4 O = {a[0], a[1], a[2]}, D = {a[3], b[0], b[1]};
  f4 W = b[2], T4;
  f4 zero = f4_of(0.0f), one = f4_of(1.0f);
  V4 A = splat(sh.a), N;
  if (sphere) {
    // hit_sphere(), accepted where 0 < t < kHuge.
    i4 ok = sphere_t4(sh, O, D, T4) & (T4 < f4_of(kHuge));
    if ((lane_bits(ok) & have) != have) return false;
  } else {
    T4 = f4{dst[0]->hit.t, dst[1]->hit.t, dst[2]->hit.t, dst[3]->hit.t};
  }
  i4 front;
  u32 self = 1u << id;
  if (!sphere && sh.kind == kPlane) {
    i4 pc = {dst[0]->hit.piece, dst[1]->hit.piece, dst[2]->hit.piece, dst[3]->hit.piece};
    front = pc != i4_of(0); // plane_normal()
    N = select(front, A, V4{-A.x, -A.y, -A.z});
  } else if (!sphere && sh.kind == kTriangle) {
    V4 out = splat(Vec3{sh.r0, sh.r1, sh.h});
    front = dot(out, D) < zero;
    N = select(front, out, V4{-out.x, -out.y, -out.z});
  } else if (!sphere) {
    // A cylinder's or cone's: frustum_outward()'s steps as shade_primary4's
    // one-object path takes them, each lane from its own origin; a lane
    // beyond the domain (rho^2 > 1e20, or NaN) through hit_normal().
    V4 axis = splat(sh.b);
    V4 q = (O - A) + D * T4;
    V4 pPerp = q - axis * dot(q, axis);
    f4 rho2 = dot(pPerp, pPerp);
    u32 ok = lane_bits(rho2 <= f4_of(1e20f));
    V4 av = pPerp - axis * (f4_of(sh.c.x) * lane_sqrt(rho2));
    f4 len2 = dot(av, av);
    V4 side = select(len2 > f4_of(1e-30f), av * (1.0f / lane_sqrt(len2)), axis);
    i4 piece = {dst[0]->hit.piece, dst[1]->hit.piece, dst[2]->hit.piece, dst[3]->hit.piece};
    V4 cap = select(piece == i4_of(kFrustumTop), axis, V4{-axis.x, -axis.y, -axis.z});
    V4 out = select(piece == i4_of(kFrustumSide), side, cap);
    ok |= lane_bits(piece != i4_of(kFrustumSide));
    front = dot(out, D) < zero;
    N = select(front, out, V4{-out.x, -out.y, -out.z});
    for (u32 q2 = have & ~ok; q2; q2 &= q2 - 1) {
      int k = __builtin_ctz(q2);
      Hit hit = dst[k]->hit;
      hit_normal(sh, src[k]->ray, hit);
      N.x[k] = hit.normal.x;
      N.y[k] = hit.normal.y;
      N.z[k] = hit.normal.z;
      front[k] = -(i32)hit.front;
    }
  } else {
    // sphere_outward() (shapes.h): m = (org - centre) + t dir where |m|^2
    // lies in [r^2 / 4, 4 r^2], the other lanes by the scalar function.
    V4 m = (O - A) + D * T4;
    f4 len2 = dot(m, m), r2 = f4_of(sh.r0 * sh.r0);
    u32 ok = lane_bits((len2 >= 0.25f * r2) & (len2 <= 4.0f * r2));
    V4 out = m * (1.0f / lane_sqrt(len2));
    for (u32 q = have & ~ok; q; q &= q - 1) {
      int k = __builtin_ctz(q);
      Hit hit;
      hit.t = T4[k];
      Vec3 w = sphere_outward(sh, src[k]->ray, hit);
      out.x[k] = w.x;
      out.y[k] = w.y;
      out.z[k] = w.z;
    }
    front = dot(out, D) < zero;
    N = select(front, out, V4{-out.x, -out.y, -out.z});
  }
  i4 live = lanes_of(have);
  V4 p = O + D * T4;
  V4 col = splat(s.ambient) * splat(mt.color);
  f4 ax = lane_abs(p.x), ay = lane_abs(p.y), az = lane_abs(p.z);
  f4 off = kSpawnPos * max4(ax, max4(ay, az)) + kSpawnRel * (f4_of(sh.size) + T4);
  V4 lightOrg = p + N * off;
  bool flat = sh.kind == kPlane || sh.kind == kTriangle;
  u32 foreground = s.numForeground >= 32 ? ~0u : (1u << s.numForeground) - 1;
  i4 range = front | i4_of(-(i32)flat) ? i4_of((i32)(foreground & ~self)) : i4_of((i32)foreground);
  u32 inside = closed_convex(sh) ? ~lane_bits(front) & have : 0;
  // The record's tests: recordable and records.
  i4 recordable = depth <= kRecordDepth ? W >= f4_of(kRecordWeight) : i4_of(0);
  u32 records = lane_bits(recordable | (pastGlass ? W >= f4_of(kRecordWeightGlass) : recordable));

  // Where each lane's node is written: its own for the lanes of `have`,
  // else `spare` (written, never read). The stores below go to all four
  // lanes without a test of the lane's bit (the bits follow the rays' data
  // and mispredict); a node's child is read only where its waiting bit is
  // set, so a lane of `have` may receive a child it does not cast.
  PreNode spare;
  PreNode* out[4];
#pragma GCC unroll 4
  for (int k = 0; k < 4; ++k)
    out[k] = have >> k & 1 ? dst[k] : &spare;
  i4 waiting = i4_of(0);
  if (depth < maxDepth) {
    f4 transmit = f4_of(mt.transmit);
    bool glass = mt.transmit > 0;
    f4 eta = glass ? (front ? f4_of(1.0f / mt.ior) : f4_of(mt.ior)) : one;
    V4 negD = {-D.x, -D.y, -D.z};
    f4 cosI = glass ? dot(N, negD) : one;
    f4 sin2T = glass ? eta * eta * (1.0f - cosI * cosI) : zero;
    i4 tir = glass ? sin2T > one : i4_of(0);
    f4 dT = zero, fR = f4_of(mt.reflect) + (tir ? transmit : zero);
    i4 castRL = (fR > zero) & (W * fR >= f4_of(kMinRayWeight)) & live;
    i4 castTL = glass ? ~tir & (W * transmit >= f4_of(kMinRayWeight)) & live : i4_of(0);
    u32 castR = lane_bits(castRL), castT = lane_bits(castTL);
    V4 R = D - N * (2.0f * dot(N, D));
    f4 dR = dot(R, N);
    f4 offR = dR >= zero ? off : -off;
    V4 T = D;
    f4 offT = zero;
    if (castT) {
      V4 t = D * eta + N * (eta * cosI - lane_sqrt(1.0f - sin2T));
      f4 len2 = dot(t, t);
      T = select(len2 > f4_of(1e-30f), t * (1.0f / lane_sqrt(len2)), D);
      dT = dot(T, N);
      offT = dT >= zero ? off : -off;
    }
    // The skip bits in lanes: the object where the ray leaves it for good
    // (leaves_for_good_dot(): a flat shape always, else front ? d > 0 : d <
    // 0), else the lone-solid shortcut's bits where the offset allows.
    i4 onlyL = i4_of(0);
    if (s.aloneMask & self)
      onlyL =
          (off <= f4_of(0.5f * kAloneSlack * sh.size)) & i4_of((i32)((u32)(id + 1) << kOnlyShift));
    i4 flatL = i4_of(-(i32)flat);
    i4 skR = flatL | (front ? dR > zero : dR < zero) ? i4_of((i32)self) : onlyL;
    waiting = (castRL & i4_of(1 << (2 * depth + 3))) | (castTL & i4_of(1 << (2 * depth + 2)));
    ctx.stats.secondary +=
        (0x4332322132212110ull >> 4 * castR & 15) + (0x4332322132212110ull >> 4 * castT & 15);
    if (castR) {
      PendingRows rayR(p + N * offR, R, W * fR, skR);
#pragma GCC unroll 4
      for (int k = 0; k < 4; ++k)
        rayR.put(k, out[k]->child[1], pastGlass);
    }
    if (castT) {
      i4 skT = flatL | (front ? dT > zero : dT < zero) ? i4_of((i32)self) : onlyL;
      PendingRows rayT(p + N * offT, T, W * transmit, skT);
#pragma GCC unroll 4
      for (int k = 0; k < 4; ++k)
        rayT.put(k, out[k]->child[0], true);
    }
  }

  alignas(16) u32 bits[4] = {0, 0, 0, 0};
  f4 diffuse = f4_of(mt.diffuse), specular = f4_of(mt.specular);
  f4 shininess = f4_of(mt.shininess);
  V4 mc = splat(mt.color);
  for (int li = 0; li < s.numLights; ++li) {
    const Light& light = s.lights[li];
    alignas(16) float dist[4];
    V4 L, term;
    f4 spec;
    u32 lit = light_term4(s, light, lightOrg, N, D, live, mc, diffuse, specular, shininess,
                          f4_of(mt.roughness), f4_of(mt.f0), dist, L, spec, term);
    if (!lit) continue;
    // The shadow ray where the record needs it or the term can move the
    // pixel by kShadowSkip (max_abs(lit) = max(|x|, max(|y|, |z|))).
    f4 big = max4(lane_abs(term.x), max4(lane_abs(term.y), lane_abs(term.z)));
    u32 cast = lit & lane_bits(recordable | (W * big >= f4_of(kShadowSkip)));
    u32 shadowed = 0;
    V4 through = term; // term * transmittance: term where no ray meets a bound (term * 1)
    if (cast) {
      V4 tv = {one, one, one};
      alignas(16) u32 objects[4];
      *(i4*)objects = shadow_mask4(s, li, L.x, L.y, L.z, *(f4*)dist, range);
      u32 cand = ~lane_bits(*(i4*)objects == i4_of(0)) & cast;
      ctx.stats.shadow += 0x4332322132212110ull >> 4 * cast & 15;
      // A lane inside the solid whose ray to a light outside its bound meets
      // no other bound (scene 1's glass spheres at every bench frame):
      // shadow_test() crosses the solid untested, so its transmittance is
      // v3(1) * (colour * transmit), colour * transmit bit for bit, code 1
      // (3 for an opaque solid: no light).
      bool exitsLight = s.lightC[li][id] > 0;
      if (exitsLight && inside) {
        u32 alone = lane_bits(*(i4*)objects == i4_of((i32)self)) & cand & inside;
        if (alone) {
          i4 in = lanes_of(alone);
          V4 ct = mt.transmit <= 0 ? V4{zero, zero, zero} : splat(mt.color) * f4_of(mt.transmit);
          tv = select(in, ct, tv);
          u32 code = mt.transmit <= 0 ? 3 : 1;
          if (code == 3) shadowed |= alone;
          *(i4*)bits |= in & i4_of((i32)(code << (5 + 3 * li)));
          cand &= ~alone;
        }
      }
      if (cand) {
        auto exiting = [&](int j) { return j == id && exitsLight ? inside : 0u; };
        cand = one_solid_shadows4(s, li, cand, objects, exiting, lightOrg, L, dist, tv, shadowed,
                                  bits);
      }
      if (cand) {
        auto exits = [&](int k) { return (inside >> k & 1) && exitsLight ? self : 0u; };
        shadow_objects4(s, li, cand, lightOrg, L, dist, objects, exits, tv, shadowed, bits);
      }
      through = term * tv;
    }
    i4 add = lanes_of(lit & ~shadowed);
    col = select(add, col + through, col);
    *(i4*)bits |= add & (spec * max_abs(light.color) > f4_of(kHighlightEdge)) &
                  i4_of((i32)(4u << (5 + 3 * li)));
  }
  // Each lane's node in two stores: `records` (a word: the bool and its
  // padding) and the colour as one row, the record node and the waiting
  // bits as one pair of words.
  static_assert(__builtin_offsetof(PreNode, color) == __builtin_offsetof(PreNode, records) + 4 &&
                    __builtin_offsetof(PreNode, waiting) == __builtin_offsetof(PreNode, node) + 4,
                "PreNode's colour follows its records flag, its waiting bits its node");
  f4 rc[4];
  rows((f4)(lanes_of(records) & i4_of(1)), col.x, col.y, col.z, rc);
  i4 node = i4_of(id + 1) | *(i4*)bits;
  f4 nw[2] = {__builtin_ia32_unpcklps((f4)node, (f4)waiting),
              __builtin_ia32_unpckhps((f4)node, (f4)waiting)};
#pragma GCC unroll 4
  for (int k = 0; k < 4; ++k) {
    char* pre = (char*)out[k];
    __builtin_memcpy(pre + __builtin_offsetof(PreNode, records), &rc[k], 16);
    __builtin_memcpy(pre + __builtin_offsetof(PreNode, node),
                     (const char*)&nw[k >> 1] + 8 * (k & 1), 8);
  }
  return true;
}

// The lone-solid test of a cylinder or cone for the waiting rays *src[k]
// of the lanes `have` (tMin 0, from hit.t = kHuge): hit_frustum() in lanes
// (frustum_lanes4(), packet/frustum.h), the lanes it does not mirror through
// intersect_t(). True, with each lane's t, piece and local in dst[k]->hit,
// where every lane's ray hits it. All four lanes' pointers are read (second4()).
bool frustum_hits4(const Shape& sh, const Pending* const src[4], PreNode* const dst[4], u32 have) {
  f4 a[4], b[4];
  rows(load4(&src[0]->ray.org.x), load4(&src[1]->ray.org.x), load4(&src[2]->ray.org.x),
       load4(&src[3]->ray.org.x), a);
  rows(load4(&src[0]->ray.dir.y), load4(&src[1]->ray.dir.y), load4(&src[2]->ray.dir.y),
       load4(&src[3]->ray.dir.y), b);
  f4 org[3] = {a[0], a[1], a[2]}, dir[3] = {a[3], b[0], b[1]};
  FrustumTerms4 terms;
  frustum_terms4(sh, org, terms);
  f4 t = f4_of(kHuge), local = f4_of(0.0f);
  i4 piece = i4_of(0);
  FrustumLanes fl = frustum_lanes4(sh, terms, dir, have, t, piece, local);
  if ((fl.hit | fl.rest) != have) return false;
#pragma GCC unroll 4
  for (int k = 0; k < 4; ++k)
    if (fl.hit >> k & 1) {
      Hit& hit = dst[k]->hit;
      hit.t = t[k];
      hit.piece = (u8)piece[k];
      hit.local = local[k];
    }
  for (u32 q = fl.rest; q; q &= q - 1) {
    int k = __builtin_ctz(q);
    Hit& hit = dst[k]->hit;
    hit.t = kHuge;
    if (!intersect_t(sh, src[k]->ray, 0.0f, hit)) return false;
  }
  return true;
}

// The refracted children (depth 2) of the lanes `have`, each into the lone
// solid `id` (the lone-solid shortcut's bits): each one's hit by the tree's
// own first step (that solid's intersect_t()), and where every lane's finds
// it, the nodes shaded in lanes (shade_child4()) into root[k].pre[0]; then
// likewise their reflected children, inside the same solid, into pre[1]
// (root[k].deep). Returns the lanes shaded (0 or `have`);
// trace_children4() takes them up in the tree's order.
__attribute__((noinline)) u32 second4(TraceContext& ctx, RootNode root[4], u32 have, int id,
                                      int maxDepth) {
  const Shape& sh = ctx.scene->objects[id].shape;
  const Pending* src[4];
  PreNode* dst[4];
  const u32 only = (u32)(id + 1) << kOnlyShift;
  bool sphere = sh.kind == kSphere;
  // Lane k's root: its own where it is in `have`, else the first lane's
  // (shade_child4() and frustum_hits4() read all four pointers); the four
  // lanes unrolled. The lanes outside `have` repeat a test of `have`'s;
  // root[k].deep and .exit are read only for the lanes returned, so all
  // four are written.
  int first = __builtin_ctz(have), at[4];
#pragma GCC unroll 4
  for (int k = 0; k < 4; ++k)
    at[k] = have >> k & 1 ? k : first;
#pragma GCC unroll 4
  for (int k = 0; k < 4; ++k) {
    if (root[at[k]].child[0].skip != only) return 0;
    src[k] = &root[at[k]].child[0];
    dst[k] = &root[at[k]].pre[0];
    root[k].deep = false;
    root[k].exit = 0;
  }
  if (sphere) {
    if (!shade_child4<2, true>(ctx, src, dst, have, true, id, maxDepth)) return 0;
  } else {
    if (!frustum_hits4(sh, src, dst, have)) return 0; // the tree searches again
    shade_child4<2, false>(ctx, src, dst, have, true, id, maxDepth);
  }
  // The reflected children inside the solid (depth 3), where every lane has
  // one that the lone-solid test finds.
  const u32 reflected = 1u << (2 * 2 + 3);
#pragma GCC unroll 4
  for (int k = 0; k < 4; ++k) {
    PreNode& pre = root[at[k]].pre[0];
    if (!(pre.waiting & reflected) || pre.child[1].skip != only) return have;
    src[k] = &pre.child[1];
    dst[k] = &root[at[k]].pre[1];
  }
  if (sphere) {
    if (!shade_child4<3, true>(ctx, src, dst, have, true, id, maxDepth)) return have;
  } else {
    if (!frustum_hits4(sh, src, dst, have)) return have;
    shade_child4<3, false>(ctx, src, dst, have, true, id, maxDepth);
  }
#pragma GCC unroll 4
  for (int k = 0; k < 4; ++k)
    root[k].deep = true;
  // The refracted children out of the solid (depth 3, after the reflected
  // ones: where every lane has one): found by find_hit(); the lanes that see
  // nothing become the tree's miss, the lanes that hit the first hitting
  // lane's object (at least two) are shaded in lanes, the others' hits are
  // handed to the tree.
  const Scene& s = *ctx.scene;
  const u32 refracted = 1u << (2 * 2 + 2);
#pragma GCC unroll 4
  for (int k = 0; k < 4; ++k) {
    if (!(root[at[k]].pre[0].waiting & refracted)) return have;
    src[k] = &root[at[k]].pre[0].child[0];
    dst[k] = &root[at[k]].pre[2];
  }
  alignas(16) i32 outId[4] = {-1, -1, -1, -1};
  for (u32 q = have; q; q &= q - 1) {
    int k = __builtin_ctz(q);
    const Pending& p = *src[k];
    outId[k] = dst[k]->id = find_hit(s, p.ray, p.skip, dst[k]->hit);
    root[k].exit = 1;
  }
  u32 miss = lane_bits(*(i4*)outId < i4_of(0)) & have;
  for (u32 q = miss; q; q &= q - 1) {
    // trace_tree's miss (depth 3, past glass): node 0, the background.
    int k = __builtin_ctz(q);
    PreNode& out = root[k].pre[2];
    float w = root[k].pre[0].child[0].weight;
    out.color = s.background;
    out.node = 0;
    out.records = w >= kRecordWeight || w >= kRecordWeightGlass;
    out.waiting = 0;
    root[k].exit = 2;
  }
  u32 hits = have & ~miss;
  if (!hits) return have;
  int out0 = outId[__builtin_ctz(hits)];
  u32 sub = lane_bits(*(i4*)outId == i4_of(out0)) & hits;
  if (sub & (sub - 1)) {
    bool ok = s.objects[out0].shape.kind == kSphere
                  ? shade_child4<3, true>(ctx, src, dst, sub, true, out0, maxDepth)
                  : shade_child4<3, false>(ctx, src, dst, sub, true, out0, maxDepth);
    if (ok)
      for (u32 q = sub; q; q &= q - 1)
        root[__builtin_ctz(q)].exit = 2;
  }
  return have;
}

} // namespace

void shade_primary4(TraceContext& ctx, Vec3 org, const f4 dir[3], const Hits4& h, u32 lanes,
                    PathRecord* paths, Vec3 color[4]) {
  const Scene& s = *ctx.scene;
  alignas(16) i32 id[4];
  *(i4*)id = h.id;
  // Each lane's Hit where the scalar hit_normal() needs one (a sphere's band
  // lanes, mixed packets); the one-object normals take t and piece in lanes.
  Hit hit[4];
  V4 D = {dir[0], dir[1], dir[2]};
  int first = __builtin_ctz(lanes);
  const Object* obj[4];       // mixed packets: each lane's object
  alignas(16) i32 frontOf[4]; // mixed packets: each lane's front
  alignas(16) u32 range[4];
  u32 inside = 0;
  u32 foreground = s.numForeground >= 32 ? ~0u : (1u << s.numForeground) - 1;
  V4 mc, N;
  f4 T4, size, diffuse, specular, shininess, reflect, transmit, ior, roughness, f0;
  i4 front;
  const Object& o0 = s.objects[id[first]];
  i4 ids = h.id; // lanes outside `lanes` do not count
  i4 held = lanes_of(lanes);
  ShapeKind kind0 = o0.shape.kind;
  bool uniform = (lane_bits(ids == i4_of(id[first])) & lanes) == lanes;
  if (uniform) {
    // Every lane sees one object (most calls): the material in every lane,
    // and hit_normal() (shapes.cpp) in lanes: sphere_outward() where |m|^2
    // lies in [r^2 / 4, 4 r^2], frustum_outward() where rho^2 <= 1e20, then
    // face(); plane_normal(). The other lanes (a sphere's band, a frustum's
    // point beyond the domain) through the scalar hit_normal().
    const Material& mt = o0.mat;
    mc = splat(mt.color);
    diffuse = f4_of(mt.diffuse);
    specular = f4_of(mt.specular);
    shininess = f4_of(mt.shininess);
    reflect = f4_of(mt.reflect);
    transmit = f4_of(mt.transmit);
    ior = f4_of(mt.ior);
    roughness = f4_of(mt.roughness);
    f0 = f4_of(mt.f0);
    size = f4_of(o0.shape.size);
    // The lanes outside `lanes` repeat the first lane's hit.
    T4 = held ? h.t : f4_of(h.t[first]);
    i4 piece = held ? h.piece : i4_of(h.piece[first]);
    const Shape& sh = o0.shape;
    V4 A = splat(sh.a);
    u32 self = 1u << id[first];
    if (kind0 == kPlane) {
      front = piece != i4_of(0);
      N = select(front, A, V4{-A.x, -A.y, -A.z});
    } else if (kind0 == kTriangle) {
      V4 out = splat(Vec3{sh.r0, sh.r1, sh.h}); // normalize(n), stored
      front = dot(out, D) < f4_of(0.0f);
      N = select(front, out, V4{-out.x, -out.y, -out.z});
    } else {
      V4 out;
      u32 ok;
      if (kind0 == kSphere) {
        V4 m = (splat(org) - A) + D * T4;
        f4 len2 = dot(m, m), r2 = f4_of(sh.r0 * sh.r0);
        ok = lane_bits((len2 >= 0.25f * r2) & (len2 <= 4.0f * r2));
        out = m * (1.0f / lane_sqrt(len2));
      } else {
        // A cylinder's or cone's side: the axial part of q = org - a + t dir
        // taken out, the slope's c.x times rho back along the axis; the caps:
        // +-axis.
        V4 axis = splat(sh.b);
        V4 q = (splat(org) - A) + D * T4;
        V4 pPerp = q - axis * dot(q, axis);
        f4 rho2 = dot(pPerp, pPerp);
        ok = lane_bits(rho2 <= f4_of(1e20f));
        V4 a = pPerp - axis * (f4_of(sh.c.x) * lane_sqrt(rho2));
        f4 len2 = dot(a, a);
        V4 side = select(len2 > f4_of(1e-30f), a * (1.0f / lane_sqrt(len2)), axis); // normalize
        V4 cap = select(piece == i4_of(kFrustumTop), axis, V4{-axis.x, -axis.y, -axis.z});
        out = select(piece == i4_of(kFrustumSide), side, cap);
        ok |= lane_bits(piece != i4_of(kFrustumSide));
      }
      front = dot(out, D) < f4_of(0.0f);
      N = select(front, out, V4{-out.x, -out.y, -out.z});
      for (u32 q = lanes & ~ok; q; q &= q - 1) {
        int k = __builtin_ctz(q);
        hit[k].t = h.t[k];
        hit[k].piece = (u8)h.piece[k];
        hit[k].local = h.local[k];
        hit_normal(sh, Ray{org, Vec3{D.x[k], D.y[k], D.z[k]}}, hit[k]);
        N.x[k] = hit[k].normal.x;
        N.y[k] = hit[k].normal.y;
        N.z[k] = hit[k].normal.z;
        front[k] = -(i32)hit[k].front;
      }
    }
    bool flat = kind0 == kPlane || kind0 == kTriangle;
    *(i4*)range =
        front | i4_of(-(i32)flat) ? i4_of((i32)(foreground & ~self)) : i4_of((i32)foreground);
    inside = closed_convex(sh) ? ~lane_bits(front) & 15 : 0;
  } else {
    RayRow rr[4];
    ray_rows(splat(org), D, rr);
    for (u32 q = lanes; q; q &= q - 1) {
      int k = __builtin_ctz(q);
      hit[k].t = h.t[k];
      hit[k].piece = (u8)h.piece[k];
      hit[k].local = h.local[k];
      hit_normal(s.objects[id[k]].shape, rr[k].ray, hit[k]);
    }
    // Each lane's object, material and hit as columns (the lanes outside
    // `lanes` repeat the first lane's, so that every lane computes with
    // finite numbers).
    const float *rowC[4], *rowS[4], *rowI[4], *rowH[4];
    for (int k = 0; k < 4; ++k) {
      int src = lanes >> k & 1 ? k : first;
      const Object* o = obj[k] = &s.objects[id[src]];
      rowC[k] = &o->mat.color.x;  // color, diffuse
      rowS[k] = &o->mat.specular; // specular, shininess, reflect, transmit
      rowI[k] = &o->mat.transmit; // transmit, ior, roughness, f0
      rowH[k] = &hit[src].t;      // t, normal
      size[k] = o->shape.size;
      frontOf[k] = -(i32)hit[src].front;
      // What the shadow rays test (trace_tree's shadowRange and `inside`).
      const Shape& sh = o->shape;
      bool flat = sh.kind == kPlane || sh.kind == kTriangle;
      range[k] = flat || hit[src].front ? foreground & ~(1u << id[src]) : foreground;
      inside |= (u32)(!hit[src].front && closed_convex(sh)) << k;
    }
    f4 c[4], sp[4], gl[4], hc[4];
    columns(rowC, c);
    columns(rowS, sp);
    columns(rowI, gl);
    columns(rowH, hc);
    mc = V4{c[0], c[1], c[2]};
    N = V4{hc[1], hc[2], hc[3]};
    T4 = hc[0];
    diffuse = c[3];
    specular = sp[0];
    shininess = sp[1];
    reflect = sp[2];
    transmit = sp[3];
    ior = gl[1];
    roughness = gl[2];
    f0 = gl[3];
    front = *(i4*)frontOf;
  }
  f4 zero = f4_of(0.0f), one = f4_of(1.0f);
  i4 live = held;
  V4 p = splat(org) + D * T4;
  V4 col = splat(s.ambient) * mc;
  f4 ax = lane_abs(p.x), ay = lane_abs(p.y), az = lane_abs(p.z);
  f4 off = kSpawnPos * max4(ax, max4(ay, az)) + kSpawnRel * (size + T4); // spawn_offset
  V4 lightOrg = p + N * off;

  RootNode root[4];
  i4 waiting = i4_of(0);
  u32 castT = 0; // the lanes with a refracted child
  int maxDepth = s.maxDepth < kMaxTraceDepth ? s.maxDepth : kMaxTraceDepth;
  if (1 < maxDepth) {
    // Snell where the material transmits; the mirror ray everywhere.
    i4 glass = transmit > zero;
    f4 eta = one, cosI = one, sin2T = zero; // the lanes that do not transmit
    i4 tir = i4_of(0);
    if (lane_bits(glass)) {
      eta = glass ? (front ? 1.0f / ior : ior) : one;
      V4 negD = {-D.x, -D.y, -D.z};
      cosI = glass ? dot(N, negD) : one;
      sin2T = glass ? eta * eta * (1.0f - cosI * cosI) : zero;
      tir = glass & (sin2T > one);
    }
    f4 dT = zero, fR = reflect + (tir ? transmit : zero);
    i4 castRL = (fR > zero) & (one * fR >= f4_of(kMinRayWeight)) & live;
    i4 castTL = glass & ~tir & (one * transmit >= f4_of(kMinRayWeight)) & live;
    u32 castR = lane_bits(castRL);
    castT = lane_bits(castTL);
    V4 R = D - N * (2.0f * dot(N, D)); // reflect(): I - N (2 N.I)
    f4 dR = dot(R, N);
    V4 oR = p + N * (dR >= zero ? off : -off), T = D, oT = p;
    if (castT) {
      V4 a = D * eta + N * (eta * cosI - lane_sqrt(1.0f - sin2T));
      f4 len2 = dot(a, a);
      T = select(len2 > f4_of(1e-30f), a * (1.0f / lane_sqrt(len2)), D); // normalize(a, dir)
      dT = dot(T, N);
      oT = p + N * (dT >= zero ? off : -off);
    }
    alignas(16) u32 skR[4] = {0, 0, 0, 0}, skT[4] = {0, 0, 0, 0};
    if (uniform) {
      // One object in every lane: the skip bits (leaves_for_good_dot(),
      // else the lone-solid shortcut's bits where the offset allows), the
      // waiting bits and the ray count in lanes, as shade_child4() takes them.
      const Shape& sh = o0.shape;
      int j = id[first];
      u32 self = 1u << j;
      i4 onlyL = i4_of(0);
      if (s.aloneMask & self)
        onlyL =
            (off <= f4_of(0.5f * kAloneSlack * sh.size)) & i4_of((i32)((u32)(j + 1) << kOnlyShift));
      i4 flatL = i4_of(-(i32)(kind0 == kPlane || kind0 == kTriangle));
      *(i4*)skR = flatL | (front ? dR > zero : dR < zero) ? i4_of((i32)self) : onlyL;
      *(i4*)skT = flatL | (front ? dT > zero : dT < zero) ? i4_of((i32)self) : onlyL;
      waiting = (castRL & i4_of(1 << (kRootSlot + 1))) | (castTL & i4_of(1 << kRootSlot));
      ctx.stats.secondary +=
          (0x4332322132212110ull >> 4 * castR & 15) + (0x4332322132212110ull >> 4 * castT & 15);
    } else {
      // Mixed packets: per lane.
      for (u32 q = castR | castT; q; q &= q - 1) {
        int k = __builtin_ctz(q);
        const Shape& sh = obj[k]->shape;
        u32 self = 1u << id[k];
        u32 only = (s.aloneMask & self) && off[k] <= 0.5f * kAloneSlack * sh.size
                       ? (u32)(id[k] + 1) << kOnlyShift
                       : 0;
        if (castR >> k & 1) {
          skR[k] = leaves(sh, frontOf[k], dR[k]) ? self : only;
          waiting[k] |= 1u << (kRootSlot + 1);
          ++ctx.stats.secondary;
        }
        if (castT >> k & 1) {
          skT[k] = leaves(sh, frontOf[k], dT[k]) ? self : only;
          waiting[k] |= 1u << kRootSlot;
          ++ctx.stats.secondary;
        }
      }
    }
    // Every lane's rays stored (root[] is this call's: a lane's child is
    // read only where its waiting bit is set).
    PendingRows rayR(oR, R, one * fR, *(i4*)skR);
#pragma GCC unroll 4
    for (int k = 0; k < 4; ++k)
      rayR.put(k, root[k].child[1], false);
    if (castT) {
      PendingRows rayT(oT, T, one * transmit, *(i4*)skT);
#pragma GCC unroll 4
      for (int k = 0; k < 4; ++k)
        rayT.put(k, root[k].child[0], true);
    }
  }

  // The lights: the terms and the shadow rays' bound tests in lanes; the
  // object tests of a lane's shadow ray where a bound is met through the
  // scalar shadow_objects() (a primary ray records: every lit term casts a
  // shadow ray).
  alignas(16) u32 bits[4] = {0, 0, 0, 0};
  for (int li = 0; li < s.numLights; ++li) {
    const Light& light = s.lights[li];
    // The light's term unshadowed (trace_tree's `lit`).
    alignas(16) float dist[4];
    V4 L, term;
    f4 spec;
    u32 lit = light_term4(s, light, lightOrg, N, D, live, mc, diffuse, specular, shininess,
                          roughness, f0, dist, L, spec, term);
    if (!lit) continue;
    // Each lane's shadow_mask() (trace.h), four lanes a bound.
    alignas(16) u32 objects[4];
    *(i4*)objects = shadow_mask4(s, li, L.x, L.y, L.z, *(f4*)dist, *(i4*)range);
    u32 cand = ~lane_bits(*(i4*)objects == i4_of(0)) & lit;
    u32 shadowed = 0;
    ctx.stats.shadow += 0x4332322132212110ull >> 4 * lit & 15; // lit's bits, counted
    // term * transmittance; where no lane's ray meets a bound, term (term * 1, the same bits).
    V4 through = term;
    if (cand) {
      V4 tv = {one, one, one};
      auto exiting = [&](int j) {
        return s.lightC[li][j] > 0 ? inside & lane_bits(ids == i4_of(j)) : 0u;
      };
      cand =
          one_solid_shadows4(s, li, cand, objects, exiting, lightOrg, L, dist, tv, shadowed, bits);
      if (cand) {
        // The lanes whose ray meets a bound; the others are lit: code 0, through 1.
        auto exits = [&](int k) {
          return (inside >> k & 1) && s.lightC[li][id[k]] > 0 ? 1u << id[k] : 0u;
        };
        shadow_objects4(s, li, cand, lightOrg, L, dist, objects, exits, tv, shadowed, bits);
      }
      through = term * tv;
    }
    i4 add = lanes_of(lit & ~shadowed);
    col = select(add, col + through, col);
    if (paths)
      *(i4*)bits |= add & (spec * max_abs(light.color) > f4_of(kHighlightEdge)) &
                    i4_of((i32)(4u << (5 + 3 * li)));
  }
  // Each lane's waiting bits and sum (v3(0) + colour * 1, trace_tree's sum
  // += color * weight) as one row, RootNode's `waiting` then `sum`: every
  // lane stored (root[] is this call's).
  static_assert(__builtin_offsetof(RootNode, sum) == __builtin_offsetof(RootNode, waiting) + 4,
                "RootNode's sum follows its waiting bits");
  V4 sum = V4{zero, zero, zero} + col * one;
  f4 ws[4];
  rows((f4)waiting, sum.x, sum.y, sum.z, ws);
#pragma GCC unroll 4
  for (int k = 0; k < 4; ++k)
    __builtin_memcpy(&root[k].waiting, &ws[k], 16);
  if (paths) {
    // Each lane's record: count 1 (a word: the count and its padding) and
    // its first node, id + 1 and the bits, as one pair of words.
    static_assert(__builtin_offsetof(PathRecord, node) == 4, "PathRecord's nodes follow its count");
    i4 node = (h.id + 1) | *(i4*)bits;
    i4 cn[2] = {(i4)__builtin_ia32_unpcklps((f4)i4_of(1), (f4)node),
                (i4)__builtin_ia32_unpckhps((f4)i4_of(1), (f4)node)};
#pragma GCC unroll 4
    for (int k = 0; k < 4; ++k)
      __builtin_memcpy(&paths[k], (const char*)&cn[k >> 1] + 8 * (k & 1), 8);
  }
  // The second level: the refracted children into a lone solid (second4()).
  u32 shaded = 0;
  if (castT) {
    // The lanes with a refracted child whose primary ray hit the first such
    // lane's object, a lone solid (every lane of a uniform packet; two or
    // more of a mixed one).
    int j = id[__builtin_ctz(castT)];
    u32 grp = uniform ? castT : lane_bits(ids == i4_of(j)) & castT;
    if ((s.aloneMask >> j & 1) && (uniform || (grp & (grp - 1))))
      shaded = second4(ctx, root, grp, j, maxDepth);
  }
  trace_children4(ctx, root, lanes, shaded, paths, color);
}
