// adaptive.h - adaptive subsampling with bilinear interpolation (thesis
// 3.4.2, 5.5.1; SPEC "Adaptive subsampling").
//
// The image is cut into square blocks of `baseBlock` pixels. A block's four
// corners are traced; then per block:
//   * all four corner colours identical      -> fill the block with that colour;
//   * else all four PathRecords identical     -> bilinear interpolation;
//   * else, larger than `minBlock`            -> split into four and repeat;
//   * else                                    -> trace every pixel.
// Ours beyond the thesis (issue 9, measured in docs/speed-vs-error.md): a
// block whose corners see glass is filled or interpolated only where its
// corner colours span at most kGlassContrast per channel (16/255; 24/255 at
// minBlock), else split (traced per pixel at minBlock); and when a block splits,
// the midpoint of a side whose ends have equal records and colours within
// kEstimateContrast (8/255) is estimated from them instead of traced
// (adaptive_estimate; kept also where a block is traced per pixel); and a
// block of up to 2 `minBlock` pixels whose corner colours span at most
// kSmallContrast per channel (32/255 at minBlock, 16/255 up to twice it) is
// interpolated even where the records differ (kModeAdaptive only); and a
// block larger than 8 pixels (kMaxInterpolated) is copied or split, never
// interpolated, its sides' midpoints traced (base blocks up to 8 unaffected).
// A block owns the pixels [x0, x0 + size) x [y0, y0 + size); its right and
// bottom corners belong to its neighbours and are only read. So every pixel
// has exactly one writer and the picture is the same for any thread count.
//
// No sample is traced twice: a sample on an edge two blocks share (a corner,
// the midpoint of a split block's side, any point of a side at a finer
// level) is traced by whichever block needs it first and kept for the other,
// within a row of blocks and across rows. Samples are gathered into batches
// and traced through one function (adaptive.cpp: flush), the seam
// where a packet tracer takes over four primary rays at a time.
//
// Threads: the core has none. A frame is one work item per row of base
// blocks (a band); the caller's threads ask adaptive_take() for a band to
// run and run it with adaptive_run(), in one pass, with no barrier. An even
// band traces the corners on its top and bottom line and keeps every
// sample it traces on those lines for the odd bands next to it; an odd band
// reads them and may add samples of its own there, so it is handed out
// only once both even bands next to it have finished (per-band done flags),
// and two bands that run at once never touch the same sample. Even bands
// are handed out from the last (the bottom of the picture) up; an odd band
// whose neighbours are done comes first (odd bands too from the last up),
// except while the last few even bands are handed out (adaptive.cpp:
// kTailEvens; a few odd bands kept ready for the frame's end).
// No deadlock: adaptive_take() answers "wait" only when every even band has
// been taken and the next odd band's neighbours are still running, and even
// bands wait for nothing, so they finish and the odd band becomes ready.
// A running band's own working memory (its column arrays and split blocks'
// inner lines) is the first of the caller's per-band scratches that no
// other running band holds: with T threads only T are ever touched.
#pragma once
#include "abi.h"
#include "trace.h"

enum AdaptiveMode : u8 {
  kModeAdaptive, // colour copy + interpolation + subdivision (the thesis's method)
  kModeCopyOnly, // colour copy + subdivision, never interpolate
};

// A traced sample: its packed colour and what the decision compares, and
// the renderer's bookkeeping of the slot that keeps it (adaptive.cpp:
// SlotState; not compared). The record first, at offset 0: a slot copied
// whole (adaptive.cpp: copy_slot, two 16-byte stores and an 8-byte one) and
// then read soon after by same_records (the record's two 16-byte halves) is
// forwarded from the store buffer; with the record at offset 4 each of those
// loads straddled two of the stores, a forward that fails and waits for
// them to be written.
struct CornerSample {
  PathRecord path;
  u32 packed;
  u8 state;
};

// Largest base block the renderer takes (the tools accept 2..256).
constexpr int kMaxBaseBlock = 256;

