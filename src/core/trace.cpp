// trace.cpp - Whitted ray tracing (the ray tree traced without recursion) with Phong or
// Cook-Torrance shading.
#include "trace.h"

#include "packet/lanes.h"
#include "packet/packet.h"

bool same_path(const PathRecord& a, const PathRecord& b) {
  if (a.count != b.count) return false;
  for (int i = 0; i < a.count; ++i)
    if (a.node[i] != b.node[i]) return false;
  return true;
}

namespace {

// A colour in an SSE register's lanes x, y, z (lane 3 a finite float that
// no result reads): the light loop's products and sums lane for lane, as
// mulss and addss round them (lanes.h). `at` loads the 16 bytes from v (a
// Material's colour: lane 3 its diffuse); `after` the 16 bytes that end
// with v, rotated (lane 3 the float before v: a Light's pos.z, Scene's
// background.z), so that no load reaches past the object or into an int.
inline f4 at(const Vec3& v) { return lanes_at(&v); }
inline f4 after(const Vec3& v) {
  i4 q;
  __builtin_memcpy(&q, (const char*)&v - 4, 16);
  return (f4)__builtin_ia32_pshufd(q, 0x39);
}
// x, y, z of a Vec3 that 4 bytes of its object precede (RootNode's sum
// after its waiting bits, PreNode's colour after its records word) and 0 in
// lane 3: one load, a shuffle and an and, where (f4){v.x, v.y, v.z, 0} took
// three loads and two shuffles.
inline f4 after0(const Vec3& v) {
  i4 q, keep = {-1, -1, -1, 0};
  __builtin_memcpy(&q, (const char*)&v - 4, 16);
  return (f4)(__builtin_ia32_pshufd(q, 0x39) & keep);
}
// The x, y, z lanes of a sum or a colour (trace_tree's, in lanes).
inline Vec3 xyz(f4 v) { return Vec3{v[0], v[1], v[2]}; }

// Bit i set: the ray may hit object i (of those in `range`), judged by its
// bounding sphere (conservative: a clear bit is a sure miss). Four bounds
// per step with SSE. Per bound: f = org - centre, b = f.d, c = |f|^2 - r^2;
// a miss when the ray passes beside (b^2 < c), or starts outside (c > 0) and
// points away (b > 0). Both groups of four are tested, unrolled, whatever
// `range` holds (kMaxObjects = 8): a slot outside it is dropped by the
// mask, and every slot holds finite terms (scene_clear). Asking whether to
// run the second group, in a loop, cost more than running it: 1.5-2.7 % of
// a frame with shadow_mask's the same (docs/tracer-speed.md, round seven).
__attribute__((always_inline)) inline u32 bound_mask(const Scene& s, const Ray& ray, u32 range) {
  u32 missed = 0; // bit i: bound i surely missed
  // The six broadcasts from two 16-byte loads of the Ray's 24 bytes (org.x
  // .. dir.x and org.z .. dir.z) and a pshufd each (a shuffle that needs no
  // copy of its source first): 8 instructions where a load and a shufps per
  // coordinate took 12, the same values (docs/tracer-speed.md, round
  // thirteen).
  static_assert(sizeof(Ray) == 24, "Ray: org then dir, six floats");
  i4 lo, hi;
  __builtin_memcpy(&lo, (const char*)&ray, 16);
  __builtin_memcpy(&hi, (const char*)&ray + 8, 16);
  f4 ox = (f4)__builtin_ia32_pshufd(lo, 0x00), oy = (f4)__builtin_ia32_pshufd(lo, 0x55);
  f4 oz = (f4)__builtin_ia32_pshufd(lo, 0xaa), dx = (f4)__builtin_ia32_pshufd(lo, 0xff);
  f4 dy = (f4)__builtin_ia32_pshufd(hi, 0xaa), dz = (f4)__builtin_ia32_pshufd(hi, 0xff);
  f4 zero = {0, 0, 0, 0};
#pragma GCC unroll 2
  for (int g = 0; g < kMaxObjects; g += 4) {
    f4 fx = ox - *(const f4*)(s.boundX + g), fy = oy - *(const f4*)(s.boundY + g);
    f4 fz = oz - *(const f4*)(s.boundZ + g);
    f4 b = fx * dx + fy * dy + fz * dz;
    f4 c = fx * fx + fy * fy + fz * fz - *(const f4*)(s.boundR2 + g);
    // min(b, c) > 0: both are (one minps). A NaN ray (never a hit) may be
    // culled here where the two compares kept it for intersect_t().
    auto miss = (b * b < c) | (__builtin_ia32_minps(b, c) > zero);
    missed |= (u32)__builtin_ia32_movmskps((f4)miss) << g;
  }
  // (unboundedMask | the bounds not missed) & range: the same bits as each
  // group's (~m & 15) << g masked by range, since range holds object bits
  // only (below kMaxObjects): one not, one or, one and for both groups.
  return (s.unboundedMask | ~missed) & range;
}

inline u32 range_mask(int begin, int end) {
  return (end >= 32 ? ~0u : (1u << end) - 1) & ~((1u << begin) - 1);
}

// Nearest hit (nearest_among(), trace.h) among the objects of `range` whose
// bounds the ray may hit. A caller leaves out of `range` the object a ray
// leaves on a side it cannot return from (leaves_for_good() in shapes.h).
// hit.normal and hit.front are left unset: hit_normal() fills them. Inlined
// into trace_tree (the call and its register saves cost ~20 instructions a
// secondary ray) and first_hit.
template <bool Pairs = false>
__attribute__((always_inline)) inline int nearest(const Scene& s, const Ray& ray, Hit& hit,
                                                  u32 range, u32 foreground) {
  return nearest_among<Pairs>(s, ray, bound_mask(s, ray, range), hit, foreground);
}

// Light transmitted from p towards a light at distance `dist` along unit L:
// each foreground object on the way multiplies it by its transmit * colour
// (a tinted shadow), an opaque one blocks it. `code` gets the shadow code of
// PathRecord. Background objects cast no shadows (the contract).
// Only the objects in `range` are tested: the foreground less the object
// the ray leaves for good (the caller's, as left out of nearest()'s range). Objects in `exits` are
// crossed without a test: the ray starts inside that closed convex solid
// and the light lies outside it (trace_hit), so the ray leaves it exactly
// once on the way; it stays in index order with the others, so the product
// is the one the test would give.
// The ray is the caller's (its origin set once for all lights of a shading
// point, its direction L per light).
// The objects of `mask` (what shadow_mask() left) in index order. Inlined
// into trace_tree, as when it had no other caller; shadow_objects()
// (trace.h) is its copy for the packet tracer's shading (packet/shade.cpp),
// which intro.exe does not link (--gc-sections drops it).
__attribute__((always_inline)) inline f4 shadow_test(const Scene& s, const Ray& ray, float dist,
                                                     u32 mask, int& code, u32 exits) {
  f4 t = f4_of(1.0f);
  int crossed = 0;
  for (; mask; mask &= mask - 1) {
    int i = __builtin_ctz(mask);
    Hit hit;
    hit.t = dist;
    if (!(exits >> i & 1) && !intersect_t(s.objects[i].shape, ray, 0.0f, hit)) continue;
    const Material& m = s.objects[i].mat;
    if (m.transmit <= 0) {
      code = 3;
      return f4_of(0.0f);
    }
    t = t * (at(m.color) * m.transmit);
    ++crossed;
  }
  code = crossed > 1 ? 2 : crossed;
  return t;
}

__attribute__((always_inline)) inline f4 shadow_ray(TraceContext& ctx, int light, const Ray& ray,
                                                    float dist, int& code, u32 range, u32 exits) {
  const Scene& s = *ctx.scene;
  ++ctx.stats.shadow;
  return shadow_test(s, ray, dist, shadow_mask(s, light, ray.dir, dist, range), code, exits);
}

// Cook-Torrance specular factor F D G / (N.V), the 1/(N.L) of the model
// cancelled by the N.L of the incoming irradiance (Cook & Torrance 1982:
// I_r = I_L (N.L) dw (s R_s + d R_d)). D is their Beckmann distribution
// exp(-tan^2(a) / m^2) / (m^2 cos^4(a)) with the 1/pi of their
// R_s = F D G / (pi (N.L)(N.V)) folded in; so normalised, its lobe
// integrates to exactly 1 over the projected hemisphere (Walter et al.,
// EGSR 2007, eq. 33), and roughness changes a highlight's width, not its
// energy. It needs only cos^2(a) = (N.H)^2: tan^2(a) = (1 - cos^2) / cos^2.
// (Until issue 9 D was the Gaussian exp(-(a/m)^2) / (pi m^2), which needed
// a = acos(N.H) and integrates to 0.99, 0.97, 0.92 for the scenes' m =
// 0.12, 0.22, 0.35.) Below kCos2Min, D is 0.
//
// Where D's exponent -tan^2(a) / m^2 is below -kSpecExp the term is not
// computed: 0 (trace.h). tan^2(a) = (h.h - (N.h)^2) / (N.h)^2 with h = L + V
// unnormalised, so the test needs no square root and no division.
//
// V is -I, I the incident ray's direction: L + V = L - I and N.V = -(N.I)
// bit for bit (negation is exact and round-to-nearest symmetric; a zero's
// sign, which the two forms may give differently, is lost in the rt_max
// with a positive floor), so the caller keeps no negated copy.
__attribute__((always_inline)) inline float cook_torrance(const Material& m, Vec3 N, Vec3 I,
                                                          Vec3 L) {
  Vec3 h = L - I;
  float nh = dot(N, h), m2 = m.roughness * m.roughness;
  if (!(nh > 0) || dot(h, h) - nh * nh > kSpecExp * m2 * (nh * nh)) return 0.0f;
  Vec3 H = normalize(h, N);
  float NdotH = rt_clamp(dot(N, H), 0.0f, 1.0f);
  float NdotV = rt_max(-dot(N, I), kCosEps);
  float NdotL = rt_max(dot(N, L), 0.0f);
  // V.H = |V + L| / 2 >= (N.V + N.L) / 2 (the length of V + L is at least its
  // component along N): an identity, so this floor only undoes rounding. It
  // keeps G's ratios <= 2 and the returned F D G / (N.V), times N.L, below
  // 4 F D for every V and L (trace.h, above kCosEps).
  float VdotH = rt_max(-dot(I, H), 0.5f * (NdotV + NdotL));
  float x = 1.0f - VdotH, x2 = x * x;
  float F = m.f0 + x2 * x2 * x * (1.0f - m.f0);
  float G = rt_min(1.0f, 2.0f * NdotH * rt_min(NdotV, NdotL) / VdotH);
  // D last. Its exponent (c2 - 1) / (c2 m2) is <= 0 (c2 = NdotH^2 <= 1: NdotH
  // is clamped to [0, 1]), or -Inf or NaN for m2 = 0, so rt_exp_nonpositive,
  // inline, gives rt_exp's value bit for bit without a call, around which the
  // light loop saved its values (rtmath.h; docs/tracer-speed.md, round seven,
  // third wave: -1.0 to -1.4 % of scene 2's instructions, 0 packed bytes).
  float c2 = NdotH * NdotH;
  float D =
      c2 > kCos2Min ? rt_exp_nonpositive((c2 - 1.0f) / (c2 * m2)) / (kPi * m2 * c2 * c2) : 0.0f;
  return F * D * G / NdotV;
}

Vec3 reflect(Vec3 I, Vec3 N) { return I - N * (2.0f * dot(N, I)); }

// trace_tree's id of a ray whose nearest hit is still to be found.
constexpr int kFindHit = -2;

} // namespace

