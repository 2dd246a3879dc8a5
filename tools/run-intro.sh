#!/usr/bin/env bash
# Builds intro.exe and runs it under Wine (on Windows, double-click the exe).
# Installs what is missing first (Debian packages, UPX). Runs the shipped
# packed exe (intro-shipped.exe: the smaller of UPX's and our own packer's,
# the one the compo zip ships). Extra arguments go
# to the intro (e.g. /t:40 /hold, /f, /once, /mute). With no X display (a
# headless machine) it runs under a virtual X server for RT64K_SECONDS
# (default 20) seconds, checks the intro is still running, and saves a
# screenshot of its window to build/intro-screenshot.png.
# Environment: BUILD_DIR (default build), RT64K_WINEPREFIX (default
# BUILD_DIR/wine-prefix-run), RT64K_SECONDS, RT64K_SCREENSHOT (where the
# screenshot goes).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh intro
build=${BUILD_DIR:-build}
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" --target intro_exe -j"$(nproc)" >/dev/null
exe=$PWD/$build/win32/intro.exe
[ "${build:0:1}" = / ] && exe=$build/win32/intro.exe
if [ -f "${exe%.exe}-shipped.exe" ]; then
  echo "intro.exe: $(stat -c %s "${exe%.exe}-shipped.exe") bytes packed by" \
    "$(cat "${exe%.exe}-shipped.txt") ($(stat -c %s "$exe") unpacked)"
  exe=${exe%.exe}-shipped.exe
else
  echo "intro.exe: $(stat -c %s "$exe") bytes (not packed)"
fi
wine=$(command -v wine || command -v wine64 || echo /usr/lib/wine/wine64)
wineserver=$(command -v wineserver || echo /usr/lib/wine/wineserver64)
prefix=${RT64K_WINEPREFIX:-$PWD/$build/wine-prefix-run}
export WINEPREFIX=$prefix WINEDEBUG=-all
# No Mono or Gecko installers: the intro needs neither.
export WINEDLLOVERRIDES="mscoree,mshtml="

if [ ! -f "$WINEPREFIX/system.reg" ]; then
  echo "creating a Wine prefix in $WINEPREFIX (once, ~20 s)"
  DISPLAY= "$wine" wineboot -i >/dev/null 2>&1 || true
  # wineboot returns while the session it started (without a display) is
  # still running; an intro started now would join that session and find no
  # display (it exited with code 1 on the first run). Wait for it to end.
  timeout 60 "$wineserver" -w || "$wineserver" -k || true
fi

# Sound: with no sound card (and no PulseAudio server) Wine's audio drivers
# print a page of ALSA errors and the intro plays nothing anyway. Then the
# drivers are left out and one line says so.
has_sound() {
  command -v pactl >/dev/null && pactl info >/dev/null 2>&1 && return 0
  [ -r /proc/asound/cards ] && grep -q '^ *[0-9]' /proc/asound/cards
}
if ! has_sound; then
  echo "no sound card (nor PulseAudio) found: the intro runs silent"
  export WINEDLLOVERRIDES="$WINEDLLOVERRIDES;winepulse.drv,winealsa.drv,wineoss.drv=d"
fi

if [ -n "${DISPLAY:-}" ]; then
  exec "$wine" "$exe" "$@"
fi
seconds=${RT64K_SECONDS:-20}
shot=${RT64K_SCREENSHOT:-$build/intro-screenshot.png}
log=$build/intro-run.log
echo "no DISPLAY: running under Xvfb for $seconds s (a screenshot is taken at the end)"
exec 3< <(exec Xvfb -displayfd 1 -screen 0 1024x768x24 -nolisten tcp 2>/dev/null)
xvfb_pid=$!
read -r -u 3 display
export DISPLAY=:$display
"$wine" "$exe" "$@" >"$log" 2>&1 &
intro=$!
finish() {
  kill "$intro" 2>/dev/null || true
  timeout 30 "$wineserver" -w 2>/dev/null || "$wineserver" -k 2>/dev/null || true
  kill "$xvfb_pid" 2>/dev/null || true
}
trap finish EXIT
sleep "$seconds"
# Still running? (An exited child stays a zombie, state Z, until waited for.)
state=$(sed 's/.*) //' "/proc/$intro/stat" 2>/dev/null | cut -d' ' -f1) || state=
if [ -z "$state" ] || [ "$state" = Z ]; then
  rc=0
  wait "$intro" || rc=$?
  echo "intro.exe exited with code $rc before the screenshot (its output: $log)" >&2
  exit 1
fi
window=$(xdotool search --onlyvisible --name '^rt64k$' 2>/dev/null | head -n1) || window=
if [ -n "$window" ] && import -window "$window" "$shot" 2>/dev/null; then
  echo "intro.exe still running after $seconds s; screenshot of its window: $shot"
else
  echo "intro.exe is running but shows no window after $seconds s (its output: $log)" >&2
  exit 1
fi
