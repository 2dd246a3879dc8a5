// rt64k - the Linux command-line tool: look at any frame of the intro.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "audio.h"
#include "bench.h"
#include "frame.h"
#include "output.h"
#include "overlay.h"

namespace {

const char* kUsage =
    "rt64k - headless renderer of the rt64k intro\n"
    "\n"
    "usage:\n"
    "  rt64k render --time T [--size WxH] [--view color|ids|blocks] [--mode full|copy|adaptive]\n"
    "               [--block N] [--threads N] [--overlay on|off] --out FILE.png\n"
    "      one frame of the 64-s timeline at time T seconds (any finite T; it loops),\n"
    "      with the intro's captions (--overlay on, the default; not in the ids view)\n"
    "  rt64k scene --time T [--size WxH]\n"
    "      the scene state at time T as JSON on stdout\n"
    "  rt64k sheet --out FILE.png [--threads N]\n"
    "      a contact sheet: 16 frames across the 64 s (scene 1 on top, scene 2 below)\n"
    "  rt64k bench [--step S] [--size WxH] [--threads N] [--modes LIST] [--csv FILE]\n"
    "              [--plot FILE.png] [--scaling on|off] [--repeat N]\n"
    "      renders the timeline every S seconds (default 0.25: 256 frames) in each mode\n"
    "      (default full,copy8,adaptive4,adaptive8,adaptive16) and prints a Markdown table\n"
    "      of ms/frame, rays/pixel and error against the full trace; writes CSV (default\n"
    "      bench.csv) and, with --plot, a PNG of ms/frame against PSNR (drawn by gnuplot);\n"
    "      --repeat N (1..32, default 1) times each frame N times, the fastest counting\n"
    "  rt64k audio --out FILE.wav\n"
    "      the intro's 64-s music loop, sample for sample what intro.exe plays\n"
    "  rt64k --help\n"
    "\n"
    "defaults: --size 800x600, --view color, --mode adaptive, --block 8, --threads = all cores\n"
    "exit codes: 0 ok, 2 bad arguments or output not writable\n"
    "outputs: a file appears whole or not at all (written beside it, then renamed\n"
    "over it); a device or pipe (/dev/null, /dev/stdout) is written in place\n";

struct UsageError {
  std::string message;
};

[[noreturn]] void fail(const std::string& message) { throw UsageError{message}; }

// Options of one command: "--name value" pairs, each allowed name listed.
struct Options {
  std::map<std::string, std::string> values;