// The ray tree without recursion (docs/tracer-speed.md, round seven). A
// node's colour is its own shading plus f times each child's colour, with
// no absorption: the pixel is linear in the nodes, the sum over the tree of
// each node's shading times its weight (the product of the f's on its path:
// the very products the cuts and records use). The nodes are visited depth
// first, the reflected child before the refracted one, as the recursion
// did, so PathRecord's nodes come out in the same order with the same
// values; the colour differs from the recursion's only by the order of the
// float sums. A spawned ray waits in slot 2 depth + 1 for a reflected and 2
// depth for a refracted ray of that depth, and the highest slot goes first
// (__builtin_clz of the `waiting` bits): a node's children are deeper than
// every ray waiting while it is shaded (the invariant: those are each at
// most its depth), so highest-first is the stack's last-in first-out, the
// reflected child before its sibling, and the two slots of the children's
// depth are free when they are filled. The slot is bounded by the depth
// itself, at most kMaxTraceDepth, so `pending` cannot overflow whatever the
// scene (tests/test_raytree.cpp). One function for trace() and trace_hit(),
// so that intro.exe holds one copy of the nearest-hit search (a second,
// inlined into trace(), cost 430 packed bytes).
//
// Resume (trace_children4(), one lane at a time): the root (a primary ray's node, depth 1,
// weight 1) was shaded elsewhere (the packet tracer, packet/shade.h), maybe
// some of its children too (the second level), and `part` holds waiting
// rays of one depth and the sum so far; the result is the sum after their
// subtrees (not divided by the root's weight, 1). One pointer argument,
// as before the second level, so that trace_tree<false>, called with null,
// compiles to the same bytes in intro.exe. A template
// argument, so that trace() and trace_hit() keep the loop without the
// resume (intro.exe, which links no packet code, holds that copy only;
// the native tool holds both: docs/tracer-speed.md, round eleven).
template <bool Resume>
static RT64K_HOT_ABI f4 trace_tree(TraceContext& ctx, const Ray& first, int id, Hit& hit, int depth,
                                   float weight, u32 skip, const TreePart* part) {
  const Scene& s = *ctx.scene;
  // (Resume: computed once a packet by trace_children4.)
  int maxDepth = Resume                        ? part->maxDepth
                 : s.maxDepth < kMaxTraceDepth ? s.maxDepth
                                               : kMaxTraceDepth;
  Pending pending[2 * kMaxTraceDepth + 2];
  u32 waiting = 0;
  bool pastGlass = false; // the ray shaded has passed through glass
  float rootWeight = weight;
  // The ray of the node shaded: the root's, then a waiting ray's own slot
  // (read in place: its children go to the slots of the next depth).
  const Ray* cur = &first;
  // The sum in one SSE register's lanes x, y, z (lane 3 unused): a node adds
  // its colour times its weight with one mulps and one addps, lane for lane
  // the scalar products and sums (the same bits: lanes.h).
  f4 sum = {0, 0, 0, 0};
  // The lane's record, read once (the calls below cannot be seen not to
  // change ctx.record, so it was loaded again for every node).
  PathRecord* const rec = ctx.record;
  // What nearest() and shadow_mask() test, less the skipped objects.
  u32 all = Resume ? part->all : range_mask(0, s.numObjects);
  u32 foreground = Resume ? part->foreground : range_mask(0, s.numForeground);
  if (Resume) {
    // A part of a primary ray's tree (trace_children4): the sum so far and
    // waiting rays of one depth, part->kids (their bits in part->waiting, a
    // pair of slots: kids[0] the refracted ray's, kids[1] the reflected's),
    // started at the first as the loop's end would pop it (the loop itself
    // as without them: a test in it cost 0.5 % of a frame). The first is
    // read in place; a refracted ray after a reflected one waits in its
    // slot.
    const Pending* kids = part->kids;
    sum = part->sum;
    waiting = part->waiting;
    int slot = 31 - __builtin_clz(waiting);
    waiting ^= 1u << slot;
    int base = slot & ~1;
    if (waiting) pending[base] = kids[0];
    const Pending& next = kids[slot - base];
    cur = &next.ray;
    weight = next.weight;
    depth = slot >> 1;
    skip = next.skip;
    pastGlass = next.pastGlass;
  }
  for (;;) {
    const Ray& ray = *cur;
    if (id == kFindHit) {
      // The lone-solid shortcut (below, at the spawn): skip's bits from
      // kOnlyShift name the one object to test first.
      u32 only = skip >> kOnlyShift;
      // (nearest_among() sets hit.t itself: the resumed copy stores it here
      // for the lone solid's test only.)
      if (!Resume || only) hit.t = kHuge;
      if (only && intersect_t(s.objects[only - 1].shape, ray, 0.0f, hit))
        id = (int)only - 1;
      else
        id = nearest<Resume>(s, ray, hit, all & ~skip, foreground); // pairs: the tool's copy
    }
    u32* node = nullptr;
    bool recordable = depth <= kRecordDepth && weight >= kRecordWeight;
    // Rays through glass: recorded deeper (trace.h, kRecordWeightGlass).
    bool records = recordable || (pastGlass && weight >= kRecordWeightGlass);
    if (rec && records && rec->count < kMaxPathNodes) {
      node = &rec->node[rec->count++];
      *node = (u32)(id + 1);
    }
    if (id < 0) {
      // background, then ambient.x in lane 3 (unused): one 16-byte load.
      static_assert(__builtin_offsetof(Scene, ambient) ==
                        __builtin_offsetof(Scene, background) + 12,
                    "Scene: background, then ambient");
      f4 bg;
      __builtin_memcpy(&bg, &s.background, 16);
      sum += bg * weight;
    } else {
      const Object& obj = s.objects[id];
      const Material& m = obj.mat;
      // A sphere's normal inline (hit_normal's own steps; most of scene 1's
      // hits): no call, around which this loop saved its values
      // (docs/tracer-speed.md, rounds ten and eleven).
      // In the resumed copy (the native tool's only) a plane's too:
      // scene 1's floor under the glass.
      if (obj.shape.kind == kSphere)
        face_ray(sphere_outward(obj.shape, ray, hit), ray, hit);
      else if (Resume && obj.shape.kind == kPlane)
        plane_normal(obj.shape, hit);
      else if (Resume && obj.shape.kind == kTriangle) // its stored unit normal (shapes.h)
        face_ray(Vec3{obj.shape.r0, obj.shape.r1, obj.shape.h}, ray, hit);
      else
        hit_normal(obj.shape, ray, hit);
      u32 self = 1u << id;
      Vec3 N = hit.normal;
      Vec3 p = ray.org + ray.dir * hit.t;
      // The colour in lanes (at, after): s.ambient * m.color, lane for lane.
      f4 mcolor = at(m.color);
      f4 color = after(s.ambient) * mcolor;
      float off = spawn_offset(p, spawn_scale(obj.shape, hit));
      // spawn_origin(p, N, N, off): dot(N, N) >= 0 always (N is finite).
      Ray shadow;
      shadow.org = p + N * off;
      Vec3 lightOrg = shadow.org;
      // A hit from inside a closed convex solid: lightOrg is inside it too (N
      // faces the ray), so a shadow ray to a light outside the solid's bound
      // leaves it exactly once (transmittance's `exits`). A shadow ray is cast
      // only where N.L > 0, and leaves_for_good(obj.shape, hit, L) tests the
      // same product (dot(L, N) = dot(N, L) bit for bit): it leaves for good
      // when the shape is flat or the hit is on the front. So an inside hit's
      // shadow ray never leaves for good, and it exits when the light is
      // outside the bound: |light - centre|^2 > R^2, i.e. Scene::lightC > 0
      // (a float difference is > 0 exactly when a > b).
      bool flat = obj.shape.kind == kPlane || obj.shape.kind == kTriangle;
      bool leavesToLight = flat || hit.front;
      bool inside = !hit.front && closed_convex(obj.shape);
      u32 shadowRange = leavesToLight ? foreground & ~self : foreground;
      // The secondary rays are spawned before the lights are shaded (they wait
      // in their slots), so that p, off and the Snell terms need not live across
      // the light loop's calls.
      if (depth < maxDepth) {
        // The reflected ray (k = 0), then the refracted one (k = 1): one loop,
        // so that the spawn has one copy in the code (intro.exe: 512 bytes
        // less; docs/tracer-speed.md). Under total internal reflection (sin2T >
        // 1) the refracted ray is the mirror ray: one ray carries both weights
        // (reflect + transmit) instead of the same ray traced twice
        // (docs/tracer-speed.md, round five).
        // An opaque material casts the reflected ray only (its refracted
        // one has f = transmit <= 0).
        float eta = 1, cosI = 1, sin2T = 0;
        bool tir = false;
        int rays = 1;
        if (m.transmit > 0) {
          // Snell: eta = n1/n2; entering (front) goes air -> solid.
          eta = hit.front ? 1.0f / m.ior : m.ior;
          cosI = dot(N, -ray.dir); // >= 0: N faces the ray
          sin2T = eta * eta * (1.0f - cosI * cosI);
          tir = sin2T > 1.0f;
          rays = 2 - tir;
        }
        for (int k = 0; k < rays; ++k) {
          float f = k ? m.transmit : m.reflect + (tir ? m.transmit : 0.0f);
          if (!(f > 0 && weight * f >= kMinRayWeight)) continue;
          Vec3 D;
          if (k)
            D = normalize(ray.dir * eta + N * (eta * cosI - rt_sqrt(1.0f - sin2T)), ray.dir);
          else
            D = reflect(ray.dir, N); // the mirror, or total internal reflection
          float d = dot(D, N);       // spawn_origin's and leaves_for_good's product
          ++ctx.stats.secondary;
          int slot = 2 * depth + 3 - k; // 2 (depth + 1) + 1 for the reflected ray
          // A ray that does not leave the object goes into it (N faces the
          // incoming ray: a refracted ray entering, or one reflected inside).
          // Into a lone solid (Scene::aloneMask) from an origin at most
          // kAloneSlack / 2 of its size off the surface, the ray's segment to
          // the exit stays in the solid's widened capsule, clear of every other
          // foreground bound: no other foreground hit can be nearer, and with a
          // foreground hit no background object is tested. So the solid is
          // tested alone (kOnlyShift); where that finds nothing (rounding at a
          // rim) the ray searches as any other.
          u32 skipOrOnly = leaves_for_good_dot(obj.shape, hit, d) ? self
                           : (s.aloneMask & self) && off <= 0.5f * kAloneSlack * obj.shape.size
                               ? (u32)(id + 1) << kOnlyShift
                               : 0;
          pending[slot] = Pending{Ray{spawn_origin_dot(p, N, d, off), D}, weight * f, skipOrOnly,
                                  pastGlass || k};
          waiting |= 1u << slot;
        }
      }
      for (int li = 0; li < s.numLights; ++li) {
        const Light& light = s.lights[li];
        Vec3 toLight = light.pos - lightOrg;
        float dist = length(toLight);
        Vec3 L = toLight * (1.0f / rt_max(dist, 1e-20f));
        float NdotL = dot(N, L);
        // A surface facing away from the light records code 0 like a lit one:
        // the diffuse term fades to 0 at the terminator, so there is no edge
        // there to split on (a cast shadow, code 3, is one).
        int code = 0;
        u32 bits = 0;
        if (NdotL > 0) {
          // The light's term unshadowed; a shadow ray scales it by its transmittance.
          float spec;
          f4 lcolor = after(light.color), lit;
          if (s.model == kPhong) {
            // (V.R)^h <= exp(-h (1 - V.R)) (ln x <= x - 1): below exp(-kSpecExp)
            // the power is not computed (trace.h).
            // V.R = -(I.R), bit for bit but a zero's sign (cook_torrance).
            float VdotR = rt_max(-dot(ray.dir, N * (2.0f * NdotL) - L), 0.0f);
            spec = m.shininess * (1.0f - VdotR) > kSpecExp
                       ? 0.0f
                       : m.specular * rt_pow_inline(VdotR, m.shininess);
            lit = (mcolor * (m.diffuse * NdotL) + spec) * lcolor;
          } else {
            spec = m.specular * cook_torrance(m, N, ray.dir, L) * NdotL;
            lit = mcolor * (m.diffuse * NdotL + spec) * lcolor;
          }
          // A ray the records leave out whose term can move the pixel by less
          // than kShadowSkip casts no shadow ray: it counts as lit (with or
          // without a record, the colour is the same).
          f4 through = f4_of(1.0f);
          if (recordable || weight * max_abs(xyz(lit)) >= kShadowSkip) {
            bool exits = inside && s.lightC[li][id] > 0;
            shadow.dir = L;
            through = shadow_ray(ctx, li, shadow, dist, code, shadowRange, exits ? self : 0);
          }
          bits = (u32)code;
          if (code != 3) {
            color += lit * through;
            if (node && spec * max_abs(light.color) > kHighlightEdge) bits |= 4;
          }
        }
        if (node) *node |= bits << (5 + 3 * li);
      }
      sum += color * weight;
    }
    if (!waiting) break;
    int slot = 31 - __builtin_clz(waiting);
    waiting ^= 1u << slot;
    const Pending& next = pending[slot];
    cur = &next.ray;
    weight = next.weight;
    depth = slot >> 1;
    skip = next.skip;
    pastGlass = next.pastGlass;
    id = kFindHit;
  }
  // Weights are relative to the root's (1 for a primary ray: no rounding).
  if (Resume) return sum;
  return sum * (1.0f / rootWeight);
}

