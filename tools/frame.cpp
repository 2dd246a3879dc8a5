// frame.cpp - a frame of the timeline, split into work items that threads
// pull from a shared counter. The core renders items; the threads live here.
#include "frame.h"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include <immintrin.h>

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

namespace {

// How long the calling thread spins for the workers' last items before it
// sleeps: longer than an adaptive8 band at 800x600 takes (0.1-1 ms), short
// beside a frame of the full trace.
constexpr std::chrono::microseconds kFinishSpin{2000};

// A persistent pool: workers sleep between jobs, so a frame costs one wake-up
// (the workers'), not thread creation. The calling thread works too.
class Pool {
public:
  explicit Pool(int workers) {
    for (int i = 0; i < workers; ++i)
      threads_.emplace_back([this] { loop(); });
  }
  ~Pool() {
    {
      std::lock_guard<std::mutex> g(mutex_);
      quit_ = true;
    }
    wake_.notify_all();
    for (auto& t : threads_)
      t.join();
  }
  int workers() const { return int(threads_.size()); }

  void run(int count, const std::function<void(int, RayStats&)>& fn, RayStats* total) {
    {
      std::lock_guard<std::mutex> g(mutex_);
      fn_ = &fn;
      count_ = count;
      next_ = 0;
      busy_.store(int(threads_.size()), std::memory_order_relaxed);
      sum_ = RayStats{0, 0, 0};
      ++generation_;
    }
    wake_.notify_all();
    work();
    // The caller has nothing else to do until the workers finish their last
    // items: it watches busy_ for up to kFinishSpin before it sleeps, so the
    // frame does not end with a wake-up (docs/speed-vs-error.md, "Round
    // four: thread scaling").
    auto spinEnd = std::chrono::steady_clock::now() + kFinishSpin;
    while (busy_.load(std::memory_order_acquire) != 0 && std::chrono::steady_clock::now() < spinEnd)
      _mm_pause();
    std::unique_lock<std::mutex> g(mutex_);
    done_.wait(g, [this] { return busy_.load(std::memory_order_acquire) == 0; });
    if (total) {
      total->primary += sum_.primary;
      total->secondary += sum_.secondary;
      total->shadow += sum_.shadow;
    }
  }

private:
  void work() {
    RayStats local{0, 0, 0};
    for (int i; (i = next_.fetch_add(1)) < count_;)
      (*fn_)(i, local);
    std::lock_guard<std::mutex> g(mutex_);
    sum_.primary += local.primary;
    sum_.secondary += local.secondary;
    sum_.shadow += local.shadow;
  }
  void loop() {
    unsigned long seen = 0;
    for (;;) {
      {
        std::unique_lock<std::mutex> g(mutex_);
        wake_.wait(g, [&] { return quit_ || generation_ != seen; });
        if (quit_) return;
        seen = generation_;
      }
      work();
      // Counted down outside the lock, which the caller then takes to see
      // the count (done_'s predicate) or to be notified: no lost wake-up.
      if (busy_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
        std::lock_guard<std::mutex> g(mutex_);
        done_.notify_one();
      }
    }
  }

  std::vector<std::thread> threads_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  const std::function<void(int, RayStats&)>* fn_ = nullptr;
  int count_ = 0;
  std::atomic<int> next_{0}, busy_{0};
  unsigned long generation_ = 0;
  bool quit_ = false;
  RayStats sum_{0, 0, 0};
};

} // namespace

void parallel_for(int count, int threads, const std::function<void(int, RayStats&)>& fn,
                  RayStats* total) {
  // One pool per thread count, kept for the life of the process.
  static std::mutex poolsLock;
  static std::vector<std::unique_ptr<Pool>> pools;
  Pool* pool = nullptr;
  {
    std::lock_guard<std::mutex> g(poolsLock);
    for (auto& p : pools)
      if (p->workers() == threads - 1) pool = p.get();
    if (!pool) {
      pools.push_back(std::make_unique<Pool>(threads - 1));
      pool = pools.back().get();
    }
  }
  pool->run(count, fn, total);
}

void render_frame(const Scene& scene, Image& img, const RenderOptions& opt, RayStats* stats) {
  if (stats) *stats = RayStats{0, 0, 0};
  if (opt.view == View::Ids) {
    CameraRays cam = camera_rays(scene.camera, img.width, img.height);
    parallel_for(
        img.height, opt.threads,
        [&](int y, RayStats& st) {
          for (int x = 0; x < img.width; ++x) {
            ++st.primary;
            img.at(x, y) = id_color(first_hit_object(scene, primary_ray(cam, float(x), float(y))));
          }
        },
        stats);
    return;
  }
  if (opt.mode == Mode::Full && opt.view != View::Blocks) {
    parallel_for(
        img.height, opt.threads,
        [&](int y, RayStats& st) {
          render_full_rows(scene, img.pixels.data(), img.width, img.height, img.width, y, y + 1,
                           &st);
        },
        stats);
    return;
  }
  // Not zeroed (new[] of a plain struct): the renderer sets every slot's state
  // before reading it, and zeroing ~3 MB at 800x600 (2.7 MB when measured) cost ~0.2 ms a frame.
  std::unique_ptr<CornerSample[]> corners(
      new CornerSample[size_t(adaptive_corner_count(img.width, img.height, opt.block))]);
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
  f.corners = corners.get();
  f.kinds = opt.kinds;
  adaptive_begin(f);
  // One pass, no barrier: each thread takes bands until none is left
  // (adaptive.h: an odd band waits only for its two even neighbours). A
  // thread may run two of these loops; the second finds nothing left.
  parallel_for(
      opt.threads, opt.threads,
      [&](int, RayStats& st) {
        for (int band; (band = adaptive_take(f)) != kAdaptiveDone;) {
          if (band == kAdaptiveWait)
            std::this_thread::yield(); // lets a preempted neighbour's thread finish
          else
            adaptive_run(f, band, &st);
        }
      },
      stats);
}
