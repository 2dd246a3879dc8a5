// intro.cpp - the Win32 entry point of intro.exe: window, clock, threads.
//
// Platform contract (STYLE.md 1): this file alone owns the window, the clock,
// the worker threads and the framebuffer; src/core and scenes/ only turn a
// time into pixels, exactly as they do for the Linux tool. No C runtime: the
// linker enters at intro_entry(), which never returns; every way out is
// ExitProcess (0 for Esc, closing the window and the end of /bench; 1 when
// the system refuses memory, a thread or the window).
#define WIN32_LEAN_AND_MEAN
#define _WIN32_WINNT 0x0601 // Windows 7: SetProcessDPIAware, AttachConsole
#include <windows.h>

#include "overlay.h"
#include "scenes.h"
#include "text.h"
#include "trace.h"

namespace {

constexpr int kWidth = 800; // client area and framebuffer, pixels
constexpr int kHeight = 600;
// A work item of the full trace is a band of kBandRows rows. 8 divides 600
// and is one of the thesis's block sizes; 75 bands keep every core busy to
// the end of a frame.
constexpr int kBandRows = 8;
constexpr int kBands = kHeight / kBandRows;
static_assert(kHeight % kBandRows == 0, "bands must tile the frame");
// Render threads: one per logical processor, at most this many (the most
// GetSystemInfo reports for one processor group).
constexpr DWORD kMaxWorkers = 64;

// /bench renders kBenchFrames frames at times kBenchFirst + i * kBenchStep:
// the middle of each 2-s slot of the whole 64-s timeline, so both scenes
// count equally and no frame falls on a fade to black at a scene cut.
constexpr int kBenchFrames = 32;
constexpr double kBenchStep = (double)kTimelineSeconds / kBenchFrames;
constexpr double kBenchFirst = kBenchStep / 2;
constexpr int kBenchDecimals = 2; // fps and seconds in the report

const char kClassName[] = "rt64k";
const char kWindowTitle[] = "rt64k";
const char kBenchFileName[] = "rt64k-bench.txt";
// Room for a full path (MAX_PATH) plus the report's file name.
constexpr DWORD kPathChars = MAX_PATH + sizeof kBenchFileName;
constexpr int kReportChars = 256;

constexpr DWORD kWindowStyle = WS_OVERLAPPED | WS_CAPTION | WS_SYSMENU | WS_MINIMIZEBOX;

// A top-down (negative height) 32-bit DIB: rows in memory order, 0xAARRGGBB.
const BITMAPINFO kDib = {{sizeof(BITMAPINFOHEADER), kWidth, -kHeight, 1, 32, BI_RGB, 0, 0, 0, 0, 0},
                         {}};

// One pass of work items, shared by the main thread and the workers. A
// frame is one pass of the full trace; a renderer with phases (the adaptive
// one: corners, then blocks) runs one pass per phase. The job lives on the
// main thread's stack (mutable globals would land in the file: MinGW puts
// zero-initialised data of -fdata-sections builds into .data). The main
// thread writes `scene`, `items` and the counters only while every worker
// waits on `start`; the semaphore release and the interlocked operations
// order those writes before the workers' reads.
struct FrameJob {
  Scene scene;
  u32* pixels;              // kWidth x kHeight, rows kWidth pixels apart
  HANDLE start;             // semaphore: one count per worker per pass
  HANDLE done;              // auto-reset event: set by the last worker to finish
  LONG items;               // work items in this pass
  volatile LONG nextItem;   // next item to take
  volatile LONG busyCounts; // counts of `start` taken and not yet handed back
};

// A render worker. Each pass it takes one count of job.start, pulls items
// from the shared counter until none is left and calls the core once per
// item; the worker that hands back the pass's last count signals job.done.
// A worker may take two counts of one pass; every item is still finished
// before its own count is handed back, so "all counts back" means "all
// items done".
DWORD WINAPI render_worker(void* parameter) {
  FrameJob& job = *(FrameJob*)parameter;
  for (;;) {
    WaitForSingleObject(job.start, INFINITE);
    for (LONG item; (item = InterlockedIncrement(&job.nextItem) - 1) < job.items;)
      render_full_rows(job.scene, job.pixels, kWidth, kHeight, kWidth, item * kBandRows,
                       (item + 1) * kBandRows, nullptr);
    if (InterlockedDecrement(&job.busyCounts) == 0) SetEvent(job.done);
  }
}

LRESULT CALLBACK window_proc(HWND window, UINT message, WPARAM wParam, LPARAM lParam) {
  // Esc and closing (the close box, Alt+F4) end the intro at once.
  if ((message == WM_KEYDOWN && wParam == VK_ESCAPE) || message == WM_CLOSE ||
      message == WM_DESTROY)
    ExitProcess(0);
  return DefWindowProcA(window, message, wParam, lParam);
}

void pump_messages() {
  MSG msg;
  while (PeekMessageA(&msg, nullptr, 0, 0, PM_REMOVE)) {
    if (msg.message == WM_QUIT) ExitProcess(0);
    DispatchMessageA(&msg);
  }
}

// Runs `items` work items on all workers and returns when all are done.
// The main thread keeps serving the window meanwhile, so Esc acts within one
// message round trip however long a frame takes.
void run_pass(FrameJob& job, LONG workers, LONG items) {
  job.items = items;
  job.nextItem = 0;
  job.busyCounts = workers;
  ReleaseSemaphore(job.start, workers, nullptr);
  for (;;) {
    pump_messages();
    if (MsgWaitForMultipleObjectsEx(1, &job.done, INFINITE, QS_ALLINPUT, MWMO_INPUTAVAILABLE) ==
        WAIT_OBJECT_0)
      return;
  }
}

double seconds_between(LARGE_INTEGER from, LARGE_INTEGER to, LARGE_INTEGER frequency) {
  return (double)(to.QuadPart - from.QuadPart) / (double)frequency.QuadPart;
}

// The /bench line goes to stdout (the parent's console, or wherever the
// handle is redirected; under Wine the Unix stdout) and to kBenchFileName
// next to the exe (in the current directory if the exe's path is too long).
void write_bench_report(const char* text, DWORD length) {
  DWORD written;
  HANDLE out = GetStdHandle(STD_OUTPUT_HANDLE);
  if (!out || out == INVALID_HANDLE_VALUE) {
    if (AttachConsole(ATTACH_PARENT_PROCESS))
      out = CreateFileA("CONOUT$", GENERIC_WRITE, FILE_SHARE_WRITE, nullptr, OPEN_EXISTING, 0,
                        nullptr);
  }
  if (out && out != INVALID_HANDLE_VALUE) WriteFile(out, text, length, &written, nullptr);

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
  if (file != INVALID_HANDLE_VALUE) {
    WriteFile(file, text, length, &written, nullptr);
    CloseHandle(file);
  }
}

// CPU time (user + kernel) of all the process's threads so far, seconds. On
// a busy machine the wall-clock fps drops, CPU seconds per frame do not.
double process_cpu_seconds() {
  constexpr double kFileTimeTick = 1e-7; // FILETIME counts 100-ns ticks
  FILETIME creation, exit, kernel, user;
  if (!GetProcessTimes(GetCurrentProcess(), &creation, &exit, &kernel, &user)) return 0.0;
  auto ticks = [](FILETIME f) { return (double)(((u64)f.dwHighDateTime << 32) | f.dwLowDateTime); };
  return (ticks(kernel) + ticks(user)) * kFileTimeTick;
}

[[noreturn]] void finish_bench(double seconds, LONG workers) {
  char storage[kReportChars];
  TextBuffer b = text_buffer(storage, kReportChars);
  append(b, "rt64k bench: ");
  append_uint(b, kBenchFrames);
  append(b, " frames ");
  append_uint(b, kWidth);
  append(b, "x");
  append_uint(b, kHeight);
  append(b, " on ");
  append_uint(b, (unsigned long long)workers);
  append(b, " threads in ");
  append_fixed(b, seconds, kBenchDecimals);
  append(b, " s = ");
  append_fixed(b, kBenchFrames / seconds, kBenchDecimals);
  append(b, " fps, CPU ");
  append_fixed(b, process_cpu_seconds(), kBenchDecimals);
  append(b, " s\r\n");
  write_bench_report(storage, (DWORD)text_length(b));
  ExitProcess(0);
}

[[noreturn]] void run(const IntroOptions& options) {
  // Real pixels on scaled desktops: otherwise Windows would stretch the
  // 800x600 client area (blurring it) on a display set above 100 %.
  SetProcessDPIAware();

  FrameJob job;
  job.pixels = (u32*)VirtualAlloc(nullptr, kWidth * kHeight * sizeof(u32), MEM_COMMIT | MEM_RESERVE,
                                  PAGE_READWRITE);
  job.start = CreateSemaphoreA(nullptr, 0, kMaxWorkers, nullptr);
  job.done = CreateEventA(nullptr, FALSE, FALSE, nullptr);
  if (!job.pixels || !job.start || !job.done) ExitProcess(1);

  SYSTEM_INFO system;
  GetSystemInfo(&system);
  DWORD cores = system.dwNumberOfProcessors;
  if (cores < 1) cores = 1;
  if (cores > kMaxWorkers) cores = kMaxWorkers;
  LONG workers = 0;
  for (DWORD i = 0; i < cores; ++i)
    if (CreateThread(nullptr, 0, render_worker, &job, 0, nullptr)) ++workers;
  if (workers == 0) ExitProcess(1);

  HINSTANCE instance = GetModuleHandleA(nullptr);
  WNDCLASSA windowClass = {};
  windowClass.style = CS_OWNDC; // one DC kept for the whole run
  windowClass.lpfnWndProc = window_proc;
  windowClass.hInstance = instance;
  windowClass.hCursor = LoadCursorA(nullptr, (LPCSTR)IDC_ARROW);
  windowClass.lpszClassName = kClassName;
  RegisterClassA(&windowClass);
  RECT outer = {0, 0, kWidth, kHeight};          // the client area we want ...
  AdjustWindowRect(&outer, kWindowStyle, FALSE); // ... and the window around it
  HWND window = CreateWindowExA(0, kClassName, kWindowTitle, kWindowStyle | WS_VISIBLE,
                                CW_USEDEFAULT, CW_USEDEFAULT, outer.right - outer.left,
                                outer.bottom - outer.top, nullptr, nullptr, instance, nullptr);
  if (!window) ExitProcess(1);
  HDC dc = GetDC(window);

  LARGE_INTEGER frequency, start, now;
  QueryPerformanceFrequency(&frequency);
  QueryPerformanceCounter(&start);
  for (int frame = 0;; ++frame) {
    // Time is real elapsed time (never the frame count), except under
    // /bench, whose fixed steps make runs comparable.
    double t = options.startSeconds;
    if (options.bench) {
      t = kBenchFirst + frame * kBenchStep;
    } else if (!options.hold) {
      QueryPerformanceCounter(&now);
      t += seconds_between(start, now, frequency);
    }
    build_timeline_scene(job.scene, t);
    run_pass(job, workers, kBands);
    overlay_draw(job.pixels, kWidth, kHeight, kWidth, timeline_wrap(t)); // the captions
    StretchDIBits(dc, 0, 0, kWidth, kHeight, 0, 0, kWidth, kHeight, job.pixels, &kDib,
                  DIB_RGB_COLORS, SRCCOPY);
    if (options.bench && frame + 1 == kBenchFrames) {
      QueryPerformanceCounter(&now);
      finish_bench(seconds_between(start, now, frequency), workers);
    }
  }
}

} // namespace

extern "C" [[noreturn]] void intro_entry() { run(parse_command_line(GetCommandLineA())); }
