// bench.cpp - `rt64k bench`: speed against error over the whole timeline.
#include "bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <sys/stat.h>

#include "output.h"
#include "plot.h"

namespace {

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  size_t i = size_t(std::ceil(p * double(v.size()))) - 1;
  return v[std::min(i, v.size() - 1)];
}

struct ModeResult {
  std::vector<double> ms, ms1, psnr, off;
  std::vector<double> flicker;          // per frame pair, %
  std::vector<int> scene;               // per frame, 1 or 2
  std::vector<int> maxErrors;           // per frame
  double kindPixels[4] = {0, 0, 0, 0};  // BlockKind counts over all frames
  int maxError = 0;
  RayStats rays{0, 0, 0};
};

std::string fmt(double v, int decimals) {
  if (std::isinf(v)) return "inf";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

double now_ms() {
  using namespace std::chrono;
  return duration<double, std::milli>(steady_clock::now().time_since_epoch()).count();
}

// Flicker of one mode between a frame (ref0, img0) and the next, kFlickerStep
// later (`next`, its reference ref1): renders the mode there, untimed, into
// `scratch`. The full trace is deterministic, so its next frame is ref1.
double measure_flicker(const Scene& next, const Image& ref0, const Image& img0, const Image& ref1,
                       RenderOptions opt, Image& scratch) {
  if (opt.mode == Mode::Full) return flicker_percent(ref0, img0, ref1, ref1);
  opt.kinds = nullptr;
  render_frame(next, scratch, opt, nullptr);
  return flicker_percent(ref0, img0, ref1, scratch);
}

// The viewer's table: per mode and per scene (and both), what the frame
// times feel like next to what the error looks like.
void print_viewer_table(const std::vector<BenchMode>& specs,
                        const std::vector<ModeResult>& results) {
  std::printf("\n| mode | scene | median ms | p95 ms | max ms | fps at median | fps at slowest | "
              "min PSNR dB | median PSNR dB | max abs error | pixels off > 8/255 (mean %%) | "
              "flicker > %d/255 (mean %%) | flicker (max %%) |\n",
              kFlickerThreshold);
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (size_t m = 0; m < specs.size(); ++m) {
    const ModeResult& r = results[m];
    for (int scene : {1, 2, 0}) {  // 0: both scenes
      std::vector<double> ms, psnr, off, flicker;
      int maxError = 0;
      for (size_t f = 0; f < r.ms.size(); ++f) {
        if (scene && r.scene[f] != scene) continue;
        ms.push_back(r.ms[f]);
        psnr.push_back(r.psnr[f]);
        off.push_back(r.off[f]);
        flicker.push_back(r.flicker[f]);
        maxError = std::max(maxError, r.maxErrors[f]);
      }
      if (ms.empty()) continue;
      FrameTimes ft = frame_times(ms);
      double offMean = 0, flickerMean = 0;
      for (size_t f = 0; f < ms.size(); ++f) {
        offMean += off[f] / double(ms.size());
        flickerMean += flicker[f] / double(ms.size());
      }
      std::printf("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %d | %s | %s | %s |\n",
                  specs[m].name.c_str(), scene ? std::to_string(scene).c_str() : "both",
                  fmt(ft.median, 2).c_str(), fmt(ft.p95, 2).c_str(), fmt(ft.max, 2).c_str(),
                  fmt(ft.fpsMedian, 1).c_str(), fmt(ft.fpsSlowest, 1).c_str(),
                  fmt(*std::min_element(psnr.begin(), psnr.end()), 2).c_str(),
                  fmt(percentile(psnr, 0.5), 2).c_str(), maxError, fmt(offMean, 3).c_str(),
                  fmt(flickerMean, 3).c_str(),
                  fmt(*std::max_element(flicker.begin(), flicker.end()), 3).c_str());
    }
  }
}

}  // namespace

