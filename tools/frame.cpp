// frame.cpp - a frame of the timeline, split into rows that threads pull from
// a shared counter. The core renders rows; the threads live here.
#include "frame.h"

#include <atomic>
#include <thread>

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

void render_frame(const Scene& scene, Image& img, View view, int threads, RayStats* stats) {
  std::atomic<int> nextRow{0};
  std::atomic<uint64_t> primary{0}, secondary{0}, shadow{0};
  CameraRays cam = camera_rays(scene.camera, img.width, img.height);
  auto worker = [&] {
    RayStats local{0, 0, 0};
    for (int y; (y = nextRow.fetch_add(1)) < img.height;) {
      if (view == View::Color) {
        render_full_rows(scene, img.pixels.data(), img.width, img.height, img.width, y, y + 1,
                         &local);
      } else {
        for (int x = 0; x < img.width; ++x)
          img.at(x, y) = id_color(first_hit_object(scene, primary_ray(cam, float(x), float(y))));
      }
    }
    primary += local.primary;
    secondary += local.secondary;
    shadow += local.shadow;
  };
  std::vector<std::thread> pool;
  for (int i = 1; i < threads; ++i) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  if (stats) *stats = RayStats{primary, secondary, shadow};
}
