#!/bin/bash
# wine.bad_args: malformed and unknown options are ignored safely. The
# command line starts at 12 s and holds (in upper case); every later /t: is
# malformed or out of range, so the picture must still be the frame at 12 s.
# Then Esc still ends it with exit code 0.
source "$(dirname "$0")/common.sh"
setup
long=$(printf '/t:%.0s' $(seq 2000))  # one 6000-character token
launch_intro /t:12 /HOLD /t: /t:abc /t:1e5 /t:1.2.3 /t:--5 /t:nan /t:inf \
  /t:99999999999999999999999999 /t:1000000001 /zzz -bogus / - // /t:12x '"' "$long" /BENCHMARK
wait_window
match_render 12
intro_running || fail "intro.exe exited by itself"
escape_exits_cleanly
echo "PASS"
