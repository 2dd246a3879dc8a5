// test_adaptive_interp.cpp - the adaptive renderer's exact interpolation of
// 2-, 4- and 8-px square blocks (adaptive.cpp: interpolate_exact) against
// the float path it replaces there, and the fill's 8-px rows.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "adaptive.h"
#include "frame.h"
#include "scenes.h"

namespace {

struct Lcg {
  uint32_t seed;
  uint32_t next() {
    seed = seed * 1664525u + 1013904223u;
    return seed >> 8;
  }
};

// The exact bilinear value of channel `sh` at (x, y) of an S x S block,
// times S^2 (an integer), rounded to nearest with ties to even.
uint32_t bilinear_even(const uint32_t c[4], int sh, int size, int x, int y) {
  auto ch = [sh](uint32_t v) { return int(v >> sh & 255); };
  int p = (ch(c[0]) * (size - x) + ch(c[1]) * x) * (size - y) +
          (ch(c[2]) * (size - x) + ch(c[3]) * x) * y;
  int d = size * size, q = p / d, r = p % d;
  if (2 * r > d || (2 * r == d && q % 2 == 1)) ++q;
  return uint32_t(q);
}

} // namespace

// A block that owns neither its right column nor its bottom row, of 2, 4 or
// 8 px, takes the integer path; the same corners with xEnd = x1 + 1 and
// yEnd = y1 + 1 (a block at the image's corner) take the float path for
// the whole block. Every pixel both write is the same, and is the exact
// bilinear value rounded to nearest, ties to even; nothing outside the
// block is written. Seeded corners, a fifth of them with equal or extreme
// channels (0 and 255, ties on every midpoint).
TEST(AdaptiveInterpolate, ExactPathEqualsFloatPathBitForBit) {
  Lcg rng{2026};
  constexpr int kStride = 16, kRows = 12;
  constexpr uint32_t kGuard = 0x5a5a5a5au;
  int pixels = 0, ties = 0;
  for (int iter = 0; iter < 6000; ++iter) {
    int size = 2 << (iter % 3); // 2, 4, 8
    int x0 = 1 + int(rng.next() % 4), y0 = 1 + int(rng.next() % 2);
    uint32_t c[4];
    for (uint32_t& v : c)
      v = 0xff000000u | (rng.next() & 0xffffffu);
    if (iter % 5 == 0) {
      for (uint32_t& v : c) // channels 0 or 255 only, or one odd step apart
        v = 0xff000000u | ((rng.next() % 2 ? 0xff00ffu : 0x00ff00u) ^ (rng.next() & 0x010101u));
    }
    int x1 = x0 + size, y1 = y0 + size;
    std::vector<uint32_t> exact(kStride * kRows, kGuard), flt(kStride * kRows, kGuard);
    adaptive_interpolate(exact.data(), kStride, x0, y0, x1, y1, x1, y1, c[0], c[1], c[2], c[3]);
    adaptive_interpolate(flt.data(), kStride, x0, y0, x1, y1, x1 + 1, y1 + 1, c[0], c[1], c[2],
                         c[3]);
    for (int y = 0; y < kRows; ++y)
      for (int x = 0; x < kStride; ++x) {
        uint32_t p = exact[size_t(y * kStride + x)];
        if (x < x0 || x >= x1 || y < y0 || y >= y1) {
          ASSERT_EQ(p, kGuard) << "wrote outside the block at " << x << "," << y;
          continue;
        }
        ASSERT_EQ(p, flt[size_t(y * kStride + x)])
            << "iter " << iter << " size " << size << " at " << x - x0 << "," << y - y0;
        for (int sh = 0; sh < 24; sh += 8) {
          ASSERT_EQ(p >> sh & 255, bilinear_even(c, sh, size, x - x0, y - y0))
              << "iter " << iter << " size " << size << " at " << x - x0 << "," << y - y0;
          // A tie: the exact value is a half (the case ties-to-even decides).
          auto ch = [sh](uint32_t v) { return int(v >> sh & 255); };
          int fx = x - x0, fy = y - y0;
          int num = (ch(c[0]) * (size - fx) + ch(c[1]) * fx) * (size - fy) +
                    (ch(c[2]) * (size - fx) + ch(c[3]) * fx) * fy;
          if (2 * (num % (size * size)) == size * size) ++ties;
        }
        ASSERT_EQ(p >> 24, 255u);
        ++pixels;
      }
  }
  EXPECT_EQ(pixels, 2000 * (4 + 16 + 64));
  EXPECT_GT(ties, 10000); // the rounding of halves is exercised, not assumed
}

