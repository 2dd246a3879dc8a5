// Captions (issue 5): they appear at their times, fade, and stay inside the frame.
#include <gtest/gtest.h>

#include <vector>

#include "overlay.h"

namespace {

constexpr int kW = 800, kH = 600;
constexpr uint32_t kGrey = 0xff404040u;

// Pixels the overlay changed on a flat grey frame at timeline time t.
int changed_pixels(float t) {
  std::vector<uint32_t> fb(kW * kH, kGrey);
  overlay_draw(fb.data(), kW, kH, kW, t);
  int n = 0;
  for (uint32_t p : fb)
    n += p != kGrey;
  return n;
}

TEST(Overlay, EveryCaptionShowsInsideItsTimesAndNothingOutside) {
  ASSERT_GT(kCaptionCount, 0);
  for (int i = 0; i < kCaptionCount; ++i) {
    const Caption& c = kCaptions[i];
    float mid = 0.5f * (c.start + c.end);
    EXPECT_FLOAT_EQ(caption_alpha(c, mid), 1.0f) << c.text;
    EXPECT_GT(changed_pixels(mid), 500) << c.text; // a line of text at scale 3+
    EXPECT_EQ(caption_alpha(c, c.start - 0.01f), 0.0f) << c.text;
    EXPECT_EQ(caption_alpha(c, c.end + 0.01f), 0.0f) << c.text;
  }
  // Times no caption covers: nothing drawn.
  for (float t : {0.5f, 9.0f, 17.0f, 31.5f, 45.0f, 63.5f}) {
    for (int i = 0; i < kCaptionCount; ++i)
      ASSERT_FALSE(t > kCaptions[i].start && t < kCaptions[i].end) << "pick another time";
    EXPECT_EQ(changed_pixels(t), 0) << "t=" << t;
  }
}

// The font holds only the characters the captions use: each caption
// character has a glyph (or is a space or a line break), and characters no
// caption uses have none.
TEST(Overlay, FontHoldsEveryCaptionCharacter) {
  bool used[256] = {};
  for (int i = 0; i < kCaptionCount; ++i)
    for (const char* p = kCaptions[i].text; *p; ++p) {
      used[(unsigned char)*p] = true;
      if (*p != ' ' && *p != '\n') {
        EXPECT_GE(overlay_glyph(*p), 0) << "'" << *p << "' in " << kCaptions[i].text;
      }
    }
  int glyphs = 0;
  for (int ch = 1; ch < 256; ++ch) {
    int g = overlay_glyph((char)ch);
    if (g < 0) continue;
    ++glyphs;
    EXPECT_TRUE(used[ch]) << "glyph for '" << (char)ch << "' that no caption uses";
  }
  EXPECT_EQ(glyphs, 29);
  EXPECT_EQ(overlay_glyph(' '), -1);
  EXPECT_EQ(overlay_glyph('J'), -1);
}

TEST(Overlay, FadesInAndOutSmoothly) {
  const Caption& c = kCaptions[0];
  float prev = 0;
  for (float t = c.start; t <= c.start + kCaptionFade; t += 0.05f) {
    float a = caption_alpha(c, t);
    EXPECT_GE(a, prev);
    EXPECT_LE(a, 1.0f);
    prev = a;
  }
  EXPECT_GT(caption_alpha(c, c.start + 0.5f * kCaptionFade), 0.1f);
  EXPECT_LT(caption_alpha(c, c.start + 0.5f * kCaptionFade), 0.9f);
}

TEST(Overlay, TitleIsWhiteOverAShadowAndFramesOfAnySizeAreSafe) {
  std::vector<uint32_t> fb(kW * kH, kGrey);
  float mid = 0.5f * (kCaptions[0].start + kCaptions[0].end);
  overlay_draw(fb.data(), kW, kH, kW, mid);
  int white = 0, darker = 0;
  for (uint32_t p : fb) {
    white += p == 0xffffffffu;
    darker += (p & 0xff) < 0x40;
  }
  EXPECT_GT(white, 1000);
  EXPECT_GT(darker, 500);
  // Tiny and odd sizes: nothing written outside the buffer (its guard words
  // stay intact), no crash.
  for (int w : {1, 7, 33}) {
    for (int h : {1, 5, 40}) {
      std::vector<uint32_t> buf(size_t(w * h) + 2, 0xdeadbeefu);
      overlay_draw(buf.data() + 1, w, h, w, mid);
      EXPECT_EQ(buf.front(), 0xdeadbeefu);
      EXPECT_EQ(buf.back(), 0xdeadbeefu);
    }
  }
}

} // namespace