struct AdaptiveFrame {
  // Set by the caller.
  const Scene* scene;
  u32* fb; // width x height, `stride` pixels per row
  int width, height, stride;
  int baseBlock; // 2..kMaxBaseBlock
  int minBlock;  // >= 1; blocks this size or smaller are traced per pixel (or
                 // interpolated when their corners' colours are close)
  AdaptiveMode mode;
  bool showBlocks;       // tint copied blocks red, interpolated ones blue
  CornerSample* corners; // caller-owned, adaptive_corner_count() entries: the samples
                         // kept on every line of corners, and the running bands' scratch
  // Optional (null: none): per pixel (width x height), bits 0-1 the BlockKind
  // that filled it, bits 6-7 how many samples were traced at that pixel
  // (saturating at 3; a test of "no sample traced twice"). Reading the
  // BlockKind: kinds[i] & kKindMask.
  u8* kinds;
  // Set by adaptive_begin().
  CameraRays cam;
  int gridW, gridH; // corners per row / column
};

enum BlockKind : u8 { kTraced, kCopied, kInterpolated, kSplit };
constexpr u8 kKindMask = 3;
constexpr int kSampleCountShift = 6;

// The decision for a block with these four corner samples.
RT64K_HOT_ABI BlockKind adaptive_decide(const CornerSample& c00, const CornerSample& c10,
                                        const CornerSample& c01, const CornerSample& c11,
                                        AdaptiveMode mode);

// The midpoint of a block's side whose ends are a and b, estimated instead
// of traced: when the records of a and b are equal and their colours differ
// by at most kEstimateContrast (8) / 255 per channel (adaptive.cpp), sets mid
// to their record and rounded mean colour and returns true.
RT64K_HOT_ABI bool adaptive_estimate(const CornerSample& a, const CornerSample& b,
                                     CornerSample& mid);

// Number of CornerSample entries the caller's `corners` buffer needs for a
// frame of this size and base block (baseBlock in 2..kMaxBaseBlock).
RT64K_HOT_ABI int adaptive_corner_count(int width, int height, int baseBlock);

// Prepares the frame (camera, grid, the bands' queue). Call once per frame,
// before any thread takes a band.
RT64K_HOT_ABI void adaptive_begin(AdaptiveFrame& f);

// Work items in the frame: its bands.
int adaptive_items(const AdaptiveFrame& f);

// The next band for a thread to run (0 .. adaptive_items() - 1; each band is
// handed out once), or kAdaptiveWait: no band is ready yet, the bands still
// running will make one ready (yield and ask again); or kAdaptiveDone: every
// band has been handed out. Safe to call from any number of threads at once
// (atomic operations on the caller's buffer).
constexpr int kAdaptiveWait = -2, kAdaptiveDone = -1;
RT64K_HOT_ABI int adaptive_take(const AdaptiveFrame& f);

// Runs band `band` (from adaptive_take()), marks it done for the bands that
// wait on it, and adds the rays it cast to *stats (not null).
RT64K_HOT_ABI void adaptive_run(const AdaptiveFrame& f, int band, RayStats* stats);

// The pixels [x0, xEnd) x [y0, yEnd) of fb (`stride` pixels per row) set to
// `packed` (colour copy), with SSE2.
RT64K_HOT_ABI void adaptive_fill(u32* fb, int stride, int x0, int y0, int xEnd, int yEnd,
                                 u32 packed);

// Bilinear interpolation over the pixels [x0, xEnd) x [y0, yEnd) of fb
// (xEnd <= x1 + 1, yEnd <= y1 + 1) of the packed colours c00 at (x0, y0),
// c10 at (x1, y0), c01 at (x0, y1), c11 at (x1, y1): rounded to nearest,
// exact at the corners; alpha 255. A square of 2, 4 or 8 px owning neither
// its right column nor its bottom row in 16-bit integers (the exact value,
// ties to even), any other block in float (SSE2, four pixels a step); the
// same pixels where both apply (adaptive.cpp: interpolate_exact).
RT64K_HOT_ABI void adaptive_interpolate(u32* fb, int stride, int x0, int y0, int x1, int y1,
                                        int xEnd, int yEnd, u32 c00, u32 c10, u32 c01, u32 c11);

// The showBlocks tints (thesis fig. 5.1: red = colour copy, blue = interpolated).
u32 tint_copied(u32 packed);
u32 tint_interpolated(u32 packed);
