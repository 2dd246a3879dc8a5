// packet.cpp - primary rays from the per-frame terms; the contract is in
// packet.h.
//
// Bit-identical to the general tracer by construction: each kernel below
// repeats its counterpart in shapes.cpp (hit_sphere, hit_plane,
// hit_triangle) or trace.cpp (bound_mask, nearest) for four rays, with the
// same operations in the same order, the origin terms coming from
// PrimaryTerms (computed by the same expressions), and per lane the same
// accept/reject decisions; cylinders and cones likewise in frustum.cpp.
// Every case the kernels do not mirror goes to the scalar intersect_t() for
// that lane: a frustum's lanes within 45 deg of its axis and flat-sided
// frustums (frustum.h), a triangle when the four rays do not share the
// watertight test's axis order, or when one of its edge functions is
// exactly 0 (the test's recomputation in double).
#include "packet/packet.h"

#include "packet/lanes.h"
#include "packet/shade.h"

namespace {

// Four unit directions, component c of lane k in v[c][k].
struct Dirs {
  f4 v[3];
  Vec3 lane(int k) const { return Vec3{v[0][k], v[1][k], v[2][k]}; }
};

// nearest()'s running state (trace.cpp) in four lanes.
struct Nearest {
  f4 t;     // nearest t so far; kHuge: none
  i4 id;    // its object; -1: none
  i4 piece; // Hit::piece and Hit::local of that hit
  f4 local;

