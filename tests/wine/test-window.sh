#!/bin/bash
# wine.window: intro.exe opens one window whose client area is 800x600.
source "$(dirname "$0")/common.sh"
setup
launch_intro /t:12 /hold
wait_window
window_geometry
echo "window $WINDOW_ID: client area ${WIN_W}x${WIN_H} at +${WIN_X}+${WIN_Y}"
[ "${WIN_W}x${WIN_H}" = 800x600 ] || fail "client area is ${WIN_W}x${WIN_H}, not 800x600"
count=$(xdotool search --onlyvisible --name '^rt64k$' | wc -l)
[ "$count" = 1 ] || fail "$count visible windows titled rt64k, expected 1"
intro_running || fail "intro.exe exited by itself"
echo "PASS"
