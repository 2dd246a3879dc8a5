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

// Error of `img` against the every-pixel reference.
struct FrameError {
  double psnr;        // dB over RGB; +inf when identical
  int maxError;       // largest absolute channel difference, 0..255
  double offPercent;  // % of pixels with some channel off by more than 8/255
};

FrameError compare(const Image& ref, const Image& img) {
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

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  size_t i = size_t(std::ceil(p * double(v.size()))) - 1;
  return v[std::min(i, v.size() - 1)];
}

struct ModeResult {
  std::vector<double> ms, ms1, psnr, off;
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
  std::fprintf(csv, "time,mode,ms,ms_1thread,psnr_db,max_error,off_percent,primary,secondary,shadow\n");
  Image ref(o.width, o.height), img(o.width, o.height);
  std::vector<uint8_t> kinds(size_t(o.width) * size_t(o.height));
  double started = now_ms();
  for (int f = 0; f < frames; ++f) {
    double t = f * o.step;
    Scene scene;
    build_timeline_scene(scene, t);
    RenderOptions full;
    full.mode = Mode::Full;
    full.threads = o.threads;
    render_frame(scene, ref, full, nullptr);  // the reference, untimed
    for (size_t m = 0; m < specs.size(); ++m) {
      RenderOptions opt;
      opt.mode = specs[m].mode;
      opt.block = specs[m].block ? specs[m].block : kDefaultBlock;
      opt.threads = o.threads;
      RayStats rays;
      std::fill(kinds.begin(), kinds.end(), uint8_t(kTraced));
      opt.kinds = kinds.data();
      double t0 = now_ms();
      render_frame(scene, img, opt, &rays);
      double ms = now_ms() - t0;
      opt.kinds = nullptr;
      double ms1 = NAN;
      if (o.scaling) {
        opt.threads = 1;
        t0 = now_ms();
        render_frame(scene, img, opt, nullptr);
        ms1 = now_ms() - t0;
      }
      FrameError e = compare(ref, img);
      ModeResult& r = results[m];
      for (uint8_t k : kinds) r.kindPixels[k & 3] += 1;
      r.ms.push_back(ms);
      if (o.scaling) r.ms1.push_back(ms1);
      r.psnr.push_back(e.psnr);
      r.off.push_back(e.offPercent);
      r.maxError = std::max(r.maxError, e.maxError);
      r.rays.primary += rays.primary;
      r.rays.secondary += rays.secondary;
      r.rays.shadow += rays.shadow;
      std::fprintf(csv, "%.3f,%s,%.4f,%.4f,%.3f,%d,%.4f,%llu,%llu,%llu\n", t,
                   specs[m].name.c_str(), ms, ms1, std::isinf(e.psnr) ? 999.0 : e.psnr,
                   e.maxError, e.offPercent, (unsigned long long)rays.primary,
                   (unsigned long long)rays.secondary, (unsigned long long)rays.shadow);
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
  std::printf("\nCSV: %s\n", printable(o.csvPath).c_str());

  if (!o.plotPath.empty()) return write_bench_plot(o, gnuplot, frames, results);
  return 0;
}
