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
  bool progress = true;  // progress lines on stderr
  std::vector<BenchMode> modes;
  std::string csvPath = "bench.csv";
  std::string plotPath;  // empty: no plot
};

// Parses "full", "copy", "copyN", "adaptive", "adaptiveN" (N = base block,
// 2..256). Returns false for anything else.
bool parse_bench_mode(const std::string& text, BenchMode& out);

// Prints the Markdown table to stdout, writes the CSV (and the plot).
// Returns 0, or 2 when an output cannot be written.
int run_bench(const BenchOptions& o);