Vec3 trace(TraceContext& ctx, const Ray& ray, int depth, float weight, u32 skip) {
  Hit hit;
  // The caller's skip names objects only: bits from kOnlyShift are trace_tree's.
  return xyz(trace_tree<false>(ctx, ray, kFindHit, hit, depth, weight,
                               skip & ((1u << kOnlyShift) - 1), nullptr));
}

Vec3 trace_hit(TraceContext& ctx, const Ray& ray, int id, Hit& hit, int depth, float weight) {
  return xyz(trace_tree<false>(ctx, ray, id, hit, depth, weight, 0, nullptr));
}

int find_hit(const Scene& s, const Ray& ray, u32 skip, Hit& hit) {
  // trace_tree's kFindHit step, line for line. Not shared with trace_tree
  // through an inline function: that moved GCC's register and stack-slot
  // choices in intro.exe's copy of the loop (3,334 lines of its disassembly
  // differ, payload +2 bytes; round twelve), which tree18 kept unchanged.
  // (The masks without range_mask's test for 32 objects or more: a scene
  // holds at most kMaxObjects. hit.t = kHuge for the lone solid's test only:
  // nearest_among() sets it itself. About 10 instructions a call.)
  static_assert(kMaxObjects < 32, "an object mask is a u32");
  u32 all = (1u << s.numObjects) - 1, foreground = (1u << s.numForeground) - 1;
  u32 only = skip >> kOnlyShift;
  if (only) {
    hit.t = kHuge;
    if (intersect_t(s.objects[only - 1].shape, ray, 0.0f, hit)) return (int)only - 1;
  }
  return nearest(s, ray, hit, all & ~skip, foreground);
}

