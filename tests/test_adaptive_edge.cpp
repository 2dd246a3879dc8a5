// test_adaptive_edge.cpp - round twelve (docs/speed-vs-error.md "Round
// twelve: the shadow edge and the renderer's own work"): the upper cone's
// shadow edge on the floor at 13 s, which adaptive8 draws about a pixel
// higher than the full trace at the left of the picture, is the small-contrast
// rule (adaptive.cpp: kSmallContrast) interpolating 4-px blocks whose records
// differ, each pixel the exact bilinear value of corners that are the full
// trace's pixels: not a sample placed, read or interpolated at the wrong
// pixel. And the split blocks' children (process_group writes their fields
// directly since round twelve) tile each split block exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "adaptive.h"
#include "frame.h"
#include "scenes.h"

namespace {

constexpr int kW = 800, kH = 600;

int channel(uint32_t p, int k) { return int(p >> (8 * k) & 255); }

// The bilinear value at (x, y) of a 4 x 4 block (corners c00, c10, c01,
// c11), rounded to nearest, ties to even, per channel: the value times 16 is
// an integer.
uint32_t bilinear4(uint32_t c00, uint32_t c10, uint32_t c01, uint32_t c11, int x, int y) {
  uint32_t out = 0xff000000u;
  for (int k = 0; k < 3; ++k) {
    int p = (channel(c00, k) * (4 - x) + channel(c10, k) * x) * (4 - y) +
            (channel(c01, k) * (4 - x) + channel(c11, k) * x) * y;
    int q = p / 16, r = p % 16;
    if (r > 8 || (r == 8 && q % 2 == 1)) ++q;
    out |= uint32_t(q) << (8 * k);
  }
  return out;
}

// A side's midpoint estimated from its ends (adaptive_estimate): per channel
// (a + b + 1) / 2.
uint32_t estimated(uint32_t a, uint32_t b) {
  uint32_t out = 0xff000000u;
  for (int k = 0; k < 3; ++k)
    out |= uint32_t((channel(a, k) + channel(b, k) + 1) / 2) << (8 * k);
  return out;
}

CornerSample traced_sample(const Scene& s, const CameraRays& cam, int x, int y) {
  CornerSample c{};
  TraceContext ctx{&s, {0, 0, 0}, &c.path};
  c.packed = pack_color(trace(ctx, primary_ray(cam, float(x), float(y)), 1));
  return c;
}

// The band y = 368..376, x = 0..96 (12 base blocks of 8 px) at 13 s: the top
// edge of the upper cone's shadow on the floor crosses it between rows 371
// and 373. Every base block there splits (its top corners lit, its bottom
// ones in the shadow: the records differ) into four 4-px children; every
// child is interpolated, those the edge crosses by the small-contrast rule
// (their corners' records differ by the shadow code, their colours by at
// most 16/255 = kSmallContrast[1]). The samples: the base corners and
// the children's corners on row 372 traced (the full trace's pixels), the
// midpoints of the base blocks' top and bottom sides estimated from their
// ends. Each pixel is the exact bilinear value of its child's corners. So
// the step (rows 369-371 darker than the full trace for x = 12..57, rows
// 373-375 lighter for x < 12 and x > 57) is the rule's own error, measured
// here.
TEST(AdaptiveFrame, ShadowEdgeAtThirteenSecondsIsTheSmallContrastRule) {
  Scene s;
  build_timeline_scene(s, 13.0);
  Image full(kW, kH), adaptive(kW, kH);
  RenderOptions fo;
  fo.mode = Mode::Full;
  fo.threads = 2;
  render_frame(s, full, fo, nullptr);
  std::vector<uint8_t> kinds(size_t(kW) * kH, kSplit);
  RenderOptions opt;
  opt.threads = 2;
  opt.kinds = kinds.data();
  render_frame(s, adaptive, opt, nullptr);

  const int y0 = 368, x1 = 96;
  auto at = [](const Image& img, int x, int y) { return img.pixels[size_t(y) * kW + size_t(x)]; };
  // The children's corners, rows 368, 372, 376 and every 4th column:
  // traced where the full trace's pixel is the sample (one sample there),
  // else estimated (the base blocks' top and bottom midpoints).
  uint32_t grid[3][x1 / 4 + 1];
  int traced = 0, estimates = 0;
  for (int r = 0; r < 3; ++r)
    for (int i = 0; i <= x1 / 4; ++i) {
      int x = 4 * i, y = y0 + 4 * r;
      if (r != 1 && i % 2 == 1) {
        ++estimates;
        grid[r][i] = estimated(at(full, x - 4, y), at(full, x + 4, y));
        EXPECT_EQ(kinds[size_t(y) * kW + size_t(x)] >> kSampleCountShift, 0) << x << "," << y;
      } else {
        ++traced;
        grid[r][i] = at(full, x, y);
        EXPECT_EQ(kinds[size_t(y) * kW + size_t(x)] >> kSampleCountShift, 1) << x << "," << y;
      }
    }
  EXPECT_EQ(traced, 25 + 2 * 13);
  EXPECT_EQ(estimates, 2 * 12);
  int interpolated = 0;
  for (int r = 0; r < 2; ++r)
    for (int i = 0; i < x1 / 4; ++i) {
      int bx = 4 * i, by = y0 + 4 * r;
      uint32_t c00 = grid[r][i], c10 = grid[r][i + 1], c01 = grid[r + 1][i],
               c11 = grid[r + 1][i + 1];
      for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
          ASSERT_EQ(at(adaptive, bx + x, by + y), bilinear4(c00, c10, c01, c11, x, y))
              << "pixel " << bx + x << "," << by + y;
          interpolated +=
              (kinds[size_t(by + y) * kW + size_t(bx + x)] & kKindMask) == kInterpolated;
        }
    }
  EXPECT_EQ(interpolated, 8 * x1);

