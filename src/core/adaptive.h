// adaptive.h - adaptive subsampling with bilinear interpolation (thesis
// 3.4.2, 5.5.1; SPEC "Adaptive subsampling").
//
// The image is cut into square blocks of `baseBlock` pixels. A block's four
// corners are traced (corners shared by neighbouring blocks are traced once,
// in phase 0); then, in phase 1, per block:
//   * all four corner colours identical      -> fill the block with that colour;
//   * else all four PathRecords identical     -> bilinear interpolation;
//   * else, larger than `minBlock`            -> split into four and repeat;
//   * else                                    -> trace every pixel.
// A block owns the pixels [x0, x0 + size) x [y0, y0 + size); its right and
// bottom corners belong to its neighbours and are only read. So every pixel
// has exactly one writer and the picture is the same for any thread count.
//
// Threads: the core has none. A frame is two phases of independent work
// items; the caller runs every item of phase 0 (on any threads, in any
// order), waits for all of them, then every item of phase 1.
#pragma once
#include "trace.h"

enum AdaptiveMode : u8 {
  kModeAdaptive,  // colour copy + interpolation + subdivision (the thesis's method)
  kModeCopyOnly,  // colour copy + subdivision, never interpolate
};

// A traced sample: its packed colour and what the decision compares.
struct CornerSample {
  u32 packed;
  PathRecord path;
};

struct AdaptiveFrame {
  // Set by the caller.
  const Scene* scene;
  u32* fb;  // width x height, `stride` pixels per row
  int width, height, stride;
  int baseBlock;  // >= 2
  int minBlock;   // >= 1; blocks this size or smaller are traced per pixel
  AdaptiveMode mode;
  bool showBlocks;        // tint copied blocks red, interpolated ones blue
  CornerSample* corners;  // caller-owned, adaptive_corner_count() entries
  u8* kinds;  // optional (null: none): per pixel, the BlockKind that filled it
  // Set by adaptive_begin().
  CameraRays cam;
  int gridW, gridH;  // corners per row / column
};

enum BlockKind : u8 { kTraced, kCopied, kInterpolated, kSplit };

// The decision for a block with these four corner samples.
BlockKind adaptive_decide(const CornerSample& c00, const CornerSample& c10,
                          const CornerSample& c01, const CornerSample& c11, AdaptiveMode mode);

// Number of CornerSample entries a frame of this size and block size needs.
int adaptive_corner_count(int width, int height, int baseBlock);

// Prepares the frame (camera, grid). Call once per frame before phase 0.
void adaptive_begin(AdaptiveFrame& f);

// Work items in a phase: phase 0 = rows of corners, phase 1 = rows of blocks.
int adaptive_items(const AdaptiveFrame& f, int phase);

// Runs one work item; adds the rays it cast to *stats (not null).
void adaptive_run(const AdaptiveFrame& f, int phase, int item, RayStats* stats);

// The showBlocks tints (thesis fig. 5.1: red = colour copy, blue = interpolated).
u32 tint_copied(u32 packed);
u32 tint_interpolated(u32 packed);
