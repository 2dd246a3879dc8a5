// bench.h - `rt64k bench`: every mode over the timeline, speed against error.
#pragma once
#include <string>
#include <vector>

#include "frame.h"

struct BenchMode {
  std::string name;  // as printed: full, copy8, adaptive8, ...
  Mode mode;
  int block;
};

struct BenchOptions {
  double step = 0.25;  // seconds between frames; 0.25 gives 256 frames
  int width = 800, height = 600;
  int threads = 1;
  bool scaling = true;   // also time each mode on 1 thread
  int repeat = 1;        // timed renders per frame and thread count; the fastest counts
  bool progress = true;  // progress lines on stderr
  std::vector<BenchMode> modes;
  std::string csvPath = "bench.csv";
  std::string plotPath;  // empty: no plot
};

// Parses "full", "copy", "copyN", "adaptive", "adaptiveN" (N = base block,
// 2..256). Returns false for anything else.
bool parse_bench_mode(const std::string& text, BenchMode& out);

// Error of a frame against the every-pixel reference of the same time.
struct FrameError {
  double psnr;        // dB over RGB; +inf when identical
  int maxError;       // largest absolute channel difference, 0..255
  double offPercent;  // % of pixels with some channel off by more than 8/255
};
FrameError compare_images(const Image& ref, const Image& img);

// Flicker: the adaptive renderer's error seen over time. Frames 0 and 1 are
// kFlickerStep apart (one frame at 60 fps); a pixel flickers when, in some
// channel, its error against the reference changes by more than
// kFlickerThreshold / 255 from frame 0 to frame 1, i.e. its change on screen
// differs that much from the every-pixel picture's change (a small object or
// highlight that vanishes between two frames, or pops back). Returns the %
// of such pixels. All four images have one size.
constexpr double kFlickerStep = 1.0 / 60;
constexpr int kFlickerThreshold = 32;
double flicker_percent(const Image& ref0, const Image& img0, const Image& ref1, const Image& img1);

// What a viewer feels from a run of frame times (ms): the median and p95
// frame (nearest rank), the slowest, and the frame rates those give.
struct FrameTimes {
  double median, p95, max;
  double fpsMedian, fpsSlowest;  // 1000 / median, 1000 / max
};
FrameTimes frame_times(const std::vector<double>& ms);

// Prints the Markdown table to stdout, writes the CSV (and the plot).
// Returns 0, or 2 when an output cannot be written.
int run_bench(const BenchOptions& o);
