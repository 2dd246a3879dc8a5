#!/bin/bash
# wine.screenshot_*: `intro.exe /t:T /hold` shows the frame that
# `rt64k render --time T` renders (tolerance and its reasons: common.sh).
# Usage: test-screenshot.sh T
source "$(dirname "$0")/common.sh"
TEST_NAME="$TEST_NAME-$1"
setup
launch_intro "/t:$1" /hold
wait_window
match_render "$1"
intro_running || fail "intro.exe exited by itself"
echo "PASS"
