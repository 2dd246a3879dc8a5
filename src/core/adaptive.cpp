// adaptive.cpp - adaptive subsampling renderer; the contract is in adaptive.h.
//
// Where samples live. Every sample a block reads lies on one of its four
// sides. A side is an Edge: an array indexed by the offset from the block's
// top-left corner (top and bottom: 0..w, left and right: 0..h), both ends
// being corners. Sides shared between blocks are one array, so a sample one
// block traced is there for the other:
//   * a line of corners (the top or bottom of a band) is an array of `width`
//     samples in the caller's buffer, kept for the whole frame;
//   * a base block's left side is its left neighbour's right side: each band
//     carries one column array from block to block;
//   * a split block's two inner lines (x = xm and y = ym) are fresh arrays
//     from the band's scratch, shared by its four children.
// A corner or midpoint that is an end of several arrays is copied into each
// once it is traced. Each slot has a state (CornerSample::state, in the
// sample, so that a side is one pointer): unknown, pending (in the current
// batch), known (traced) or estimated (adaptive_estimate; kept, also where
// a block traced per pixel needs that pixel).
#include "adaptive.h"

#include "packet/packet.h"

namespace {

typedef CornerSample Sample;

// SSE2 through GCC's vector extensions (as trace.cpp): no intrinsics
// header, which would pull in the C library's.
typedef i32 v4i __attribute__((vector_size(16)));
typedef short v8s __attribute__((vector_size(16)));
typedef char v16c __attribute__((vector_size(16)));
typedef i32 v4i_unaligned __attribute__((vector_size(16), aligned(4), may_alias));
typedef float v4f __attribute__((vector_size(16)));
typedef long long v2ll __attribute__((vector_size(16)));

// The four records equal (same_path() of a with each of b, c, d, in
// trace.cpp), without its loops or branches: the count and nodes 0-2 as one
// vector (the count's byte, not the padding after it), nodes 3-6 as
// another, the nodes past a's count masked out (where the counts differ,
// the first lane does).
static_assert(kMaxPathNodes == 7 && __builtin_offsetof(PathRecord, node) == 4,
              "same_records compares the count and nodes 0-2, then nodes 3-6");
inline bool same_records(const PathRecord& a, const PathRecord& b, const PathRecord& c,
                         const PathRecord& d) {
  typedef const v4i_unaligned* V;
  v4i n = {a.count, a.count, a.count, a.count}, first = {-1, 0, 1, 2}, last = {3, 4, 5, 6};
  v4i lo = *(V)&a, hi = *(V)(a.node + 3), countByte = {255, -1, -1, -1};
  v4i lo2 = (lo ^ *(V)&b) | (lo ^ *(V)&c) | (lo ^ *(V)&d);
  v4i hi2 = (hi ^ *(V)(b.node + 3)) | (hi ^ *(V)(c.node + 3)) | (hi ^ *(V)(d.node + 3));
  v4i differ = (lo2 & (first < n) & countByte) | (hi2 & (last < n)), zero = {0, 0, 0, 0};
  return __builtin_ia32_movmskps((v4f)(differ == zero)) == 15;
}

// The four samples' packed colours as one vector (c00, c10, c01, c11), each
// loaded straight into a register (movd): GCC builds the vector literal
// through a general register for two of them.
inline v4i corner_colours(const CornerSample& a, const CornerSample& b, const CornerSample& c,
                          const CornerSample& d) {
  v4i va = {(i32)a.packed, 0, 0, 0}, vb = {(i32)b.packed, 0, 0, 0};
  v4i vc = {(i32)c.packed, 0, 0, 0}, vd = {(i32)d.packed, 0, 0, 0};
  return (v4i)__builtin_ia32_punpcklqdq128((v2ll)__builtin_ia32_punpckldq128(va, vb),
                                           (v2ll)__builtin_ia32_punpckldq128(vc, vd));
}

// Per block or per band, not per pixel: kept out of line, which saves bytes
// in intro.exe for a call's few instructions.
#define RT64K_COLD __attribute__((noinline))

enum SlotState : u8 { kUnknown, kPending, kKnown, kEstimated };

// Set in the state of a line's corner (a base block's top-left or
// bottom-left corner on a line of corners) once the slots between it and
// the next corner on that line are cleared (open_side); the corner stays
// known (states are only compared with kUnknown and kEstimated).
constexpr u8 kSideOpen = 4;

// A side's midpoint is estimated instead of traced when the records at its
// two ends are equal and no colour channel differs between them by more than
// kEstimateContrast / 255: the midpoint takes their record and the rounded
// mean of their colours, also where a block traced per pixel needs it.
// Measured in docs/speed-vs-error.md: at 16 (issue 9's first round) -11 %
// samples; at 4 (second round) less flicker for a few more samples; at 8
// and kept where a block is traced per pixel (third round), paid for in
// flicker by the glass rule below.
constexpr int kEstimateContrast = 8;

// adaptive_estimate (inline in request_midpoint): the records compared as
// in decide, the colours' per-channel differences with SSE2 (both
// saturating differences, less kEstimateContrast, saturating at 0).
inline bool estimate(const Sample& a, const Sample& b, Sample& mid) {
  v4i ca = {(i32)a.packed, 0, 0, 0}, cb = {(i32)b.packed, 0, 0, 0};
  v16c d =
      __builtin_ia32_psubusb128((v16c)ca, (v16c)cb) | __builtin_ia32_psubusb128((v16c)cb, (v16c)ca);
  i32 l = kEstimateContrast * 0x01010101;
  v4i limits = {l, l, l, l};
  v16c over = __builtin_ia32_psubusb128(d, (v16c)limits);
  if ((((v4i)over)[0] & 0xffffff) || !same_records(a.path, b.path, b.path, b.path)) return false;
  // Per channel (a + b + 1) / 2: the halves and the carry of the low bits.
  mid.packed = 0xff000000u | (((a.packed | b.packed) & 0x010101u) + (a.packed >> 1 & 0x7f7f7fu) +
                              (b.packed >> 1 & 0x7f7f7fu));
  mid.path = a.path;
  return true;
}

// A block whose corners see a transparent object (at any recorded depth) is
// copied or interpolated only when no colour channel of its corners spans
// more than kGlassContrast[0] / 255 (kGlassContrast[1] / 255 at the minimum
// size), else split (traced per pixel at the minimum size). Glass shows a
// minified image of what lies behind and around it, whose edges partly go
// unrecorded (deeper than kRecordDepth, or reflections weaker than
// kRecordWeight): most of the flicker was in glass blocks interpolated from
// corners whose colours differ. Measured in docs/speed-vs-error.md (before
// the third round: split down to 4 px whatever the colours). Round nine:
// rays through glass are recorded deeper (trace.h, kRecordWeightGlass), so
// the edges they see split by records, and the limits rose from {16, 24}.
constexpr int kGlassContrast[2] = {18, 64};
static_assert(kGlassContrast[0] <= kGlassContrast[1],
              "process_group tests the smaller limit first: a block over the larger is over it");

// A block of the minimum size whose corners' records differ is traced per
// pixel, and one of up to twice that size is split, unless no colour channel
// of its corners spans more than kSmallContrast[0] / 255 (minimum size) or
// kSmallContrast[1] / 255 (up to twice it): then it is interpolated like a
// block whose records agree. What such a block can hide is a feature that
// passes between corners at most 2 minBlock apart and differs from all four
// by more than that. Most of the blocks traced per pixel were of this kind:
// edges of faint shadows and highlights, two surfaces of similar colour
// meeting. Measured in docs/speed-vs-error.md (second round, 12 and 6:
// -19 % samples, flicker as before; third round, 32 and 16, spending the
// flicker that the glass rule's change saves).
constexpr int kSmallContrast[2] = {32, 16};

// A block wider or taller than kMaxInterpolated pixels is copied (four equal
// colours and records) or split, never interpolated, and the midpoints of
// its sides are traced, not estimated: with a base block of 16 or 32 the
// decisions are those of base 8 except inside a 16- or 32-px block copied
// whole, whose inner corners of the 8-px grid are not traced (the same
// picture where both grids end on the image's last pixel). Measured in
// docs/speed-vs-error.md (round four): base 16 so casts 9 % fewer primary
// rays than base 8 at the same minimum PSNR, pixels off and flicker (the
// thesis's base 16, interpolating 16-px blocks, missed the 40-dB floor).
// Base blocks up to 8 are not affected.
constexpr int kMaxInterpolated = 8;

// A side: its samples, each with its state (CornerSample::state).
typedef Sample* Edge;

// Sets e[0 .. count) unknown. Counts 5 to 9 (with base block 8 nearly every
// call: a column's or side's inner 7, an inner line's 9 or 5) without a
// loop: e[0 .. 4] and e[count - 4 .. count), which overlap; a loop's exit
// at a count that varies from call to call was mispredicted about once a
// call (4.0 k at 13 s).
RT64K_HOT_ABI void clear_states(Edge e, int count) {
  if ((unsigned)(count - 5) <= 4) {
    Edge last = e + count;
    e[0].state = e[1].state = e[2].state = e[3].state = e[4].state = kUnknown;
    last[-4].state = last[-3].state = last[-2].state = last[-1].state = kUnknown;
    return;
  }
  for (; count >= 2; count -= 2, e += 2) // (two a step: half the loop's own work)
    e[0].state = e[1].state = kUnknown;
  if (count > 0) e->state = kUnknown;
}

// A base block that splits or is traced per pixel reads and writes the
// slots of its top and bottom sides between their corners, slots of the
// lines of corners (76 lines of 800 samples, 2.4 MB at 800x600), which
// trace_line does not clear (only the corners): the first of the line's two
// bands that needs a side's slots clears them and marks the side open
// (kSideOpen in its left corner); the other band runs after it (adaptive.h),
// and sides no block splits are not touched in the frame.
RT64K_COLD RT64K_HOT_ABI void open_side(Edge side, int w) {
  if (side[0].state & kSideOpen) return;
  side[0].state |= kSideOpen;
  clear_states(side + 1, w - 1);
}

inline void copy_slot(Edge to, int i, Edge from, int j) { to[i] = from[j]; }

// A block: corners at x0, x1 (x1 >= x0) and y0, y1; owns [x0, xEnd) x [y0, yEnd).
struct Node {
  int x0, y0, x1, y1, xEnd, yEnd;
  Edge top, bottom, left, right;
  // Set while the node is processed.
  BlockKind kind;
  int xm, ym;
  bool splitX, splitY;
  Edge v, h; // the inner lines x = xm (0..h) and y = ym (0..w)
};

// Most blocks processed as one group (their new samples in one batch). 32,
// not 16: each group's batch ends in a packet of four that is mostly not
// full, and the packets' fixed cost (the bound tests, the shading packet's
// call) is paid per packet (docs/speed-vs-error.md, round eleven, second
// pass: 4,957 -> 4,870 packets for 18,633 samples at 13 s, -0.3 %). The
// scratch grows by 16 split blocks' inner lines a level; Node kids[kGroup]
// stays under the 4-kB frame that would call ___chkstk_ms.
constexpr int kGroup = 32;

// The base blocks of a band are processed in groups too: a group ends after
// kBaseGroup blocks that split or are traced per pixel (each holds its
// inner lines and up to two new column arrays until the group's children
// are done), or after kBaseChunk blocks (run_band's array). Most base blocks
// are copied or interpolated and ask for nothing, so a band's few split
// blocks share their batches and packets of four (docs/speed-vs-error.md,
// round eleven: 5,500 -> 4,957 packets at 13 s). 8 and 32: within 0.1 % of
// the fewest instructions (16 and 64 blocks), with fewer first-level cache
// misses (the nodes, the scratch and the picture's rows they write).
constexpr int kBaseGroup = 8;
constexpr int kBaseChunk = 32;

// Samples gathered for one call of flush. A full batch is traced at
// once; no sample of a batch depends on another, so any cut is fine.
constexpr int kBatch = 32;
struct Batch {
  int n;
  float x[kBatch], y[kBatch]; // pixel coordinates, as trace_primary4 takes them
  Sample* out[kBatch];
  u32* pixel[kBatch]; // the framebuffer pixel to write too, or &sink
  Sample spare[kBatch];
  u32 sink; // the pixel of a sample no pixel shows (flush writes every lane's)
};

struct Context {
  const AdaptiveFrame* f;
  RayStats* stats;
  Batch batch;
  Edge scratch; // the band's scratch for inner lines; `used` entries taken
  int used;
  const Node* base; // the base blocks being processed (run_band's array)
  bool large;       // the block being split is larger than kMaxInterpolated
  bool exact;       // no kinds map and no tints: interpolate_exact where it applies
  // The band's column arrays (base blocks' left and right sides): a ring of
  // kColumns, the next one to start, the last one started and its x (-1:
  // none); and what start_column needs: the band's lines of corners and
  // height.
  Edge columns;
  int nextColumn;
  Edge lastColumn;
  int lastColumnX;
  Edge top, bottom;
  int h;
};

// A group of base blocks starts at most two column arrays per block it
// holds (kBaseGroup), and the last one started before it may still be read (the
// left side of its first block): the ring never hands out an array in use.
constexpr int kColumns = 2 * kBaseGroup + 1;

// A column array for the block side x = x of the band: ends copied from the
// lines, inside unknown.
RT64K_COLD RT64K_HOT_ABI void start_column(Edge col, Edge top, Edge bottom, int x, int h) {
  clear_states(col + 1, h - 1);
  copy_slot(col, 0, top, x);
  copy_slot(col, h, bottom, x);
}

// A base block that splits or is traced per pixel reads and writes its left
// and right sides; one copied or interpolated reads only its corners, from
// the lines. So a column is started (start_column) only when the first of
// the two base blocks it separates needs it: the block on its left (as its
// right side) or else the one on its right (as its left side, which the
// block on its left, not needing it, has not touched). Blocks are taken
// left to right, so the column at x is started already only if it is the
// last one started.
RT64K_COLD RT64K_HOT_ABI Edge open_column(Context& c, int x) {
  if (c.lastColumnX == x) return c.lastColumn;
  int stride = c.f->baseBlock + 1;
  Edge col = c.columns + c.nextColumn * stride;
  c.nextColumn = c.nextColumn + 1 == kColumns ? 0 : c.nextColumn + 1;
  c.lastColumn = col;
  c.lastColumnX = x;
  start_column(col, c.top, c.bottom, x, c.h);
  return col;
}

// The one place the adaptive renderer casts primary rays: traces the batch,
// four samples at a time (trace_primary4: an SSE2 packet; the samples of a
// batch lie close together, a line of corners or one group's new samples
// and traced pixels), into their slots (now known) and pixels.
RT64K_HOT_ABI void flush(Context& c) {
  Batch& b = c.batch;
  const AdaptiveFrame& f = *c.f;
  Vec3 color[4] = {}; // (lanes past a short packet's count: packed, not used)
  // n loaded once: the stores below may alias the batch (its spares).
  // The lanes past the last packet's count (up to a multiple of 4, at most
  // kBatch) go to spare slots and the sink, so that every packet stores its
  // four lanes: the loop below unrolled (GCC 12 at -O2 keeps a loop of a
  // variable count rolled).
  int n = b.n;
  static_assert(kBatch % 4 == 0, "a batch is whole packets");
  for (int j = n; j & 3; ++j) {
    b.out[j] = &b.spare[j];
    b.pixel[j] = &b.sink;
  }
  for (int i = 0; i < n; i += 4) {
    int count = n - i < 4 ? n - i : 4;
    PathRecord paths[4];
    u32 packs[4];
    trace_primary4(*f.scene, f.cam, b.x + i, b.y + i, count, color, paths, c.stats);
    pack_color4(color, packs);
#pragma GCC unroll 4
    for (int k = 0; k < 4; ++k) {
      int j = i + k;
      u32 packed = packs[k];
      Sample* out = b.out[j]; // (loaded once: the stores below may alias the batch)
      out->packed = packed;
      out->path = paths[k];
      out->state = kKnown; // (a spare's is not read)
      *b.pixel[j] = packed;
    }
  }
  // The samples counted in the kinds map (most frames keep none: the test
  // once a batch, not once a sample).
  if (f.kinds)
    for (int j = 0; j < n; ++j) {
      u8& kind = f.kinds[(int)b.y[j] * f.width + (int)b.x[j]];
      if (kind >> kSampleCountShift != 3) kind = (u8)(kind + (1 << kSampleCountShift));
    }
  b.n = 0;
}

// Puts the sample at (x, y) into the batch for slot e[0], whose state is
// unknown (the caller's test), and marks it pending.
RT64K_HOT_ABI void enqueue(Context& c, int x, int y, Edge e) {
  e->state = kPending;
  Batch& b = c.batch;
  int n = b.n; // (loaded once: the build has no strict aliasing)
  b.x[n] = (float)x;
  b.y[n] = (float)y;
  b.out[n] = e;
  b.pixel[n] = &b.sink;
  b.n = ++n;
  if (n == kBatch) flush(c);
}

// Asks for the sample at (x, y) into slot e[0]: traced unless already
// traced, asked for or estimated.
inline void request(Context& c, int x, int y, Edge e) {
  if (e->state == kUnknown) enqueue(c, x, y, e);
}

// Asks for the pixel (x, y) inside a block, which no other block reads:
// traced straight into the framebuffer.
RT64K_HOT_ABI void request_pixel(Context& c, int x, int y) {
  Batch& b = c.batch;
  int n = b.n;
  b.x[n] = (float)x;
  b.y[n] = (float)y;
  b.out[n] = &b.spare[n];
  b.pixel[n] = c.f->fb + y * c.f->stride + x;
  b.n = ++n;
  if (n == kBatch) flush(c);
}

} // namespace

