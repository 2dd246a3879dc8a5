// frame.cpp - a frame of the timeline, split into work items that threads
// pull from a shared counter. The core renders items; the threads live here.
#include "frame.h"

#include <atomic>
#include <mutex>
#include <thread>
#include <vector>

uint32_t id_color(int index) {
  if (index < 0) return 0xff000000u;
  // Hues spread by the golden angle, full saturation: neighbours in index
  // order get clearly different colours.
  float h = float(index) * 0.618034f;
  h -= float(int(h));
  auto channel = [h](float offset) {
    float x = h + offset;
    x -= float(int(x));
    float v = x < 1.0f / 6 ? 6 * x : x < 0.5f ? 1.0f : x < 2.0f / 3 ? 4 - 6 * x : 0.0f;
    return uint32_t(55 + 200 * v);
  };
  return 0xff000000u | channel(1.0f / 3) << 16 | channel(0.0f) << 8 | channel(2.0f / 3);
}

int default_threads() {
  unsigned n = std::thread::hardware_concurrency();
  return n ? int(n) : 1;
}

void parallel_for(int count, int threads, const std::function<void(int, RayStats&)>& fn,
                  RayStats* total) {
  std::atomic<int> next{0};
  std::mutex lock;
  RayStats sum{0, 0, 0};
  auto worker = [&] {
    RayStats local{0, 0, 0};
    for (int i; (i = next.fetch_add(1)) < count;) fn(i, local);
    std::lock_guard<std::mutex> g(lock);
    sum.primary += local.primary;
    sum.secondary += local.secondary;
    sum.shadow += local.shadow;
  };
  std::vector<std::thread> pool;
  for (int i = 1; i < threads; ++i) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  if (total) {
    total->primary += sum.primary;
    total->secondary += sum.secondary;
    total->shadow += sum.shadow;
  }
}

void render_frame(const Scene& scene, Image& img, const RenderOptions& opt, RayStats* stats) {
  if (stats) *stats = RayStats{0, 0, 0};
  if (opt.view == View::Ids) {
    CameraRays cam = camera_rays(scene.camera, img.width, img.height);
    parallel_for(img.height, opt.threads, [&](int y, RayStats& st) {
      for (int x = 0; x < img.width; ++x) {
        ++st.primary;
        img.at(x, y) = id_color(first_hit_object(scene, primary_ray(cam, float(x), float(y))));
      }
    }, stats);
    return;
  }
  if (opt.mode == Mode::Full && opt.view != View::Blocks) {
    parallel_for(img.height, opt.threads, [&](int y, RayStats& st) {
      render_full_rows(scene, img.pixels.data(), img.width, img.height, img.width, y, y + 1, &st);
    }, stats);
    return;
  }
  std::vector<CornerSample> corners(size_t(adaptive_corner_count(img.width, img.height, opt.block)));
  AdaptiveFrame f{};
  f.scene = &scene;
  f.fb = img.pixels.data();
  f.width = img.width;
  f.height = img.height;
  f.stride = img.width;
  f.baseBlock = opt.block;
  f.minBlock = opt.minBlock;
  f.mode = opt.mode == Mode::Copy ? kModeCopyOnly : kModeAdaptive;
  f.showBlocks = opt.view == View::Blocks;
  f.corners = corners.data();
  adaptive_begin(f);
  for (int phase = 0; phase < 2; ++phase)
    parallel_for(adaptive_items(f, phase), opt.threads,
                 [&](int item, RayStats& st) { adaptive_run(f, phase, item, &st); }, stats);
}