Vec3 shadow_objects(const Scene& s, const Ray& ray, float dist, u32 mask, int& code, u32 exits) {
  return xyz(shadow_test(s, ray, dist, mask, code, exits));
}

// A lane whose refracted child was shaded ahead (packet/shade.h, the
// second level): the tree in parts, in its order: the reflected child's
// subtree; the shaded child entering the record and the sum here; where
// its reflected child was shaded too (r.deep), that one likewise, then its
// children's subtrees; then the shaded child's other children's subtrees.
// One call site of the tree, inlined into trace_children4 (flattened): a
// second copy of the tree there (out of line: +0.05 to +0.18 % of scene 1's
// frames).
__attribute__((always_inline)) inline f4 trace_split(TraceContext& ctx, const RootNode& r, Hit& hit,
                                                     const TreePart& scene) {
  static_assert(__builtin_offsetof(RootNode, sum) == __builtin_offsetof(RootNode, waiting) + 4 &&
                    __builtin_offsetof(PreNode, color) == __builtin_offsetof(PreNode, records) + 4,
                "after0(): 4 bytes of the node before its sum or colour");
  f4 sum = after0(r.sum);
  PathRecord* rec = ctx.record;
  // A shaded node where the tree reaches it: its record node, then
  // sum += color * weight, as trace_tree's loop adds them.
  auto take = [&](const PreNode& n, float weight) {
    if (rec && n.records && rec->count < kMaxPathNodes) rec->node[rec->count++] = n.node;
    sum += after0(n.color) * weight;
  };
  const PreNode& pre = r.pre[0];
  for (int step = 0; step < 3; ++step) {
    const Pending* kids;
    u32 part;
    int id = kFindHit;
    if (step == 0) {
      kids = r.child;
      part = r.waiting & 1u << (kRootSlot + 1);
    } else if (step == 1) {
      take(pre, r.child[0].weight);
      if (!r.deep) continue;
      const PreNode& deep = r.pre[1];
      take(deep, pre.child[1].weight);
      kids = deep.child;
      part = deep.waiting;
    } else {
      kids = pre.child;
      part = r.deep ? pre.waiting & ~(1u << (2 * 2 + 3)) : pre.waiting;
      const PreNode& out = r.pre[2];
      if (r.exit == 2) {
        take(out, pre.child[0].weight);
        kids = out.child;
        part = out.waiting;
      } else if (r.exit == 1) {
        id = out.id;
        hit = out.hit;
      }
    }
    if (part) {
      TreePart tp{kids, part, sum, scene.all, scene.foreground, scene.maxDepth};
      sum = trace_tree<true>(ctx, kids->ray, id, hit, 2, 1.0f, 0, &tp);
    }
  }
  return sum;
}

