// trace.h - the Whitted ray tracer, shading, camera and the full-trace renderer.
#pragma once
#include "abi.h"
#include "packet/primary.h"
#include "scene.h"

// Counts of rays cast, for the bench's rays-per-pixel figures.
struct RayStats {
  u64 primary, secondary, shadow;
};

// What the adaptive renderer compares between a block's corners (thesis
// 5.5.1): one node per traced ray that matters to the picture, in depth-first
// order (primary, then its reflection subtree, then its refraction subtree).
// A ray is recorded when its depth is at most kRecordDepth (the thesis: level
// 2 behind a mirror, level 3 through glass) and its weight in the pixel (the
// product of reflect/transmit factors along its path) is at least
// kRecordWeight: an edge seen with weight w can put at most w of the
// contrast into an interpolated block, so faint reflections need not split.
// A node packs the object hit (index + 1; 0 = nothing) in bits 0..4 and, per
// light i, 3 bits from bit 5 + 3i: a 2-bit shadow code (0 lit, 1 behind one
// transparent object, 2 behind several, 3 blocked; a surface facing away
// from the light counts as lit, its diffuse term being 0 there) and a
// highlight bit (the specular term exceeds kHighlightEdge), so blocks across
// a highlight's rim are split too, which the thesis's test missed.
constexpr int kRecordDepth = 3;
constexpr float kRecordWeight = 0.25f;
// A ray that has passed through a transparent surface (a refracted ray or
// any ray under one) is recorded at any depth while its weight is at least
// kRecordWeightGlass: what glass shows is a small image of what lies behind
// and around it, and its edges lie deeper than kRecordDepth (scene 1's
// floor reflection seen through the small sphere is a depth-4 ray of weight
// 0.43), so blocks across them now split by records rather than by the
// adaptive renderer's glass contrast rule (docs/speed-vs-error.md, "Round
// nine: what glass shows, recorded"). Records only: a ray's shadow rays
// are cast as before (kShadowSkip below), so the full trace is unchanged.
constexpr float kRecordWeightGlass = 0.2f;
constexpr float kHighlightEdge = 1.0f / 32;
constexpr int kMaxPathNodes = 7; // a full binary tree of depth 3
struct PathRecord {
  u8 count;
  u32 node[kMaxPathNodes];
};
RT64K_HOT_ABI bool same_path(const PathRecord& a, const PathRecord& b);

struct TraceContext {
  const Scene* scene;
  RayStats stats;
  PathRecord* record; // may be null: nothing recorded
};

// Colour seen along `ray` (unit direction). depth is 1 for a primary ray;
// weight is the ray's share of the pixel (1 for a primary ray). Secondary
// rays whose weight falls below kMinRayWeight are not cast: for radiance up
// to 1 their share of a pixel is under 4/255 (1/128 until issue 9; 1/64
// costs a min PSNR of 52.4 dB against it over the 256 bench frames, max
// error 38/255 where a cut ray would have seen a highlight above 1, and
// saves 6 % of a scene-1 and 11-13 % of a scene-2 full frame). A light's
// term at a hit of a ray that records would leave out (deeper than
// kRecordDepth or lighter than kRecordWeight) gets no shadow ray when it can
// move the pixel by less than kShadowSkip (weight times its largest channel
// unshadowed): it counts as lit. These are choices of the
// tracer (full and adaptive renderers trace alike), not adaptive-renderer
// errors (docs/speed-vs-error.md). Under total internal reflection the
// refracted ray would be the mirror ray: one ray is cast with weight reflect
// + transmit (docs/tracer-speed.md, round five). The ray tree is traced
// without recursion (trace_hit, trace.cpp): the result is the sum of each
// node's shading times its weight relative to `weight`, which equals the
// recursion's colour up to the order of the float sums. depth >= 1; no ray
// deeper than the scene's maxDepth, nor than kMaxTraceDepth, is cast.
// The result is finite and non-negative in every channel. Objects whose bit
// (1 << index) is set in `skip` are not tested: a secondary ray skips the
// object it leaves when leaves_for_good() (shapes.h) says it cannot meet it again.
RT64K_HOT_ABI Vec3 trace(TraceContext& ctx, const Ray& ray, int depth, float weight = 1.0f,
                         u32 skip = 0);
