// test_frustum4.cpp - the four-lane frustum kernel of primary rays
// (packet/frustum.h) against the scalar hit_frustum() (through
// intersect_t(), shapes.cpp), bit for bit: for every lane the kernel
// solves, the same hit or miss, and the same t, piece and local bits; the
// lanes it hands back (`rest`) are exactly those frustum_frame() solves
// from a clamped centre (u.u < c.z) or on a flat side; lanes outside the
// mask and the handed-back ones are left alone.
//
// Four rays share one origin (the kernel's terms are per origin, as a
// frame's primary rays share the camera); each lane takes a ray of a random
// class, so a packet mixes hits and misses: random rays at the shape,
// rays tangent to the side (the silhouette found in double from the origin,
// then nudged by 0 or a few float ulps of the size), rays at the rims and
// at points just inside or outside a cap's edge (within a few pieces'
// overlaps `rim`), through a cone's apex, near or along the axis (u = 0
// included) and at 45 deg to it (the clamp's u.u = 1/2 boundary),
// perpendicular to the axis (dy = 0 exactly for an upright axis) and clear
// misses. A lane's nearest distance on entry is kHuge, a random distance,
// or the scalar hit's own t (the strict t < hit.t).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "packet/frustum.h"
#include "scenes.h"
#include "trace.h"

