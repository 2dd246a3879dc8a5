// test_frames.cpp - whole 800x600 frames of the 64-s timeline, and the
// timeline's wrapping of any time.
//
// Frames: 32 times in the middle of every 2-s slot (0.5, 2.5, ..., 62.5) plus
// the loop's start and the seams (0, 31.99, 32, 63.99) and the renderer-
// visualisation segment. Each is built by build_timeline_scene and drawn by
// render_frame (full trace, all threads); every pixel is also traced
// directly with trace(), whose float colour must be finite and non-negative
// (pack_color maps NaN to 0, so a NaN cannot be seen in the packed frame)
// and pack to the very pixel render_frame wrote.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <random>
#include <set>
#include <thread>
#include <vector>

#include "frame.h"

namespace {

constexpr int kW = 800, kH = 600;

struct FrameStats {
  long nonFinite = 0, negative = 0, packMismatch = 0;
  int distinct = 0;         // distinct packed colours
  double lumaStd = 0;       // standard deviation of the luma, 0..1
  double maxChannel = 0;    // brightest channel, 0..255
  bool floatVaries = false; // the float colours are not all equal
};

FrameStats check_frame(double t) {
  Scene scene;
  build_timeline_scene(scene, t);
  Image img(kW, kH);
  RenderOptions opt;
  opt.mode = Mode::Full;
  opt.view = View::Color;
  opt.threads = default_threads();
  render_frame(scene, img, opt, nullptr);

  // Every pixel again through trace() itself, rows shared among threads.
  std::atomic<long> nonFinite{0}, negative{0}, mismatch{0};
  std::atomic<int> nextRow{0};
  std::atomic<bool> varies{false};
  Vec3 first = [&] {
    TraceContext ctx{&scene, {0, 0, 0}, nullptr};
    return trace(ctx, primary_ray(camera_rays(scene.camera, kW, kH), 0, 0), 1);
  }();
  auto worker = [&] {
    TraceContext ctx{&scene, {0, 0, 0}, nullptr};
    CameraRays cam = camera_rays(scene.camera, kW, kH);
    long nf = 0, neg = 0, mm = 0;
    bool v = false;
    for (int y; (y = nextRow.fetch_add(1)) < kH;) {
      for (int x = 0; x < kW; ++x) {
        Vec3 c = trace(ctx, primary_ray(cam, float(x), float(y)), 1);
        if (!(std::isfinite(c.x) && std::isfinite(c.y) && std::isfinite(c.z))) ++nf;
        if (c.x < 0 || c.y < 0 || c.z < 0) ++neg;
        if (pack_color(c) != img.at(x, y)) ++mm;
        v |= c.x != first.x || c.y != first.y || c.z != first.z;
      }
    }
    nonFinite += nf;
    negative += neg;
    mismatch += mm;
    if (v) varies = true;
  };
  std::vector<std::thread> pool;
  for (int i = 1; i < default_threads(); ++i)
    pool.emplace_back(worker);
  worker();
  for (auto& th : pool)
    th.join();

  FrameStats st;
  st.nonFinite = nonFinite;
  st.negative = negative;
  st.packMismatch = mismatch;
  st.floatVaries = varies;
  std::set<uint32_t> colours;
  double sum = 0, sum2 = 0;
  for (uint32_t p : img.pixels) {
    colours.insert(p & 0xffffffu);
    double r = (p >> 16) & 255, g = (p >> 8) & 255, b = p & 255;
    double luma = (0.299 * r + 0.587 * g + 0.114 * b) / 255;
    sum += luma;
    sum2 += luma * luma;
    st.maxChannel = std::max({st.maxChannel, r, g, b});
  }
  double n = double(img.pixels.size()), mean = sum / n;
  st.distinct = int(colours.size());
  st.lumaStd = std::sqrt(std::max(0.0, sum2 / n - mean * mean));
  return st;
}

void expect_clean(const FrameStats& st, double t) {
  EXPECT_EQ(st.nonFinite, 0) << "t = " << t;
  EXPECT_EQ(st.negative, 0) << "t = " << t;
  EXPECT_EQ(st.packMismatch, 0) << "t = " << t << ": render_frame differs from trace()";
}

TEST(Frames, ThirtyTwoTimesAcrossTheLoopAreCleanAndNotFlat) {
  int worstDistinct = 1 << 30;
  double worstStd = 1e9;
  for (int i = 0; i < 32; ++i) {
    double t = 0.5 + 2.0 * i;
    FrameStats st = check_frame(t);
    expect_clean(st, t);
    // Not one flat colour: thousands of distinct colours and a spread of
    // brightness (measured: see the printed minima).
    EXPECT_GE(st.distinct, 1000) << "t = " << t;
    EXPECT_GE(st.lumaStd, 0.02) << "t = " << t;
    worstDistinct = std::min(worstDistinct, st.distinct);
    worstStd = std::min(worstStd, st.lumaStd);
  }
  std::printf("[ measured ] 32 frames at 0.5 + 2k s: every pixel finite, >= 0 and packed as "
              "traced; fewest distinct colours %d, lowest luma std dev %.3f\n",
              worstDistinct, worstStd);
}

TEST(Frames, SeamsFadeThroughBlackCleanly) {
  // The scenes fade in and out over 0.8 s at each end (scenes.cpp), so at the
  // cuts the picture is (nearly) black rather than popping: assert that, and
  // that it is still a clean picture underneath.
  for (double t : {0.0, 31.99, 32.0, 63.99, 64.0}) {
    FrameStats st = check_frame(t);
    expect_clean(st, t);
    EXPECT_LE(st.maxChannel, 2.0) << "t = " << t << ": not faded at the seam";
    if (t == 31.99 || t == 63.99) {
      EXPECT_TRUE(st.floatVaries) << t; // a scene, scaled down
    }
  }
  // One second inside each scene the fade is over and the frame has content.
  for (double t : {1.0, 31.0, 33.0, 63.0}) {
    FrameStats st = check_frame(t);
    expect_clean(st, t);
    EXPECT_GE(st.distinct, 1000) << "t = " << t;
  }
}

TEST(Frames, RendererVisualisationSegmentIsClean) {
  // Scene 2's blocks segment: the scene itself is an ordinary frame.
  double t = kSceneSeconds + kBlocksViewStart + 1.0;
  EXPECT_TRUE(timeline_state(t).showBlocks);
  FrameStats st = check_frame(t);
  expect_clean(st, t);
  EXPECT_GE(st.distinct, 1000);
}

// ------------------------------------------------------------ timeline

TEST(Timeline, WrapsNegativeHugeAndNonFiniteTimes) {
  EXPECT_EQ(timeline_wrap(0.0), 0.0f);
  EXPECT_EQ(timeline_wrap(10.25), 10.25f);
  EXPECT_EQ(timeline_wrap(64.0), 0.0f);
  EXPECT_EQ(timeline_wrap(64.5), 0.5f);
  EXPECT_EQ(timeline_wrap(-0.5), 63.5f);
  EXPECT_EQ(timeline_wrap(-64.0), 0.0f);
  EXPECT_EQ(timeline_wrap(-64.25), 63.75f);
  EXPECT_EQ(timeline_wrap(-1e-300), 0.0f); // rounds to 64, which is 0 again
  EXPECT_EQ(timeline_wrap(1e9), 0.0f);     // 64 * 15625000
  EXPECT_EQ(timeline_wrap(1e9 + 0.5), 0.5f);
  EXPECT_EQ(timeline_wrap(1e15 + 3.25), 3.25f); // 1e15 = 64 * 15625000000000
  EXPECT_EQ(timeline_wrap(-1e15 + 3.25), 3.25f);
  // Beyond 2^52 a double holds no fraction of a second: 0, documented.
  EXPECT_EQ(timeline_wrap(4503599627370496.0), 0.0f);
  EXPECT_EQ(timeline_wrap(1e300), 0.0f);
  EXPECT_EQ(timeline_wrap(-std::numeric_limits<double>::max()), 0.0f);
  // Non-finite: 0.
  EXPECT_EQ(timeline_wrap(std::numeric_limits<double>::infinity()), 0.0f);
  EXPECT_EQ(timeline_wrap(-std::numeric_limits<double>::infinity()), 0.0f);
  EXPECT_EQ(timeline_wrap(std::numeric_limits<double>::quiet_NaN()), 0.0f);
}

TEST(Timeline, WrapMatchesFmodAndStaysInRange) {
  std::mt19937 rng(64);
  std::uniform_real_distribution<double> small(-200, 200), big(-1e7, 1e7);
  double worst = 0;
  for (int i = 0; i < 200000; ++i) {
    double t = i & 1 ? small(rng) : big(rng);
    float w = timeline_wrap(t);
    ASSERT_GE(w, 0.0f) << t;
    ASSERT_LT(w, 64.0f) << t;
    double ref = std::fmod(t, 64.0);
    if (ref < 0) ref += 64;
    double err = std::fabs(double(w) - ref);
    err = std::min(err, 64 - err); // 63.9999999 and 0 are the same instant
    worst = std::max(worst, err);
    ASSERT_LE(err, 4e-6) << t; // float's half-spacing near 64 is 3.8e-6
  }
  std::printf("[ measured ] timeline_wrap vs fmod over 200,000 times in +-1e7 s: max %.3g s\n",
              worst);
}

TEST(Timeline, ScenesSwitchAtTheSeamsAndLoopExactly) {
  EXPECT_EQ(timeline_state(31.99).scene, 1);
  EXPECT_EQ(timeline_state(32.0).scene, 2);
  EXPECT_EQ(timeline_state(32.0).sceneTime, 0.0f);
  EXPECT_EQ(timeline_state(63.99).scene, 2);
  EXPECT_EQ(timeline_state(64.0).scene, 1);
  EXPECT_EQ(timeline_state(-0.01).scene, 2);
  EXPECT_FALSE(timeline_state(32 + kBlocksViewStart - 0.01).showBlocks);
  EXPECT_TRUE(timeline_state(32 + kBlocksViewStart).showBlocks);
  EXPECT_FALSE(timeline_state(32 + kBlocksViewStart + kBlocksViewSeconds).showBlocks);
  EXPECT_FALSE(timeline_state(kBlocksViewStart + 1).showBlocks); // scene 1: never
  // A time and the same time any number of loops later give the same scene.
  for (double t : {0.25, 7.5, 31.75, 40.125, 63.5}) {
    Scene a, b;
    build_timeline_scene(a, t);
    for (double loops : {-3.0, 1.0, 1000.0, 1e6}) {
      build_timeline_scene(b, t + 64 * loops);
      ASSERT_EQ(a.numObjects, b.numObjects);
      EXPECT_EQ(0, std::memcmp(&a.camera, &b.camera, sizeof a.camera)) << t << " " << loops;
      for (int i = 0; i < a.numObjects; ++i)
        EXPECT_EQ(0, std::memcmp(&a.objects[i].shape, &b.objects[i].shape, sizeof(Shape)))
            << t << " " << loops << " object " << i;
    }
  }
}

TEST(Timeline, ScenesAreFiniteAtEveryFrameTime) {
  // Every scene parameter finite over the loop at 60 fps (3840 times): a NaN
  // in a position or radius would reach the pixels only at some angles.
  auto finite3 = [](Vec3 v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
  };
  for (int f = 0; f < 3840; ++f) {
    double t = f / 60.0;
    Scene s;
    build_timeline_scene(s, t);
    ASSERT_TRUE(finite3(s.camera.pos) && finite3(s.camera.target)) << t;
    ASSERT_GT(s.numObjects, 0);
    for (int i = 0; i < s.numObjects; ++i) {
      const Shape& sh = s.objects[i].shape;
      ASSERT_TRUE(finite3(sh.a) && finite3(sh.b) && finite3(sh.c)) << t << " object " << i;
      ASSERT_TRUE(std::isfinite(sh.r0) && std::isfinite(sh.r1) && std::isfinite(sh.h)) << t;
    }
    for (int i = 0; i < s.numLights; ++i)
      ASSERT_TRUE(finite3(s.lights[i].pos) && finite3(s.lights[i].color)) << t;
  }
}

} // namespace