constexpr float kMinRayWeight = 1.0f / 64;
// The deepest ray ever cast (a primary ray is depth 1): a Scene::maxDepth
// above it is taken as it. It sizes trace_hit's slots of waiting rays (two a
// depth), so that they need no bound check (docs/tracer-speed.md, round seven).
constexpr int kMaxTraceDepth = 8;
constexpr float kShadowSkip = 2.0f / 255;
// A specular term is taken as 0 without computing it where it is below
// e^-kSpecExp = 1.1e-7 of its peak: Phong's (V.R)^h when h (1 - V.R) >
// kSpecExp ((V.R)^h <= e^(-h (1 - V.R))), and Cook-Torrance where the
// Beckmann D's exponent -tan^2(a) / m^2 is below -kSpecExp: there D <
// (1 + 16 m^2)^2 e^-16 / (pi m^2), below 4e-6 for the scenes' m = 0.12 ..
// 0.35 (the term, at most 4 F D r_S, below 1.6e-5 of the light), below 1e-3
// for m in 0.01 .. 10. Full trace against computing every term, 256 frames:
// scene 1 identical, scene 2 min PSNR 91 dB. They save rt_pow's log2 and
// exp2, and Cook-Torrance's half vector, exp and four divisions, where most
// shading points are (docs/speed-vs-error.md).
constexpr float kSpecExp = 16.0f;

// trace() is its nearest-hit search (first_hit()) followed by trace_hit():
// with `id` and `hit` (t, piece, local) as first_hit() gave them for `ray`,
// it records the ray, shades the hit and casts the secondary rays, exactly
// as trace() would. The scalar primary tracer (scalar/primary.cpp) and the
// tests shade through here; the packet tracer (packet/packet.h) finds first
// hits its own way, shades them four at once (packet/shade.h) and traces
// each lane's secondary rays through trace_children4() below.
RT64K_HOT_ABI Vec3 trace_hit(TraceContext& ctx, const Ray& ray, int id, Hit& hit, int depth,
                             float weight);
