// test_packet.cpp - the primary-ray tracers of packet/packet.h against the
// general tracer (trace(), first_hit()): the same object, the same hit (t,
// piece and local, bit for bit), the same colour (tolerance 0: every float
// channel bit-identical), the same PathRecord and the same ray counts.
//
// Over frames of the whole timeline (every pixel), over seeded random rays
// from random camera positions, and on the hard cases: rays tangent to a
// sphere within a few ulps, rays parallel (and nearly parallel) to the
// ground plane, rays onto the stage's diagonal edge shared by its two
// triangles (where the watertight test's edge functions come out 0), and
// packets whose rays disagree on the triangle test's axis order.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "frame.h"
#include "packet/packet.h"
#include "scenes.h"

namespace {

bool same_bits(float a, float b) { return rt_bits(a) == rt_bits(b); }
bool same_bits(Vec3 a, Vec3 b) {
  return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z);
}

// Counts of disagreements between the packet path and the general one.
struct Mismatch {
  long rays = 0, id = 0, hit = 0, color = 0, path = 0, stats = 0;
  long hits = 0; // rays that hit an object (how much was compared)
};

// First hits of up to four rays from cam.org: packet, one-ray terms path and
// the general first_hit() must agree; t, piece and local only matter (and
// are only set) when something is hit.
void compare_first_hits(const Scene& s, const CameraRays& cam, const Vec3* dir, int count,
                        Mismatch& m) {
  int id4[4];
  Hit hit4[4];
  first_hit_primary4(s, cam, dir, count, id4, hit4);
  for (int k = 0; k < count; ++k) {
    Hit ref, one;
    int idRef = first_hit(s, Ray{cam.org, dir[k]}, ref);
    int idOne = first_hit_primary(s, cam, dir[k], one);
    ++m.rays;
    if (idRef >= 0) ++m.hits;
    if (id4[k] != idRef || idOne != idRef) {
      ++m.id;
      continue;
    }
    if (idRef < 0) continue;
    bool ok4 = same_bits(hit4[k].t, ref.t) && hit4[k].piece == ref.piece &&
               same_bits(hit4[k].local, ref.local);
    bool ok1 = same_bits(one.t, ref.t) && one.piece == ref.piece && same_bits(one.local, ref.local);
    if (!ok4 || !ok1) ++m.hit;
  }
}

// trace_primary4 on pixels (x[k], y[k]) against trace() of primary_ray().
void compare_pixels(const Scene& s, const CameraRays& cam, const float* x, const float* y,
                    int count, Mismatch& m) {
  Vec3 color[4];
  PathRecord path[4];
  RayStats stats{0, 0, 0};
  trace_primary4(s, cam, x, y, count, color, path, &stats);
  RayStats ref{0, 0, 0};
  for (int k = 0; k < count; ++k) {
    PathRecord rec;
    rec.count = 0;
    TraceContext ctx{&s, {0, 0, 0}, &rec};
    Ray ray = primary_ray(cam, x[k], y[k]);
    Vec3 c = trace(ctx, ray, 1);
    ref.primary += 1;
    ref.secondary += ctx.stats.secondary;
    ref.shadow += ctx.stats.shadow;
    ++m.rays;
    if (!same_bits(c, color[k])) ++m.color;
    if (!same_path(rec, path[k])) ++m.path;
    // The scalar terms path, pixel by pixel.
    PathRecord rec1;
    rec1.count = 0;
    TraceContext ctx1{&s, {0, 0, 0}, &rec1};
    Vec3 c1 = trace_primary(ctx1, cam, x[k], y[k]);
    if (!same_bits(c, c1) || !same_path(rec, rec1)) ++m.color;
    Hit h;
    if (first_hit(s, ray, h) >= 0) ++m.hits;
  }
  if (stats.primary != ref.primary || stats.secondary != ref.secondary ||
      stats.shadow != ref.shadow)
    ++m.stats;
}

void expect_none(const Mismatch& m, const char* what) {
  EXPECT_EQ(m.id, 0) << what << ": object ids differ on " << m.id << " of " << m.rays;
  EXPECT_EQ(m.hit, 0) << what << ": t/piece/local differ on " << m.hit;
  EXPECT_EQ(m.color, 0) << what << ": colours differ on " << m.color;
  EXPECT_EQ(m.path, 0) << what << ": path records differ on " << m.path;
  EXPECT_EQ(m.stats, 0) << what << ": ray counts differ in " << m.stats << " packets";
}