// The tree inlined (flatten: trace_tree<true> has no other caller here), so
// that its frame, register saves and per-scene masks are set up once a
// packet rather than once a lane.
__attribute__((flatten)) void trace_children4(TraceContext& ctx, const RootNode root[4], u32 lanes,
                                              u32 shaded, PathRecord* paths, Vec3 color[4]) {
  Hit hit;
  const Scene& s = *ctx.scene;
  const TreePart scene{nullptr,
                       0,
                       {0, 0, 0, 0},
                       range_mask(0, s.numObjects),
                       range_mask(0, s.numForeground),
                       s.maxDepth < kMaxTraceDepth ? s.maxDepth : kMaxTraceDepth};
  for (; lanes; lanes &= lanes - 1) {
    int k = __builtin_ctz(lanes);
    if (paths) ctx.record = &paths[k];
    if (shaded >> k & 1)
      color[k] = xyz(trace_split(ctx, root[k], hit, scene));
    else if (root[k].waiting) {
      TreePart tp{root[k].child, root[k].waiting,  after0(root[k].sum),
                  scene.all,     scene.foreground, scene.maxDepth};
      color[k] = xyz(trace_tree<true>(ctx, root[k].child[0].ray, kFindHit, hit, 1, 1.0f, 0, &tp));
    } else
      color[k] = root[k].sum * 1.0f; // sum * (1 / rootWeight)
  }
}