// A secondary ray waiting for its turn (trace.cpp's trace_tree): where it
// starts, its weight and the objects it skips; its depth is its slot's (the
// slots of depth d: 2 d + 1 for the reflected ray, 2 d for the refracted).
struct Pending {
  Ray ray;
  float weight;
  u32 skip;
  bool pastGlass; // it or a ray above it was refracted (kRecordWeightGlass)
};
// A waiting ray's skip holds, from this bit, the index + 1 of the one object
// the lone-solid shortcut tests first (0: none); the bits below are the
// skipped objects (kMaxObjects = 8 of them).
constexpr int kOnlyShift = 16;
// The slots of a primary ray's children (depth 2): kRootSlot the refracted
// ray, kRootSlot + 1 the reflected one.
constexpr int kRootSlot = 4;
// A node of a primary ray's tree at depth 2 or 3 whose hit, and maybe its
// whole node, the packet tracer found ahead of the tree (packet/shade.h,
// "the second level"): `id` and `hit` as trace_tree's nearest-hit step
// gives them for its ray (find_hit()); when shaded, also the node's own
// colour (ambient plus the light terms, not yet times its weight; the
// background for a miss), its PathRecord node (id + 1 and the light bits,
// highlight bits as if recorded), whether it records, and its children
// (child[0] in the next depth's refracted slot, child[1] in its reflected
// one, each valid where its slot's bit is set in `waiting`). Its rays were
// counted when it was shaded.
struct PreNode {
  Pending child[2];
  Hit hit;
  int id;
  u32 node;
  u32 waiting;
  bool records;
  Vec3 color;
};
// A primary ray's node (depth 1, weight 1) shaded by the caller, exactly as
// trace_hit() would have: its children (child[0] in slot kRootSlot, child[1]
// in kRootSlot + 1, each valid where its bit 1 << slot is set in `waiting`)
// and the root's share of the sum, v3(0) + colour * 1 (packet/shade.h).
// Where the refracted child (slot kRootSlot) was shaded ahead, pre[0]
// holds it (trace_children4's `shaded` lanes); where `deep` is set, pre[1]
// holds that child's reflected child (depth 3, its slot 7), shaded too, and
// where `exit` is 1 or 2, pre[2] its refracted child (slot 6), found or
// shaded (only where `deep` is set).
struct RootNode {
  Pending child[2];
  u32 waiting;
  Vec3 sum;
  bool deep;
  u8 exit; // pre[2]: the shaded child's refracted child (its slot 6): 1 found, 2 shaded
  PreNode pre[3];
};
// A part of a primary ray's tree for trace.cpp's resume (trace_children4):
// waiting rays of one depth, kids[0] in the refracted ray's slot and kids[1]
// in the reflected's (each where its bit is set in `waiting`), traced with
// their subtrees after the sum so far, `sum`; `all`, `foreground` and
// `maxDepth` the scene's object masks and depth limit as trace_tree computes
// them, once a packet (trace_children4).
struct TreePart {
  const Pending* kids;
  u32 waiting;
  f4 sum; // x, y, z (lane 3 unused): trace_tree's sum is kept in lanes
  u32 all, foreground;
  int maxDepth;
};
// trace_hit() of four primary rays from after their root nodes: for each
// lane k of `lanes` (bits), in order, the children's subtrees of root[k]
// traced (appending their nodes to paths[k] when paths is set, which holds
// the root's node already) and added to root[k].sum in trace_hit's order;
// color[k] the pixel's colour, bit for bit trace_hit's.
// The lanes of `shaded` have their refracted child shaded ahead, in
// root[k].pre[0] (packet/shade.h).
RT64K_HOT_ABI void trace_children4(TraceContext& ctx, const RootNode root[4], u32 lanes, u32 shaded,
                                   PathRecord* paths, Vec3 color[4]);
// trace_tree's kFindHit step for one waiting ray with its skip (object
// bits, and from kOnlyShift the lone solid to test first): hit.t = kHuge,
// that solid's intersect_t() where one is named, else (or where it finds
// nothing) nearest() over the scene's objects less the skipped ones. Returns
// the object (-1: none) with hit's t, piece and local (the second level's
// exit rays, packet/shade.cpp).
int find_hit(const Scene& s, const Ray& ray, u32 skip, Hit& hit);
// Bit i set: a shadow ray from p = light - dist L along L (unit) to light l
// may meet object i (of those in `range`) before the light, judged by its
// bound (conservative, as bound_mask). The segment is taken from the light's
// end, whose terms the scene holds (Scene::lightFX..): along -L from the
// light, beta = f.L is minus bound_mask's b; a miss when the line passes
// beside (beta^2 < c), or the light is outside the bound (c > 0) and the
// segment points away from it (beta < 0) or ends before it (beta - R >= dist).
// Both groups, unrolled, as in trace.cpp's bound_mask. Inline: trace.cpp's
// shadow rays hold a copy; the packet tracer's shading point takes four rays
// a bound with the same operations (shadow_mask4(), packet/shade.h), which
// tests/test_shade4.cpp checks against this one.
__attribute__((always_inline)) inline u32 shadow_mask(const Scene& s, int l, Vec3 L, float dist,
                                                      u32 range) {
  typedef float v4 __attribute__((vector_size(16)));
  u32 missed = 0; // bit i: bound i surely missed
  v4 lx = {L.x, L.x, L.x, L.x}, ly = {L.y, L.y, L.y, L.y}, lz = {L.z, L.z, L.z, L.z};
  v4 tm = {dist, dist, dist, dist}, zero = {0, 0, 0, 0};
#pragma GCC unroll 2
  for (int g = 0; g < kMaxObjects; g += 4) {
    v4 beta = *(const v4*)(s.lightFX[l] + g) * lx + *(const v4*)(s.lightFY[l] + g) * ly +
              *(const v4*)(s.lightFZ[l] + g) * lz;
    v4 c = *(const v4*)(s.lightC[l] + g);
    auto miss = (beta * beta < c) |
                ((c > zero) & ((beta < zero) | (beta - *(const v4*)(s.boundR + g) >= tm)));
    missed |= (u32)__builtin_ia32_movmskps((v4)miss) << g;
  }
  // As bound_mask's (trace.cpp): range holds object bits only.
  return (s.unboundedMask | ~missed) & range;
}

