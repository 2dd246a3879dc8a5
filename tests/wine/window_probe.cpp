// window_probe.cpp - window_probe.exe, a test helper run under Wine by the
// wine.minimised test: does to intro.exe's window (class "rt64k") what a
// person does with the title bar's buttons or the taskbar, through the
// Win32 API (under Xvfb there is no window manager to ask).
//   window_probe.exe minimise   ShowWindow(SW_MINIMIZE)
//   window_probe.exe restore    ShowWindow(SW_RESTORE)
// Exit code: 0 done, and the window is then iconic (minimise) or not
// (restore); 1 no such window; 2 unknown verb; 3 the state did not change.
#define WIN32_LEAN_AND_MEAN
#include <windows.h>

namespace {

// The last blank-separated word of the command line, as a pointer into it.
const char* last_word(const char* line) {
  const char* word = line;
  for (const char* p = line; *p; ++p)
    if ((*p == ' ' || *p == '\t') && p[1] && p[1] != ' ' && p[1] != '\t') word = p + 1;
  return word;
}

bool equals(const char* a, const char* b) {
  for (; *a && *a == *b; ++a, ++b) {
  }
  return *a == *b;
}

} // namespace

extern "C" [[noreturn]] void window_probe_entry() {
  const char* verb = last_word(GetCommandLineA());
  HWND window = FindWindowA("rt64k", nullptr);
  if (!window) ExitProcess(1);
  bool minimise = equals(verb, "minimise");
  if (!minimise && !equals(verb, "restore")) ExitProcess(2);
  ShowWindow(window, minimise ? SW_MINIMIZE : SW_RESTORE);
  ExitProcess((IsIconic(window) != 0) == minimise ? 0 : 3);
}
