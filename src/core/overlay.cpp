// overlay.cpp - captions and their pixel font.
#include "overlay.h"

namespace {

// The characters the font has, in table order; others draw as a space. Only
// those the captions use (model only what the intro needs: the 20 glyphs
// no caption drew cost 140 bytes; tests/test_overlay.cpp checks that every
// caption character is here).
constexpr char kFontChars[] = "ABCDEFGHIKLMNOPRSTUWY01246,:-";
constexpr int kGlyphW = 5, kGlyphH = 7;
constexpr int kAdvance = 6;      // glyph width plus one column of spacing
constexpr int kLineAdvance = 10; // glyph height plus three rows of leading

// Rows top to bottom, bit 4 = leftmost column. Drawn for rt64k.
constexpr u8 kFont[][kGlyphH] = {
    {0b01110, 0b10001, 0b10001, 0b11111, 0b10001, 0b10001, 0b10001}, // A
    {0b11110, 0b10001, 0b10001, 0b11110, 0b10001, 0b10001, 0b11110}, // B
    {0b01110, 0b10001, 0b10000, 0b10000, 0b10000, 0b10001, 0b01110}, // C
    {0b11110, 0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b11110}, // D
    {0b11111, 0b10000, 0b10000, 0b11110, 0b10000, 0b10000, 0b11111}, // E
    {0b11111, 0b10000, 0b10000, 0b11110, 0b10000, 0b10000, 0b10000}, // F
    {0b01110, 0b10001, 0b10000, 0b10111, 0b10001, 0b10001, 0b01111}, // G
    {0b10001, 0b10001, 0b10001, 0b11111, 0b10001, 0b10001, 0b10001}, // H
    {0b01110, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b01110}, // I
    {0b10001, 0b10010, 0b10100, 0b11000, 0b10100, 0b10010, 0b10001}, // K
    {0b10000, 0b10000, 0b10000, 0b10000, 0b10000, 0b10000, 0b11111}, // L
    {0b10001, 0b11011, 0b10101, 0b10101, 0b10001, 0b10001, 0b10001}, // M
    {0b10001, 0b11001, 0b10101, 0b10011, 0b10001, 0b10001, 0b10001}, // N
    {0b01110, 0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b01110}, // O
    {0b11110, 0b10001, 0b10001, 0b11110, 0b10000, 0b10000, 0b10000}, // P
    {0b11110, 0b10001, 0b10001, 0b11110, 0b10100, 0b10010, 0b10001}, // R
    {0b01111, 0b10000, 0b10000, 0b01110, 0b00001, 0b00001, 0b11110}, // S
    {0b11111, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100, 0b00100}, // T
    {0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b10001, 0b01110}, // U
    {0b10001, 0b10001, 0b10001, 0b10101, 0b10101, 0b10101, 0b01010}, // W
    {0b10001, 0b10001, 0b01010, 0b00100, 0b00100, 0b00100, 0b00100}, // Y
    {0b01110, 0b10001, 0b10011, 0b10101, 0b11001, 0b10001, 0b01110}, // 0
    {0b00100, 0b01100, 0b00100, 0b00100, 0b00100, 0b00100, 0b01110}, // 1
    {0b01110, 0b10001, 0b00001, 0b00010, 0b00100, 0b01000, 0b11111}, // 2
    {0b00010, 0b00110, 0b01010, 0b10010, 0b11111, 0b00010, 0b00010}, // 4
    {0b00110, 0b01000, 0b10000, 0b11110, 0b10001, 0b10001, 0b01110}, // 6
    {0b00000, 0b00000, 0b00000, 0b00000, 0b01100, 0b00100, 0b01000}, // ,
    {0b00000, 0b01100, 0b01100, 0b00000, 0b01100, 0b01100, 0b00000}, // :
    {0b00000, 0b00000, 0b00000, 0b11111, 0b00000, 0b00000, 0b00000}, // -
};

int line_length(const char* s) {
  int n = 0;
  while (s[n] && s[n] != '\n')
    ++n;
  return n;
}

// Blends colour (0xRRGGBB) into the pixel with alpha in [0, 256].
inline void blend(u32& dst, u32 colour, u32 alpha) {
  u32 inv = 256 - alpha;
  u32 rb = ((dst & 0xff00ffu) * inv + (colour & 0xff00ffu) * alpha) >> 8 & 0xff00ffu;
  u32 g = ((dst & 0x00ff00u) * inv + (colour & 0x00ff00u) * alpha) >> 8 & 0x00ff00u;
  dst = 0xff000000u | rb | g;
}

// One pass over the text: the shadow pass draws every lit font pixel
// offset by `shadow` screen pixels in a dark colour.
void draw_text(u32* fb, int width, int height, int stride, const Caption& c, u32 colour, u32 alpha,
               int shadow) {
  int scale = (int)c.size * height / 600;
  if (scale < 1) scale = 1;
  int lines = 1;
  for (const char* p = c.text; *p; ++p)
    lines += *p == '\n';
  int blockH = ((lines - 1) * kLineAdvance + kGlyphH) * scale;
  int y0 = (int)(c.centreY * (float)height) - blockH / 2 + shadow;
  for (const char* line = c.text;; ++line) {
    int n = line_length(line);
    int x0 = (width - (n * kAdvance - 1) * scale) / 2 + shadow;
    for (int i = 0; i < n; ++i) {
      int g = overlay_glyph(line[i]);
      if (g < 0) continue;
      for (int row = 0; row < kGlyphH; ++row) {
        for (int col = 0; col < kGlyphW; ++col) {
          if (!(kFont[g][row] >> (kGlyphW - 1 - col) & 1)) continue;
          int px = x0 + (i * kAdvance + col) * scale, py = y0 + row * scale;
          for (int y = py; y < py + scale; ++y) {
            if (y < 0 || y >= height) continue;
            for (int x = px; x < px + scale; ++x)
              if (x >= 0 && x < width) blend(fb[y * stride + x], colour, alpha);
          }
        }
      }
    }
    line += n;
    if (!*line) break;
    y0 += kLineAdvance * scale;
  }
}

} // namespace