// The end of trace_hit's shadow ray from ray.org along unit ray.dir to a
// light at distance `dist`, after its bound test (trace.cpp's shadow_mask)
// left the objects of `mask`: its transmittance and shadow code (0 lit, 1
// behind one transparent object, 2 behind several, 3 blocked), crossing the
// objects of `exits` untested (the ray starts inside them). The caller
// counts the ray.
RT64K_HOT_ABI Vec3 shadow_objects(const Scene& s, const Ray& ray, float dist, u32 mask, int& code,
                                  u32 exits);

// trace_hit() of a ray that hits nothing (id < 0), inline: its node (0) in
// the record and the background, without trace_hit's frame set-up (~20
// instructions a miss).
inline Vec3 trace_miss(TraceContext& ctx, int depth, float weight) {
  PathRecord* rec = ctx.record;
  if (rec && depth <= kRecordDepth && weight >= kRecordWeight && rec->count < kMaxPathNodes)
    rec->node[rec->count++] = 0;
  return ctx.scene->background;
}

// Index of the object a ray sees first (foreground before background, as
// trace() does), or -1 when it sees nothing. first_hit() also returns the
// hit's t, piece and local (hit.normal and hit.front are left unset).
int first_hit_object(const Scene& scene, const Ray& ray);
int first_hit(const Scene& scene, const Ray& ray, Hit& hit);

// The nearest hit among the objects whose bit is set in `candidates` (what
// a bound test left): foreground objects first; background objects only
// when no foreground object was hit (the background contract in scene.h).
// hit.t is reset to kHuge first; returns the object index or -1, with hit's
// t, piece and local (first_hit() and the packet tracer's scalar path).
// `foreground` is the mask of objects [0, numForeground), which a caller
// that searches many rays (trace_tree) computes once.
// Pairs: a triangle pair (kPairNext, shapes.h) whose halves are both
// candidates is tested by one intersect_pair() call, and a plane flagged
// kInlinePlane by plane_t() without a call (the same answers, the same
// bits); only the resumed tree (the native tool's) takes them: the exe's
// copy stays without them (its bytes; docs/tracer-speed.md, round
// thirteen, second wave).
template <bool Pairs = false>
inline int nearest_among(const Scene& s, const Ray& ray, u32 candidates, Hit& hit, u32 foreground) {
  hit.t = kHuge;
  int found = -1;
  for (u32 m = candidates & foreground; m; m &= m - 1) {
    int i = __builtin_ctz(m);
    if (intersect_t(s.objects[i].shape, ray, 0.0f, hit)) found = i;
  }
  if (found >= 0) return found;
  for (u32 m = candidates & ~foreground; m; m &= m - 1) {
    int i = __builtin_ctz(m);
    const Shape& sh = s.objects[i].shape;
    if (Pairs && (sh.caps & kPairNext) && (m >> (i + 1) & 1)) { // both halves of a pair
      int r = intersect_pair(sh, s.objects[i + 1].shape, ray, 0.0f, hit);
      if (r) found = i + r - 1;
      m &= ~(2u << i);
    } else if (Pairs && (sh.caps & kInlinePlane)) { // the floor without a call (shapes.h)
      if (plane_t(sh, ray, hit)) found = i;
    } else if (intersect_t(sh, ray, 0.0f, hit))
      found = i;
  }
  return found;
}
inline int nearest_among(const Scene& s, const Ray& ray, u32 candidates, Hit& hit) {
  return nearest_among(s, ray, candidates, hit,
                       s.numForeground >= 32 ? ~0u : (1u << s.numForeground) - 1);
}

