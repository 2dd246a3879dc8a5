#!/bin/bash
# wine.no_sound: with no sound device at all the exe starts, runs on the
# QueryPerformanceCounter clock, and shows the right pictures. Wine's audio
# drivers (winepulse, winealsa, wineoss) are switched off for this run, so
# waveOutOpen has no device whatever the machine has (a desktop with
# PulseAudio included). `/t:44 /log`, no /hold: the clock runs.
# Checked: the window appears; every frame's time comes from the system clock
# (a = -1); it advances with the wall clock (same QueryPerformanceCounter,
# read before the frame and after its blit: they differ by at most a frame's
# render time, kMaxClockSkew); a screenshot taken while it runs is the
# rt64k render of one of the logged times; Esc ends it with code 0. The
# start-up figures (window, first frame, the synth's precalc) are printed.
source "$(dirname "$0")/common.sh"
readonly kStart=44
readonly kRunSeconds=3
readonly kMinFrames=10
readonly kMaxClockSkew=0.25  # seconds: a frame takes 25-100 ms here
readonly kMaxPrecalcSeconds=5
setup
export WINEDLLOVERRIDES="$WINEDLLOVERRIDES;winepulse.drv,winealsa.drv,wineoss.drv=d"
t0=$(now_ms)
launch_intro /t:$kStart /log
wait_window
windowMs=$(($(now_ms) - t0))
sleep $kRunSeconds
intro_running || fail "intro.exe exited by itself"
match_logged_frame
log_lines >"$WORK/log.txt"
awk -v s=$kStart -v minFrames=$kMinFrames -v skew=$kMaxClockSkew -v maxPre=$kMaxPrecalcSeconds \
  -v windowMs=$windowMs '
  {
    n++
    if ($2 != -1) music++
    if (n == 1) { w0 = $3; if ($1 != s) bad0 = 1; next }
    if (n == 2) { t1 = $1; w1 = $3 }
    tl = $1; wl = $3
  }
  END {
    d = (tl - t1) - (wl - w1); if (d < 0) d = -d
    printf "start-up: window mapped %d ms after launch (Wine included), first frame (t=%s) on screen at w=%.3f s,", windowMs, s, w0
    printf " clock started after the synth precalc at w=%.3f s\n", w1
    printf "%d frames, %d with a music position; t advanced %.3f s while the wall clock advanced %.3f s (difference %.3f s, limit %.2f)\n", n, music, tl - t1, wl - w1, d, skew
    exit !(n >= minFrames && music == 0 && !bad0 && d <= skew && tl > t1 && w1 <= maxPre)
  }' "$WORK/log.txt" || fail "the clock is not the system clock, or too few frames (log: $WORK/log.txt)"
escape_exits_cleanly
echo "PASS"
