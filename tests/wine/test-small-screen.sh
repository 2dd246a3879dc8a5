#!/bin/bash
# wine.small_screen: on a screen too small for the 800x600 window (issue 12:
# at 640x480 the picture was cut off at the right and bottom), the window's
# client area is the largest 4:3 size that fits the work area with the
# window's frame, wholly on the screen, and the picture is rendered at that
# size: the screenshot equals `rt64k render --size WxH` (common.sh
# tolerance). Usage: test-small-screen.sh WxH
export RT64K_SCREEN="$1x24"
source "$(dirname "$0")/common.sh"
readonly kTime=12
TEST_NAME="$TEST_NAME-$1"
sw=${1%x*}
sh=${1#*x}
setup
launch_intro /t:$kTime /hold
wait_window
window_geometry
echo "client area ${WIN_W}x${WIN_H} at +${WIN_X}+${WIN_Y} on a ${sw}x${sh} screen"
[ "$WIN_X" -ge 0 ] && [ "$WIN_Y" -ge 0 ] && [ $((WIN_X + WIN_W)) -le "$sw" ] &&
  [ $((WIN_Y + WIN_H)) -le "$sh" ] || fail "the client area is not wholly on the screen"
[ "$WIN_W" -lt 800 ] && [ "$WIN_H" -lt 600 ] || fail "the window was not made smaller"
[ $(((WIN_W * 3 - WIN_H * 4) * (WIN_W * 3 - WIN_H * 4))) -le 16 ] ||
  fail "the client area ${WIN_W}x${WIN_H} is not 4:3 within a pixel"
# The largest that fits: a frame of at most kMaxFrame pixels around it.
readonly kMaxFrame=64
[ $((WIN_W + kMaxFrame)) -ge "$sw" ] || [ $((WIN_H + kMaxFrame)) -ge "$sh" ] ||
  fail "the client area ${WIN_W}x${WIN_H} is far smaller than the screen"
match_render $kTime "${WIN_W}x${WIN_H}"
intro_running || fail "intro.exe exited by itself"
echo "PASS"