  // shapes.cpp's accept() for the lanes of `accepted`: piece 0, local 0.
  void take(i4 accepted, f4 tNew, int object) {
    t = accepted ? tNew : t;
    id = accepted ? i4_of(object) : id;
    piece = accepted ? i4_of(0) : piece;
    local = accepted ? f4_of(0.0f) : local;
  }
};

// The lanes of `lanes` through the general intersect_t(): the shapes and
// cases the kernels leave out.
void scalar_lanes(const Shape& shape, Vec3 org, const Dirs& d, u32 lanes, int object, Nearest& st) {
  for (; lanes; lanes &= lanes - 1) {
    int k = __builtin_ctz(lanes);
    Hit hit;
    hit.t = st.t[k];
    if (!intersect_t(shape, Ray{org, d.lane(k)}, 0.0f, hit)) continue;
    st.t[k] = hit.t;
    st.id[k] = object;
    st.piece[k] = hit.piece;
    st.local[k] = hit.local;
  }
}

// bound_mask (trace.cpp) for four rays, one bound at a time, with f
// and c from the terms. Returns the lanes of `live` that may hit object i's
// bound in bits 4i..4i+3 (a nibble per object), and b[i] their f.d (which
// is a sphere's own b: its bound has its centre). A miss is bound_mask's:
// b^2 < c, or c > 0 and b > 0 (PrimaryTerms::away); an unbounded object's
// c of -1 keeps every lane.
u32 bound_lanes(const Scene& s, const PrimaryTerms& p, const Dirs& d, u32 live, f4 b[kMaxObjects]) {
  f4 zero = f4_of(0.0f);
  u32 keep = 0;
  for (int i = 0; i < s.numObjects; ++i) {
    const f4* t = (const f4*)p.splat[i];
    f4 bb = t[0] * d.v[0] + t[1] * d.v[1] + t[2] * d.v[2];
    b[i] = bb;
    i4 miss = (bb * bb < t[3]) | ((bb > zero) & *(const i4*)p.away[i]);
    keep |= lane_bits(~miss) << 4 * i;
  }
  return keep & live * 0x11111111u;
}

// hit_sphere (shapes.cpp), tMin = 0, with f, b and c from the terms.
void sphere_lanes(const PrimaryTerms& p, int i, const Dirs& d, f4 b, u32 lanes, Nearest& st) {
  f4 zero = f4_of(0.0f);
  f4 px = p.fx[i] - d.v[0] * b, py = p.fy[i] - d.v[1] * b, pz = p.fz[i] - d.v[2] * b;
  f4 disc = p.r2[i] - (px * px + py * py + pz * pz);
  // The scalar code returns at disc < 0; a NaN disc it rejects at accept().
  i4 ok = (disc >= zero) & lanes_of(lanes);
  if (!lane_bits(ok)) return;
  f4 root = lane_sqrt(disc);
  f4 q = -(b + (b >= zero ? root : -root));
  ok &= q != zero;
  f4 t0 = p.shapeC[i] / q, t1 = q;
  i4 swap = t0 > t1;
  f4 lo = swap ? t1 : t0, hi = swap ? t0 : t1;
  f4 t = lo > zero ? lo : hi;
  ok &= (t > zero) & (t < st.t);
  st.take(ok, t, i);
}

// hit_plane from the terms, in float for lanes with |cos| >= kPlaneCosFloat
// (piece: 1 when the ray comes against the normal); the lanes nearer
// parallel take hit_plane's double path through the scalar test.
void plane_lanes(const Scene& s, const PrimaryTerms& p, int i, const Dirs& d, u32 lanes,
                 Nearest& st) {
  const Shape& sh = s.objects[i].shape;
  Vec3 n = sh.a;
  f4 zero = f4_of(0.0f);
  f4 c = n.x * d.v[0] + n.y * d.v[1] + n.z * d.v[2];
  i4 inFloat = lane_abs(c) >= f4_of(kPlaneCosFloat);
  u32 nearParallel = lanes & ~lane_bits(inFloat);
  f4 t = p.shapeC[i] / c;
  i4 ok = lanes_of(lanes) & inFloat & (t > zero) & (t < st.t);
  st.take(ok, t, i);
  st.piece = ok ? (i4)(c < zero) & i4_of(1) : st.piece;
  if (nearParallel) scalar_lanes(sh, p.org, d, nearParallel, i, st);
}

// The watertight test's axis order (hit_triangle): kz the direction's
// largest component, kx, ky the next two cyclically, swapped when d[kz] < 0.
// `uniform` is false when the lanes of `live` disagree; their triangles then
// go to the scalar test.
struct AxisOrder {
  int kx, ky, kz;
  bool uniform;
};

AxisOrder axis_order(const Dirs& d, u32 live) {
  f4 ax = lane_abs(d.v[0]), ay = lane_abs(d.v[1]), az = lane_abs(d.v[2]);
  i4 kz = ax > ay ? (ax > az ? i4_of(0) : i4_of(2)) : (ay > az ? i4_of(1) : i4_of(2));
  f4 dz = kz == i4_of(0) ? d.v[0] : (kz == i4_of(1) ? d.v[1] : d.v[2]);
  i4 code = kz + (dz < f4_of(0.0f) ? i4_of(4) : i4_of(0));
  i32 c0 = code[__builtin_ctz(live)];
  AxisOrder o;
  o.uniform = (lane_bits(code == i4_of(c0)) & live) == live;
  o.kz = c0 & 3;
  o.kx = o.kz == 2 ? 0 : o.kz + 1;
  o.ky = o.kx == 2 ? 0 : o.kx + 1;
  if (c0 & 4) {
    int tmp = o.kx;
    o.kx = o.ky;
    o.ky = tmp;
  }
  return o;
}

// hit_triangle (Woop et al., shapes.cpp) from the terms, for lanes sharing
// the axis order o.
void triangle_lanes(const Scene& s, const PrimaryTerms& p, int i, const Dirs& d, const AxisOrder& o,
                    u32 lanes, Nearest& st) {
  const Shape& sh = s.objects[i].shape;
  f4 zero = f4_of(0.0f);
  if (p.sideFar >> i & 1) { // starts off the plane: skip the rays moving away (kSideRel)
    f4 away = sh.n.x * d.v[0] + sh.n.y * d.v[1] + sh.n.z * d.v[2];
    lanes &= ~lane_bits(p.side[i] > 0 ? away > zero : away < zero);
    if (!lanes) return;
  }
  f4 dz = d.v[o.kz];
  f4 Sx = d.v[o.kx] / dz, Sy = d.v[o.ky] / dz, Sz = 1.0f / dz;
  const float(*v)[3] = p.vert[i];
  float akx = v[0][o.kx], aky = v[0][o.ky], akz = v[0][o.kz];
  float bkx = v[1][o.kx], bky = v[1][o.ky], bkz = v[1][o.kz];
  float ckx = v[2][o.kx], cky = v[2][o.ky], ckz = v[2][o.kz];
  f4 Ax = akx - Sx * akz, Ay = aky - Sy * akz;
  f4 Bx = bkx - Sx * bkz, By = bky - Sy * bkz;
  f4 Cx = ckx - Sx * ckz, Cy = cky - Sy * ckz;
  f4 U = Cx * By - Cy * Bx, V = Ax * Cy - Ay * Cx, W = Bx * Ay - By * Ax;
  // An edge function of exactly 0: the scalar test recomputes all three in double.
  u32 exact = lane_bits((U == zero) | (V == zero) | (W == zero)) & lanes;
  lanes &= ~exact;
  if (lanes) {
    i4 outside = ((U < zero) | (V < zero) | (W < zero)) & ((U > zero) | (V > zero) | (W > zero));
    f4 det = U + V + W;
    f4 T = U * Sz * akz + V * Sz * bkz + W * Sz * ckz;
    f4 t = T / det;
    i4 ok = lanes_of(lanes) & ~outside & (det != zero) & (t > zero) & (t < st.t);
    st.take(ok, t, i);
  }
  if (exact) scalar_lanes(sh, p.org, d, exact, i, st);
}

// nearest() (trace.cpp) for the lanes of `live`: foreground objects in
// index order, then the background for the lanes that saw none.
void nearest_lanes(const Scene& s, const PrimaryTerms& p, const Dirs& d, u32 live, Nearest& st) {
  st.t = f4_of(kHuge);
  st.id = i4_of(-1);
  st.piece = i4_of(0);
  st.local = f4_of(0.0f);
  f4 b[kMaxObjects];
  u32 objects = bound_lanes(s, p, d, live, b); // a nibble of lanes per object
  u32 foreground = s.numForeground >= 8 ? ~0u : (1u << 4 * s.numForeground) - 1;
  AxisOrder order{0, 0, 0, false};
  bool ordered = false;
  for (u32 m = objects & foreground;;) {
    if (!m) {
      u32 none = lane_bits(st.id < i4_of(0)) & live;
      u32 background = objects & ~foreground;
      if (!none || !background) break;
      m = background & none * 0x11111111u;
      objects = 0;
      if (!m) break;
    }
    int i = __builtin_ctz(m) >> 2;
    u32 l = m >> 4 * i & 15;
    m &= ~(15u << 4 * i);
    const Shape& sh = s.objects[i].shape;
    switch (sh.kind) {
    case kSphere:
      sphere_lanes(p, i, d, b[i], l, st);
      break;
    case kPlane:
      plane_lanes(s, p, i, d, l, st);
      break;
    case kTriangle:
      if (!ordered) {
        order = axis_order(d, live);
        ordered = true;
      }
      if (order.uniform)
        triangle_lanes(s, p, i, d, order, l, st);
      else
        scalar_lanes(sh, p.org, d, l, i, st);
      break;
    case kCylinder:
    case kCone: {
      FrustumLanes r = frustum_lanes(sh, p.frustum[i], d.v, l, st.t, st.piece, st.local);
      st.id = lanes_of(r.hit) ? i4_of(i) : st.id;
      if (r.rest) scalar_lanes(sh, p.org, d, r.rest, i, st);
      break;
    }
    default:
      scalar_lanes(sh, p.org, d, l, i, st);
      break;
    }
  }
}

void lane_hit(const Nearest& st, int k, int& id, Hit& hit) {
  id = st.id[k];
  hit.t = st.t[k];
  hit.piece = (u8)st.piece[k];
  hit.local = st.local[k];
}

// Directions of primary_ray() (trace.h) for four pixels, operation for
// operation: c.corner + c.dx (x + 0.5) + c.dy (y + 0.5), then normalize().
Dirs pixel_dirs(const CameraRays& c, f4 x, f4 y) {
  f4 px = x + 0.5f, py = y + 0.5f;
  f4 vx = c.corner.x + c.dx.x * px + c.dy.x * py;
  f4 vy = c.corner.y + c.dx.y * px + c.dy.y * py;
  f4 vz = c.corner.z + c.dx.z * px + c.dy.z * py;
  f4 len2 = vx * vx + vy * vy + vz * vz;
  i4 ok = len2 > 1e-30f; // normalize()'s threshold; else its fallback (0, 1, 0)
  f4 inv = 1.0f / lane_sqrt(len2);
  f4 zero = f4_of(0.0f);
  return Dirs{{ok ? vx * inv : zero, ok ? vy * inv : f4_of(1.0f), ok ? vz * inv : zero}};
}

// v[0..3] in lanes (all four read: trace_primary4's contract), lanes k >=
// count replaced by lane 0, so that every lane holds a valid ray. One load
// and a select, no per-lane branch or loop (count varies with the caller's
// batch; the rolled loop cost ~32 instructions a call and mispredicted).
f4 load_lanes(const float* v, int count) {
  f4 r = lanes_at(v);
  return i4{0, 1, 2, 3} < i4_of(count) ? r : f4_of(r[0]);
}

} // namespace

