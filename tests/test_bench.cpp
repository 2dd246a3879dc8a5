// Tests of the bench's figures (issue 9): error against the reference,
// flicker between two frames, and the frame-time summary a viewer feels.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "bench.h"

namespace {

Image flat(int w, int h, uint32_t c) {
  Image img(w, h);
  for (uint32_t& p : img.pixels)
    p = c;
  return img;
}

TEST(BenchFigures, CompareCountsEveryChannel) {
  Image ref = flat(4, 2, 0xff102030u), img = ref;
  EXPECT_TRUE(std::isinf(compare_images(ref, img).psnr));
  img.at(1, 0) = 0xff102039u; // blue off by 9: over 8/255
  img.at(2, 1) = 0xff182030u; // red off by 8: not over
  FrameError e = compare_images(ref, img);
  EXPECT_EQ(e.maxError, 9);
  EXPECT_DOUBLE_EQ(e.offPercent, 100.0 / 8);
  // MSE over 8 pixels x 3 channels: (81 + 64) / 24.
  EXPECT_NEAR(e.psnr, 10 * std::log10(255.0 * 255.0 / (145.0 / 24)), 1e-9);
}

TEST(BenchFigures, FlickerIsAChangeOfErrorNotOfPicture) {
  constexpr int kW = 10, kH = 10;
  Image ref0 = flat(kW, kH, 0xff808080u), ref1 = flat(kW, kH, 0xff404040u);
  // The picture darkens by 64 everywhere and the adaptive one follows it
  // exactly: a change on screen, but no flicker.
  EXPECT_EQ(flicker_percent(ref0, ref0, ref1, ref1), 0.0);
  // A constant error (a red highlight missed in both frames) does not
  // flicker, however the picture changes around it.
  Image img0 = ref0, img1 = ref1;
  ref0.at(0, 0) = 0xffc08080u;
  ref1.at(0, 0) = 0xff804040u;
  img0.at(0, 0) = 0xff408080u; // red 128 short in both frames
  img1.at(0, 0) = 0xff004040u;
  EXPECT_EQ(flicker_percent(ref0, img0, ref1, img1), 0.0);
  // Missed in frame 0 only: the error changes by 128 there.
  img1.at(0, 0) = ref1.at(0, 0);
  EXPECT_DOUBLE_EQ(flicker_percent(ref0, img0, ref1, img1), 1.0);
  // An error of 33 in one channel appearing: flickers; 32 does not.
  img1.at(5, 5) = 0xff404040u + 33;
  img1.at(6, 6) = 0xff404040u + 32;
  EXPECT_DOUBLE_EQ(flicker_percent(ref0, img0, ref1, img1), 2.0);
  // Signed: an error of +20 turning into -20 changes it by 40.
  img0.at(7, 7) = 0xff808080u + (20 << 8);
  img1.at(7, 7) = 0xff404040u - (20 << 8);
  EXPECT_DOUBLE_EQ(flicker_percent(ref0, img0, ref1, img1), 3.0);
}

TEST(BenchFigures, FrameTimesAreNearestRankWithFrameRates) {
  std::vector<double> ms;
  for (int i = 1; i <= 20; ++i)
    ms.push_back(double(21 - i)); // 20, 19, ..., 1
  FrameTimes t = frame_times(ms);
  EXPECT_EQ(t.median, 10.0); // rank ceil(0.5 * 20) = 10
  EXPECT_EQ(t.p95, 19.0);    // rank ceil(0.95 * 20) = 19
  EXPECT_EQ(t.max, 20.0);
  EXPECT_DOUBLE_EQ(t.fpsMedian, 100.0);
  EXPECT_DOUBLE_EQ(t.fpsSlowest, 50.0);
}

} // namespace