// The extremes of the 16-bit lanes: every corner 255 in every channel (the
// largest value, 255 * 64 + 31 before the shift), and 0 next to 255 (the
// largest step), at 8 px.
TEST(AdaptiveInterpolate, ExactPathAtTheChannelExtremes) {
  constexpr int kStride = 8;
  std::vector<uint32_t> fb(kStride * 8);
  adaptive_interpolate(fb.data(), kStride, 0, 0, 8, 8, 8, 8, 0xffffffffu, 0xffffffffu, 0xffffffffu,
                       0xffffffffu);
  for (uint32_t p : fb)
    ASSERT_EQ(p, 0xffffffffu);
  adaptive_interpolate(fb.data(), kStride, 0, 0, 8, 8, 8, 8, 0xff000000u, 0xffffffffu, 0xffffffffu,
                       0xff000000u);
  // Channel value at (x, y): (255 x (8 - y) + 255 (8 - x) y) / 64, rounded.
  EXPECT_EQ(fb[0], 0xff000000u);
  EXPECT_EQ(fb[7], 0xffdfdfdfu);               // 255 * 7 / 8 = 223.125
  EXPECT_EQ(fb[7 * kStride], 0xffdfdfdfu);     // the same, down the left side
  EXPECT_EQ(fb[4 * kStride + 4], 0xff808080u); // 255 * 32 / 64 = 127.5: ties to 128
  EXPECT_EQ(fb[2 * kStride + 2], 0xff606060u); // 255 * 24 / 64 = 95.625
}

// Copy: the 8-px rows' two stores and the general rows write the same
// colour on exactly the block's pixels, for widths 1-12 and 8 at offsets.
TEST(AdaptiveInterpolate, FillOfEightPixelRowsWritesExactlyTheBlock) {
  constexpr int kStride = 20;
  for (int x0 = 0; x0 < 4; ++x0)
    for (int w = 1; w <= 12; ++w) {
      std::vector<uint32_t> fb(kStride * 10, 7u);
      adaptive_fill(fb.data(), kStride, x0, 1, x0 + w, 9, 0xff336699u);
      int written = 0;
      for (int y = 0; y < 10; ++y)
        for (int x = 0; x < kStride; ++x) {
          bool in = x >= x0 && x < x0 + w && y >= 1 && y < 9;
          ASSERT_EQ(fb[size_t(y * kStride + x)], in ? 0xff336699u : 7u) << x0 << " " << w;
          written += in;
        }
      EXPECT_EQ(written, 8 * w);
    }
}

// Copy of no row, one row or two: the rows counted by offset (8 and 2 px)
// and the general rows write exactly those rows, for widths 0-9 (no row:
// yEnd = y0, and yEnd one above y0, write nothing).
TEST(AdaptiveInterpolate, FillOfNoRowOneRowOrTwoWritesExactlyThoseRows) {
  constexpr int kStride = 16;
  for (int rows = -1; rows <= 2; ++rows)
    for (int w = 0; w <= 9; ++w) {
      std::vector<uint32_t> fb(kStride * 6, 7u);
      adaptive_fill(fb.data(), kStride, 3, 2, 3 + w, 2 + rows, 0xff204060u);
      int written = 0;
      for (int y = 0; y < 6; ++y)
        for (int x = 0; x < kStride; ++x) {
          bool in = x >= 3 && x < 3 + w && y >= 2 && y < 2 + rows;
          ASSERT_EQ(fb[size_t(y * kStride + x)], in ? 0xff204060u : 7u) << rows << " " << w;
          written += in;
        }
      EXPECT_EQ(written, rows > 0 ? rows * w : 0);
    }
}

// In a frame, interpolated blocks go to the exact path unless the caller
// keeps a kinds map (or the blocks view): then every one takes the float
// path. Both give the same picture, at times of both scenes, for base
// blocks 8, 4 and 16 and an odd size whose edge blocks are not squares;
// the frame has many interpolated pixels (the exact path is exercised).
TEST(AdaptiveInterpolate, FrameWithAndWithoutKindsMapIsTheSame) {
  struct Case {
    double t;
    int w, h, block;
  };
  for (Case c : {Case{12.75, 400, 300, 8}, Case{44.0, 400, 300, 8}, Case{29.0, 203, 157, 4},
                 Case{58.75, 203, 157, 16}}) {
    Scene s;
    build_timeline_scene(s, c.t);
    Image exact(c.w, c.h), viaFloat(c.w, c.h);
    std::vector<uint8_t> kinds(size_t(c.w * c.h), 0);
    RenderOptions opt;
    opt.block = c.block;
    render_frame(s, exact, opt, nullptr);
    opt.kinds = kinds.data();
    render_frame(s, viaFloat, opt, nullptr);
    int interpolated = 0;
    for (uint8_t k : kinds)
      interpolated += (k & kKindMask) == kInterpolated;
    EXPECT_GT(interpolated, c.w * c.h / 5) << "t=" << c.t;
    EXPECT_EQ(exact.pixels, viaFloat.pixels) << "t=" << c.t << " " << c.w << "x" << c.h;
  }
}
