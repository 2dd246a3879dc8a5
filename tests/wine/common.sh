# common.sh - shared set-up of the end-to-end tests of intro.exe under Wine.
# Sourced (bash) by every tests/wine/test-*.sh; ctest passes, in the environment:
#   RT64K_INTRO_EXE       the freshly built intro.exe
#   RT64K_TOOL            the native rt64k tool (reference renders)
#   RT64K_RENDER_ARGS     the rt64k render options that match the exe's renderer
#   RT64K_WINE_DIR        build-tree folder for the Wine prefix and the tests' work
#   RT64K_WINE_REQUIRED   1: a missing tool is a failure instead of a skip
#   RT64K_PACKED          1: RT64K_INTRO_EXE is the shipped packed exe
#                         (intro-shipped.exe: the smaller of UPX's and our own
#                         packer's; RT64K_PACKED_NOTE names its packer);
#                         ours: our own packer's exe (intro-packed.exe)
#
# Each test gets its own Xvfb (a free display number chosen by Xvfb itself,
# -displayfd) and its own work folder; all tests share one Wine prefix inside
# the build tree, created once by `wineboot -i` and cached (ctest runs the
# Wine tests one at a time: RESOURCE_LOCK in tests/wine/CMakeLists.txt; the
# prefix creation also takes a file lock).
# Exit codes: 0 pass, 1 fail, 77 skipped (ctest SKIP_RETURN_CODE).
set -u

readonly kSkipCode=77
readonly kScreenSize=${RT64K_SCREEN:-1024x768x24}  # Xvfb screen: holds the 800x600 window
readonly kWindowTimeoutSeconds=30 # from launch to the window being mapped
readonly kWineserverTimeoutSeconds=30

TEST_NAME=$(basename "$0" .sh)

banner() {
  echo "************************************************************************"
  echo "*** $TEST_NAME: $*"
  echo "************************************************************************"
}

fail() {
  banner "FAIL: $*"
  exit 1
}

skip() {
  if [ "${RT64K_WINE_REQUIRED:-0}" = 1 ]; then
    fail "$* (RT64K_WINE_REQUIRED=1, so this is a failure, not a skip)"
  fi
  banner "SKIPPED - NOT TESTED: $*"
  exit $kSkipCode
}

: "${RT64K_INTRO_EXE:?set by ctest}" "${RT64K_WINE_DIR:?set by ctest}"

# first_executable CANDIDATE...: the first one that is a command or an
# executable path.
first_executable() {
  local c
  for c in "$@"; do
    if command -v "$c" >/dev/null 2>&1; then
      command -v "$c"
      return 0
    fi
  done
  return 1
}

# Tools, by command and Debian package. Wine: the `wine` package gives
# /usr/bin/wine and wineserver; with only `wine64` (apt-get
# --no-install-recommends) they are /usr/lib/wine/wine64 and wineserver64.
# RT64K_WINE and RT64K_WINESERVER override the search (another Wine build).
find_tools() {
  WINE=$(first_executable ${RT64K_WINE:-} wine wine-stable wine64 /usr/lib/wine/wine64) || WINE=
  WINESERVER=$(first_executable ${RT64K_WINESERVER:-} wineserver wineserver-stable \
    /usr/lib/wine/wineserver64 /usr/lib/wine/wineserver) || WINESERVER=
  local missing=""
  [ -n "$WINE" ] || missing+=" wine(packages wine wine64)"
  [ -n "$WINESERVER" ] || missing+=" wineserver(package wine64)"
  local tool package
  for tool in Xvfb:xvfb xdotool:xdotool xwininfo:x11-utils import:imagemagick \
    compare:imagemagick convert:imagemagick flock:util-linux timeout:coreutils; do
    command -v "${tool%%:*}" >/dev/null || missing+=" ${tool%%:*}(package ${tool#*:})"
  done
  [ -z "$missing" ] || skip "missing:$missing"
  if [ ! -f "$RT64K_INTRO_EXE" ]; then
    [ "${RT64K_PACKED:-0}" != 0 ] && fail "no packed exe at $RT64K_INTRO_EXE (built with intro.exe)"
    fail "no intro.exe at $RT64K_INTRO_EXE"
  fi
  [ "${RT64K_PACKED:-0}" = 1 ] &&
    echo "testing the shipped packed exe ($(cat "$RT64K_PACKED_NOTE")): $(stat -c %s "$RT64K_INTRO_EXE") bytes"
  [ "${RT64K_PACKED:-0}" = ours ] &&
    echo "testing our own packer's exe: $(stat -c %s "$RT64K_INTRO_EXE") bytes"
}

