// adaptive.cpp - adaptive subsampling renderer; the contract is in adaptive.h.
#include "adaptive.h"

#include "packet/packet.h"

namespace {

typedef CornerSample Sample;

Sample trace_sample(const AdaptiveFrame& f, int x, int y, RayStats* stats) {
  Sample s;
  s.path.count = 0;
  TraceContext ctx{f.scene, {1, 0, 0}, &s.path};
  s.packed = pack_color(trace_primary(ctx, f.cam, (float)x, (float)y));
  stats->primary += ctx.stats.primary;
  stats->secondary += ctx.stats.secondary;
  stats->shadow += ctx.stats.shadow;
  return s;
}

// Up to four samples at once (packet/packet.h): out[k] for pixel (x[k], y[k]).
void trace_samples4(const AdaptiveFrame& f, const float x[4], const float y[4], int count,
                    Sample out[4], RayStats* stats) {
  u32 packed[4];
  PathRecord path[4];
  trace_primary4_packed(*f.scene, f.cam, x, y, count, packed, path, stats);
  for (int k = 0; k < count; ++k)
    out[k] = Sample{packed[k], path[k]};
}

int grid_count(int size, int block) {
  int n = (size - 1 + block - 1) / block + 1;
  return n < 2 ? 2 : n;
}

int grid_coord(int i, int block, int size) {
  int c = i * block;
  return c < size - 1 ? c : size - 1;
}

// A block: corners at x0, x1 (x1 >= x0) and y0, y1; owns [x0, xEnd) x [y0, yEnd).
struct Block {
  int x0, y0, x1, y1, xEnd, yEnd;
};

void mark(const AdaptiveFrame& f, const Block& b, BlockKind kind) {
  if (!f.kinds) return;
  for (int y = b.y0; y < b.yEnd; ++y)
    for (int x = b.x0; x < b.xEnd; ++x) f.kinds[y * f.width + x] = kind;
}

void fill(const AdaptiveFrame& f, const Block& b, u32 packed) {
  mark(f, b, kCopied);
  if (f.showBlocks) packed = tint_copied(packed);
  for (int y = b.y0; y < b.yEnd; ++y) {
    u32* row = f.fb + y * f.stride;
    for (int x = b.x0; x < b.xEnd; ++x) row[x] = packed;
  }
}

// Bilinear interpolation of the packed corner colours in 8.16 fixed point:
// each channel's value at the block's left and right edge is stepped down the
// rows, and along each row by a constant increment. Rounds to nearest.
void interpolate(const AdaptiveFrame& f, const Block& b, u32 c00, u32 c10, u32 c01, u32 c11) {
  mark(f, b, kInterpolated);
  int spanX = b.x1 - b.x0, spanY = b.y1 - b.y0;
  i32 invX = spanX ? 65536 / spanX : 0, invY = spanY ? 65536 / spanY : 0;
  for (int y = b.y0; y < b.yEnd; ++y) {
    i32 wy = (y - b.y0) * invY;  // 16-bit fraction
    if (y == b.y1) wy = 65536;
    u32* row = f.fb + y * f.stride;
    i32 value[3], step[3], right[3];
    for (int ch = 0; ch < 3; ++ch) {
      int sh = 16 - 8 * ch;
      i32 a = (i32)(c00 >> sh & 255), bb = (i32)(c01 >> sh & 255);
      i32 c = (i32)(c10 >> sh & 255), d = (i32)(c11 >> sh & 255);
      i32 l = (a << 16) + (bb - a) * wy;  // left edge, 8.16
      i32 r = (c << 16) + (d - c) * wy;   // right edge
      value[ch] = l + 32768;              // + 0.5 rounds to nearest
      right[ch] = r + 32768;
      step[ch] = (i32)(((long long)(r - l) * invX) >> 16);
    }
    for (int x = b.x0; x < b.xEnd; ++x) {
      // Only a block at the image's right edge owns its right corner column:
      // that column takes the right edge's value exactly.
      const i32* v = x == b.x1 ? right : value;
      u32 p = 0xff000000u | (u32)(v[0] >> 16) << 16 | (u32)(v[1] >> 16) << 8 | (u32)(v[2] >> 16);
      row[x] = f.showBlocks ? tint_interpolated(p) : p;
      for (int ch = 0; ch < 3; ++ch) value[ch] += step[ch];
    }
  }
}

void trace_all(const AdaptiveFrame& f, const Block& b, const Sample& c00, RayStats* stats) {
  mark(f, b, kTraced);
  f.fb[b.y0 * f.stride + b.x0] = c00.packed;
  float xs[4], ys[4];
  int n = 0;
  for (int y = b.y0; y < b.yEnd; ++y)
    for (int x = b.x0; x < b.xEnd; ++x) {
      if (x == b.x0 && y == b.y0) continue;
      xs[n] = (float)x;
      ys[n++] = (float)y;
      bool last = y + 1 == b.yEnd && x + 1 == b.xEnd;
      if (n < 4 && !last) continue;
      u32 packed[4];
      trace_primary4_packed(*f.scene, f.cam, xs, ys, n, packed, nullptr, stats);
      for (int k = 0; k < n; ++k)
        f.fb[(int)ys[k] * f.stride + (int)xs[k]] = packed[k];
      n = 0;
    }
}

void process(const AdaptiveFrame& f, const Block& b, const Sample& c00, const Sample& c10,
             const Sample& c01, const Sample& c11, RayStats* stats) {
  BlockKind kind = adaptive_decide(c00, c10, c01, c11, f.mode);
  if (kind == kCopied) {
    fill(f, b, c00.packed);
    return;
  }
  if (kind == kInterpolated) {
    interpolate(f, b, c00.packed, c10.packed, c01.packed, c11.packed);
    return;
  }
  int w = b.x1 - b.x0, h = b.y1 - b.y0;
  if ((w <= f.minBlock && h <= f.minBlock) || (w < 2 && h < 2)) {
    trace_all(f, b, c00, stats);
    return;
  }
  // Split at the midpoints; sides of length < 2 are not split.
  int xm = w >= 2 ? (b.x0 + b.x1) / 2 : b.x1;
  int ym = h >= 2 ? (b.y0 + b.y1) / 2 : b.y1;
  bool splitX = xm != b.x1, splitY = ym != b.y1;
  Sample top = splitX ? trace_sample(f, xm, b.y0, stats) : c10;
  Sample bottom = splitX ? trace_sample(f, xm, b.y1, stats) : c11;
  Sample left = splitY ? trace_sample(f, b.x0, ym, stats) : c01;
  Sample right = splitY ? trace_sample(f, b.x1, ym, stats) : c11;
  if (splitX && splitY) {
    Sample mid = trace_sample(f, xm, ym, stats);
    process(f, Block{b.x0, b.y0, xm, ym, xm, ym}, c00, top, left, mid, stats);
    process(f, Block{xm, b.y0, b.x1, ym, b.xEnd, ym}, top, c10, mid, right, stats);
    process(f, Block{b.x0, ym, xm, b.y1, xm, b.yEnd}, left, mid, c01, bottom, stats);
    process(f, Block{xm, ym, b.x1, b.y1, b.xEnd, b.yEnd}, mid, right, bottom, c11, stats);
  } else if (splitX) {  // a block one pixel high: split left/right only
    process(f, Block{b.x0, b.y0, xm, b.y1, xm, b.yEnd}, c00, top, c01, bottom, stats);
    process(f, Block{xm, b.y0, b.x1, b.y1, b.xEnd, b.yEnd}, top, c10, bottom, c11, stats);
  } else {  // a block one pixel wide: split top/bottom only
    process(f, Block{b.x0, b.y0, b.x1, ym, b.xEnd, ym}, c00, c10, left, right, stats);
    process(f, Block{b.x0, ym, b.x1, b.y1, b.xEnd, b.yEnd}, left, right, c01, c11, stats);
  }
}

}  // namespace