bool adaptive_estimate(const CornerSample& a, const CornerSample& b, CornerSample& mid) {
  return estimate(a, b, mid);
}

namespace {

// The midpoint of a side (slot side[mid], ends side[0] and side[len]):
// estimated (adaptive_estimate; not for a block larger than
// kMaxInterpolated: c.large) or asked for.
RT64K_HOT_ABI void request_midpoint(Context& c, int x, int y, Edge side, int mid, int len) {
  if (side[mid].state != kUnknown) return;
  if (!c.large && estimate(side[0], side[len], side[mid])) {
    side[mid].state = kEstimated;
    return;
  }
  enqueue(c, x, y, side + mid); // (still unknown: estimate() changes no state)
}

RT64K_HOT_ABI Edge allocate(Context& c, int count) {
  Edge e = c.scratch + c.used;
  c.used += count;
  clear_states(e, count);
  return e;
}

// The slot of pixel (x, y) if it lies on a side of the node, else {null}.
RT64K_HOT_ABI Edge side_slot(const Node& n, int x, int y) {
  if (y == n.y0) return n.top + (x - n.x0);
  if (y == n.y1) return n.bottom + (x - n.x0);
  if (x == n.x0) return n.left + (y - n.y0);
  if (x == n.x1) return n.right + (y - n.y0);
  return nullptr;
}

RT64K_HOT_ABI int grid_count(int size, int block) {
  int n = (size - 1 + block - 1) / block + 1;
  return n < 2 ? 2 : n;
}

RT64K_HOT_ABI int grid_coord(int i, int block, int size) {
  int c = i * block;
  return c < size - 1 ? c : size - 1;
}

// Scratch entries one band needs: kColumns column arrays of baseBlock + 1,
// and the inner lines of the split blocks alive at once: per level one
// group of at most kBaseGroup (base level) or kGroup blocks that split
// (process_group); a child is at most half its parent, rounded up.
RT64K_HOT_ABI int band_scratch(int baseBlock) {
  int total = kColumns * (baseBlock + 1), nodes = kBaseGroup;
  for (int s = baseBlock; s >= 2; s = (s + 1) / 2, nodes = kGroup)
    total += nodes * 2 * (s + 1);
  return total;
}

RT64K_HOT_ABI int bytes_as_samples(int bytes) {
  return (bytes + (int)sizeof(Sample) - 1) / (int)sizeof(Sample);
}

// The caller's buffer: the lines of corners (gridH x width samples), then
// a scratch per band (each sample with its slot state), then the bands'
// queue (Queue: two counters, then a done flag per band, then a busy flag
// per scratch). A band runs in the first scratch no other running band
// holds (adaptive_run): with T threads only the first T are ever used, and
// they stay in the cache from band to band (a scratch per band touched
// 1.8 MB a frame at 800 x 600 with round eleven's groups).
RT64K_HOT_ABI int sample_slots(const AdaptiveFrame& f) {
  return f.gridH * f.width + (f.gridH - 1) * band_scratch(f.baseBlock);
}

struct Queue {
  i32 nextEven, nextOdd; // the next band of each parity to hand out
  u8 done[1];            // [bands]: 1 once the band has run; then [bands] busy flags
};

int queue_bytes(int bands) { return (int)sizeof(Queue) + 2 * bands; }

RT64K_HOT_ABI Queue* queue(const AdaptiveFrame& f) {
  int samples = sample_slots(f);
  return (Queue*)(f.corners + samples);
}

RT64K_HOT_ABI Edge line_edge(const AdaptiveFrame& f, int k) { return f.corners + k * f.width; }

RT64K_HOT_ABI Edge band_scratch_edge(const AdaptiveFrame& f, int slot) {
  int offset = f.gridH * f.width + slot * band_scratch(f.baseBlock);
  return f.corners + offset;
}

RT64K_COLD RT64K_HOT_ABI void mark_kinds(const AdaptiveFrame& f, const Node& b, BlockKind kind) {
  for (int y = b.y0; y < b.yEnd; ++y)
    for (int x = b.x0; x < b.xEnd; ++x) {
      u8& k = f.kinds[y * f.width + x];
      k = (u8)((k & ~kKindMask) | kind);
    }
}

// (The test inline: most frames keep no kinds map.)
inline void mark(const AdaptiveFrame& f, const Node& b, BlockKind kind) {
  if (f.kinds) mark_kinds(f, b, kind);
}

RT64K_COLD RT64K_HOT_ABI void fill(const AdaptiveFrame& f, const Node& b, u32 packed) {
  mark(f, b, kCopied);
  if (f.showBlocks) packed = tint_copied(packed);
  adaptive_fill(f.fb, f.stride, b.x0, b.y0, b.xEnd, b.yEnd, packed);
}

RT64K_HOT_ABI void interpolate_float(u32* fb, int stride, int x0, int y0, int x1, int y1, int xEnd,
                                     int yEnd, u32 c00, u32 c10, u32 c01, u32 c11);
RT64K_HOT_ABI void interpolate_exact(u32* row, int stride, int s, v4i corners);

RT64K_COLD RT64K_HOT_ABI void interpolate_block(const AdaptiveFrame& f, const Node& b, u32 c00,
                                                u32 c10, u32 c01, u32 c11) {
  mark(f, b, kInterpolated);
  // (The float path: the same pixels as the exact one where both apply.)
  interpolate_float(f.fb, f.stride, b.x0, b.y0, b.x1, b.y1, b.xEnd, b.yEnd, c00, c10, c01, c11);
  if (!f.showBlocks) return;
  for (int y = b.y0; y < b.yEnd; ++y)
    for (int x = b.x0; x < b.xEnd; ++x)
      f.fb[y * f.stride + x] = tint_interpolated(f.fb[y * f.stride + x]);
}

// Most interpolated blocks (a square of 2, 4 or 8 px inside the picture, no
// kinds map, no tints) go straight to the exact path; the rest through
// interpolate_block, but for a block wider or taller than kMaxInterpolated:
// returns false, nothing written (the block splits). The size test here, past
// the exact path's, not for every block that would be interpolated.
// w and h are the block's x1 - x0 and y1 - y0 (the caller's: the build has
// no strict aliasing, so the node's fields would be loaded again).
static_assert(kMaxInterpolated >= 8, "the exact path's blocks (2, 4, 8 px) are interpolated");
inline bool interpolate(const Context& c, const Node& b, int w, int h, v4i corners) {
  const AdaptiveFrame& f = *c.f;
  if (c.exact && w == h && ((b.xEnd - b.x1) | (b.yEnd - b.y1)) == 0 &&
      (w == 2 || w == 4 || w == 8)) {
    interpolate_exact(f.fb + b.y0 * f.stride + b.x0, f.stride, __builtin_ctz(w), corners);
    return true;
  }
  if (w > kMaxInterpolated || h > kMaxInterpolated) return false;
  interpolate_block(f, b, (u32)corners[0], (u32)corners[1], (u32)corners[2], (u32)corners[3]);
  return true;
}

RT64K_HOT_ABI bool sees_glass(const AdaptiveFrame& f, const Sample& s) {
  for (int i = 0; i < s.path.count; ++i) {
    int id = (int)(s.path.node[i] & 31) - 1;
    if (id >= 0 && f.scene->objects[id].mat.transmit > 0) return true;
  }
  return false;
}

// True when no colour channel of the four packed colours v (a block's
// corners) spans more than limit / 255. SSE2: per byte the largest and smallest of the four colours
// (two lane swaps each), their difference less `limit`, saturating at 0.
inline bool low_contrast(v4i v, int limit) {
  v16c hi = __builtin_ia32_pmaxub128((v16c)v, (v16c)__builtin_ia32_pshufd(v, 0x4e));
  v16c lo = __builtin_ia32_pminub128((v16c)v, (v16c)__builtin_ia32_pshufd(v, 0x4e));
  hi = __builtin_ia32_pmaxub128(hi, (v16c)__builtin_ia32_pshufd((v4i)hi, 0xb1));
  lo = __builtin_ia32_pminub128(lo, (v16c)__builtin_ia32_pshufd((v4i)lo, 0xb1));
  i32 l = limit * 0x01010101;
  v4i limits = {l, l, l, l};
  v16c over = __builtin_ia32_psubusb128(__builtin_ia32_psubusb128(hi, lo), (v16c)limits);
  return (((v4i)over)[0] & 0xffffff) == 0;
}

// Blocks this size or smaller are traced per pixel (unless low_contrast).
RT64K_HOT_ABI bool is_small(const AdaptiveFrame& f, int w, int h) {
  return (w <= f.minBlock && h <= f.minBlock) || (w < 2 && h < 2);
}

// A small block, traced per pixel. Before the batch (`written` false):
// asks for every pixel, those on its sides into their slots (other blocks may
// read them), the rest straight into the picture. After it: writes the
// pixels on its sides from their slots; an estimated one counts as
// interpolated in `kinds`.
RT64K_COLD RT64K_HOT_ABI void trace_block(Context& c, const Node& n, bool written) {
  const AdaptiveFrame& f = *c.f;
  if (!f.kinds && n.x1 - n.x0 == 2 && n.y1 - n.y0 == 2 && n.xEnd == n.x1 && n.yEnd == n.y1) {
    // (Most blocks traced per pixel: 2 px, owning neither their right column
    // nor their bottom row.) Its pixels: the top-left corner, the midpoints
    // of its top and left sides, and its centre, as the loop below takes them.
    if (!written) {
      request(c, n.x0 + 1, n.y0, n.top + 1);
      request(c, n.x0, n.y0 + 1, n.left + 1);
      request_pixel(c, n.x0 + 1, n.y0 + 1);
      return;
    }
    u32* p = f.fb + n.y0 * f.stride + n.x0;
    p[0] = n.top[0].packed;
    p[1] = n.top[1].packed;
    p[f.stride] = n.left[1].packed;
    return;
  }
  if (written) mark(f, n, kTraced);
  for (int y = n.y0; y < n.yEnd; ++y)
    for (int x = n.x0; x < n.xEnd; ++x) {
      Edge e = side_slot(n, x, y);
      if (!e) {
        if (!written) request_pixel(c, x, y);
      } else if (written) {
        f.fb[y * f.stride + x] = e->packed;
        if (f.kinds && e->state == kEstimated) {
          u8& k = f.kinds[y * f.width + x];
          k = (u8)((k & ~kKindMask) | kInterpolated);
        }
      } else {
        request(c, x, y, e);
      }
    }
}

// A child block's fields (process_group).
inline void put_kid(Node& kid, int x0, int y0, int x1, int y1, int xEnd, int yEnd, Edge top,
                    Edge bottom, Edge left, Edge right) {
  kid.x0 = x0;
  kid.y0 = y0;
  kid.x1 = x1;
  kid.y1 = y1;
  kid.xEnd = xEnd;
  kid.yEnd = yEnd;
  kid.top = top;
  kid.bottom = bottom;
  kid.left = left;
  kid.right = right;
}

// Processes `count` blocks whose corners are known: copies, interpolates,
// or asks for the samples of those traced per pixel and the new samples of
// those split, traces them in one batch, then processes each split block's
// children the same way. Returns the number of blocks processed: `count`,
// but base blocks (c.base) only until kBaseGroup of them split or are
// traced per pixel.
RT64K_HOT_ABI int process_group(Context& c, Node* nodes, int count) {
  const AdaptiveFrame& f = *c.f;
  int used = c.used, held = 0, i = 0, end = count; // (base: up to the kBaseGroup-th held)
  bool base = nodes == c.base;
  // The blocks split or traced per pixel (`held`), in order: the only ones
  // the second pass below visits (most blocks are copied or interpolated).
  u8 heldAt[kGroup];
  static_assert(kBaseChunk <= kGroup, "heldAt holds a base group's blocks too");
  for (; i < end; ++i) {
    Node& n = nodes[i];
    int w = n.x1 - n.x0, h = n.y1 - n.y0;
    const Sample &c00 = n.top[0], &c10 = n.top[w];
    const Sample &c01 = n.bottom[0], &c11 = n.bottom[w];
    // adaptive_decide(), with the rules below in its branches (is_small only
    // where a rule asks: not for most copied and interpolated blocks).
    BlockKind kind = kInterpolated;
    // The corners' colours as one vector, made where a contrast test needs it
    // (not for a copied block) and kept for the interpolation.
    v4i cv;
    if (!same_records(c00.path, c10.path, c01.path, c11.path)) {
      cv = corner_colours(c00, c10, c01, c11);
      // Small blocks whose records differ: interpolated where the corners'
      // colours are close (kSmallContrast).
      int limit = is_small(f, w, h)                            ? kSmallContrast[0]
                  : w <= 2 * f.minBlock && h <= 2 * f.minBlock ? kSmallContrast[1]
                                                               : -1;
      if (f.mode != kModeAdaptive || limit < 0 || !low_contrast(cv, limit)) kind = kSplit;
    } else if (c00.packed == c10.packed && c00.packed == c01.packed && c00.packed == c11.packed) {
      kind = kCopied;
    } else if ((cv = corner_colours(c00, c10, c01, c11), f.mode != kModeAdaptive) ||
               // The glass limit: kGlassContrast[0] for every size first (most
               // blocks pass it), the size and the larger limit only where it fails.
               // The four records are equal, so c00's stands for all.
               (!low_contrast(cv, kGlassContrast[0]) &&
                (!is_small(f, w, h) || !low_contrast(cv, kGlassContrast[1])) && sees_glass(f, c00))) {
      kind = kSplit;
    }
    if (kind == kCopied) {
      if (c.exact) // (no kinds map, no tint: fill() would only pass it on)
        adaptive_fill(f.fb, f.stride, n.x0, n.y0, n.xEnd, n.yEnd, c00.packed);
      else
        fill(f, n, c00.packed);
      continue;
    }
    if (kind == kInterpolated && interpolate(c, n, w, h, cv)) continue;
    n.kind = kSplit; // (read by the second pass, which sees only held blocks)
    heldAt[held++] = (u8)i;
    if (base) {
      if (held == kBaseGroup) end = i + 1;
      open_side(n.top, w);
      open_side(n.bottom, w);
      n.left = open_column(c, n.x0);
      n.right = open_column(c, n.x1); // (the same array for a one-pixel-wide image)
    }
    if (is_small(f, w, h)) {
      n.kind = kTraced;
      trace_block(c, n, false);
      continue;
    }
    // Split at the midpoints; sides of length < 2 are not split.
    c.large = w > kMaxInterpolated || h > kMaxInterpolated;
    n.xm = w >= 2 ? (n.x0 + n.x1) / 2 : n.x1;
    n.ym = h >= 2 ? (n.y0 + n.y1) / 2 : n.y1;
    n.splitX = n.xm != n.x1;
    n.splitY = n.ym != n.y1;
    int a = n.xm - n.x0, b = n.ym - n.y0;
    if (n.splitX) {
      request_midpoint(c, n.xm, n.y0, n.top, a, w);
      request_midpoint(c, n.xm, n.y1, n.bottom, a, w);
      n.v = allocate(c, h + 1);
    }
    if (n.splitY) {
      request_midpoint(c, n.x0, n.ym, n.left, b, h);
      request_midpoint(c, n.x1, n.ym, n.right, b, h);
      n.h = allocate(c, w + 1);
    }
    if (n.splitX && n.splitY) enqueue(c, n.xm, n.ym, n.v + b); // (v is fresh: unknown)
  }
  if (c.batch.n) flush(c); // (most base blocks ask for nothing)
  Node kids[kGroup];
  int k = 0;
  for (int p = 0; p < held; ++p) {
    Node& n = nodes[heldAt[p]];
    if (n.kind == kTraced) {
      trace_block(c, n, true);
      continue;
    }
    int w = n.x1 - n.x0, h = n.y1 - n.y0, a = n.xm - n.x0, b = n.ym - n.y0;
    if (n.splitX) {
      copy_slot(n.v, 0, n.top, a);
      copy_slot(n.v, h, n.bottom, a);
    }
    if (n.splitY) {
      copy_slot(n.h, 0, n.left, b);
      copy_slot(n.h, w, n.right, b);
    }
    if (n.splitX && n.splitY) copy_slot(n.h, a, n.v, b);
    // The children: quadrants, two halves when one side is not split (then
    // xm = x1 or ym = y1, and that side's arrays are the block's), in the
    // order top-left, top-right, bottom-left, bottom-right. The children of
    // several split blocks form one group, up to kGroup blocks: their
    // samples go in one batch.
    int nx = n.splitX ? 2 : 1, ny = n.splitY ? 2 : 1;
    if (k + nx * ny > kGroup) {
      process_group(c, kids, k);
      k = 0;
    }
    // The left column's right end and the top row's bottom end.
    int xa = n.splitX ? n.xm : n.x1, xe = n.splitX ? n.xm : n.xEnd;
    int ya = n.splitY ? n.ym : n.y1, ye = n.splitY ? n.ym : n.yEnd;
    Edge right = n.splitX ? n.v : n.right, bottom = n.splitY ? n.h : n.bottom;
    put_kid(kids[k++], n.x0, n.y0, xa, ya, xe, ye, n.top, bottom, n.left, right);
    if (n.splitX)
      put_kid(kids[k++], n.xm, n.y0, n.x1, ya, n.xEnd, ye, n.top + a, bottom + a, n.v, n.right);
    if (n.splitY) {
      put_kid(kids[k++], n.x0, n.ym, xa, n.y1, xe, n.yEnd, n.h, n.bottom, n.left + b, right + b);
      if (n.splitX)
        put_kid(kids[k++], n.xm, n.ym, n.x1, n.y1, n.xEnd, n.yEnd, n.h + a, n.bottom + a, n.v + b,
                n.right + b);
    }
  }
  if (k) process_group(c, kids, k);
  c.used = used;
  return i;
}

// Line k of corners is traced by one band next to it: an even band, or the
// last band when only that odd band touches it.
RT64K_HOT_ABI int line_owner(int k, int bands) {
  if (k % 2 == 0) return k < bands ? k : k - 1;
  return k - 1;
}

RT64K_COLD RT64K_HOT_ABI void trace_line(Context& c, int k) {
  const AdaptiveFrame& f = *c.f;
  int y = grid_coord(k, f.baseBlock, f.height), last = f.width - 1;
  // A one-pixel-high image: both lines are row 0; the band reads line 0 as
  // its bottom too (run_band), so line 1 is neither traced nor read.
  if (k > 0 && y == grid_coord(k - 1, f.baseBlock, f.height)) return;
  // The corners (grid_coord: x = 0, baseBlock, ..., and the last column),
  // each asked for as request() would but without marking its slot pending,
  // into the batch (the slots between them are open_side's); n kept in a
  // register (the build has no strict aliasing). No state is read before
  // run_band's flush, which marks every corner known (and so clears its
  // kSideOpen). Each corner is a cache line of its own (320 B apart at base
  // 8), cold since the previous frame: its store here stalled this loop once
  // the store buffer filled, and a store in flush without the line held up
  // the next packet (trace_primary4 reads its lanes back from the stack, a
  // load that waits for every older store); so the line is prefetched here,
  // a batch ahead of flush's store, and not written.
  Edge line = line_edge(f, k);
  Batch& b = c.batch;
  int n = b.n;
  float fy = (float)y;
  for (int x = 0;; x += f.baseBlock) {
    if (x > last) x = last;
    b.x[n] = (float)x;
    b.y[n] = fy;
    b.out[n] = line + x;
    __builtin_prefetch(line + x); // (prefetcht0: SSE)
    b.pixel[n] = &b.sink;
    if (++n == kBatch) {
      b.n = n;
      flush(c);
      n = 0;
    }
    if (x == last) break;
  }
  b.n = n;
}

RT64K_HOT_ABI void run_band(const AdaptiveFrame& f, int band, int slot, RayStats* stats) {
  Context c;
  c.f = &f;
  c.stats = stats;
  c.batch.n = 0;
  c.exact = !f.kinds && !f.showBlocks;
  int bands = f.gridH - 1, B = f.baseBlock;
  for (int k = band; k <= band + 1; ++k) // (both lines' corners in one batch)
    if (line_owner(k, bands) == band) trace_line(c, k);
  if (c.batch.n) flush(c);
  int y0 = grid_coord(band, B, f.height), y1 = grid_coord(band + 1, B, f.height);
  int yEnd = band + 1 == bands ? f.height : y1, h = y1 - y0;
  Edge top = line_edge(f, band), bottom = line_edge(f, band + 1);
  if (h == 0) bottom = top; // a one-pixel-high image
  Edge scratch = band_scratch_edge(f, slot);
  c.columns = scratch;
  c.nextColumn = 0;
  c.lastColumn = nullptr;
  c.lastColumnX = -1;
  c.top = top;
  c.bottom = bottom;
  c.h = h;
  c.scratch = scratch + kColumns * (B + 1);
  c.used = 0;
  Node nodes[kBaseChunk];
  c.base = nodes;
  for (int i = 0; i + 1 < f.gridW;) { // base blocks i, i + 1, ... as one group
    int count = f.gridW - 1 - i, x0 = grid_coord(i, B, f.width); // (one test a block)
    if (count > kBaseChunk) count = kBaseChunk;
    for (int k = 0; k < count; ++k) {
      Node& n = nodes[k]; // (its left and right sides: process_group, open_column)
      int j = i + k, x1 = grid_coord(j + 1, B, f.width);
      n.x0 = x0;
      n.y0 = y0;
      n.x1 = x1;
      n.y1 = y1;
      n.xEnd = j + 2 == f.gridW ? f.width : x1;
      n.yEnd = yEnd;
      n.top = top + x0;
      n.bottom = bottom + x0;
      x0 = x1;
    }
    i += process_group(c, nodes, count);
  }
}

} // namespace

