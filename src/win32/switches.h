// switches.h - intro.exe's feature switches, each 0 or 1 (STYLE.md 8: size is
// a feature with a budget). All are 1 in the shipped exe; docs/win32.md lists
// what each one costs in bytes, measured by tests/wine/measure-flags.sh, which
// rebuilds with one switch at 0 (-DRT64K_FEATURES=RT64K_MUSIC=0 and so on).
// The code tests them as ordinary constants (`if (RT64K_ONCE && ...)`), so a
// switched-off feature is compiled, checked, and then dropped as dead code.
#pragma once

// The adaptive subsampling renderer (src/core/adaptive.h); 0: every pixel
// traced (render_full_rows), the renderer before issue 3.
#ifndef RT64K_ADAPTIVE
#define RT64K_ADAPTIVE 1
#endif

// Music: the synth renders the loop at start-up, waveOut plays it, and its
// position is the clock. 0 also drops src/win32/audio.cpp and winmm
// (src/win32/CMakeLists.txt) and /mute.
#ifndef RT64K_MUSIC
#define RT64K_MUSIC 1
#endif

// /mute: no music, the QueryPerformanceCounter clock.
#ifndef RT64K_MUTE
#define RT64K_MUTE RT64K_MUSIC
#endif

// /f: a borderless window over the whole screen, the picture letterboxed.
#ifndef RT64K_FULLSCREEN
#define RT64K_FULLSCREEN 1
#endif

// /once: the timeline plays once and the intro exits with code 0.
#ifndef RT64K_ONCE
#define RT64K_ONCE 1
#endif

// /log: one line per frame on stdout (the time shown, the music's position,
// the wall clock): the tests' window into the clock.
#ifndef RT64K_LOG
#define RT64K_LOG 1
#endif

// Captions: the title, credits and greetings over the picture
// (src/core/overlay.h: the pixel font, the texts, the drawing).
#ifndef RT64K_CAPTIONS
#define RT64K_CAPTIONS 1
#endif

// /bench: fixed frame times, the report line and rt64k-bench.txt.
#ifndef RT64K_BENCH
#define RT64K_BENCH 1
#endif

// Ray packets (src/core/packet/) are a build switch, not a macro, because
// they choose source files: the CMake cache variable RT64K_PACKETS of
// src/win32/CMakeLists.txt, OFF in the shipped exe (src/core/scalar/ traces
// the same primary rays one at a time; docs/win32.md "Ray packets in
// intro.exe" has the bytes and the instructions of both).