  Options(int argc, char** argv, int first, const std::vector<std::string>& allowed) {
    for (int i = first; i < argc; ++i) {
      std::string name = argv[i];
      bool known = false;
      for (const auto& a : allowed) known |= a == name;
      if (!known) fail("unknown option '" + name + "'");
      if (i + 1 >= argc) fail("option " + name + " needs a value");
      if (values.count(name)) fail("option " + name + " given twice");
      values[name] = argv[++i];
    }
  }
  bool has(const std::string& name) const { return values.count(name) != 0; }
  std::string get(const std::string& name, const std::string& def = "") const {
    auto it = values.find(name);
    return it == values.end() ? def : it->second;
  }
  std::string require(const std::string& name) const {
    if (!has(name)) fail("missing required option " + name);
    return get(name);
  }
};

double parse_time(const std::string& text) {
  const char* s = text.c_str();
  char* end = nullptr;
  errno = 0;
  double t = std::strtod(s, &end);
  if (text.empty() || *end != '\0' || end == s) fail("--time: '" + text + "' is not a number");
  // Overflow gives +-inf; underflow (ERANGE with a denormal or 0) is a finite time.
  if (!std::isfinite(t)) fail("--time: '" + text + "' is not a finite number");
  return t;
}

long parse_int(const std::string& text, const std::string& what, long lo, long hi) {
  const char* s = text.c_str();
  char* end = nullptr;
  errno = 0;
  long v = std::strtol(s, &end, 10);
  if (text.empty() || *end != '\0' || errno == ERANGE || v < lo || v > hi)
    fail(what + ": '" + text + "' is not an integer in [" + std::to_string(lo) + ", " +
         std::to_string(hi) + "]");
  return v;
}

// Largest side accepted by --size: 16384 px (a 1 GiB framebuffer at 16384^2).
constexpr long kMaxSide = 16384;

void parse_size(const std::string& text, int& w, int& h) {
  size_t x = text.find('x');
  if (x == std::string::npos) fail("--size: '" + text + "' is not WxH (e.g. 800x600)");
  w = int(parse_int(text.substr(0, x), "--size width", 1, kMaxSide));
  h = int(parse_int(text.substr(x + 1), "--size height", 1, kMaxSide));
}

int parse_threads(const Options& o) {
  if (!o.has("--threads")) return default_threads();
  return int(parse_int(o.get("--threads"), "--threads", 1, 256));
}

void save(const std::string& path, const Image& img) {
  std::string error;
  if (!write_png(path, img, error)) fail(error);
}

// An output path that cannot be written fails before any rendering.
void check_output(const std::string& path) {
  std::string error;
  if (!check_output_path(path, error)) fail(error);
}

int cmd_render(int argc, char** argv) {
  Options o(argc, argv, 2,
            {"--time", "--size", "--view", "--mode", "--block", "--threads", "--overlay", "--out"});
  double t = parse_time(o.require("--time"));
  std::string out = o.require("--out");
  int w = 800, h = 600;
  if (o.has("--size")) parse_size(o.get("--size"), w, h);
  RenderOptions opt;
  std::string viewName = o.get("--view", "color");
  if (viewName == "color")
    opt.view = View::Color;
  else if (viewName == "ids")
    opt.view = View::Ids;
  else if (viewName == "blocks")
    opt.view = View::Blocks;
  else
    fail("--view: '" + viewName + "' is not one of color, ids, blocks");
  std::string modeName = o.get("--mode", "adaptive");
  if (modeName == "full")
    opt.mode = Mode::Full;
  else if (modeName == "copy")
    opt.mode = Mode::Copy;
  else if (modeName == "adaptive")
    opt.mode = Mode::Adaptive;
  else
    fail("--mode: '" + modeName + "' is not one of full, copy, adaptive");
  if (o.has("--block")) opt.block = int(parse_int(o.get("--block"), "--block", 2, 256));
  opt.threads = parse_threads(o);
  std::string overlay = o.get("--overlay", "on");
  if (overlay != "on" && overlay != "off") fail("--overlay: '" + overlay + "' is not on or off");
  check_output(out);
  Scene scene;
  TimelineState st = build_timeline_scene(scene, t);
  // The timeline's renderer-visualisation segment shows the blocks by itself.
  if (st.showBlocks && opt.view == View::Color) opt.view = View::Blocks;
  Image img(w, h);
  render_frame(scene, img, opt, nullptr);
  if (overlay == "on" && opt.view != View::Ids)
    overlay_draw(img.pixels.data(), w, h, w, timeline_wrap(t));
  save(out, img);
  return 0;
}

std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}
std::string vec(Vec3 v) {
  // One snprintf (as num's "%.9g"): GCC 12's -Wrestrict misfires on the
  // chain of string concatenations this was (a false positive, GCC PR 105329).
  char buf[96];
  std::snprintf(buf, sizeof buf, "[%.9g, %.9g, %.9g]", double(v.x), double(v.y), double(v.z));
  return buf;
}
std::string hex(uint32_t c) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "\"#%06x\"", c & 0xffffffu);
  return buf;
}

const char* kind_name(ShapeKind k) {
  switch (k) {
  case kSphere: return "sphere";
  case kPlane: return "plane";
  case kCylinder: return "cylinder";
  case kCone: return "cone";
  case kTriangle: return "triangle";
  case kEmpty: return "empty";
  }
  return "?";
}

