// text.h - intro.exe's command line and its few lines of text output.
//
// Freestanding (no C runtime, no standard library, no heap), so the same file
// is linked into intro.exe and into a native unit test (tests/wine/test_text.cpp).
// Contract of every function here: any input (null, unterminated only where
// an explicit end is given, garbage bytes) is safe; nothing reads or writes
// outside the ranges it is given.
#pragma once
#include "switches.h"

// Largest |/t:SECONDS| accepted: 1e9 s is ~31.7 years, beyond any compo; a
// larger value is ignored like any malformed option. Keeps the clock finite
// and its double time far from losing sub-microsecond precision.
constexpr double kMaxStartSeconds = 1e9;

struct IntroOptions {
  double startSeconds; // /t:SECONDS (default 0); finite, |value| <= kMaxStartSeconds
  bool hold;           // /hold: the clock stands still at startSeconds
  bool bench;          // /bench: fixed time steps, report frames per second, exit
  bool fullscreen;     // /f: the whole screen, the picture letterboxed
  bool once;           // /once: exit with code 0 at the end of the timeline
  bool mute;           // /mute: no music; the system clock
  bool log;            // /log: one line per frame on stdout (tests)
  bool scaled;         // /scaled: with /f, render 800x600 and scale it (slow machines)
};

// The timeline's loop (scenes.h kTimelineSeconds; intro.cpp checks they agree).
constexpr double kOnceLoopSeconds = 64.0;

// /once's end: the end of the timeline loop that `startSeconds` lies in,
// computed in double (floor(start / 64) + 1) * 64, so that
// 0 < end - start <= 64 for every start |start| <= kMaxStartSeconds. (The
// picture's float wrap rounds a start just below a loop's end up to the next
// loop's 0 s; the end must not follow it a loop later.)
double once_end_seconds(double startSeconds);

// Parses a Win32 command line as GetCommandLineA returns it: the program name
// first (possibly in double quotes), then options separated by spaces or tabs.
// Options start with '/' or '-' and are case-insensitive: /t:SECONDS, /hold,
// /bench, /f, /scaled, /once, /mute, /log (each only where its switch in switches.h is
// on; otherwise it is unknown). Unknown options, and a /t: whose number is malformed or out of
// range, are ignored. A later /t: overrides an earlier one. Null gives defaults.
IntroOptions parse_command_line(const char* line);

// Parses the decimal number [begin, end): optional sign, digits with an
// optional '.' and fraction, at least one digit, nothing else (no exponent,
// no spaces). On success stores the value and returns true. The value is
// the correctly rounded double (as strtod gives) when its significant digits,
// read as one integer, are below 2^53 - always for 15 digits or fewer; with
// more, it is within a few ulps. Fails (out untouched) on anything else or
// when |value| > kMaxStartSeconds.
bool parse_seconds(const char* begin, const char* end, double* out);

// A bounded text builder: appends never write past `end`, and text() is
// always NUL-terminated. Text that does not fit is cut off.
struct TextBuffer {
  char* begin;
  char* end; // one past the last byte of the storage (room for the NUL included)
  char* at;  // where the next character goes
};
TextBuffer text_buffer(char* storage, int size); // size >= 1
void append(TextBuffer& b, const char* s);
void append_uint(TextBuffer& b, unsigned long long v);
// v with `decimals` (0..9) digits after the point, rounded half up. Values
// that are negative zero print as 0; NaN, infinities and |v| >= 1e15 print "?".
void append_fixed(TextBuffer& b, double v, int decimals);
int text_length(const TextBuffer& b);