namespace {

bool same_bits(float a, float b) { return rt_bits(a) == rt_bits(b); }

enum RayClass { kRandom, kTangent, kRim, kCapEdge, kApex, kAxis, kAcross, kMiss, kClasses };

struct Tally {
  long lanes = 0, solved = 0, handed = 0, hits = 0, piece[3] = {0, 0, 0};
  long dyZero = 0; // solved lanes exactly across the axis (dy = 0: no caps)
  long differ = 0, wrongRest = 0, touched = 0; // must stay 0
  long classLanes[kClasses] = {}, classHits[kClasses] = {};
};

// frustum_frame()'s choice of a clamped centre, as the scalar test makes it.
bool clamped(const Shape& s, Vec3 dir) {
  float dy = dot(dir, s.b);
  Vec3 u = dir - s.b * dy;
  return !(dot(u, u) >= s.c.z);
}

// The kernel on the lanes of `lanes` (four rays from org, lane k starting
// at nearest distance t0[k]) against intersect_t() lane by lane. With
// `orgs`, lane k starts at orgs[k] instead: frustum_lanes4() on the terms
// frustum_terms4() gives (the second level's lone cylinders and cones,
// packet/shade.cpp), f unused.
void check4(const Shape& s, const FrustumTerms& f, Vec3 org, const Vec3 dir[4], const float t0[4],
            const int cls[4], u32 lanes, Tally& tl, const Vec3* orgs = nullptr) {
  f4 d[3], t, local, o[3];
  i4 piece;
  for (int k = 0; k < 4; ++k) {
    Vec3 ok = orgs ? orgs[k] : org;
    o[0][k] = ok.x;
    o[1][k] = ok.y;
    o[2][k] = ok.z;
    d[0][k] = dir[k].x;
    d[1][k] = dir[k].y;
    d[2][k] = dir[k].z;
    t[k] = t0[k];
    piece[k] = 7;
    local[k] = -3.0f;
  }
  FrustumLanes r;
  if (orgs) {
    FrustumTerms4 f4terms;
    frustum_terms4(s, o, f4terms);
    r = frustum_lanes4(s, f4terms, d, lanes, t, piece, local);
  } else {
    r = frustum_lanes(s, f, d, lanes, t, piece, local);
  }
  for (int k = 0; k < 4; ++k) {
    bool hit = r.hit >> k & 1, rest = r.rest >> k & 1;
    bool untouched = same_bits(t[k], t0[k]) && piece[k] == 7 && same_bits(local[k], -3.0f);
    if (!(lanes >> k & 1)) {
      if (hit || rest || !untouched) ++tl.touched;
      continue;
    }
    ++tl.lanes;
    ++tl.classLanes[cls[k]];
    if (rest != (s.c.z > 1 || clamped(s, dir[k]))) ++tl.wrongRest;
    Hit ref;
    ref.t = t0[k];
    ref.piece = 7;
    ref.local = -3.0f;
    bool got = intersect_t(s, Ray{orgs ? orgs[k] : org, dir[k]}, 0.0f, ref);
    if (got) ++tl.classHits[cls[k]];
    if (rest) {
      ++tl.handed;
      if (hit || !untouched) ++tl.touched;
      continue;
    }
    ++tl.solved;
    if (dot(dir[k], s.b) == 0) ++tl.dyZero;
    if (got != hit || !same_bits(ref.t, t[k]) || ref.piece != piece[k] ||
        !same_bits(ref.local, local[k]))
      ++tl.differ;
    if (got) {
      ++tl.hits;
      ++tl.piece[ref.piece];
    }
  }
}

// A frustum in double, for aiming rays.
struct Geo {
  double a[3], b[3], e1[3], e2[3], r0, r1, h, size;
  bool hasApex; // a radius-0 end
  double apexY;
};

double dotd(const double* x, const double* y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; }

Geo geo_of(const Shape& s) {
  Geo g;
  const float a[3] = {s.a.x, s.a.y, s.a.z}, b[3] = {s.b.x, s.b.y, s.b.z};
  for (int i = 0; i < 3; ++i) {
    g.a[i] = a[i];
    g.b[i] = b[i];
  }
  // e1, e2: an orthonormal pair across the axis.
  double t[3] = {1, 0, 0};
  if (std::fabs(g.b[0]) > 0.6) t[0] = 0, t[1] = 1;
  double bt = dotd(t, g.b);
  double n = 0;
  for (int i = 0; i < 3; ++i) {
    g.e1[i] = t[i] - g.b[i] * bt;
    n += g.e1[i] * g.e1[i];
  }
  for (double& x : g.e1)
    x /= std::sqrt(n);
  g.e2[0] = g.b[1] * g.e1[2] - g.b[2] * g.e1[1];
  g.e2[1] = g.b[2] * g.e1[0] - g.b[0] * g.e1[2];
  g.e2[2] = g.b[0] * g.e1[1] - g.b[1] * g.e1[0];
  g.r0 = s.r0;
  g.r1 = s.r1;
  g.h = s.h;
  g.size = s.h + std::max(g.r0, g.r1);
  g.hasApex = s.r0 == 0 || s.r1 == 0;
  g.apexY = s.r0 == 0 ? 0 : s.h;
  return g;
}

// The point at height y, azimuth phi, distance rho from the axis.
void point(const Geo& g, double y, double phi, double rho, double* p) {
  for (int i = 0; i < 3; ++i)
    p[i] = g.a[i] + g.b[i] * y + (g.e1[i] * std::cos(phi) + g.e2[i] * std::sin(phi)) * rho;
}
double radius_at(const Geo& g, double y) { return g.r0 + (g.r1 - g.r0) * y / g.h; }

Vec3 unit_to(const double* p, Vec3 org) {
  double d[3] = {p[0] - org.x, p[1] - org.y, p[2] - org.z};
  double n = std::sqrt(dotd(d, d));
  return normalize(v3((float)(d[0] / n), (float)(d[1] / n), (float)(d[2] / n)));
}

// A direction from org of class c at the frustum (random parts from rng).
Vec3 aim(const Shape& s, const Geo& g, Vec3 org, int c, std::mt19937& rng) {
  std::uniform_real_distribution<double> u01(0.0, 1.0), sym(-1.0, 1.0);
  const double kTwoPiD = 6.283185307179586;
  double p[3];
  double rimTol = kRimRel * (max_abs(org - s.a) + s.c.y);         // the pieces' overlap
  double nudge[] = {0, 0, 1e-7, -1e-7, 6e-8, -6e-8, 1e-6, -1e-6}; // of the size
  double e = nudge[rng() % 8] * g.size;
  switch (c) {
  case kTangent: {
    // The silhouette at height y: (P - org).n = 0, n the side's normal.
    double y = g.h * (0.02 + 0.96 * u01(rng)), r = radius_at(g, y), k = (g.r1 - g.r0) / g.h;
    auto side = [&](double phi) {
      double q[3], n[3], o[3] = {org.x, org.y, org.z};
      point(g, y, phi, r, q);
      for (int i = 0; i < 3; ++i) {
        n[i] = g.e1[i] * std::cos(phi) + g.e2[i] * std::sin(phi) - g.b[i] * k;
        q[i] -= o[i];
      }
      return dotd(q, n);
    };
    double phi0 = kTwoPiD * u01(rng);
    for (int j = 0; j < 72; ++j) {
      double lo = phi0 + kTwoPiD * j / 72, hi = lo + kTwoPiD / 72;
      if ((side(lo) < 0) == (side(hi) < 0)) continue;
      for (int it = 0; it < 80; ++it) {
        double mid = 0.5 * (lo + hi);
        ((side(mid) < 0) == (side(lo) < 0) ? lo : hi) = mid;
      }
      point(g, y, lo, r + e, p);
      return unit_to(p, org);
    }
    break; // no silhouette (the origin inside): a random ray
  }
  case kRim:
  case kCapEdge: {
    bool top = rng() & 1;
    if (g.hasApex && (top ? g.r1 : g.r0) == 0) top = !top;
    double y = top ? g.h : 0, r = top ? g.r1 : g.r0;
    if (c == kRim) {
      r *= 1 + nudge[rng() % 8];
      y += nudge[rng() % 8] * g.size;
    } else { // within a few overlaps of the cap's edge, in its plane or off it
      r += rimTol * (double)((int)(rng() % 7) - 3);
      y += rimTol * (double)((int)(rng() % 5) - 2);
    }
    point(g, y, kTwoPiD * u01(rng), r, p);
    return unit_to(p, org);
  }
  case kApex: {
    double y = g.hasApex ? g.apexY : (rng() & 1 ? g.h : 0);
    point(g, y, 0, 0, p);
    for (double& x : p)
      x += sym(rng) * std::fabs(e);
    return unit_to(p, org);
  }
  case kAxis: {
    // Along the axis, tilted by tan = 0, 1e-7 .. 0.5, or 45 deg +- an ulp.
    double tilt[] = {0, 1e-7, 1e-4, 0.3, 1, 1 + 1.2e-7, 1 - 1.2e-7, 2};
    double tn = tilt[rng() % 8], phi = kTwoPiD * u01(rng), sgn = rng() & 1 ? 1 : -1;
    double d[3];
    for (int i = 0; i < 3; ++i)
      d[i] = sgn * g.b[i] + tn * (g.e1[i] * std::cos(phi) + g.e2[i] * std::sin(phi));
    double n = std::sqrt(dotd(d, d));
    return normalize(v3((float)(d[0] / n), (float)(d[1] / n), (float)(d[2] / n)));
  }
  case kAcross: {
    // Perpendicular to the axis at a height of the shape (dy = 0 exactly
    // when the axis is (0, 1, 0)).
    double y = g.h * (-0.1 + 1.2 * u01(rng));
    point(g, y, kTwoPiD * u01(rng), radius_at(g, y) * u01(rng) * 1.2, p);
    double d[3] = {p[0] - org.x, p[1] - org.y, p[2] - org.z};
    double along = dotd(d, g.b);
    for (int i = 0; i < 3; ++i)
      d[i] -= g.b[i] * along;
    if (dotd(d, d) < 1e-12) break;
    Vec3 v = unit_to(d, v3(0, 0, 0));
    if (s.b.x == 0 && s.b.z == 0) v = normalize(v3(v.x, 0, v.z));
    return v;
  }
  case kMiss: {
    double y = g.h * u01(rng), rm = std::max(g.r0, g.r1);
    point(g, y, kTwoPiD * u01(rng), rm * (1.6 + 3 * u01(rng)), p);
    return unit_to(p, org);
  }
  default:
    break;
  }
  // kRandom: a point of the shape's bounding box, a little beyond it.
  point(g, g.h * (-0.15 + 1.3 * u01(rng)), kTwoPiD * u01(rng),
        std::max(g.r0, g.r1) * 1.15 * std::sqrt(u01(rng)), p);
  return unit_to(p, org);
}

// An origin around (or inside) s: 1.5 .. 15 sizes from the middle of the
// axis, or on the axis inside the solid.
Vec3 origin_for(const Geo& g, bool inside, std::mt19937& rng) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::normal_distribution<double> nd(0.0, 1.0);
  double o[3];
  if (inside) {
    point(g, g.h * (0.1 + 0.8 * u01(rng)), 0, 0, o);
  } else {
    double dist = g.size * (1.5 + 13.5 * u01(rng)), n = 0;
    for (double& x : o) {
      x = nd(rng);
      n += x * x;
    }
    for (int i = 0; i < 3; ++i)
      o[i] = g.a[i] + g.b[i] * 0.5 * g.h + o[i] / std::sqrt(n) * dist;
  }
  return v3((float)o[0], (float)o[1], (float)o[2]);
}

