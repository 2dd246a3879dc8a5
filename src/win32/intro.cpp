// intro.cpp - the Win32 entry point of intro.exe: window, clock, threads, music.
//
// Platform contract (STYLE.md 1): this file alone owns the window, the clock,
// the worker threads, the framebuffer and the sample buffer; src/core and
// scenes/ only turn a time into pixels (and the synth into samples), exactly
// as they do for the Linux tool. No C runtime: the linker enters at
// intro_entry(), which never returns; every way out is ExitProcess (0 for Esc,
// closing the window, the end of /once and of /bench; 1 when the system
// refuses memory, a thread or the window).
#define WIN32_LEAN_AND_MEAN
#define _WIN32_WINNT 0x0601 // Windows 7: SetProcessDPIAware, AttachConsole
#include <windows.h>

#include "adaptive.h"
#include "audio.h"
#include "overlay.h"
#include "scenes.h"
#include "switches.h"
#include "synth.h"
#include "text.h"

// The exe's own module handle is its load address, which GNU ld (as MSVC's
// linker) names __ImageBase: GetModuleHandleA(nullptr) without the import.
extern "C" IMAGE_DOS_HEADER __ImageBase;

namespace {

// The picture's own size: the window's client area, and what /f /scaled
// renders and scales to the screen. /f renders at the screen's largest 4:3
// size instead; a window that does not fit the screen renders smaller.
constexpr int kWidth = 800;
constexpr int kHeight = 600;
static_assert(kOnceLoopSeconds == kTimelineSeconds, "/once ends at the timeline's loop");
// The adaptive renderer's settings: those of `rt64k render --mode adaptive`
// (kDefaultBlock, kDefaultMinBlock in tools/frame.h, chosen from the
// speed-against-error bench), so the screenshot tests can demand the same
// pixels. Change both together.
constexpr int kBaseBlock = 8;
constexpr int kMinBlock = 2;
// Without RT64K_ADAPTIVE a work item is a band of kBandRows fully traced
// rows (75 bands at 600 rows keep every core busy to the end of a frame; the
// last band of a height that 8 does not divide is shorter).
constexpr int kBandRows = 8;
// Render threads: one per logical processor, at most this many (the most
// GetSystemInfo reports for one processor group).
constexpr DWORD kMaxWorkers = 64;

// /bench renders kBenchFrames frames at times kBenchFirst + i * kBenchStep:
// the middle of each 2-s slot of the whole 64-s timeline, so both scenes
// count equally and no frame falls on a fade to black at a scene cut.
constexpr int kBenchFrames = 32;
constexpr double kBenchStep = (double)kTimelineSeconds / kBenchFrames;
constexpr double kBenchFirst = kBenchStep / 2;
constexpr int kBenchDecimals = 2; // fps, seconds and milliseconds in the report
// /log prints the picture's time with enough decimals to give back the same
// float timeline time when `rt64k render --time` reads it (timeline_wrap's
// float has ~4e-6 s steps near 64 s), the other times to the microsecond.
constexpr int kLogTimeDecimals = 9;
constexpr int kLogDecimals = 6;

// Music: the loop is rendered once and stored twice in a row, so that a
// window of kAudioFrames frames starting anywhere in the first copy is the
// loop played from that point: waveOut plays it from the /t: time, in step
// with the picture. 4 bytes per stereo frame.
constexpr int kSampleCopies = 2;
constexpr SIZE_T kLoopBytes = (SIZE_T)kAudioFrames * 4;
constexpr int kShortsPerFrame = 2;

const char kClassName[] = "rt64k";
const char kWindowTitle[] = "rt64k";
const char kBenchFileName[] = "rt64k-bench.txt";
// Room for a full path (MAX_PATH) plus the report's file name.
constexpr DWORD kPathChars = MAX_PATH + sizeof kBenchFileName;
constexpr int kReportChars = 256;

constexpr DWORD kWindowStyle = WS_OVERLAPPED | WS_CAPTION | WS_SYSMENU | WS_MINIMIZEBOX;
constexpr DWORD kFullscreenStyle = WS_POPUP; // no caption, no border
// While minimised no frame is rendered; the main thread sleeps in the
// message wait and wakes at least this often to check /once's end.
constexpr DWORD kMinimisedWaitMs = 250;

// One frame of work items, shared by the main thread and the workers. The
// adaptive renderer hands out its bands itself (adaptive_take, adaptive.h):
// one pass, no barrier; an odd band is handed out once its two even
// neighbours are done, and a worker told to wait (every even band taken,
// the next odd band's neighbours still running) yields and asks again. That
// cannot deadlock: even bands wait for nothing, so the bands the waiting
// worker needs finish (on other workers, or on this core once SwitchToThread
// lets a preempted one run). The ordering of the samples one band writes
// before the next reads them is the core's (release/acquire done flags).
// Without RT64K_ADAPTIVE the items are bands of rows taken from `nextItem`.
//
// The job lives on the main thread's stack (no global to address; see
// audio.cpp for the exe's one global, in .bss). The main thread writes
// `scene`, `frame` and the counters only while
// every worker waits on `start`; the semaphore release and the interlocked
// operations order those writes before the workers' reads.
struct FrameJob {
  Scene scene;
  AdaptiveFrame frame;      // frame.scene points at `scene`
  HANDLE start;             // semaphore: one count per worker per frame
  HANDLE done;              // semaphore (0 or 1): released by the last worker to finish
  LONG items;               // bands of rows (without RT64K_ADAPTIVE)
  volatile LONG nextItem;   // next item to take (without RT64K_ADAPTIVE)
  volatile LONG busyCounts; // counts of `start` taken and not yet handed back
};

// A render worker. Each frame it takes one count of job.start, pulls items
// from the shared counter until none is left and calls the core once per
// item; the worker that hands back the frame's last count signals job.done.
// A worker may take two counts of one frame; every item is still finished
// before its own count is handed back, so "all counts back" means "all
// items done".
DWORD WINAPI render_worker(void* parameter) {
  FrameJob& job = *(FrameJob*)parameter;
  const AdaptiveFrame& f = job.frame;
  for (;;) {
    WaitForSingleObject(job.start, INFINITE);
    RayStats stats; // adaptive_run adds to it; intro.exe does not report rays
    if (RT64K_ADAPTIVE) {
      for (int band; (band = adaptive_take(f)) != kAdaptiveDone;) {
        if (band == kAdaptiveWait)
          SwitchToThread(); // lets a preempted neighbour's worker finish on this core
        else
          adaptive_run(f, band, &stats);
      }
    } else {
      for (LONG item; (item = InterlockedIncrement(&job.nextItem) - 1) < job.items;) {
        int rowEnd = (item + 1) * kBandRows;
        render_full_rows(job.scene, f.fb, f.width, f.height, f.stride, item * kBandRows,
                         rowEnd < f.height ? rowEnd : f.height, nullptr);
      }
    }
    if (InterlockedDecrement(&job.busyCounts) == 0) ReleaseSemaphore(job.done, 1, nullptr);
  }
}

// The music's precalc thread: renders the loop into `parameter` (two loops'
// room, VirtualAlloc'ed, so zero-filled) and copies it after itself. The
// synth's scratch (237 KiB) lives on this thread's stack, within the exe's
// 2-MB stack reserve (the probe ___chkstk_ms commits it page by page), and
// goes when the thread ends: no allocation, nothing to free.
DWORD WINAPI synth_worker(void* parameter) {
  short* samples = (short*)parameter;
  float scratch[kSynthScratchFloats];
  synth_render(samples, scratch);
  memcpy(samples + kAudioFrames * kShortsPerFrame, samples, kLoopBytes);
  return 0;
}

[[noreturn]] void quit() {
  if (RT64K_MUSIC) audio_stop();
  ExitProcess(0);
}

LRESULT CALLBACK window_proc(HWND window, UINT message, WPARAM wParam, LPARAM lParam) {
  // Esc and closing (the close box, Alt+F4) end the intro at once.
  if ((message == WM_KEYDOWN && wParam == VK_ESCAPE) || message == WM_CLOSE ||
      message == WM_DESTROY)
    quit();
  return DefWindowProcA(window, message, wParam, lParam);
}

void pump_messages() {
  MSG msg;
  while (PeekMessageA(&msg, nullptr, 0, 0, PM_REMOVE)) {
    if (msg.message == WM_QUIT) quit();
    DispatchMessageA(&msg);
  }
}

// Waits for `object` (a semaphore or a thread) while serving the window, so Esc
// acts within one message round trip however long the wait.
void wait_pumping(HANDLE object) {
  for (;;) {
    pump_messages();
    if (MsgWaitForMultipleObjectsEx(1, &object, INFINITE, QS_ALLINPUT, MWMO_INPUTAVAILABLE) ==
        WAIT_OBJECT_0)
      return;
  }
}

// Renders job.scene into job.frame.fb on all workers and returns when done.
void render_frame(FrameJob& job, LONG workers) {
  if (RT64K_ADAPTIVE)
    adaptive_begin(job.frame);
  else
    job.items = (job.frame.height + kBandRows - 1) / kBandRows;
  job.nextItem = 0;
  job.busyCounts = workers;
  ReleaseSemaphore(job.start, workers, nullptr);
  wait_pumping(job.done);
}

double seconds_between(LARGE_INTEGER from, LARGE_INTEGER to, LARGE_INTEGER frequency) {
  return (double)(to.QuadPart - from.QuadPart) / (double)frequency.QuadPart;
}

// Writes to stdout: the parent's console, or wherever the handle is
// redirected (under Wine the Unix stdout). Nothing when there is none.
void write_stdout(const char* text, DWORD length) {
  DWORD written;
  HANDLE out = GetStdHandle(STD_OUTPUT_HANDLE);
  if (!out || out == INVALID_HANDLE_VALUE) {
    if (AttachConsole(ATTACH_PARENT_PROCESS))
      out = CreateFileA("CONOUT$", GENERIC_WRITE, FILE_SHARE_WRITE, nullptr, OPEN_EXISTING, 0,
                        nullptr);
  }
  if (out && out != INVALID_HANDLE_VALUE) WriteFile(out, text, length, &written, nullptr);
}

// The /bench line goes to stdout and to kBenchFileName next to the exe (in
// the current directory if the exe's path is too long). The file is not
// closed: the process exits right after (finish_bench), which closes it;
// WriteFile has put the line into it by then (one import fewer).
void write_bench_report(const char* text, DWORD length) {
  write_stdout(text, length);
  DWORD written;
  char path[kPathChars];
  DWORD n = GetModuleFileNameA(nullptr, path, MAX_PATH);
  DWORD nameAt = 0; // where the file name goes: after the exe's last separator
  if (n > 0 && n < MAX_PATH)
    for (DWORD i = 0; i < n; ++i)
      if (path[i] == '\\' || path[i] == '/') nameAt = i + 1;
  for (DWORD i = 0; i < sizeof kBenchFileName; ++i)
    path[nameAt + i] = kBenchFileName[i];
  HANDLE file =
      CreateFileA(path, GENERIC_WRITE, 0, nullptr, CREATE_ALWAYS, FILE_ATTRIBUTE_NORMAL, nullptr);
  if (file != INVALID_HANDLE_VALUE) WriteFile(file, text, length, &written, nullptr);
}

// CPU time (user + kernel) of all the process's threads so far, seconds. On
// a busy machine the wall-clock fps drops, CPU seconds per frame do not.
double process_cpu_seconds() {
  constexpr double kFileTimeTick = 1e-7; // FILETIME counts 100-ns ticks
  FILETIME creation, exit, kernel, user;
  // (HANDLE)-1: the pseudo handle GetCurrentProcess() returns, a documented
  // constant; one import less.
  if (!GetProcessTimes((HANDLE)-1, &creation, &exit, &kernel, &user)) return 0.0;
  // Ticks < 2^63 (29,000 years): converted as signed, one instruction.
  auto ticks = [](FILETIME f) {
    return (double)(long long)(((u64)f.dwHighDateTime << 32) | f.dwLowDateTime);
  };
  return (ticks(kernel) + ticks(user)) * kFileTimeTick;
}

// /bench's figures: frames rendered at width x height on `workers` threads
// in `seconds` (wall clock), the slowest frame (scene, render, captions and
// blit) in `slowestSeconds`.
[[noreturn]] void finish_bench(int width, int height, LONG workers, double seconds,
                               double slowestSeconds) {
  char storage[kReportChars];
  TextBuffer b = text_buffer(storage, kReportChars);
  append(b, "rt64k bench: ");
  append_uint(b, kBenchFrames);
  append(b, " frames ");
  append_uint(b, (unsigned)width);
  append(b, "x");
  append_uint(b, (unsigned)height);
  append(b, " on ");
  append_uint(b, (unsigned long long)workers);
  append(b, " threads in ");
  append_fixed(b, seconds, kBenchDecimals);
  append(b, " s = ");
  append_fixed(b, kBenchFrames / seconds, kBenchDecimals);
  append(b, " fps, slowest ");
  append_fixed(b, slowestSeconds * 1000.0, kBenchDecimals);
  append(b, " ms, CPU ");
  append_fixed(b, process_cpu_seconds(), kBenchDecimals);
  append(b, " s\r\n");
  write_bench_report(storage, (DWORD)text_length(b));
  ExitProcess(0);
}

// /log: "t=T a=A w=W" per frame: T the time the frame shows (the timeline
// wraps it), A the music's position the clock read (seconds since playback
// began; -1 when the frame's time did not come from the music), W seconds of
// QueryPerformanceCounter since just before the first frame.
void log_frame(double t, double played, double wall) {
  char storage[kReportChars];
  TextBuffer b = text_buffer(storage, kReportChars);
  append(b, "t=");
  append_fixed(b, t, kLogTimeDecimals);
  append(b, " a=");
  append_fixed(b, played, kLogDecimals);
  append(b, " w=");
  append_fixed(b, wall, kLogDecimals);
  append(b, "\r\n");
  write_stdout(storage, (DWORD)text_length(b));
}

// Where the picture goes: the window, the size the picture is rendered at
// and the rectangle of the client area it is drawn into (1:1 unless /f
// /scaled stretches the 800x600 picture).
struct Layout {
  DWORD style;
  int windowX, windowY; // CW_USEDEFAULT, or where a shrunk window goes
  int clientW, clientH; // the client area
  int renderW, renderH; // the framebuffer
  int pictureX, pictureY, pictureW, pictureH;
};

// The largest width x height of the picture's 4:3 aspect ratio within
// maxW x maxH (integer division: at most a pixel short of 4:3).
void fit_picture(int maxW, int maxH, int& width, int& height) {
  width = maxW;
  height = maxW * kHeight / kWidth;
  if (height > maxH) {
    height = maxH;
    width = maxH * kWidth / kHeight;
  }
  if (width < 1) width = 1;
  if (height < 1) height = 1;
}

// /f: a borderless popup over the whole primary monitor; the picture is
// rendered at the largest 4:3 size that fits it (or, with /scaled, at
// 800x600 and stretched to that size), centred, black bars around it (the
// class's black brush). Windowed: an 800x600 client area, or, on a screen
// whose work area cannot hold that with the window's frame, the largest
// 4:3 client area that fits, rendered at that size, at the work area's top.
Layout choose_layout(const IntroOptions& options) {
  Layout l;
  l.style = kWindowStyle;
  l.windowX = l.windowY = CW_USEDEFAULT;
  l.clientW = kWidth;
  l.clientH = kHeight;
  if (RT64K_FULLSCREEN && options.fullscreen) {
    l.style = kFullscreenStyle; // CW_USEDEFAULT places a popup at 0, 0
    l.clientW = GetSystemMetrics(SM_CXSCREEN);
    l.clientH = GetSystemMetrics(SM_CYSCREEN);
    fit_picture(l.clientW, l.clientH, l.pictureW, l.pictureH);
  } else {
    RECT work, frame = {0, 0, 0, 0};
    if (!SystemParametersInfoA(SPI_GETWORKAREA, 0, &work, 0)) {
      work.left = work.top = 0;
      work.right = GetSystemMetrics(SM_CXSCREEN);
      work.bottom = GetSystemMetrics(SM_CYSCREEN);
    }
    AdjustWindowRect(&frame, l.style, FALSE); // the frame around a client area
    int roomW = (work.right - work.left) - (frame.right - frame.left);
    int roomH = (work.bottom - work.top) - (frame.bottom - frame.top);
    if (roomW < kWidth || roomH < kHeight) {
      fit_picture(roomW < kWidth ? roomW : kWidth, roomH < kHeight ? roomH : kHeight, l.clientW,
                  l.clientH);
      l.windowX = work.left;
      l.windowY = work.top;
    }
    l.pictureW = l.clientW;
    l.pictureH = l.clientH;
  }
  l.renderW = l.pictureW;
  l.renderH = l.pictureH;
  if (RT64K_FULLSCREEN && options.fullscreen && options.scaled) {
    l.renderW = kWidth;
    l.renderH = kHeight;
  }
  l.pictureX = (l.clientW - l.pictureW) / 2;
  l.pictureY = (l.clientH - l.pictureH) / 2;
  return l;
}

// While the window is minimised nothing is rendered: the main thread waits
// for messages (a restore wakes it), at most kMinimisedWaitMs at a time, and
// returns true once the window is back. False (nothing waited) if it is not
// minimised. The clock runs on meanwhile, as the music does.
bool idle_while_minimised(HWND window) {
  if (!IsIconic(window)) return false;
  MsgWaitForMultipleObjectsEx(0, nullptr, kMinimisedWaitMs, QS_ALLINPUT, MWMO_INPUTAVAILABLE);
  pump_messages();
  return true;
}

[[noreturn]] void run(const IntroOptions& options) {
  const bool bench = RT64K_BENCH && options.bench; // a constant false without the feature
  // Real pixels on scaled desktops: otherwise Windows would stretch the
  // 800x600 client area (blurring it) on a display set above 100 %, and
  // GetSystemMetrics would report a scaled-down screen.
  SetProcessDPIAware();

  const Layout layout = choose_layout(options);
  FrameJob job;
  AdaptiveFrame& f = job.frame;
  f.scene = &job.scene;
  f.width = f.stride = layout.renderW;
  f.height = layout.renderH;
  f.baseBlock = kBaseBlock;
  f.minBlock = kMinBlock;
  f.mode = kModeAdaptive;
  f.kinds = nullptr;
  // The framebuffer and the corner samples, allocated once for the whole run.
  f.fb = (u32*)VirtualAlloc(nullptr, (SIZE_T)f.width * f.height * sizeof(u32),
                            MEM_COMMIT | MEM_RESERVE, PAGE_READWRITE);
  f.corners = (CornerSample*)VirtualAlloc(
      nullptr, adaptive_corner_count(f.width, f.height, kBaseBlock) * sizeof(CornerSample),
      MEM_COMMIT | MEM_RESERVE, PAGE_READWRITE);
  job.start = CreateSemaphoreA(nullptr, 0, kMaxWorkers, nullptr);
  // A semaphore of at most one count where an auto-reset event would do: released
  // once per frame and taken by the main thread's wait, the same; two imports fewer.
  job.done = CreateSemaphoreA(nullptr, 0, 1, nullptr);
  if (!f.fb || !f.corners || !job.start || !job.done) ExitProcess(1);

  SYSTEM_INFO system;
  GetSystemInfo(&system);
  DWORD cores = system.dwNumberOfProcessors;
  if (cores < 1) cores = 1;
  if (cores > kMaxWorkers) cores = kMaxWorkers;
  LONG workers = 0;
  for (DWORD i = 0; i < cores; ++i)
    if (CreateThread(nullptr, 0, render_worker, &job, 0, nullptr)) ++workers;
  if (workers == 0) ExitProcess(1);

  // Music, unless its clock is not wanted (/hold, /bench) or /mute: the loop
  // is synthesised on a thread of its own while the window opens and shows
  // the first frame. Any failure here means silence on the system clock.
  short* samples = nullptr;
  HANDLE synth = nullptr;
  if (RT64K_MUSIC && !options.hold && !bench && !options.mute) {
    samples = (short*)VirtualAlloc(nullptr, kSampleCopies * kLoopBytes, MEM_COMMIT | MEM_RESERVE,
                                   PAGE_READWRITE);
    if (samples) synth = CreateThread(nullptr, 0, synth_worker, samples, 0, nullptr);
  }

  if (RT64K_FULLSCREEN && options.fullscreen) ShowCursor(FALSE);
  // A top-down (negative height) 32-bit DIB: rows in memory order, 0xAARRGGBB.
  BITMAPINFO dib = {{sizeof(BITMAPINFOHEADER), f.width, -f.height, 1, 32, BI_RGB, 0, 0, 0, 0, 0},
                    {}};

  HINSTANCE instance = (HINSTANCE)&__ImageBase; // = GetModuleHandleA(nullptr)
  WNDCLASSA windowClass = {};
  windowClass.style = CS_OWNDC; // one DC kept for the whole run
  windowClass.lpfnWndProc = window_proc;
  windowClass.hInstance = instance;
  windowClass.hCursor = LoadCursorA(nullptr, (LPCSTR)IDC_ARROW);
  windowClass.hbrBackground = (HBRUSH)GetStockObject(BLACK_BRUSH);
  windowClass.lpszClassName = kClassName;
  RegisterClassA(&windowClass);
  RECT outer = {0, 0, layout.clientW, layout.clientH}; // the client area we want ...
  AdjustWindowRect(&outer, layout.style, FALSE);       // ... and the window around it
  HWND window = CreateWindowExA(0, kClassName, kWindowTitle, layout.style | WS_VISIBLE,
                                layout.windowX, layout.windowY, outer.right - outer.left,
                                outer.bottom - outer.top, nullptr, nullptr, instance, nullptr);
  if (!window) ExitProcess(1);
  HDC dc = GetDC(window);
  // Scaled down (a screen under 800x600), the default BLACKONWHITE would AND
  // dropped pixels together and darken the picture.
  if (RT64K_FULLSCREEN) SetStretchBltMode(dc, COLORONCOLOR);

  // /once ends at the end of the timeline loop the start time lies in (64 s
  // for any start in [0, 64)).
  const double onceEnd = once_end_seconds(options.startSeconds);
  double slowest = 0.0; // seconds: the slowest frame so far (/bench reports it)
  bool playing = false;
  LARGE_INTEGER frequency, firstFrame, clockStart, frameStart, now;
  QueryPerformanceFrequency(&frequency);
  QueryPerformanceCounter(&firstFrame);
  clockStart = firstFrame;
  for (int frame = 0;; ++frame) {
    // Time is the music's position, or real elapsed time, never the frame
    // count; except under /bench, whose fixed steps make runs comparable,
    // and /hold. The first frame shows the start time while the music is
    // prepared; the clock starts after it.
    double t = options.startSeconds, played = -1.0;
    if (bench) {
      t = kBenchFirst + frame * kBenchStep;
    } else if (frame > 0 && !options.hold) {
      if (playing) {
        t += played = audio_seconds();
      } else {
        QueryPerformanceCounter(&now);
        t += seconds_between(clockStart, now, frequency);
      }
    }
    if (RT64K_ONCE && options.once && !bench && t >= onceEnd) quit();
    if (frame > 0 && !bench && idle_while_minimised(window)) continue;
    QueryPerformanceCounter(&frameStart);
    // Scene 2's renderer-visualisation segment tints the blocks.
    f.showBlocks = build_timeline_scene(job.scene, t).showBlocks;
    render_frame(job, workers);
    if (RT64K_CAPTIONS) overlay_draw(f.fb, f.width, f.height, f.stride, timeline_wrap(t));
    StretchDIBits(dc, layout.pictureX, layout.pictureY, layout.pictureW, layout.pictureH, 0, 0,
                  f.width, f.height, f.fb, &dib, DIB_RGB_COLORS, SRCCOPY);
    QueryPerformanceCounter(&now);
    double frameSeconds = seconds_between(frameStart, now, frequency);
    if (frameSeconds > slowest) slowest = frameSeconds;
    if (bench && frame + 1 == kBenchFrames)
      finish_bench(f.width, f.height, workers, seconds_between(firstFrame, now, frequency),
                   slowest);
    if (RT64K_LOG && options.log) log_frame(t, played, seconds_between(firstFrame, now, frequency));
    if (frame == 0) {
      if (RT64K_MUSIC && synth) {
        wait_pumping(synth);
        // The loop from the start time's place in it, to the sample.
        int offset = (int)(timeline_wrap(options.startSeconds) * kAudioRate);
        playing = audio_start(samples + offset * kShortsPerFrame);
      }
      QueryPerformanceCounter(&clockStart);
    }
  }
}

} // namespace

extern "C" [[noreturn]] void intro_entry() { run(parse_command_line(GetCommandLineA())); }