int first_hit_primary(const Scene& s, const CameraRays& cam, Vec3 dir, Hit& hit) {
  // bound_mask with f and c from the terms, four bounds per step.
  const PrimaryTerms& p = cam.terms;
  f4 dx = f4_of(dir.x), dy = f4_of(dir.y), dz = f4_of(dir.z), zero = f4_of(0.0f);
  u32 all = s.unboundedMask;
  for (int g = 0; g < s.numObjects; g += 4) {
    f4 b = *(const f4*)(p.fx + g) * dx + *(const f4*)(p.fy + g) * dy + *(const f4*)(p.fz + g) * dz;
    f4 c = *(const f4*)(p.c + g);
    all |= (~lane_bits((b * b < c) | ((c > zero) & (b > zero))) & 15u) << g;
  }
  all &= (1u << s.numObjects) - 1;
  return nearest_among(s, Ray{cam.org, dir}, all, hit);
}

void first_hit_primary4(const Scene& scene, const CameraRays& cam, const Vec3 dir[4], int count,
                        int id[4], Hit hit[4]) {
  Dirs d;
  for (int k = 0; k < 4; ++k) {
    const Vec3& v = dir[k < count ? k : 0];
    d.v[0][k] = v.x;
    d.v[1][k] = v.y;
    d.v[2][k] = v.z;
  }
  Nearest st;
  nearest_lanes(scene, cam.terms, d, (1u << count) - 1, st);
  for (int k = 0; k < count; ++k)
    lane_hit(st, k, id[k], hit[k]);
}