// `packets` packets of four lanes from origins around (or inside) s; with
// `perLane`, each lane from an origin of its own (frustum_lanes4()).
void check_shape(const Shape& s, int packets, std::mt19937& rng, Tally& tl, bool inside = false,
                 bool perLane = false) {
  Geo g = geo_of(s);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  for (int p = 0; p < packets; ++p) {
    Vec3 org[4];
    org[0] = origin_for(g, inside, rng);
    for (int k = 1; k < 4; ++k)
      org[k] = perLane ? origin_for(g, inside, rng) : org[0];
    FrustumTerms f;
    frustum_terms(s, org[0], f);
    Vec3 dir[4];
    float t0[4];
    int cls[4];
    for (int k = 0; k < 4; ++k) {
      cls[k] = (int)(rng() % kClasses);
      dir[k] = aim(s, g, org[k], cls[k], rng);
      u32 how = rng() % 8;
      t0[k] = kHuge;
      if (how == 0) t0[k] = (float)(g.size * 20 * u01(rng));
      if (how == 1) { // the scalar hit's own t, or the next float either side
        Hit h;
        h.t = kHuge;
        if (intersect_t(s, Ray{org[k], dir[k]}, 0.0f, h))
          t0[k] = rt_from_bits(rt_bits(h.t) + (u32)(rng() % 3) - 1u);
      }
    }
    u32 lanes = rng() % 4 ? 15u : (u32)(1 + rng() % 15); // now and then not all four
    check4(s, f, org[0], dir, t0, cls, lanes, tl, perLane ? org : nullptr);
  }
}