std::string shape_json(const Shape& s) {
  std::string j = "{\"kind\": \"" + std::string(kind_name(s.kind)) + "\"";
  switch (s.kind) {
  case kSphere: j += ", \"center\": " + vec(s.a) + ", \"radius\": " + num(s.r0); break;
  case kPlane: j += ", \"normal\": " + vec(s.a) + ", \"offset\": " + num(s.r0); break;
  case kCylinder:
  case kCone:
    j += ", \"base\": " + vec(s.a) + ", \"axis\": " + vec(s.b) + ", \"base_radius\": " +
         num(s.r0) + ", \"top_radius\": " + num(s.r1) + ", \"height\": " + num(s.h) +
         ", \"cap_base\": " + (s.caps & kCapBase ? "true" : "false") +
         ", \"cap_top\": " + (s.caps & kCapTop ? "true" : "false");
    break;
  case kTriangle: j += ", \"vertices\": [" + vec(s.a) + ", " + vec(s.b) + ", " + vec(s.c) + "]"; break;
  case kEmpty: break;
  }
  return j + "}";
}

std::string material_json(const Material& m, ShadingModel model) {
  std::string j = "{\"color\": " + vec(m.color) + ", \"diffuse\": " + num(m.diffuse) +
                  ", \"specular\": " + num(m.specular) + ", \"reflect\": " + num(m.reflect) +
                  ", \"transmit\": " + num(m.transmit) + ", \"ior\": " + num(m.ior);
  if (model == kPhong)
    j += ", \"shininess\": " + num(m.shininess);
  else
    j += ", \"roughness\": " + num(m.roughness) + ", \"f0\": " + num(m.f0);
  return j + "}";
}

int cmd_scene(int argc, char** argv) {
  Options o(argc, argv, 2, {"--time", "--size"});
  double t = parse_time(o.require("--time"));
  int w = 800, h = 600;
  if (o.has("--size")) parse_size(o.get("--size"), w, h);
  Scene s;
  TimelineState st = build_timeline_scene(s, t);
  std::string j = "{\n";
  j += "  \"time\": " + num(t) + ",\n";
  j += "  \"timeline_time\": " + num(timeline_wrap(t)) + ",\n";
  j += "  \"scene\": " + std::to_string(st.scene) + ",\n";
  j += "  \"scene_time\": " + num(st.sceneTime) + ",\n";
  j += "  \"blocks_view\": " + std::string(st.showBlocks ? "true" : "false") + ",\n";
  j += "  \"shading\": \"" + std::string(s.model == kPhong ? "phong" : "cook-torrance") + "\",\n";
  j += "  \"background\": " + vec(s.background) + ",\n";
  j += "  \"ambient\": " + vec(s.ambient) + ",\n";
  j += "  \"max_depth\": " + std::to_string(s.maxDepth) + ",\n";
  j += "  \"camera\": {\"position\": " + vec(s.camera.pos) + ", \"target\": " +
       vec(s.camera.target) + ", \"up\": " + vec(s.camera.up) +
       ", \"fov_y_degrees\": " + num(s.camera.fovY * 180.0 / M_PI) + ", \"width\": " +
       std::to_string(w) + ", \"height\": " + std::to_string(h) + "},\n";
  j += "  \"lights\": [";
  for (int i = 0; i < s.numLights; ++i)
    j += std::string(i ? ",\n    " : "\n    ") + "{\"position\": " + vec(s.lights[i].pos) +
         ", \"color\": " + vec(s.lights[i].color) + "}";
  j += "\n  ],\n  \"objects\": [";
  for (int i = 0; i < s.numObjects; ++i) {
    const Object& ob = s.objects[i];
    j += std::string(i ? ",\n    " : "\n    ") + "{\"index\": " + std::to_string(i) +
         ", \"background\": " + (i >= s.numForeground ? "true" : "false") +
         ", \"ids_color\": " + hex(id_color(i)) + ", \"shape\": " + shape_json(ob.shape) +
         ", \"material\": " + material_json(ob.mat, s.model) + "}";
  }
  j += "\n  ]\n}\n";
  std::fputs(j.c_str(), stdout);
  return 0;
}

