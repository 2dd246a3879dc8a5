// test_shade4_second.cpp - the second level of the packet tracer (packet/shade.cpp:
// a uniform packet's refracted children into its lone solid, and their reflected
// children inside it, shaded four lanes at a time and taken up by the scalar tree
// in its own order, trace.cpp's trace_split) against trace_primary() per lane:
// colour bits, PathRecord nodes and ray counts.
//
// Cameras around each lone solid of both scenes (scene 1's glass spheres,
// Phong; scene 2's cylinders, Cook-Torrance) at timeline frames, packets of
// 1 to 4 lanes at fractional pixels on the solid's image (uniform packets, the
// second level's case) and across its silhouette (mixed packets, lanes with
// and without each child); the solid's reflect and transmit drawn at random so
// that the children's weights fall on both sides of every cut (kMinRayWeight at
// the spawn, kRecordWeight and kRecordWeightGlass for the record, kShadowSkip
// for the shadow rays), and its colour and ior too (total internal reflection
// inside, a dark solid whose shadow rays are cut more often); in a fourth
// view of each solid the lights behind other objects.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "packet/packet.h"
#include "scenes.h"
#include "shade4_check.h"

namespace {

struct Counts : LaneCounts {
  long second = 0; // lanes of uniform packets into a lone transmitting solid, hit in front
  long mixed = 0;  // packets whose lanes see different objects (or nothing)
  // Lanes of `second` packets by the refracted child's weight (the solid's
  // transmit): under kMinRayWeight (no child), under kRecordWeightGlass,
  // between it and kRecordWeight, at least kRecordWeight.
  long band[4] = {0, 0, 0, 0};
  long deep = 0; // of `second`: transmit * reflect >= kMinRayWeight (a reflected child inside)
};

void compare_lanes(const Scene& s, const CameraRays& cam, const float* x, const float* y, int n,
                   Counts& c) {
  LaneCheck r = c.check(s, cam, x, y, n);
  int firstId = r.id[0];
  bool uniform = true, front = true;
  for (int k = 0; k < n; ++k) {
    uniform &= r.id[k] == firstId;
    front &= r.front[k];
  }
  c.mixed += !uniform;
  if (uniform && front && firstId >= 0 && (s.aloneMask >> firstId & 1)) {
    const Material& m = s.objects[firstId].mat;
    if (m.transmit > 0) {
      c.second += n;
      int b = m.transmit < kMinRayWeight        ? 0
              : m.transmit < kRecordWeightGlass ? 1
              : m.transmit < kRecordWeight      ? 2
                                                : 3;
      c.band[b] += n;
      c.deep += m.transmit * m.reflect >= kMinRayWeight ? n : 0;
    }
  }
}

TEST(Shade4Second, LoneSolidPacketsMatchPerLaneAcrossTheWeightCuts) {
  std::mt19937 rng(1812);
  std::uniform_real_distribution<float> t1(0.0f, 32.0f), t2(32.0f, 64.0f), frac(0.0f, 1.0f);
  std::uniform_real_distribution<float> sym(-1.0f, 1.0f);
  std::uniform_int_distribution<int> lanes(1, 4);
  const int w = 48, h = 36;
  Counts c;
  long solids = 0, moved = 0;
  for (int frame = 0; frame < 48; ++frame) {
    Scene s;
    build_timeline_scene(s, frame % 2 ? t2(rng) : t1(rng)); // both models
    for (int i = 0; i < s.numForeground; ++i) {
      if (!(s.aloneMask >> i & 1)) continue;
      ++solids;
      Object& o = s.objects[i];
      // Weights across the cuts: transmit in [0.005, 1], reflect in [0, 0.6];
      // the ior (1.05 .. 2.4: total internal reflection inside from ~25
      // degrees) and the colour's level (the shadow rays' kShadowSkip).
      o.mat.transmit = 0.005f + 0.995f * frac(rng) * frac(rng);
      o.mat.reflect = 0.6f * frac(rng);
      o.mat.ior = 1.05f + 1.35f * frac(rng);
      o.mat.color = o.mat.color * (0.05f + 0.95f * frac(rng));
      const Shape& sh = o.shape;
      Vec3 centre = sh.kind == kSphere ? sh.a : sh.a + sh.b * (0.5f * sh.h);
      float r = sh.kind == kSphere ? sh.r0 : rt_max(sh.r0, 0.5f * sh.h);
      for (int view = 0; view < 4; ++view) {
        if (view == 3) {
          // The lights moved behind other objects (just outside their
          // bounds, on the far side from the solid): shadow rays from the
          // solid's inside and surface whose one candidate is another
          // object, which the shading points test in lanes.
          move_lights(s, [&](int, const Light&) {
            int j = (int)(rng() % s.numForeground);
            Vec3 cj = {s.boundX[j], s.boundY[j], s.boundZ[j]};
            Vec3 away =
                normalize(cj - centre + v3(sym(rng), sym(rng), sym(rng)) * 0.3f, v3(0, 1, 0));
            return cj + away * (s.boundR[j] * (1.05f + 2.0f * frac(rng)));
          });
          ++moved;
        }
        Vec3 d = normalize(v3(sym(rng), 0.6f * sym(rng) + 0.2f, sym(rng)), v3(0, 0, 1));
        s.camera.pos = centre + d * (r * (2.5f + 6.0f * frac(rng)));
        s.camera.target = centre + v3(sym(rng), sym(rng), sym(rng)) * (0.3f * r);
        CameraRays cam = camera_rays(s, w, h);
        // 2x2 packets at a fractional offset over the whole image: the
        // solid's image (uniform packets), its silhouette and the rest.
        float ox = frac(rng), oy = frac(rng);
        for (int y = 0; y + 1 < h; y += 2)
          for (int x = 0; x + 1 < w; x += 2) {
            int n = lanes(rng);
            float xs[4], ys[4];
            for (int k = 0; k < n; ++k) {
              xs[k] = (float)(x + (k & 1)) + ox;
              ys[k] = (float)(y + (k >> 1)) + oy;
            }
            compare_lanes(s, cam, xs, ys, n, c);
          }
      }
    }
  }
  EXPECT_EQ(c.color, 0) << "colours differ on " << c.color << " of " << c.lanes;
  EXPECT_EQ(c.path, 0) << "records differ on " << c.path;
  EXPECT_EQ(c.stats, 0) << "ray counts differ in " << c.stats << " packets";
  EXPECT_GT(solids, 60);
  EXPECT_EQ(moved, solids);
  EXPECT_GT(c.lanes, 100000);
  EXPECT_GT(c.second, 30000);
  EXPECT_GT(c.mixed, 3000);
  for (int b = 0; b < 4; ++b)
    EXPECT_GT(c.band[b], 500) << "weight band " << b;
  EXPECT_GT(c.deep, 10000);
}

} // namespace