void expect_exact(const Tally& tl, const char* what) {
  EXPECT_EQ(tl.differ, 0) << what << ": lanes whose hit differs from hit_frustum's";
  EXPECT_EQ(tl.wrongRest, 0) << what << ": lanes handed back that should not be, or kept";
  EXPECT_EQ(tl.touched, 0) << what << ": lanes changed that are not the kernel's";
}

Vec3 random_axis(std::mt19937& rng) {
  std::normal_distribution<float> n(0.0f, 1.0f);
  for (;;) {
    Vec3 v = v3(n(rng), n(rng), n(rng));
    if (dot(v, v) > 1e-4f) return normalize(v);
  }
}

struct Kind {
  const char* name;
  float r0, r1, h;
};

} // namespace

TEST(Frustum4, EveryKindAndCapMatchesHitFrustumBitForBit) {
  // Cylinders, cones (apex at the top or at the base: inverted), frustums
  // narrowing and widening, long thin and short wide ones, each with every
  // cap combination, upright (axis (0, 1, 0)) and tilted at random, from
  // outside and from inside: 13 kinds x 4 caps x 2 axes x 300 packets from
  // outside + 60 from inside = 149,760 lanes at most, and half as many
  // again with an origin per lane.
  const Kind kinds[] = {{"cylinder", 1.0f, 1.0f, 2.0f},
                        {"thin cylinder", 0.05f, 0.05f, 5.0f},
                        {"disc cylinder", 2.0f, 2.0f, 0.3f},
                        {"scene 1 lower cone", 1.5f, 0.32f, 1.75f},
                        {"scene 1 upper cone", 1.25f, 0.0f, 1.9f},
                        {"cone, apex at the base", 0.0f, 1.0f, 1.5f},
                        {"widening frustum", 0.3f, 1.2f, 1.0f},
                        {"steep cone", 0.4f, 0.0f, 6.0f},
                        {"near 45 deg frustum", 1.0f, 0.02f, 1.0f},
                        {"long thin cone", 0.02f, 0.0f, 4.0f},
                        {"wide cone, |k| = 0.99", 0.99f, 0.0f, 1.0f},
                        {"flat ring (|k| > 1)", 2.0f, 0.5f, 0.3f},
                        {"flat cone (|k| > 1)", 0.0f, 3.0f, 1.0f}};
  std::mt19937 rng(1414);
  Tally all;
  for (const Kind& kd : kinds) {
    Tally tk;
    for (int caps = 0; caps < 4; ++caps)
      for (int tilted = 0; tilted < 2; ++tilted) {
        Vec3 axis = tilted ? random_axis(rng) : v3(0, 1, 0);
        std::uniform_real_distribution<float> pos(-3.0f, 3.0f);
        Vec3 base = v3(pos(rng), pos(rng), pos(rng));
        Shape s = make_cone(base, axis, kd.r0, kd.r1, kd.h, (u8)caps);
        ASSERT_TRUE(s.kind == kCylinder || s.kind == kCone) << kd.name;
        check_shape(s, 300, rng, tk);
        check_shape(s, 60, rng, tk, true);
        // Four origins a packet (frustum_lanes4): the same kinds and caps.
        check_shape(s, 150, rng, tk, false, true);
        check_shape(s, 30, rng, tk, true, true);
      }
    expect_exact(tk, kd.name);
    bool flat = std::fabs((kd.r1 - kd.r0) / kd.h) > 1;
    if (flat) {
      EXPECT_EQ(tk.solved, 0) << kd.name << ": a flat side goes to the scalar test";
    } else {
      // Most lanes are the kernel's; every kind is hit on its side.
      EXPECT_GT(tk.solved, tk.lanes / 2) << kd.name;
      EXPECT_GT(tk.piece[kPieceSide], 500) << kd.name;
    }
    for (int i = 0; i < 3; ++i)
      all.piece[i] += tk.piece[i];
    all.lanes += tk.lanes;
    all.solved += tk.solved;
    all.handed += tk.handed;
    all.hits += tk.hits;
    all.dyZero += tk.dyZero;
    for (int c = 0; c < kClasses; ++c) {
      all.classLanes[c] += tk.classLanes[c];
      all.classHits[c] += tk.classHits[c];
    }
  }
  EXPECT_GT(all.lanes, 120000);
  EXPECT_GT(all.solved, 65000);
  EXPECT_GT(all.handed, 45000); // the clamped and flat cases were asked too
  EXPECT_GT(all.hits, 28000);
  EXPECT_GT(all.piece[kPieceBase], 2200);
  EXPECT_GT(all.piece[kPieceTop], 1600);
  EXPECT_GT(all.dyZero, 1000);
  // Each class of ray both hits and misses (mixed lanes; tangent rays on
  // either side of the silhouette): at least 5 % of either.
  for (int c = 0; c < kClasses; ++c) {
    EXPECT_GT(all.classLanes[c], 15000) << "class " << c;
    EXPECT_GT(all.classHits[c], all.classLanes[c] / 20) << "class " << c;
    EXPECT_LT(all.classHits[c], all.classLanes[c] * 19 / 20) << "class " << c;
  }
}