// Contact sheet: 4 x 4 thumbnails of 240 x 180, each rendered at twice that
// size and box-filtered, at the middle of each 4-s slot of the timeline.
int cmd_sheet(int argc, char** argv) {
  Options o(argc, argv, 2, {"--out", "--threads"});
  std::string out = o.require("--out");
  int threads = parse_threads(o);
  check_output(out);
  constexpr int kCols = 4, kRows = 4, kTw = 240, kTh = 180, kGap = 4;
  Image sheet(kCols * kTw + (kCols + 1) * kGap, kRows * kTh + (kRows + 1) * kGap);
  for (auto& p : sheet.pixels) p = 0xff101010u;
  for (int i = 0; i < kCols * kRows; ++i) {
    double t = 2.0 + 4.0 * i;
    Scene s;
    TimelineState st = build_timeline_scene(s, t);
    Image big(2 * kTw, 2 * kTh);
    RenderOptions opt;
    opt.mode = Mode::Full;
    opt.view = st.showBlocks ? View::Blocks : View::Color;
    opt.threads = threads;
    render_frame(s, big, opt, nullptr);
    overlay_draw(big.pixels.data(), big.width, big.height, big.width, timeline_wrap(t));
    int ox = kGap + (i % kCols) * (kTw + kGap), oy = kGap + (i / kCols) * (kTh + kGap);
    for (int y = 0; y < kTh; ++y)
      for (int x = 0; x < kTw; ++x) {
        uint32_t sum[3] = {0, 0, 0};
        for (int k = 0; k < 4; ++k) {
          uint32_t p = big.at(2 * x + (k & 1), 2 * y + (k >> 1));
          sum[0] += (p >> 16) & 255;
          sum[1] += (p >> 8) & 255;
          sum[2] += p & 255;
        }
        sheet.at(ox + x, oy + y) =
            0xff000000u | ((sum[0] + 2) / 4) << 16 | ((sum[1] + 2) / 4) << 8 | ((sum[2] + 2) / 4);
      }
  }
  save(out, sheet);
  return 0;
}

int cmd_bench(int argc, char** argv) {
  Options o(argc, argv, 2,
            {"--step", "--size", "--threads", "--modes", "--csv", "--plot", "--scaling",
             "--repeat"});
  BenchOptions b;
  if (o.has("--step")) {
    b.step = parse_time(o.get("--step"));
    if (!(b.step >= 0.01 && b.step <= kTimelineSeconds))
      fail("--step: '" + o.get("--step") + "' is not in [0.01, 64] seconds");
  }
  if (o.has("--size")) parse_size(o.get("--size"), b.width, b.height);
  b.threads = parse_threads(o);
  std::string list = o.get("--modes", "full,copy8,adaptive4,adaptive8,adaptive16");
  size_t start = 0;
  while (start <= list.size()) {
    size_t comma = list.find(',', start);
    std::string item = list.substr(start, comma == std::string::npos ? std::string::npos
                                                                     : comma - start);
    BenchMode m;
    if (!parse_bench_mode(item, m))
      fail("--modes: '" + item + "' is not full, copyN or adaptiveN (N = block, 2..256)");
    b.modes.push_back(m);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  b.csvPath = o.get("--csv", "bench.csv");
  b.plotPath = o.get("--plot", "");
  std::string scaling = o.get("--scaling", "on");
  if (scaling != "on" && scaling != "off") fail("--scaling: '" + scaling + "' is not on or off");
  b.scaling = scaling == "on";
  if (o.has("--repeat")) b.repeat = int(parse_int(o.get("--repeat"), "--repeat", 1, 32));
  return run_bench(b);
}

int run(int argc, char** argv) {
  try {
    if (argc < 2) fail("no command given (try rt64k --help)");
    std::string cmd = argv[1];
    if (cmd == "--help" || cmd == "-h" || cmd == "help") {
      std::fputs(kUsage, stdout);
      return 0;
    }
    if (cmd == "render") return cmd_render(argc, argv);
    if (cmd == "scene") return cmd_scene(argc, argv);
    if (cmd == "sheet") return cmd_sheet(argc, argv);
    if (cmd == "bench") return cmd_bench(argc, argv);
    if (cmd == "audio") return cmd_audio(argc, argv);
    fail("unknown command '" + cmd + "' (try rt64k --help)");
  } catch (const UsageError& e) {
    report_error(e.message);
    return 2;
  } catch (const std::exception& e) {
    report_error(e.what());
    return 2;
  }
}

} // namespace

int main(int argc, char** argv) {
  install_output_signal_handlers();
  int code = run(argc, argv);
  // Whatever went to stdout must have arrived (e.g. not > /dev/full).
  if (!finish_stdout()) return 2;
  return code;
}