// Unit vector uniformly on the sphere.
Vec3 random_dir(std::mt19937& rng) {
  std::normal_distribution<float> n(0.0f, 1.0f);
  for (;;) {
    Vec3 v = v3(n(rng), n(rng), n(rng));
    if (dot(v, v) > 1e-6f) return normalize(v);
  }
}

// Every pixel of a w x h frame at time t, in 2x2 packets, plus the
// directions of those pixels through first_hit_primary4.
Mismatch compare_frame(double t, int w, int h) {
  Scene s;
  build_timeline_scene(s, t);
  CameraRays cam = camera_rays(s, w, h);
  Mismatch m;
  for (int y = 0; y < h; y += 2)
    for (int x = 0; x < w; x += 2) {
      float xs[4] = {(float)x, (float)x + 1, (float)x, (float)x + 1};
      float ys[4] = {(float)y, (float)y, (float)y + 1, (float)y + 1};
      compare_pixels(s, cam, xs, ys, 4, m);
      Vec3 d[4];
      for (int k = 0; k < 4; ++k)
        d[k] = primary_ray(cam, xs[k], ys[k]).dir;
      compare_first_hits(s, cam, d, 4, m);
    }
  return m;
}

TEST(Packet, TimelineFramesMatchTheScalarTracerBitForBit) {
  // 43 frames: every 1.6 s across both scenes (the blocks segment and the
  // fades included) and the seams; 240x180, every pixel: 1.9 million
  // comparisons each of first hits and of colours.
  std::vector<double> times;
  for (int i = 0; i < 40; ++i)
    times.push_back(1.6 * i + 0.7 + 0.013 * i);
  times.push_back(0.0);
  times.push_back(31.99);
  times.push_back(32.0);
  long hits = 0, rays = 0;
  for (double t : times) {
    Mismatch m = compare_frame(t, 240, 180);
    expect_none(m, ("t = " + std::to_string(t)).c_str());
    hits += m.hits;
    rays += m.rays;
  }
  // The frames are not empty: most primary rays hit something.
  EXPECT_GT(double(hits) / double(rays), 0.5);
}

TEST(Packet, FullSizeFramesMatchAtTheBenchTimes) {
  for (double t : {12.0, 44.0}) {
    Mismatch m = compare_frame(t, 800, 600);
    expect_none(m, ("800x600 t = " + std::to_string(t)).c_str());
    EXPECT_EQ(m.rays, 2 * 800 * 600);
  }
}

TEST(Packet, RandomRaysFromRandomCamerasMatch) {
  // 50,000 packets of random directions (so most packets mix the triangle
  // test's axis orders and hit different objects) from cameras anywhere
  // around both scenes, including below the ground and inside objects.
  std::mt19937 rng(909);
  std::uniform_real_distribution<float> pos(-9.0f, 9.0f), tt(0.0f, 64.0f);
  std::uniform_int_distribution<int> lanes(1, 4);
  Mismatch m;
  for (int frame = 0; frame < 50; ++frame) {
    Scene s;
    build_timeline_scene(s, tt(rng));
    for (int c = 0; c < 10; ++c) {
      s.camera.pos = v3(pos(rng), pos(rng) * 0.5f + 3.0f, pos(rng));
      CameraRays cam = camera_rays(s, 64, 48);
      for (int p = 0; p < 100; ++p) {
        Vec3 d[4];
        for (Vec3& v : d)
          v = random_dir(rng);
        compare_first_hits(s, cam, d, lanes(rng), m);
      }
    }
  }
  expect_none(m, "random rays");
  EXPECT_GT(m.rays, 100000);
  EXPECT_GT(m.hits, m.rays / 10); // a fair share of them hit something
}

TEST(Packet, RandomPixelsOfRandomFramesMatchInColourAndRecord) {
  // Scattered pixels (not 2x2 neighbours) in packets of 1 to 4, colours and
  // records through trace_primary4 against trace().
  std::mt19937 rng(4711);
  std::uniform_real_distribution<float> tt(0.0f, 64.0f), px(0.0f, 799.0f), py(0.0f, 599.0f);
  std::uniform_int_distribution<int> lanes(1, 4);
  Mismatch m;
  for (int frame = 0; frame < 40; ++frame) {
    Scene s;
    build_timeline_scene(s, tt(rng));
    CameraRays cam = camera_rays(s, 800, 600);
    for (int p = 0; p < 300; ++p) {
      float xs[4], ys[4];
      for (int k = 0; k < 4; ++k) {
        xs[k] = std::floor(px(rng));
        ys[k] = std::floor(py(rng));
      }
      compare_pixels(s, cam, xs, ys, lanes(rng), m);
    }
  }
  expect_none(m, "random pixels");
  EXPECT_GT(m.rays, 25000);
}