// Colour copy needs equal colours AND equal records: two different objects
// of one colour are not one surface. Interpolation needs equal records.
BlockKind adaptive_decide(const CornerSample& c00, const CornerSample& c10,
                          const CornerSample& c01, const CornerSample& c11, AdaptiveMode mode) {
  bool samePath = same_path(c00.path, c10.path) && same_path(c00.path, c01.path) &&
                  same_path(c00.path, c11.path);
  if (!samePath) return kSplit;
  if (c00.packed == c10.packed && c00.packed == c01.packed && c00.packed == c11.packed)
    return kCopied;
  return mode == kModeAdaptive ? kInterpolated : kSplit;
}

u32 tint_copied(u32 p) { return (p >> 1 & 0x7f7f7fu) | 0xff800000u; }
u32 tint_interpolated(u32 p) { return (p >> 1 & 0x7f7f7fu) | 0xff000080u; }

int adaptive_corner_count(int width, int height, int baseBlock) {
  return grid_count(width, baseBlock) * grid_count(height, baseBlock);
}

void adaptive_begin(AdaptiveFrame& f) {
  f.cam = camera_rays(*f.scene, f.width, f.height);
  f.gridW = grid_count(f.width, f.baseBlock);
  f.gridH = grid_count(f.height, f.baseBlock);
}

int adaptive_items(const AdaptiveFrame& f, int phase) { return phase == 0 ? f.gridH : f.gridH - 1; }

void adaptive_run(const AdaptiveFrame& f, int phase, int item, RayStats* stats) {
  Sample* grid = f.corners;
  int B = f.baseBlock;
  if (phase == 0) {
    float y = (float)grid_coord(item, B, f.height), xs[4], ys[4] = {y, y, y, y};
    for (int i = 0; i < f.gridW; i += 4) {
      int n = f.gridW - i < 4 ? f.gridW - i : 4;
      for (int k = 0; k < n; ++k)
        xs[k] = (float)grid_coord(i + k, B, f.width);
      trace_samples4(f, xs, ys, n, grid + item * f.gridW + i, stats);
    }
    return;
  }
  int y0 = grid_coord(item, B, f.height), y1 = grid_coord(item + 1, B, f.height);
  int yEnd = item + 1 == f.gridH - 1 ? f.height : y1;
  for (int i = 0; i + 1 < f.gridW; ++i) {
    int x0 = grid_coord(i, B, f.width), x1 = grid_coord(i + 1, B, f.width);
    int xEnd = i + 2 == f.gridW ? f.width : x1;
    const Sample* row0 = grid + item * f.gridW;
    const Sample* row1 = row0 + f.gridW;
    process(f, Block{x0, y0, x1, y1, xEnd, yEnd}, row0[i], row0[i + 1], row1[i], row1[i + 1],
            stats);
  }
}