  // The records at the children's corners (traced here; an estimated
  // corner takes its ends' record, the same as this): the shadow edge
  // crosses row 372 near x = 10 and x = 58, so it crosses the upper
  // children at x = 8..56 (lit on row 368, shadowed on row 372 between) and
  // the lower ones at x = 0..8 and 56..92 (lit on row 372 outside, shadowed
  // on row 376). Each such child is
  // interpolated across a record difference that is light 0's shadow code
  // (bits 5-6 of the floor's node) alone, its corners' colours spanning
  // more than kEstimateContrast and at most kSmallContrast[1] per channel.
  CameraRays cam = camera_rays(s, kW, kH);
  CornerSample rec[3][x1 / 4 + 1];
  for (int r = 0; r < 3; ++r)
    for (int i = 0; i <= x1 / 4; ++i)
      rec[r][i] = traced_sample(s, cam, 4 * i, y0 + 4 * r);
  int crossed = 0, upper = 0;
  for (int r = 0; r < 2; ++r)
    for (int i = 0; i < x1 / 4; ++i) {
      const CornerSample* c[4] = {&rec[r][i], &rec[r][i + 1], &rec[r + 1][i], &rec[r + 1][i + 1]};
      bool same = true;
      for (int q = 1; q < 4; ++q) {
        ASSERT_EQ(c[q]->path.count, 2) << 4 * i << "," << y0 + 4 * r;
        uint32_t d = c[q]->path.node[0] ^ c[0]->path.node[0];
        EXPECT_TRUE(d == 0 || d == 3u << 5) << 4 * i << "," << y0 + 4 * r;
        EXPECT_EQ(c[q]->path.node[1], c[0]->path.node[1]) << 4 * i << "," << y0 + 4 * r;
        same = same && same_path(c[q]->path, c[0]->path);
      }
      if (same) continue;
      ++crossed;
      upper += r == 0;
      uint32_t g[4] = {grid[r][i], grid[r][i + 1], grid[r + 1][i], grid[r + 1][i + 1]};
      int span = 0;
      for (int k = 0; k < 3; ++k) {
        int lo = 255, hi = 0;
        for (uint32_t p : g) {
          lo = std::min(lo, channel(p, k));
          hi = std::max(hi, channel(p, k));
        }
        span = std::max(span, hi - lo);
      }
      EXPECT_GT(span, 8) << 4 * i << "," << y0 + 4 * r;
      EXPECT_LE(span, 16) << 4 * i << "," << y0 + 4 * r;
    }
  EXPECT_EQ(crossed, 13 + 3 + 10);
  EXPECT_EQ(upper, 13);

  // The error it costs against the full trace, the region's pixels: off by
  // more than 8/255 in a channel, and the largest difference.
  int off = 0, worst = 0;
  for (int y = y0; y < y0 + 8; ++y)
    for (int x = 0; x < x1; ++x) {
      int d = 0;
      for (int k = 0; k < 3; ++k)
        d = std::max(d, std::abs(channel(at(adaptive, x, y), k) - channel(at(full, x, y), k)));
      worst = std::max(worst, d);
      off += d > 8;
    }
  EXPECT_EQ(worst, 12);
  EXPECT_EQ(off, 82);
}

} // namespace