TEST(Packet, ShortPacketsReadButDoNotUseTheLanesPastTheirCount) {
  // trace_primary4() loads all four x and y (packet.h); lanes k >= count
  // hold values no pixel has (NaN, infinities, 1e30, a negative pixel) and
  // must change nothing: the colours, records and ray counts of the lanes
  // k < count as trace(), the colours of the others left alone.
  const float junk[] = {std::nanf(""), INFINITY, -INFINITY, 1e30f, -1e30f, -5.0f};
  std::mt19937 rng(1234);
  std::uniform_real_distribution<float> tt(0.0f, 64.0f), px(0.0f, 799.0f), py(0.0f, 599.0f);
  Mismatch m;
  long untouched = 0, past = 0;
  for (int frame = 0; frame < 12; ++frame) {
    Scene s;
    build_timeline_scene(s, tt(rng));
    CameraRays cam = camera_rays(s, 800, 600);
    for (int p = 0; p < 120; ++p) {
      int count = 1 + p % 3;
      float xs[4], ys[4];
      for (int k = 0; k < 4; ++k) {
        xs[k] = k < count ? std::floor(px(rng)) : junk[(p + k) % 6];
        ys[k] = k < count ? std::floor(py(rng)) : junk[(p + 2 * k + 1) % 6];
      }
      compare_pixels(s, cam, xs, ys, count, m);
      Vec3 color[4];
      const Vec3 sentinel = v3(-7.0f, -8.0f, -9.0f);
      for (int k = 0; k < 4; ++k)
        color[k] = sentinel;
      RayStats stats{0, 0, 0};
      trace_primary4(s, cam, xs, ys, count, color, nullptr, &stats);
      for (int k = count; k < 4; ++k, ++past)
        untouched += same_bits(color[k], sentinel);
    }
  }
  expect_none(m, "short packets with junk past their count");
  EXPECT_EQ(untouched, past);
  EXPECT_GT(m.rays, 2000);
}

// Rays tangent to each sphere of the scene, within -4..+4 ulps of the
// tangent angle: half of them just hit, half just miss, and the hit/miss
// decision and t must be the scalar tracer's.
TEST(Packet, RaysGrazingSpheresMatch) {
  std::mt19937 rng(17);
  Mismatch m;
  long grazingHits = 0, grazingRays = 0;
  for (double t : {3.0, 12.0, 20.0, 40.0, 44.0, 58.0}) {
    Scene s;
    build_timeline_scene(s, t);
    CameraRays cam = camera_rays(s, 800, 600);
    for (int i = 0; i < s.numObjects; ++i) {
      const Shape& sh = s.objects[i].shape;
      if (sh.kind != kSphere) continue;
      Vec3 w = sh.a - cam.org;
      double L = std::sqrt(double(dot(w, w)));
      double alpha = std::asin(double(sh.r0) / L);
      Vec3 axis = normalize(w);
      for (int rep = 0; rep < 400; ++rep) {
        // A random unit vector perpendicular to the axis.
        Vec3 u = random_dir(rng);
        u = normalize(u - axis * dot(u, axis));
        Vec3 d[4];
        for (int k = 0; k < 4; ++k) {
          float a = float(alpha);
          int steps = int(rep % 9) - 4 + k; // -4..+7 ulps around the tangent
          for (; steps > 0; --steps)
            a = std::nextafter(a, 2.0f);
          for (; steps < 0; ++steps)
            a = std::nextafter(a, 0.0f);
          d[k] = normalize(axis * std::cos(a) + u * std::sin(a));
          Hit h;
          grazingHits += first_hit(s, Ray{cam.org, d[k]}, h) == i;
          ++grazingRays;
        }
        compare_first_hits(s, cam, d, 4, m);
      }
    }
  }
  expect_none(m, "grazing spheres");
  // Both outcomes occur: the rays really straddle the silhouettes.
  EXPECT_GT(grazingHits, grazingRays / 20);
  EXPECT_LT(grazingHits, grazingRays - grazingRays / 20);
}

