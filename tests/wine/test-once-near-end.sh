#!/bin/bash
# wine.once_near_end: `/t:S /once` with S just below the end of a 64-s loop
# ends at that loop's end, within a few frames (issue 12: /t:63.999999 played
# a whole extra loop, the start's float wrap rounding to 64 s = 0 s of the
# next loop). For each start: exit code 0 within kLimitMs of launch (Wine's
# start-up included; a gained loop would take 64 s), and every frame /log
# printed is inside [S, end of S's loop). /mute: no synth precalc to wait for.
source "$(dirname "$0")/common.sh"
readonly kLimitMs=6000
setup
for start in 63.99 63.9999 63.999999 63.9999999 127.999999 -0.000001; do
  end=$(awk -v s="$start" 'BEGIN { n = int(s / 64); if (n > s / 64) n--; printf "%d", (n + 1) * 64 }')
  t0=$(now_ms)
  launch_intro /t:$start /once /mute /log
  wait_exit "the end of the loop" $((kLimitMs / 5)) "$t0"
  frames=$(log_count)
  range=$(log_lines | awk 'NR == 1 {a = $1} {b = $1} END {print a " .. " b}')
  echo "/t:$start /once: exit code $EXIT_CODE after $EXIT_MS ms; $frames frames, t = $range (end $end)"
  [ "$EXIT_CODE" = 0 ] || fail "/t:$start: exit code $EXIT_CODE, expected 0"
  [ "$EXIT_MS" -le $kLimitMs ] || fail "/t:$start: took $EXIT_MS ms (limit $kLimitMs)"
  [ "$frames" -ge 1 ] || fail "/t:$start: no frame logged"
  log_lines | awk -v s="$start" -v e="$end" '$1 < s - 1e-6 || $1 >= e {bad++} END {exit bad > 0}' ||
    fail "/t:$start: a frame outside [$start, $end) (log: $WORK/intro.out)"
done
echo "PASS"