// Colour copy needs equal colours AND equal records: two different objects
// of one colour are not one surface. Interpolation needs equal records.
// (process_group makes the same decision in its own branches.)
BlockKind adaptive_decide(const CornerSample& c00, const CornerSample& c10, const CornerSample& c01,
                          const CornerSample& c11, AdaptiveMode mode) {
  bool samePath = same_records(c00.path, c10.path, c01.path, c11.path);
  if (!samePath) return kSplit;
  if (c00.packed == c10.packed && c00.packed == c01.packed && c00.packed == c11.packed)
    return kCopied;
  return mode == kModeAdaptive ? kInterpolated : kSplit;
}

void adaptive_fill(u32* fb, int stride, int x0, int y0, int xEnd, int yEnd, u32 packed) {
  v4i four = {(i32)packed, (i32)packed, (i32)packed, (i32)packed};
  int w = xEnd - x0;
  u32* row = fb + y0 * stride + x0;
  if (w == 8 && yEnd > y0) { // (the common case: an 8-px block's rows)
    // As offsets from the row past the last, counting up to 0 (as
    // interpolate_exact: the add is the loop's test).
    long step = stride, o = -(long)(yEnd - y0) * step;
    row -= o;
    do {
      *(v4i_unaligned*)(row + o) = four;
      *(v4i_unaligned*)(row + o + 4) = four;
    } while (o += step);
    return;
  }
  for (int y = y0; y < yEnd; ++y, row += stride) {
    int x = 0;
    for (; x + 4 <= w; x += 4)
      *(v4i_unaligned*)(row + x) = four;
    for (; x < w; ++x)
      row[x] = packed;
  }
}