FrameError compare_images(const Image& ref, const Image& img) {
  double sq = 0;
  int maxErr = 0;
  size_t off = 0;
  for (size_t i = 0; i < ref.pixels.size(); ++i) {
    uint32_t a = ref.pixels[i], b = img.pixels[i];
    int worst = 0;
    for (int sh = 0; sh < 24; sh += 8) {
      int d = std::abs(int(a >> sh & 255) - int(b >> sh & 255));
      sq += double(d) * d;
      worst = std::max(worst, d);
    }
    maxErr = std::max(maxErr, worst);
    off += worst > 8;
  }
  double mse = sq / (3.0 * double(ref.pixels.size()));
  double psnr = mse == 0 ? INFINITY : 10.0 * std::log10(255.0 * 255.0 / mse);
  return FrameError{psnr, maxErr, 100.0 * double(off) / double(ref.pixels.size())};
}

double flicker_percent(const Image& ref0, const Image& img0, const Image& ref1, const Image& img1) {
  size_t flickering = 0, n = ref0.pixels.size();
  for (size_t i = 0; i < n; ++i) {
    uint32_t r0 = ref0.pixels[i], a0 = img0.pixels[i], r1 = ref1.pixels[i], a1 = img1.pixels[i];
    bool flicker = false;
    for (int sh = 0; sh < 24; sh += 8) {
      int e0 = int(a0 >> sh & 255) - int(r0 >> sh & 255);  // signed error, frame 0
      int e1 = int(a1 >> sh & 255) - int(r1 >> sh & 255);
      flicker |= std::abs(e1 - e0) > kFlickerThreshold;
    }
    flickering += flicker;
  }
  return n ? 100.0 * double(flickering) / double(n) : 0.0;
}

FrameTimes frame_times(const std::vector<double>& ms) {
  FrameTimes t{percentile(ms, 0.5), percentile(ms, 0.95), percentile(ms, 1.0), 0, 0};
  t.fpsMedian = t.median > 0 ? 1000.0 / t.median : INFINITY;
  t.fpsSlowest = t.max > 0 ? 1000.0 / t.max : INFINITY;
  return t;
}

namespace {

// ---- output writing: paths checked up front, CSV and plot whole or not at all

// Every output path and gnuplot (with --plot), checked before the bench runs.
bool check_bench_outputs(const BenchOptions& o, std::string& gnuplot, std::string& error) {
  if (!check_output_path(o.csvPath, error)) {
    error = "--csv: " + error;
    return false;
  }
  if (o.plotPath.empty()) return true;
  if (!check_output_path(o.plotPath, error)) {
    error = "--plot: " + error;
    return false;
  }
  struct stat a, b;
  if (o.plotPath == o.csvPath ||
      (stat(o.csvPath.c_str(), &a) == 0 && stat(o.plotPath.c_str(), &b) == 0 &&
       a.st_dev == b.st_dev && a.st_ino == b.st_ino)) {
    error = "--csv and --plot name the same file '" + o.csvPath + "'";
    return false;
  }
  return find_gnuplot(gnuplot, error);
}

// The plot of median ms against min and median PSNR, one point per mode.
int write_bench_plot(const BenchOptions& o, const std::string& gnuplot, int frames,
                     const std::vector<ModeResult>& results) {
  std::vector<PlotPoint> points;
  for (size_t m = 0; m < o.modes.size(); ++m)
    points.push_back(PlotPoint{o.modes[m].name, percentile(results[m].ms, 0.5),
                               *std::min_element(results[m].psnr.begin(), results[m].psnr.end()),
                               percentile(results[m].psnr, 0.5), percentile(results[m].ms, 0.95)});
  std::string error;
  if (!draw_plot(gnuplot, o.plotPath, points, PlotTitle{o.width, o.height, frames, o.threads},
                 error)) {
    report_error(error);
    return 2;
  }
  std::printf("plot: %s\n", printable(o.plotPath).c_str());
  return 0;
}

}  // namespace