int first_hit_object(const Scene& scene, const Ray& ray) {
  Hit hit;
  return first_hit(scene, ray, hit);
}

int first_hit(const Scene& scene, const Ray& ray, Hit& hit) {
  return nearest(scene, ray, hit, range_mask(0, scene.numObjects),
                 range_mask(0, scene.numForeground));
}

CameraRays camera_rays(const Camera& cam, int width, int height) {
  Vec3 fwd = normalize(cam.target - cam.pos, Vec3{0, 0, 1});
  Vec3 right = normalize(cross(fwd, cam.up), Vec3{1, 0, 0});
  Vec3 up = cross(right, fwd);
  float halfH = rt_sin(cam.fovY * 0.5f) / rt_cos(cam.fovY * 0.5f);
  float pixel = 2.0f * halfH / (float)height; // square pixels
  CameraRays c;
  c.org = cam.pos;
  c.dx = right * pixel;
  c.dy = up * -pixel;
  c.corner = fwd - c.dx * (0.5f * (float)width) - c.dy * (0.5f * (float)height);
  return c;
}

CameraRays camera_rays(const Scene& scene, int width, int height) {
  CameraRays c = camera_rays(scene.camera, width, height);
  primary_terms(scene, c.org, c.terms);
  return c;
}

// Per channel v: 0 for v <= 0 and NaN, 255 for v >= 1, else (u32)(v * 255 +
// 0.5), truncated. In the lanes of one SSE2 register, blue to red and alpha
// = 1: w = minps(1, v) is 1 for v >= 1 (1 * 255 + 0.5 truncates to 255)
// and v otherwise, NaN included (minps returns its second operand when
// either is NaN); each lane does the scalar formula's very operations
// (mulps, addps, cvttps2dq round as mulss, addss, cvttss2si); two
// saturating packs give the bytes B, G, R, A of the word: a lane of 0..255
// as it is, a negative one 0 (v <= 0: v * 255 + 0.5 truncates to 0 or
// below; -Inf, NaN and huge negatives convert to INT_MIN).
namespace {

typedef short s8 __attribute__((vector_size(16)));
typedef char c16 __attribute__((vector_size(16)));

// The four lanes of c before the packs: B, G, R, A as 32-bit integers.
inline i4 quantise(Vec3 c) {
  f4 v = {c.z, c.y, c.x, 1.0f}, one = {1, 1, 1, 1};
  return __builtin_ia32_cvttps2dq(__builtin_ia32_minps(one, v) * 255.0f + 0.5f);
}

} // namespace

