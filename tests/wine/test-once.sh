#!/bin/bash
# wine.once: `intro.exe /t:60 /once` plays to the end of the timeline (64 s)
# and exits by itself with code 0: about 4 s of picture after start-up.
source "$(dirname "$0")/common.sh"
readonly kStart=60
readonly kPlaySeconds=4        # 64 - kStart
readonly kLimitMs=8000         # play time + start-up (synth ~1 s) with margin
setup
t0=$(now_ms)
launch_intro /t:$kStart /once
wait_window
wait_exit "the end of the timeline" $kLimitMs "$t0"
echo "/once from t=$kStart: exited after $EXIT_MS ms with code $EXIT_CODE"
[ "$EXIT_CODE" = 0 ] || fail "exit code $EXIT_CODE, expected 0"
[ "$EXIT_MS" -ge $((kPlaySeconds * 1000 - 500)) ] || fail "exited after $EXIT_MS ms: before the timeline's end"
[ "$EXIT_MS" -le $kLimitMs ] || fail "took $EXIT_MS ms, more than $kLimitMs ms"
echo "PASS"