# Milliseconds since the epoch.
now_ms() { echo $(($(date +%s%N) / 1000000)); }

XVFB_PID=
INTRO_PID=

cleanup() {
  if [ -n "$INTRO_PID" ] && intro_running; then
    kill "$INTRO_PID" 2>/dev/null
    wait "$INTRO_PID" 2>/dev/null
  fi
  # Let this prefix's wineserver and its helper processes (explorer.exe,
  # services.exe ...) end by themselves while their display still exists;
  # if they do not, end them: they all belong to this test's prefix.
  if [ -n "${WINEPREFIX:-}" ] && [ -n "${WINESERVER:-}" ]; then
    timeout $kWineserverTimeoutSeconds "$WINESERVER" -w 2>/dev/null || "$WINESERVER" -k 2>/dev/null
  fi
  if [ -n "$XVFB_PID" ]; then
    kill "$XVFB_PID" 2>/dev/null
    wait "$XVFB_PID" 2>/dev/null
  fi
}
trap cleanup EXIT

# Starts Xvfb on a display number it picks itself; exports DISPLAY.
start_xvfb() {
  local fdfile="$WORK/xvfb.display"
  : >"$fdfile"
  Xvfb -displayfd 3 -screen 0 $kScreenSize -nolisten tcp 3>"$fdfile" 2>"$WORK/xvfb.log" &
  XVFB_PID=$!
  local i
  for i in $(seq 100); do
    [ -s "$fdfile" ] && break
    kill -0 $XVFB_PID 2>/dev/null || fail "Xvfb did not start: $(cat "$WORK/xvfb.log")"
    sleep 0.1
  done
  [ -s "$fdfile" ] || fail "Xvfb gave no display number within 10 s"
  export DISPLAY=":$(head -n1 "$fdfile")"
  echo "Xvfb on $DISPLAY (pid $XVFB_PID)"
}

# The shared prefix; created once (first run ~25 s), then reused.
prepare_prefix() {
  export WINEPREFIX="$RT64K_WINE_DIR/prefix" WINEDEBUG=-all WINEARCH=win64
  # No Mono/Gecko installers: intro.exe needs neither.
  export WINEDLLOVERRIDES="mscoree,mshtml="
  mkdir -p "$RT64K_WINE_DIR"
  (
    flock 9
    if [ ! -f "$WINEPREFIX/.rt64k-ready" ]; then
      echo "creating the Wine prefix $WINEPREFIX (once per build tree)"
      local t0
      t0=$(now_ms)
      rm -rf "$WINEPREFIX"
      "$WINE" wineboot -i >"$RT64K_WINE_DIR/wineboot.log" 2>&1 ||
        { cat "$RT64K_WINE_DIR/wineboot.log"; exit 1; }
      timeout $kWineserverTimeoutSeconds "$WINESERVER" -w
      touch "$WINEPREFIX/.rt64k-ready"
      echo "prefix ready in $(($(now_ms) - t0)) ms"
    fi
  ) 9>"$RT64K_WINE_DIR/prefix.lock" || fail "wineboot -i failed (log above)"
}

# Common start of every test: tools, work folder, display, prefix.
setup() {
  find_tools
  [ "${RT64K_PACKED:-0}" = 1 ] && TEST_NAME="$TEST_NAME-packed"
  [ "${RT64K_PACKED:-0}" = ours ] && TEST_NAME="$TEST_NAME-ours"
  WORK="$RT64K_WINE_DIR/work/$TEST_NAME"
  rm -rf "$WORK"
  mkdir -p "$WORK"
  cp "$RT64K_INTRO_EXE" "$WORK/intro.exe"
  # No PulseAudio for Wine unless a test starts its own (test-audio.sh): a
  # server given by name that does not exist also keeps libpulse from
  # autospawning a daemon for the user that would outlive the test. Wine then
  # tries ALSA (no card here: no sound device; on a desktop, its card).
  export PULSE_SERVER="unix:$WORK/no-such-pulse-server"
  prepare_prefix
  start_xvfb
}