u32 pack_color(Vec3 c) {
  i4 q = quantise(c);
  s8 h = __builtin_ia32_packssdw128(q, q);
  c16 b = __builtin_ia32_packuswb128(h, h);
  return (u32)((i4)b)[0];
}

// The same packs over four colours: the bytes of the four words in order.
// c[0..3]'s 48 bytes in three 16-byte loads, each colour's z, y, x put in
// lanes 0..2 by one or two shuffles (no scalar load and unpack per
// channel); lane 3 then holds a neighbour's channel, so its byte is set to
// 255 after the packs, the byte quantise()'s 1.0 gives. The other lanes
// are quantise()'s very operations.
void pack_color4(const Vec3 c[4], u32 out[4]) {
  static_assert(sizeof(Vec3) == 12, "Vec3: three floats");
  i4 a, m, z; // x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3 z3
  __builtin_memcpy(&a, (const char*)c, 16);
  __builtin_memcpy(&m, (const char*)c + 16, 16);
  __builtin_memcpy(&z, (const char*)c + 32, 16);
  f4 v[4] = {(f4)__builtin_ia32_pshufd(a, 0xc6),                // z0 y0 x0 x1
             __builtin_ia32_shufps((f4)m, (f4)a, 0xf1),         // z1 y1 x1 x1
             (f4)__builtin_ia32_pshufd(                         // z2 y2 x2 z2
                 (i4)__builtin_ia32_shufps((f4)m, (f4)z, 0x0e), //   (x2 y2 z2 z2)
                 0xc6),
             (f4)__builtin_ia32_pshufd(z, 0x1b)}; // z3 y3 x3 z2
  f4 one = {1, 1, 1, 1};
  i4 q[4];
#pragma GCC unroll 4
  for (int k = 0; k < 4; ++k)
    q[k] = __builtin_ia32_cvttps2dq(__builtin_ia32_minps(one, v[k]) * 255.0f + 0.5f);
  s8 lo = __builtin_ia32_packssdw128(q[0], q[1]);
  s8 hi = __builtin_ia32_packssdw128(q[2], q[3]);
  i4 alpha = {(int)0xff000000, (int)0xff000000, (int)0xff000000, (int)0xff000000};
  i4 b = (i4)__builtin_ia32_packuswb128(lo, hi) | alpha;
  __builtin_memcpy(out, &b, 16);
}

// Primary rays in packets of four (packet/packet.h: the same pixels as one
// trace() each).
void render_full_rows(const Scene& scene, u32* fb, int width, int height, int stride, int rowBegin,
                      int rowEnd, RayStats* stats) {
  RayStats rays{0, 0, 0};
  render_rows4(scene, camera_rays(scene, width, height), fb, width, stride, rowBegin, rowEnd,
               &rays);
  if (stats) {
    stats->primary += rays.primary;
    stats->secondary += rays.secondary;
    stats->shadow += rays.shadow;
  }
}
