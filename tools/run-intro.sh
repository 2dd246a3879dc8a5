#!/usr/bin/env bash
# Builds intro.exe and runs it under Wine (on Windows, double-click the exe).
# Installs missing Debian packages first. Extra arguments go to the intro
# (e.g. /t:40 /hold, /f, /once, /mute). With no X display (a headless
# machine) it runs under a virtual X server for RT64K_SECONDS (default 20)
# seconds and saves a screenshot to build/intro-screenshot.png.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh intro
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build --target intro_exe -j"$(nproc)" >/dev/null
exe=$PWD/build/win32/intro.exe
echo "intro.exe: $(stat -c %s "$exe") bytes"
wine=$(command -v wine || command -v wine64 || echo /usr/lib/wine/wine64)
export WINEPREFIX=$PWD/build/wine-prefix-run WINEDEBUG=-all
if [ ! -d "$WINEPREFIX" ]; then
  echo "creating a Wine prefix in $WINEPREFIX (once)"
  DISPLAY= "$wine" wineboot -i >/dev/null 2>&1 || true
  fresh=1
fi
if [ -n "${DISPLAY:-}" ]; then
  exec "$wine" "$exe" "$@"
fi
seconds=${RT64K_SECONDS:-20}
# A prefix made just now finishes setting up in the background first.
[ -n "${fresh:-}" ] && seconds=$((seconds + 15))
echo "no DISPLAY: running under Xvfb for $seconds s (a screenshot is taken at the end)"
exec 3< <(Xvfb -displayfd 1 -screen 0 1024x768x24 -nolisten tcp 2>/dev/null)
xvfb_pid=$!
read -r -u 3 display
export DISPLAY=:$display
"$wine" "$exe" "$@" &
intro=$!
sleep "$seconds"
import -window root build/intro-screenshot.png 2>/dev/null && echo "screenshot: build/intro-screenshot.png"
kill "$intro" 2>/dev/null || true
wineserver -k 2>/dev/null || true
kill "$xvfb_pid" 2>/dev/null || true