namespace {

// A packed colour's channels as floats, lanes blue, green, red, alpha (255).
inline v4f channels(u32 c) {
  v4i zero = {0, 0, 0, 0}, word = {(i32)(c | 0xff000000u), 0, 0, 0};
  v8s lo = (v8s)__builtin_ia32_punpcklbw128((v16c)word, (v16c)zero);
  return __builtin_convertvector((v4i)__builtin_ia32_punpcklwd128(lo, (v8s)zero), v4f);
}

// Four pixels' channel values to four packed pixels: rounded to nearest
// (cvtps2dq), then saturating packs to bytes.
inline v16c pack_pixels(v4f p0, v4f p1, v4f p2, v4f p3) {
  v8s lo = __builtin_ia32_packssdw128(__builtin_ia32_cvtps2dq(p0), __builtin_ia32_cvtps2dq(p1));
  v8s hi = __builtin_ia32_packssdw128(__builtin_ia32_cvtps2dq(p2), __builtin_ia32_cvtps2dq(p3));
  return __builtin_ia32_packuswb128(lo, hi);
}

inline u32 pack_pixel(v4f p) { return (u32)((v4i)pack_pixels(p, p, p, p))[0]; }

typedef u64 u64_unaligned __attribute__((aligned(4), may_alias));

// Rounds the row values Q = P + 2^(shift-1) - 1 of the exact path below to
// P / 2^shift, nearest, ties to even (as cvtps2dq), per lane: (Q + the
// lowest bit of Q >> shift) >> shift. With P = q 2^shift + r, Q >> shift is
// q unless r > 2^(shift-1), where Q already carries to q + 1 and the added
// bit cannot carry further; at a tie (r = 2^(shift-1), Q's low bits all
// ones) it is q, and q odd carries to q + 1.
inline v8s round_even(v8s q, v8s shift, v8s one) {
  return __builtin_ia32_psraw128(q + (__builtin_ia32_psraw128(q, shift) & one), shift);
}

// An S x S block (S = 2^s, s = 1, 2 or 3) that owns neither its right
// column nor its bottom row (every base and split block but those at the
// image's right and bottom edges), from its top-left pixel `row`: the
// bilinear value times S^2 is an integer, P(x, y) = T(x) S + (B(x) - T(x)) y
// with T(x) = a (S - x) + b x along the top and B(x) likewise along the
// bottom, at most 255 * 64 = 16,320: a signed 16-bit lane. Two pixels a
// register (lanes 0-3 pixel x, 4-7 pixel x + 1), a row is the row above
// plus B - T, and each pixel is P / S^2 rounded to nearest, ties to even:
// the same pixels as the float path below, whose every step is exact for
// these spans (multiples of 1/64 below 512), rounded by cvtps2dq.
RT64K_COLD RT64K_HOT_ABI void interpolate_exact(u32* row, int stride, int s, v4i corners) {
  corners |= (v4i){-16777216, -16777216, -16777216, -16777216}; // alpha 255
  v16c zero = {};
  v8s ab = (v8s)__builtin_ia32_punpcklbw128((v16c)corners, zero); // a | b
  v8s cd = (v8s)__builtin_ia32_punpckhbw128((v16c)corners, zero); // c | d
  v8s one = {1, 1, 1, 1, 1, 1, 1, 1};
  // (Held in a register through the loops below: GCC would load the
  // constant again in every row, -fno-move-loop-invariants.)
  __asm__("" : "+x"(one));
  if (s == 1) { // (most calls: the two rows below in one register each)
    // T(0) | T(1) = 2a | a + b, B likewise; row 0 is T S + 1 (the bias
    // S^2/2 - 1), row 1 T S + (B - T) + 1; then rounded as below (shift 2).
    v8s t = ab + (v8s)__builtin_ia32_pshufd((v4i)ab, 0x44);
    v8s b = cd + (v8s)__builtin_ia32_pshufd((v4i)cd, 0x44), q0 = t + t + one, q1 = t + b + one;
    q0 = __builtin_ia32_psrawi128(q0 + (__builtin_ia32_psrawi128(q0, 2) & one), 2);
    q1 = __builtin_ia32_psrawi128(q1 + (__builtin_ia32_psrawi128(q1, 2) & one), 2);
    v2ll out = (v2ll)__builtin_ia32_packuswb128(q0, q1);
    *(u64_unaligned*)row = (u64)out[0];
    *(u64_unaligned*)(row + stride) = (u64)out[1];
    return;
  }
  // [e | e] with e = b - a (f = d - c): the change a pixel along the top.
  v8s e = (v8s)__builtin_ia32_pshufd((v4i)((v8s)__builtin_ia32_pshufd((v4i)ab, 0x4e) - ab), 0x44);
  v8s f = (v8s)__builtin_ia32_pshufd((v4i)((v8s)__builtin_ia32_pshufd((v4i)cd, 0x4e) - cd), 0x44);
  v8s t = __builtin_ia32_psllwi128((v8s)__builtin_ia32_pshufd((v4i)ab, 0x44), s) +
          (v8s)__builtin_ia32_pslldqi128((v2ll)e, 64); // T(0) | T(1)
  v8s bottom = __builtin_ia32_psllwi128((v8s)__builtin_ia32_pshufd((v4i)cd, 0x44), s) +
               (v8s)__builtin_ia32_pslldqi128((v2ll)f, 64);
  v8s d0 = bottom - t, dd = (f - e) + (f - e); // per row; its change per register
  short h = (short)((1 << (2 * s - 1)) - 1);
  v8s bias = {h, h, h, h, h, h, h, h};
  v8s shift = (v8s)(v2ll){2 * s, 0}; // psraw's count
  v8s q0 = __builtin_ia32_psllwi128(t, s) + bias, dq = __builtin_ia32_psllwi128(e + e, s);
  v8s q1 = q0 + dq, d1 = d0 + dd;
  v8s q2 = q1 + dq, d2 = d1 + dd;
  v8s q3 = q2 + dq, d3 = d2 + dd;
  // The rows as offsets from the row past the block's last, counting up to
  // 0: the offset's add is the loop's test (a do-while: this file is built
  // with -fno-tree-ch, which leaves a for loop's test at its top).
  long step = stride, o = -(step << s);
  row -= o;
  if (s == 2) {
    do {
      *(v4i_unaligned*)(row + o) =
          (v4i)__builtin_ia32_packuswb128(round_even(q0, shift, one), round_even(q1, shift, one));
      q0 += d0;
      q1 += d1;
    } while (o += step);
    return;
  }
  do { // (s = 3; s = 1 returned above)
    *(v4i_unaligned*)(row + o) =
        (v4i)__builtin_ia32_packuswb128(round_even(q0, shift, one), round_even(q1, shift, one));
    *(v4i_unaligned*)(row + o + 4) =
        (v4i)__builtin_ia32_packuswb128(round_even(q2, shift, one), round_even(q3, shift, one));
    q0 += d0;
    q1 += d1;
    q2 += d2;
    q3 += d3;
  } while (o += step);
}

// Per row, each channel's value at the block's left and right side; along
// the row a constant step: one pixel's four channels per SSE2 register,
// four pixels per step. Exact at the corners: row y0 starts at c00 (step
// 0 from it), row y1 is c01 and c11 themselves, column x1 is the right side.
RT64K_COLD RT64K_HOT_ABI void interpolate_float(u32* fb, int stride, int x0, int y0, int x1, int y1,
                                                int xEnd, int yEnd, u32 c00, u32 c10, u32 c01,
                                                u32 c11) {
  int spanX = x1 - x0, spanY = y1 - y0;
  v4f a = channels(c00), b = channels(c10), c = channels(c01), d = channels(c11);
  float invX = spanX ? 1.0f / (float)spanX : 0.0f, invY = spanY ? 1.0f / (float)spanY : 0.0f;
  v4f downLeft = (c - a) * invY, downRight = (d - b) * invY; // per row
  int stepEnd = xEnd > x1 ? x1 : xEnd; // pixels reached by stepping; x1 itself is exact
  for (int y = y0; y < yEnd; ++y) {
    v4f left = c, right = d;
    if (y != y1) {
      float fy = (float)(y - y0);
      left = a + downLeft * fy;
      right = b + downRight * fy;
    }
    v4f step = (right - left) * invX;
    v4f p0 = left, p1 = left + step, p2 = left + step * 2.0f, p3 = left + step * 3.0f;
    v4f step4 = step * 4.0f;
    u32* row = fb + y * stride;
    int x = x0;
    for (; x + 4 <= stepEnd; x += 4) {
      *(v4i_unaligned*)(row + x) = (v4i)pack_pixels(p0, p1, p2, p3);
      p0 += step4;
      p1 += step4;
      p2 += step4;
      p3 += step4;
    }
    for (; x < stepEnd; ++x) {
      row[x] = pack_pixel(p0);
      p0 += step;
    }
    // Only a block at the image's right edge owns its right corner column.
    if (xEnd > x1) row[x1] = pack_pixel(right);
  }
}

// adaptive_interpolate (and the renderer's blocks, without the call's
// stack arguments): the exact path where it applies (most blocks), else the
// float path.
inline void interpolate_pixels(u32* fb, int stride, int x0, int y0, int x1, int y1, int xEnd,
                               int yEnd, u32 c00, u32 c10, u32 c01, u32 c11) {
  int span = x1 - x0;
  if (span == y1 - y0 && xEnd == x1 && yEnd == y1 && (span == 2 || span == 4 || span == 8)) {
    v4i corners = {(i32)c00, (i32)c10, (i32)c01, (i32)c11};
    interpolate_exact(fb + y0 * stride + x0, stride, __builtin_ctz(span), corners);
  } else {
    interpolate_float(fb, stride, x0, y0, x1, y1, xEnd, yEnd, c00, c10, c01, c11);
  }
}

} // namespace