bool parse_bench_mode(const std::string& text, BenchMode& out) {
  auto numbered = [&](const std::string& prefix, Mode mode) {
    if (text.compare(0, prefix.size(), prefix) != 0) return false;
    std::string digits = text.substr(prefix.size());
    int block = kDefaultBlock;
    if (!digits.empty()) {
      if (digits.size() > 3 || digits.find_first_not_of("0123456789") != std::string::npos)
        return false;
      block = std::stoi(digits);
      if (block < 2 || block > 256) return false;
    }
    out = BenchMode{prefix + std::to_string(block), mode, block};
    return true;
  };
  if (text == "full") {
    out = BenchMode{"full", Mode::Full, 0};
    return true;
  }
  return numbered("adaptive", Mode::Adaptive) || numbered("copy", Mode::Copy);
}

int run_bench(const BenchOptions& o) {
  const std::vector<BenchMode>& specs = o.modes;
  int frames = int(std::floor(kTimelineSeconds / o.step + 1e-9));
  std::vector<ModeResult> results(specs.size());
  std::string gnuplot, error;
  OutputFile csvOut;
  if (!check_bench_outputs(o, gnuplot, error) || !csvOut.open(o.csvPath, error)) {
    report_error(error);
    return 2;
  }
  std::FILE* csv = csvOut.stream();
  std::fprintf(csv, "time,mode,ms,ms_1thread,psnr_db,max_error,off_percent,primary,secondary,"
                    "shadow,scene,flicker_percent\n");
  Image ref(o.width, o.height), img(o.width, o.height);
  Image refNext(o.width, o.height), imgNext(o.width, o.height);
  std::vector<uint8_t> kinds(size_t(o.width) * size_t(o.height));
  double started = now_ms();
  for (int f = 0; f < frames; ++f) {
    double t = f * o.step;
    Scene scene, next;
    int sceneIndex = build_timeline_scene(scene, t).scene;
    build_timeline_scene(next, t + kFlickerStep);
    RenderOptions full;
    full.mode = Mode::Full;
    full.threads = o.threads;
    render_frame(scene, ref, full, nullptr);  // the references, untimed
    render_frame(next, refNext, full, nullptr);
    for (size_t m = 0; m < specs.size(); ++m) {
      RenderOptions opt;
      opt.mode = specs[m].mode;
      opt.block = specs[m].block ? specs[m].block : kDefaultBlock;
      opt.threads = o.threads;
      // Both timings render the frame as a viewer gets it, without the
      // per-pixel kinds (writing them cost 4.5-11 % more instructions,
      // docs/speed-vs-error.md "Round four: thread scaling"), and take turns
      // at going first, so that neither always finds the caches warm from
      // the other. The kinds come from a third, untimed render. With
      // --repeat N each is timed N times and the fastest counts (a shared
      // machine's other work only ever adds time).
      RayStats rays{0, 0, 0};
      double ms = INFINITY, ms1 = o.scaling ? INFINITY : NAN;
      bool oneFirst = o.scaling && f % 2 == 1;
      for (int pass = 0; pass < (o.scaling ? 2 : 1) * o.repeat; ++pass) {
        bool one = (pass % 2 == 0) == oneFirst && o.scaling;
        opt.threads = one ? 1 : o.threads;
        RayStats passRays{0, 0, 0};
        double t0 = now_ms();
        render_frame(scene, img, opt, one ? nullptr : &passRays);
        double passMs = now_ms() - t0;
        if (!one) rays = passRays;
        double& best = one ? ms1 : ms;
        best = std::min(best, passMs);
      }
      opt.threads = o.threads;
      std::fill(kinds.begin(), kinds.end(), uint8_t(kTraced));
      if (opt.mode != Mode::Full) { // the full trace leaves kinds at kTraced
        opt.kinds = kinds.data();
        render_frame(scene, img, opt, nullptr);
        opt.kinds = nullptr;
      }
      FrameError e = compare_images(ref, img);
      double flicker = measure_flicker(next, ref, img, refNext, opt, imgNext);
      ModeResult& r = results[m];
      for (uint8_t k : kinds) r.kindPixels[k & kKindMask] += 1;
      r.ms.push_back(ms);
      if (o.scaling) r.ms1.push_back(ms1);
      r.psnr.push_back(e.psnr);
      r.off.push_back(e.offPercent);
      r.maxError = std::max(r.maxError, e.maxError);
      r.maxErrors.push_back(e.maxError);
      r.flicker.push_back(flicker);
      r.scene.push_back(sceneIndex);
      r.rays.primary += rays.primary;
      r.rays.secondary += rays.secondary;
      r.rays.shadow += rays.shadow;
      std::fprintf(csv, "%.3f,%s,%.4f,%.4f,%.3f,%d,%.4f,%llu,%llu,%llu,%d,%.4f\n", t,
                   specs[m].name.c_str(), ms, ms1, std::isinf(e.psnr) ? 999.0 : e.psnr,
                   e.maxError, e.offPercent, (unsigned long long)rays.primary,
                   (unsigned long long)rays.secondary, (unsigned long long)rays.shadow,
                   sceneIndex, flicker);
    }
    if (o.progress && (f % 8 == 7 || f + 1 == frames))
      std::fprintf(stderr, "bench: frame %d/%d (t = %.2f s), %.0f s elapsed\n", f + 1, frames, t,
                   (now_ms() - started) / 1000);
    if (csvOut.failed()) break; // reported by commit: no use measuring on
  }
  if (!csvOut.commit(error)) {
    report_error(error);
    return 2;
  }

  double pixels = double(o.width) * o.height * frames;
  double fullMedian = 0;
  for (size_t m = 0; m < specs.size(); ++m)
    if (specs[m].mode == Mode::Full) fullMedian = percentile(results[m].ms, 0.5);
  std::printf("%d frames at %dx%d, every %.3f s, %d threads\n\n", frames, o.width, o.height,
              o.step, o.threads);
  std::printf("| mode | median ms | p95 ms | max ms | speed-up vs full | 1-thread median ms | "
              "thread scaling | primary rays/px | secondary rays/px | shadow rays/px | "
              "min PSNR dB | median PSNR dB | max abs error | pixels off > 8/255 (mean %%) | "
              "pixels copied / interpolated / traced %% |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (size_t m = 0; m < specs.size(); ++m) {
    const ModeResult& r = results[m];
    double med = percentile(r.ms, 0.5);
    double med1 = o.scaling ? percentile(r.ms1, 0.5) : NAN;
    double offMean = 0;
    for (double v : r.off) offMean += v / double(r.off.size());
    std::string kindsText = fmt(100 * r.kindPixels[kCopied] / pixels, 1) + " / " +
                            fmt(100 * r.kindPixels[kInterpolated] / pixels, 1) + " / " +
                            fmt(100 * r.kindPixels[kTraced] / pixels, 1);
    std::printf("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %d | %s | %s |\n",
                specs[m].name.c_str(), fmt(med, 2).c_str(), fmt(percentile(r.ms, 0.95), 2).c_str(),
                fmt(percentile(r.ms, 1.0), 2).c_str(),
                fullMedian > 0 ? (fmt(fullMedian / med, 1) + "x").c_str() : "-",
                o.scaling ? fmt(med1, 2).c_str() : "-",
                o.scaling ? (fmt(med1 / med, 2) + "x").c_str() : "-",
                fmt(double(r.rays.primary) / pixels, 3).c_str(),
                fmt(double(r.rays.secondary) / pixels, 3).c_str(),
                fmt(double(r.rays.shadow) / pixels, 3).c_str(),
                fmt(*std::min_element(r.psnr.begin(), r.psnr.end()), 2).c_str(),
                fmt(percentile(r.psnr, 0.5), 2).c_str(), r.maxError, fmt(offMean, 3).c_str(),
                kindsText.c_str());
  }
  print_viewer_table(specs, results);
  std::printf("\nCSV: %s\n", printable(o.csvPath).c_str());

  if (!o.plotPath.empty()) return write_bench_plot(o, gnuplot, frames, results);
  return 0;
}
