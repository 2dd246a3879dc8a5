#!/bin/bash
# wine.escape / wine.close: a key ends the running intro within 1 s with
# exit code 0. Usage: test-key-exit.sh KEY   (xdotool names: Escape, alt+F4;
# Alt+F4 is the keyboard's way of closing a window: WM_SYSCOMMAND SC_CLOSE,
# then WM_CLOSE, as the close box would send).
source "$(dirname "$0")/common.sh"
readonly kExitLimitMs=1000
readonly kRunBeforeKeySeconds=2  # several frames rendered and blitted first
TEST_NAME="$TEST_NAME-$1"
setup
launch_intro
wait_window
sleep $kRunBeforeKeySeconds
intro_running || fail "intro.exe exited before the key"
focus_window
t0=$(now_ms)
type_key "$1"
wait_exit "$1" $kExitLimitMs "$t0"
echo "$1: intro.exe exited $EXIT_MS ms after the key, exit code $EXIT_CODE (limit $kExitLimitMs ms)"
[ "$EXIT_CODE" = 0 ] || fail "exit code $EXIT_CODE, expected 0"
[ "$EXIT_MS" -le $kExitLimitMs ] || fail "took $EXIT_MS ms, more than $kExitLimitMs ms"
echo "PASS"