void adaptive_interpolate(u32* fb, int stride, int x0, int y0, int x1, int y1, int xEnd, int yEnd,
                          u32 c00, u32 c10, u32 c01, u32 c11) {
  interpolate_pixels(fb, stride, x0, y0, x1, y1, xEnd, yEnd, c00, c10, c01, c11);
}

u32 tint_copied(u32 p) { return (p >> 1 & 0x7f7f7fu) | 0xff800000u; }
u32 tint_interpolated(u32 p) { return (p >> 1 & 0x7f7f7fu) | 0xff000080u; }

int adaptive_corner_count(int width, int height, int baseBlock) {
  AdaptiveFrame f{};
  f.width = width;
  f.baseBlock = baseBlock;
  f.gridH = grid_count(height, baseBlock);
  int samples = sample_slots(f);
  return samples + bytes_as_samples(queue_bytes(f.gridH - 1));
}

void adaptive_begin(AdaptiveFrame& f) {
  f.cam = camera_rays(*f.scene, f.width, f.height);
  f.gridW = grid_count(f.width, f.baseBlock);
  f.gridH = grid_count(f.height, f.baseBlock);
  Queue* q = queue(f);
  int bands = f.gridH - 1;
  q->nextEven = (bands - 1) & ~1;                 // the last even band
  q->nextOdd = bands % 2 ? bands - 2 : bands - 1; // the last odd band (-1: none)
  for (int b = 0; b < 2 * bands; ++b)             // done and busy flags
    q->done[b] = 0;
}