Vec3 trace_primary(TraceContext& ctx, const CameraRays& cam, float x, float y) {
  Ray ray = primary_ray(cam, x, y);
  Hit hit;
  int id = first_hit_primary(*ctx.scene, cam, ray.dir, hit);
  return trace_hit(ctx, ray, id, hit, 1, 1.0f);
}

namespace {

// trace_primary4() with the pixel coordinates in lanes; lanes outside
// `live` (bits, the lowest set) hold valid pixels too and are not shaded.
void trace_lanes(const Scene& scene, const CameraRays& cam, f4 x, f4 y, u32 live, Vec3 color[4],
                 PathRecord* paths, RayStats* stats) {
  Dirs d = pixel_dirs(cam, x, y);
  Nearest st;
  nearest_lanes(scene, cam.terms, d, live, st);
  TraceContext ctx{&scene, {0, 0, 0}, nullptr};
  // The misses here; the hits' shading points in lanes (packet/shade.h).
  u32 hits = lane_bits(st.id >= i4_of(0)) & live;
  ctx.stats.primary = 0x4332322132212110ull >> 4 * live & 15; // live's bits, counted
  // The hits first: shade_primary4 writes all four paths[k] (shade.h).
  if (hits)
    shade_primary4(ctx, cam.org, d.v, Hits4{st.t, st.id, st.piece, st.local}, hits, paths, color);
  for (u32 m = live & ~hits; m; m &= m - 1) {
    int k = __builtin_ctz(m);
    if (paths) {
      paths[k].count = 0;
      ctx.record = &paths[k];
    }
    color[k] = trace_miss(ctx, 1, 1.0f);
  }
  stats->primary += ctx.stats.primary;
  stats->secondary += ctx.stats.secondary;
  stats->shadow += ctx.stats.shadow;
}

} // namespace

void trace_primary4(const Scene& scene, const CameraRays& cam, const float x[4], const float y[4],
                    int count, Vec3 color[4], PathRecord* paths, RayStats* stats) {
  trace_lanes(scene, cam, load_lanes(x, count), load_lanes(y, count), (1u << count) - 1, color,
              paths, stats);
}

void render_rows4(const Scene& scene, const CameraRays& cam, u32* fb, int width, int stride,
                  int rowBegin, int rowEnd, RayStats* stats) {
  Vec3 color[4];
  for (int y = rowBegin; y < rowEnd; ++y) {
    u32* row = fb + y * stride;
    for (int x = 0; x < width; x += 4) {
      int n = width - x < 4 ? width - x : 4;
      f4 lx = (float)x + f4{0, 1, 2, 3};
      for (int k = n; k < 4; ++k)
        lx[k] = (float)x; // idle lanes repeat lane 0
      trace_lanes(scene, cam, lx, f4_of((float)y), (1u << n) - 1, color, nullptr, stats);
      if (n == 4) {
        pack_color4(color, row + x);
      } else {
        for (int k = 0; k < n; ++k)
          row[x + k] = pack_color(color[k]);
      }
    }
  }
}