int overlay_glyph(char ch) {
  for (int i = 0; kFontChars[i]; ++i)
    if (kFontChars[i] == ch) return i;
  return -1;
}

// The captions. Scene 1 (0-32 s) is dark: text sits low over the floor.
// Scene 2 (32-64 s) is bright: the shadow keeps white text readable. The
// line at 50-54 s names the colours of the renderer-visualisation segment.
const Caption kCaptions[] = {
    {1.2f, 7.0f, 0.80f, 8, "RT64K"},
    {2.2f, 7.0f, 0.92f, 3, "REAL-TIME RAY TRACING IN 64K"},
    {11.0f, 16.5f, 0.90f, 3, "CODE, MUSIC AND MATHS: THE RT64K TEAM"},
    {18.0f, 23.5f, 0.90f, 3, "AFTER A 2010 THESIS BY MICHAL BUTKO"},
    {25.0f, 30.5f, 0.90f, 3, "PHONG - MIRRORS - GLASS - TINTED SHADOWS"},
    {33.5f, 39.0f, 0.10f, 3, "COOK-TORRANCE GOLD"},
    {50.1f, 53.9f, 0.08f, 3, "RED: COLOUR COPY   BLUE: INTERPOLATED"},
    {55.5f, 62.5f, 0.84f, 3,
     "GREETINGS TO\nFARBRAUSCH - CONSPIRACY - MERCURY\nLOGICOMA - FAIRLIGHT - ASD"},
};
const int kCaptionCount = sizeof(kCaptions) / sizeof(kCaptions[0]);

float caption_alpha(const Caption& c, float t) {
  if (t <= c.start || t >= c.end) return 0.0f;
  return smooth01((t - c.start) / kCaptionFade) * smooth01((c.end - t) / kCaptionFade);
}

void overlay_draw(u32* fb, int width, int height, int stride, float t) {
  for (int i = 0; i < kCaptionCount; ++i) {
    float a = caption_alpha(kCaptions[i], t);
    if (a <= 0) continue;
    u32 alpha = (u32)(a * 256.0f + 0.5f);
    int shadow = height >= 300 ? 2 * height / 600 + 1 : 1;
    draw_text(fb, width, height, stride, kCaptions[i], 0x000000u, alpha * 3 / 4, shadow);
    draw_text(fb, width, height, stride, kCaptions[i], 0xffffffu, alpha, 0);
  }
}