int adaptive_items(const AdaptiveFrame& f) { return f.gridH - 1; }

// The frame's end: once only the last kTailEvens even bands (the top of the
// picture: nextEven < 2 kTailEvens) are left to hand out, ready odd bands
// are held back until none is left, so that when the even bands run out a
// few odd bands are ready for the thread that finishes first, instead of
// both odd bands next to the last costly even band waiting for it. Before
// that, an odd band comes as soon as it is ready, right after its
// neighbours (their lines still in the cache, the predictor trained on the
// same rows). 5 from a simulation of 2 threads on per-band callgrind costs
// (est = Ir + 15 Bcm) of 29 frames (docs/speed-vs-error.md, "Round
// fourteen: the bands' tail"): loss against half the summed cost, mean
// 0.50 -> 0.32 %, worst 3.03 -> 1.44 %; scene 1's 1.0 / 1.25 s 2.34 / 2.71
// -> 1.44 / 0.56 %.
constexpr int kTailEvens = 5;

// The done flags are stored with release order after the band's last write
// and loaded with acquire order before an odd band starts: what the even
// bands wrote on the shared lines is visible to the odd band that reads it.
// Bands are handed out from the bottom of the picture up: scene 1's costly
// bands lie low (the floor and what it reflects), and started first they do
// not end its frames on one thread; scene 2's (the glass) lie in the middle,
// where either order does as well (docs/speed-vs-error.md, "Round four:
// thread scaling": simulated with measured band costs).
int adaptive_take(const AdaptiveFrame& f) {
  Queue* q = queue(f);
  int bands = f.gridH - 1;
  for (;;) {
    i32 odd = __atomic_load_n(&q->nextOdd, __ATOMIC_RELAXED);
    i32 even = __atomic_load_n(&q->nextEven, __ATOMIC_RELAXED); // (< 0: none left)
    if (odd > 0 && (even < 0 || even >= 2 * kTailEvens) &&
        __atomic_load_n(&q->done[odd - 1], __ATOMIC_ACQUIRE) &&
        (odd + 1 == bands || __atomic_load_n(&q->done[odd + 1], __ATOMIC_ACQUIRE))) {
      if (__atomic_compare_exchange_n(&q->nextOdd, &odd, odd - 2, false, __ATOMIC_RELAXED,
                                      __ATOMIC_RELAXED))
        return odd;
      continue; // another thread took it: look again
    }
    // (Loaded first, so that the counter passes 0 by at most one step per
    // thread however long threads wait. Past 0: look again, now with the
    // odd band not held back.)
    if (even >= 0) {
      even = __atomic_fetch_add(&q->nextEven, -2, __ATOMIC_RELAXED);
      if (even >= 0) return even;
      continue;
    }
    return odd > 0 ? kAdaptiveWait : kAdaptiveDone;
  }
}

// The scratch: the first one free, taken with acquire order and given back
// with release order, so that one band's writes to it happen before the
// next holder's. At most `bands` bands run at once: one is always free.
void adaptive_run(const AdaptiveFrame& f, int band, RayStats* stats) {
  int bands = f.gridH - 1, slot = 0;
  u8* done = queue(f)->done;
  u8* busy = done + bands;
  while (__atomic_exchange_n(&busy[slot], (u8)1, __ATOMIC_ACQUIRE)) // (1 already: not ours)
    slot = slot + 1 < bands ? slot + 1 : 0;
  run_band(f, band, slot, stats);
  __atomic_store_n(&busy[slot], (u8)0, __ATOMIC_RELEASE);
  __atomic_store_n(&done[band], (u8)1, __ATOMIC_RELEASE);
}
