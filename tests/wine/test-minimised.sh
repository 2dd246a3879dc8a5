#!/bin/bash
# wine.minimised: minimised, the intro renders nothing and uses (almost) no
# CPU; restored, it renders again (issue 12: it kept rendering at full speed
# on every core). With /mute /log (one line per frame): the process's CPU
# time (/proc/PID/stat utime + stime) and its frames over kMeasureSeconds
# running, minimised, restored. There is no window manager under Xvfb, so
# `xdotool windowminimize` has nobody to ask; window_probe.exe does what the
# title bar's button does, ShowWindow(SW_MINIMIZE / SW_RESTORE), from another
# Wine process.
source "$(dirname "$0")/common.sh"
: "${RT64K_WINDOW_PROBE_EXE:?set by ctest}"
readonly kMeasureSeconds=3
readonly kSettleSeconds=1
readonly kMaxMinimisedTicks=10  # 0.1 s of CPU in 3 s (measured: 0); running uses ~300
readonly kMinRunningFrames=10
setup
cp "$RT64K_WINDOW_PROBE_EXE" "$WORK/window_probe.exe"
launch_intro /t:12 /mute /log
wait_window
sleep 2
# measure LABEL: CPU ticks and frames over kMeasureSeconds -> TICKS FRAMES.
measure() {
  local c0 n0
  intro_running || fail "intro.exe exited ($1)"
  c0=$(cpu_ticks)
  n0=$(log_count)
  sleep $kMeasureSeconds
  TICKS=$(($(cpu_ticks) - c0))
  FRAMES=$(($(log_count) - n0))
  echo "$1: $TICKS CPU ticks (1/$(getconf CLK_TCK) s) and $FRAMES frames in $kMeasureSeconds s"
}
probe() {
  (cd "$WORK" && timeout 30 "$WINE" ./window_probe.exe "$1")
  local rc=$?
  [ $rc = 0 ] || fail "window_probe.exe $1: exit code $rc (1 no window, 3 state unchanged)"
  sleep $kSettleSeconds
}
measure running
runTicks=$TICKS runFrames=$FRAMES
[ "$runFrames" -ge $kMinRunningFrames ] || fail "only $runFrames frames while running"
probe minimise
measure minimised
[ "$FRAMES" = 0 ] || fail "$FRAMES frames rendered while minimised"
[ "$TICKS" -le $kMaxMinimisedTicks ] ||
  fail "$TICKS CPU ticks while minimised (limit $kMaxMinimisedTicks; running: $runTicks)"
probe restore
measure restored
[ "$FRAMES" -ge $kMinRunningFrames ] || fail "only $FRAMES frames after restoring"
lastT=$(log_lines | tail -n1 | cut -d' ' -f1)
echo "after restoring, the picture shows t=$lastT (the clock ran on while minimised)"
match_logged_frame
escape_exits_cleanly
echo "PASS"
