// frame.h - rendering one frame of the timeline in the Linux tool, on threads.
#pragma once
#include "image.h"

#include "scenes.h"
#include "trace.h"

enum class View { Color, Ids };

// Flat colour of object `index` in the ids view (background: black).
uint32_t id_color(int index);

// Renders `scene` into img (already sized) with `threads` worker threads.
void render_frame(const Scene& scene, Image& img, View view, int threads, RayStats* stats);

// Number of hardware threads (at least 1).
int default_threads();
