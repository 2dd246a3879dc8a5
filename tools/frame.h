// frame.h - rendering one frame of the timeline in the Linux tool, on threads.
#pragma once
#include <functional>

#include "adaptive.h"
#include "image.h"
#include "scenes.h"

enum class View { Color, Ids, Blocks };
enum class Mode { Full, Copy, Adaptive };

// Defaults chosen from the speed-against-error bench (docs/speed-vs-error.md).
constexpr int kDefaultBlock = 8;
constexpr int kDefaultMinBlock = 2;

struct RenderOptions {
  View view = View::Color;
  Mode mode = Mode::Adaptive;
  int block = kDefaultBlock;
  int minBlock = kDefaultMinBlock;
  int threads = 1;
  uint8_t* kinds = nullptr;  // optional: width*height, AdaptiveFrame::kinds (adaptive modes)
};

// Flat colour of object `index` in the ids view (background: black).
uint32_t id_color(int index);

// Renders `scene` into img (already sized). View::Blocks is the adaptive
// renderer with its blocks tinted (copied red, interpolated blue); the
// timeline's own blocks segment (TimelineState::showBlocks) sets it too.
void render_frame(const Scene& scene, Image& img, const RenderOptions& opt, RayStats* stats);

// Runs fn(item) for item in [0, count) on `threads` threads pulling from a
// shared counter; returns when all are done.
void parallel_for(int count, int threads, const std::function<void(int item, RayStats&)>& fn,
                  RayStats* total);

// Number of hardware threads (at least 1).
int default_threads();