# Launches intro.exe from the work folder with the given options, in the
# background; stdout/stderr go to $WORK/intro.out and intro.err.
launch_intro() {
  (cd "$WORK" && exec "$WINE" ./intro.exe "$@" >"$WORK/intro.out" 2>"$WORK/intro.err") &
  INTRO_PID=$!
  local shown="$*"
  [ ${#shown} -le 200 ] || shown="${shown:0:200}... (${#shown} characters)"
  echo "launched: intro.exe $shown (pid $INTRO_PID)"
}

# Waits for the window titled rt64k to be mapped; sets WINDOW_ID.
wait_window() {
  WINDOW_ID=$(timeout $kWindowTimeoutSeconds xdotool search --sync --onlyvisible --name '^rt64k$' |
    head -n1) || true
  [ -n "$WINDOW_ID" ] || fail "no visible window titled rt64k within $kWindowTimeoutSeconds s"
}

# Client-area geometry of WINDOW_ID on the screen: WIN_X WIN_Y WIN_W WIN_H.
# Wine maps a window's client area to an X window of its own size; without
# a window manager nothing draws a frame around it.
window_geometry() {
  local info
  info=$(xwininfo -id "$WINDOW_ID")
  WIN_X=$(sed -n 's/.*Absolute upper-left X: *\(-\?[0-9]*\).*/\1/p' <<<"$info")
  WIN_Y=$(sed -n 's/.*Absolute upper-left Y: *\(-\?[0-9]*\).*/\1/p' <<<"$info")
  WIN_W=$(sed -n 's/.*Width: *\([0-9]*\).*/\1/p' <<<"$info")
  WIN_H=$(sed -n 's/.*Height: *\([0-9]*\).*/\1/p' <<<"$info")
}

# Gives the window the keyboard focus (no window manager: focus is ours to
# set) and returns at once; the key itself is typed by type_key.
focus_window() {
  xdotool windowfocus --sync "$WINDOW_ID" 2>/dev/null || xdotool windowfocus "$WINDOW_ID"
}
type_key() { xdotool key "$1"; }

# True while the intro's process exists and has not exited (an exited child
# stays a zombie, state Z, until `wait`, and kill -0 still succeeds on it).
intro_running() {
  local state
  state=$(sed 's/.*) //' "/proc/$INTRO_PID/stat" 2>/dev/null | cut -d' ' -f1) || return 1
  [ -n "$state" ] && [ "$state" != Z ]
}

# Waits for the intro to exit, polling every 10 ms, at most 5 x $2 ms after
# the time $3 (now_ms); sets EXIT_MS (exit time - $3) and EXIT_CODE. Fails if
# it is still running by then.
wait_exit() {
  local what="$1" limitMs="$2" t0="$3"
  while intro_running && [ $(($(now_ms) - t0)) -le $((5 * limitMs)) ]; do sleep 0.01; done
  EXIT_MS=$(($(now_ms) - t0))
  intro_running && fail "intro.exe still running ${EXIT_MS} ms after $what"
  wait "$INTRO_PID"
  EXIT_CODE=$?
  INTRO_PID=
}

# Types Esc into the running intro; fails unless it exits within 1 s with code 0.
escape_exits_cleanly() {
  focus_window
  local t0
  t0=$(now_ms)
  type_key Escape
  wait_exit Escape 1000 "$t0"
  [ "$EXIT_CODE" = 0 ] || fail "exit code $EXIT_CODE after Escape, expected 0"
}

# CPU time (user + system) the intro's process has used, in clock ticks
# (1/100 s, `getconf CLK_TCK`); fields 14 and 15 of /proc/PID/stat.
cpu_ticks() { sed 's/.*) //' "/proc/$INTRO_PID/stat" | awk '{print $12 + $13}'; }

# Resident set size of the intro's process in KiB (VmRSS), empty if gone.
rss_kib() { awk '/^VmRSS:/ {print $2}' "/proc/$INTRO_PID/status" 2>/dev/null; }

# A screenshot matches `rt64k render` of the same time when no channel of any
# pixel differs by more than kMaxChannelDiff (of 255) and at most
# kMaxDifferentPixels pixels differ at all. The exe and the tool run the same
# core compiled with the same floating-point flags (IEEE single/double on
# SSE2, no contraction, no fast-math; cmake/flags.cmake), so the frames are
# expected to be identical (measured: 0 of 480,000 pixels differ). The one
# step of slack per channel and 0.1 % of the pixels allow one rounding flip
# in pack_color should two compilers (native g++, MinGW g++) ever order an
# operation differently; anything larger is a different picture.
readonly kMaxChannelDiff=1
readonly kMaxDifferentPixels=480
# Time for the first frame to appear (screenshots are retaken until then).
readonly kMatchTimeoutSeconds=20
readonly kQuantum16=257  # ImageMagick's 16-bit quantum per 8-bit step

# render_ref TIME FILE [WxH]: the reference frame at TIME, rendered by the
# native tool with the exe's renderer options, at WxH (default 800x600).
render_ref() {
  local -a renderArgs
  read -r -a renderArgs <<<"${RT64K_RENDER_ARGS:-}"
  "${RT64K_TOOL:?set by ctest}" render --time "$1" --size "${3:-800x600}" "${renderArgs[@]}" \
    --out "$2" || fail "rt64k render --time $1 --size ${3:-800x600} failed"
}

# same_frame SHOT REF: compares two images of one size; sets MAX_DIFF (of 255),
# DIFF_PIXELS and PSNR; true when within kMaxChannelDiff and kMaxDifferentPixels.
same_frame() {
  local pae
  pae=$(compare -metric PAE "$1" "$2" null: 2>&1 | awk '{print $1}')
  MAX_DIFF=$(awk -v v="$pae" -v q=$kQuantum16 'BEGIN {printf "%d", v / q + 0.5}')
  DIFF_PIXELS=$(compare -metric AE "$1" "$2" null: 2>&1 | awk '{printf "%d", $1}')
  PSNR=$(compare -metric PSNR "$1" "$2" null: 2>&1 | awk '{print $1}')
  [ "$MAX_DIFF" -le $kMaxChannelDiff ] && [ "$DIFF_PIXELS" -le $kMaxDifferentPixels ]
}

# screenshot_client FILE [WxH]: the window's client area from the screen;
# fails unless the client area is WxH (default 800x600).
screenshot_client() {
  window_geometry
  [ "${WIN_W}x${WIN_H}" = "${2:-800x600}" ] ||
    fail "client area is ${WIN_W}x${WIN_H}, not ${2:-800x600}"
  import -window root -crop "${WIN_W}x${WIN_H}+${WIN_X}+${WIN_Y}" +repage "$1" ||
    fail "import (screenshot) failed"
}

# match_render TIME [WxH]: renders the reference frame at TIME (at WxH,
# default 800x600) with the native tool and compares screenshots of the
# client area (which must be WxH) with it until one is within the tolerance;
# prints the figures; fails at kMatchTimeoutSeconds.
match_render() {
  local t="$1" size="${2:-800x600}" ref="$WORK/ref-$1.png" shot="$WORK/shot-$1.png"
  render_ref "$t" "$ref" "$size"
  local t0
  t0=$(now_ms)
  while :; do
    screenshot_client "$shot" "$size"
    if same_frame "$shot" "$ref"; then
      echo "t=$t s: screenshot vs rt64k render --size $size $RT64K_RENDER_ARGS: max channel diff $MAX_DIFF/255," \
        "$DIFF_PIXELS of $((${size%x*} * ${size#*x})) pixels differ, PSNR $PSNR dB (limits: $kMaxChannelDiff," \
        "$kMaxDifferentPixels) after $(($(now_ms) - t0)) ms"
      return 0
    fi
    if [ $(($(now_ms) - t0)) -gt $((kMatchTimeoutSeconds * 1000)) ]; then
      compare "$shot" "$ref" "$WORK/diff-$t.png" 2>/dev/null
      fail "t=$t s: screenshot differs from rt64k render: max channel diff $MAX_DIFF/255," \
        "$DIFF_PIXELS pixels differ, PSNR $PSNR dB (see $WORK)"
    fi
    sleep 0.5
  done
}

# /log, the intro's per-frame lines on stdout ($WORK/intro.out):
#   t=T a=A w=W   T the time the frame shows, A the music's position the clock
#   read (-1: not from the music), W seconds since just before the first frame.
# log_lines: those lines, one "T A W" per frame, in order.
log_lines() { tr -d '\r' <"$WORK/intro.out" | sed -n 's/^t=\([-0-9.]*\) a=\([-0-9.]*\) w=\([0-9.]*\)$/\1 \2 \3/p'; }
log_count() { log_lines | wc -l; }

# Frames the log may run ahead of the screen: a frame's line is written right
# after its blit, but Wine shows the window's pixels at most every ~50 ms
# (~10 frames), so the frame on screen during a screenshot may be older than
# the newest line. The count is taken before xwininfo and import run, which
# has been early enough (matches came 5-29 lines after it, round seven): the
# frame on screen is one logged from (lines before the screenshot) -
# kLogSlack on, up to the lines written kLogSettleSeconds after it.
readonly kLogSlack=2
readonly kLogSettleSeconds=0.2

# A screenshot can show two frames at once: Wine 8 on a 24-bit Xvfb hands the
# window's pixels to the X server by XShmPutImage without waiting for the
# copy, and the intro's next blit writes the same memory ~5 ms later; with
# the X server slowed (measured: Xvfb at nice 19 beside two busy loops, 9 of
# 40 screenshots) it copies the top of one frame and the bottom of a later
# one (docs/win32.md, "A torn screenshot"). Such a screenshot matches no
# logged frame, so match_logged_frame takes another: it fails only when
# kLoggedMatchAttempts screenshots in a row, and kLoggedMatchSeconds, went by
# without a match. (Every line up to the count after the screenshot stays a
# candidate: with the X server starved, xwininfo and import took so long that
# the frame on screen was logged 157 lines after the count taken before them.)
readonly kLoggedMatchAttempts=3
readonly kLoggedMatchSeconds=45

# match_logged_frame: while the clock runs, a screenshot of the client area
# must equal (within the tolerance above) rt64k render at one of the times
# the log shows for the frames around the screenshot. Retried (above). Sets
# MATCHED_T and MATCHED_A (that frame's music position).
match_logged_frame() {
  local shot="$WORK/shot-running.png" t0 before after line t a w attempts=0
  t0=$(now_ms)
  while :; do
    attempts=$((attempts + 1))
    before=$(log_count)
    screenshot_client "$shot"
    sleep $kLogSettleSeconds
    after=$(log_count)
    local from=$((before - kLogSlack))
    [ $from -ge 1 ] || from=1
    local tried=""
    while read -r t a w; do
      [[ " $tried " == *" $t "* ]] && continue
      tried+=" $t"
      render_ref "$t" "$WORK/ref-running.png"
      if same_frame "$shot" "$WORK/ref-running.png"; then
        MATCHED_T=$t
        MATCHED_A=$a
        echo "running: the screenshot is the frame logged at t=$t (a=$a, w=$w): max channel" \
          "diff $MAX_DIFF/255, $DIFF_PIXELS pixels differ, PSNR $PSNR dB; candidates:$tried" \
          "(log lines $from-$after)"
        return 0
      fi
    done < <(log_lines | sed -n "${from},${after}p")
    cp "$shot" "$WORK/shot-unmatched-$attempts.png"
    echo "running: screenshot $attempts is none of the logged frames (log lines $from-$after;" \
      "kept as shot-unmatched-$attempts.png); another"
    if [ $attempts -ge $kLoggedMatchAttempts ] &&
      [ $(($(now_ms) - t0)) -gt $((kLoggedMatchSeconds * 1000)) ]; then
      fail "$attempts screenshots in a row are none of the logged frames (the last tried t =$tried; see $WORK)"
    fi
  done
}
