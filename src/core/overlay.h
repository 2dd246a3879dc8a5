// overlay.h - the intro's captions: title, credits and greetings drawn over
// the picture at chosen times, with a built-in 5x7 pixel font (no GDI text),
// so intro.exe and the Linux tool put identical pixels on screen.
#pragma once
#include "rtmath.h"

struct Caption {
  float start, end; // timeline seconds; fades in and out within [start, end]
  float centreY;    // vertical centre of the text block, as a fraction of the height
  u8 size; // glyph scale in units of height/600 px-per-font-pixel: 3 small, 4 normal, 8 title
  const char* text; // characters with a glyph (overlay_glyph), spaces; '\n' starts a line
};

extern const Caption kCaptions[];
extern const int kCaptionCount;

// Seconds of fade at each end of a caption.
constexpr float kCaptionFade = 0.6f;

// Draws every caption visible at timeline time t (seconds in [0, 64)) into a
// 0xAARRGGBB framebuffer, white with a dark drop shadow, alpha-blended.
void overlay_draw(u32* fb, int width, int height, int stride, float t);

// The font's glyph of character ch, or -1 when it has none (drawn as a
// space). The font holds only the characters the captions use.
int overlay_glyph(char ch);

// Opacity of caption c at time t, in [0, 1].
float caption_alpha(const Caption& c, float t);