TEST(Frustum4, FarAndTinyFrustumsMatch) {
  // The same at other scales and distances: unit shapes 1e3 from the world's
  // origin, tiny (1e-3) and large (1e3) ones, tilted.
  std::mt19937 rng(2718);
  Tally tl;
  const float scales[] = {1e-3f, 1.0f, 1e3f};
  for (float sc : scales)
    for (int rep = 0; rep < 8; ++rep) {
      Vec3 base = v3(1000.0f, -700.0f, 300.0f) * (rep & 1 ? 1.0f : sc);
      Shape cyl = make_cylinder(base, random_axis(rng), 0.7f * sc, 2.0f * sc, kCapBase | kCapTop);
      Shape cone = make_cone(base, random_axis(rng), 1.1f * sc, 0.2f * sc, 1.4f * sc, kCapBase);
      check_shape(cyl, 400, rng, tl);
      check_shape(cone, 400, rng, tl);
    }
  expect_exact(tl, "far and tiny");
  EXPECT_GT(tl.solved, 25000);
  EXPECT_GT(tl.hits, 8000);
}

TEST(Frustum4, TheScenesFrustumsOverTheTimelineMatch) {
  // Scene 1's two cones and scene 2's two glass cylinders in 128 frames
  // (every 0.5 s), from the camera: the frame's own terms
  // (camera_rays().terms, as the packet tracer reads them) must equal
  // frustum_terms() of the camera, and four-ray packets of primary pixels
  // and of rays aimed at the shape's rims, silhouettes, caps and apex must
  // match hit_frustum.
  std::mt19937 rng(64);
  std::uniform_real_distribution<float> px(0.0f, 320.0f), py(0.0f, 240.0f);
  Tally tl;
  int frustums = 0;
  long termsDiffer = 0;
  for (int f = 0; f < 128; ++f) {
    Scene s;
    build_timeline_scene(s, 0.5 * f + 0.125);
    CameraRays cam = camera_rays(s, 320, 240);
    for (int i = 0; i < s.numObjects; ++i) {
      const Shape& sh = s.objects[i].shape;
      if (sh.kind != kCylinder && sh.kind != kCone) continue;
      ++frustums;
      FrustumTerms ft;
      frustum_terms(sh, cam.org, ft);
      const float* a = (const float*)&ft;
      const float* b = (const float*)&cam.terms.frustum[i];
      for (size_t j = 0; j < sizeof ft / sizeof(float); ++j)
        termsDiffer += !same_bits(a[j], b[j]);
      Geo g = geo_of(sh);
      for (int p = 0; p < 150; ++p) {
        Vec3 dir[4];
        float t0[4] = {kHuge, kHuge, kHuge, kHuge};
        int cls[4];
        for (int k = 0; k < 4; ++k) {
          if (p & 1) { // pixels of the frame
            cls[k] = kRandom;
            dir[k] = primary_ray(cam, std::floor(px(rng)), std::floor(py(rng))).dir;
          } else {
            cls[k] = (int)(rng() % kClasses);
            dir[k] = aim(sh, g, cam.org, cls[k], rng);
          }
        }
        check4(sh, cam.terms.frustum[i], cam.org, dir, t0, cls, 15u, tl);
      }
    }
  }
  EXPECT_EQ(frustums, 256); // two per frame in either scene
  EXPECT_EQ(termsDiffer, 0);
  expect_exact(tl, "the scenes' frustums");
  EXPECT_GT(tl.solved, 120000);
  EXPECT_GT(tl.hits, 30000);
  EXPECT_GT(tl.piece[kPieceBase], 1000);
  EXPECT_GT(tl.piece[kPieceTop], 1000);
}