// Scene 1's mirror floor is the plane y = 0: rays with d.y = 0 exactly
// (denominator 0), +-denormal, +-1e-30 and +-1e-7, from cameras above it, on
// it and below it.
TEST(Packet, RaysParallelToTheGroundPlaneMatch) {
  Scene s;
  build_timeline_scene(s, 12.0);
  std::mt19937 rng(3);
  const float ys[] = {0.0f, -0.0f, 1e-40f, -1e-40f, 1e-30f, -1e-30f, 1e-7f, -1e-7f};
  Mismatch m;
  long floorHits = 0;
  for (float camY : {3.0f, 0.5f, 0.0f, -0.5f}) {
    s.camera.pos = v3(8.0f, camY, -6.0f);
    CameraRays cam = camera_rays(s, 800, 600);
    for (int rep = 0; rep < 500; ++rep) {
      float az = std::uniform_real_distribution<float>(0.0f, kTwoPi)(rng);
      Vec3 d[4];
      for (int k = 0; k < 4; ++k) {
        float dy = ys[(rep * 4 + k) % 8];
        float c = std::cos(az + 0.001f * float(k)), sn = std::sin(az + 0.001f * float(k));
        d[k] = Vec3{c, dy, sn}; // unit up to rounding: |d.y| <= 1e-7
        Hit h;
        int id = first_hit(s, Ray{cam.org, d[k]}, h);
        floorHits += id == s.numObjects - 1;
      }
      compare_first_hits(s, cam, d, 4, m);
    }
  }
  expect_none(m, "parallel to the ground");
  EXPECT_GT(m.rays, 7000);
  EXPECT_GT(floorHits, 0); // the nearly parallel ones reach the floor far away
}

// Scene 2's stage is two triangles sharing the diagonal from (-7, 0, -7) to
// (7, 0, 7). Rays aimed at points on it (and a few ulps either side) must
// get the scalar tracer's answer, and none may pass through: every ray
// whose foreground is empty there hits one of the two triangles.
TEST(Packet, RaysOnTheStageDiagonalMatchAndDoNotLeak) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<float> along(-6.9f, 6.9f);
  Mismatch m;
  long leaks = 0, perTriangle[2] = {0, 0};
  for (double t : {33.0, 40.0, 44.0, 52.0, 60.0}) {
    Scene s;
    build_timeline_scene(s, t);
    for (Vec3 camPos : {s.camera.pos, v3(0.0f, 6.0f, -1.0f), v3(-9.0f, 0.3f, -9.5f)}) {
      s.camera.pos = camPos;
      CameraRays cam = camera_rays(s, 800, 600);
      for (int rep = 0; rep < 600; ++rep) {
        Vec3 d[4];
        for (int k = 0; k < 4; ++k) {
          float a = along(rng);
          Vec3 p = v3(a, 0.0f, a);
          if (k == 3) p.x = std::nextafter(p.x, rep % 2 ? 10.0f : -10.0f); // one ulp off
          d[k] = normalize(p - cam.org);
          Hit h;
          int id = first_hit(s, Ray{cam.org, d[k]}, h);
          if (id < 0) ++leaks; // aimed at the stage from above it: must hit something
          if (id >= s.numForeground) ++perTriangle[id - s.numForeground];
        }
        compare_first_hits(s, cam, d, 4, m);
      }
    }
  }
  expect_none(m, "stage diagonal");
  EXPECT_EQ(leaks, 0);
  // Both triangles take their share of the edge: the rays really sit on it.
  EXPECT_GT(perTriangle[0], m.rays / 10);
  EXPECT_GT(perTriangle[1], m.rays / 10);
}

// The full renderer (packets of four pixels of a row, a short packet at the
// right edge when the width is not a multiple of 4) writes trace()'s pixels
// for any row range, and counts the same rays.
TEST(Packet, FullRenderAnyRowRangeAndOddSizesEqualsTrace) {
  Scene s;
  build_timeline_scene(s, 44.0);
  for (int w : {37, 40, 41}) {
    int h = 23;
    std::vector<u32> fb(size_t(w) * h, 0u);
    RayStats rows{0, 0, 0};
    const int cuts[] = {0, 3, 4, 9, 10, 11, 23};
    for (int c = 0; c + 1 < 7; ++c)
      render_full_rows(s, fb.data(), w, h, w, cuts[c], cuts[c + 1], &rows);
    CameraRays cam = camera_rays(s.camera, w, h);
    TraceContext ctx{&s, {0, 0, 0}, nullptr};
    long diff = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        diff += fb[size_t(y) * w + x] !=
                pack_color(trace(ctx, primary_ray(cam, (float)x, (float)y), 1));
    EXPECT_EQ(diff, 0) << w << "x" << h;
    EXPECT_EQ(rows.primary, u64(w) * h);
    EXPECT_EQ(rows.secondary, ctx.stats.secondary);
    EXPECT_EQ(rows.shadow, ctx.stats.shadow);
  }
}

} // namespace