// Pinhole camera set up once per frame: pixel (x, y) (x right, y down, both
// from 0) looks through its centre (x + 0.5, y + 0.5). Made from a Scene,
// it also holds `terms`, what every primary ray of that scene shares
// (packet/primary.h), which the primary-ray tracers (packet/packet.h) need;
// made from a Camera alone, terms are not set and only primary_ray() and
// the general tracer may use it.
struct CameraRays {
  Vec3 org, corner, dx, dy;
  PrimaryTerms terms;
};
RT64K_HOT_ABI CameraRays camera_rays(const Camera& cam, int width, int height);
RT64K_HOT_ABI CameraRays camera_rays(const Scene& scene, int width, int height);
inline Ray primary_ray(const CameraRays& c, float x, float y) {
  return Ray{c.org, normalize(c.corner + c.dx * (x + 0.5f) + c.dy * (y + 0.5f))};
}

// 0xAARRGGBB (BGRA in memory, as a Win32 DIB wants), channels clamped to
// [0, 1] and rounded; NaN maps to 0.
RT64K_HOT_ABI u32 pack_color(Vec3 c);
// pack_color() of c[0..3] into out[0..3] (the full trace's rows of packets).
void pack_color4(const Vec3 c[4], u32 out[4]);

// Full trace (every pixel) of rows [rowBegin, rowEnd) into a caller-owned
// framebuffer of `width` x `height` pixels with `stride` pixels per row.
void render_full_rows(const Scene& scene, u32* fb, int width, int height, int stride, int rowBegin,
                      int rowEnd, RayStats* stats);

// Constants of the shading model, named for the tests and docs.
// kCosEps: floor of N.V in Cook-Torrance, so 1/(N.V) stays finite for a
// view ray that grazes the surface (1e-4 is cos(89.994 deg)). There G <=
// 2 (N.H)(N.V)/(V.H) cancels the 1/(N.V) unless N.L is as small.
//
// V.H: with H the half vector, V.H = |V + L| / 2 >= (N.V + N.L) / 2, so
// V.H -> 0 only when V and L are nearly opposite, i.e. both graze the
// surface from opposite sides: the mirror configuration at grazing.
// There the model's own limit holds and is kept: G -> 1 (Torrance-Sparrow's
// V-groove G, which Cook & Torrance 1982 use and SPEC prescribes, masks no
// microfacet parallel to the surface, and H -> N selects those), Schlick's
// F -> 1, D is at its peak: the term F D G / (N.V), times N.L, tends to
// F D (N.L / N.V), and for every V, L above the surface it is at most 4 F D
// (G N.L / N.V <= 2 (N.H) N.L / (V.H) <= 4 N.L / (N.V + N.L) <= 4): a bright
// but bounded glint, the grazing specular reflection that Fresnel makes
// strong. (Walter et al. 2007, who write the BRDF as F G D / (4 |N.L||N.V|),
// likewise put V.H only in F and G, never in a denominator of their own; a
// Smith G, which they prefer, would dim this glint further, but is not the
// thesis's model.) V.H is floored at (N.V + N.L) / 2, the identity above,
// which removes only rounding: no clamp changes the physics.
constexpr float kCosEps = 1e-4f;
// kCos2Min: the Beckmann D is taken as 0 where (N.H)^2 <= 1e-4 (the half
// vector beyond 89.4 deg from N): there its exponent -(1 - c^2) / (c^2 m^2)
// is below -99 for every roughness m <= 10, where rt_exp() is already 0, and
// the floor keeps c^4 a normal float, so 0 / 0 cannot occur.
constexpr float kCos2Min = 1e-4f;
