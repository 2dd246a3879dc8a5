#!/bin/bash
# wine.audio: with a PulseAudio null sink standing in for a sound card, the
# exe plays its music through waveOut (Wine's winepulse) and the picture
# follows the music's position: with /log each frame prints the time it shows
# (t), the music's position the clock read (a, -1 when not from the music)
# and the wall clock (w). Checked: from the second frame on every frame's time
# comes from the music (a >= 0), equals start + a to the printed digits, a
# never goes back, and the music advances with the wall clock.
source "$(dirname "$0")/common.sh"
readonly kStart=30            # seconds: across the scene cut at 32 s
readonly kRunSeconds=8
readonly kMinFrames=20        # frames with the music's clock
readonly kMinAdvance=0.5      # music seconds per wall second, at least (the null
                              # sink's clock runs slow on a loaded machine: 0.86 seen)
command -v pulseaudio >/dev/null || skip "pulseaudio not installed (package pulseaudio)"
setup
export XDG_RUNTIME_DIR="$WORK/run"
mkdir -p "$XDG_RUNTIME_DIR"
chmod 700 "$XDG_RUNTIME_DIR"
pulseaudio --daemonize=no --exit-idle-time=-1 -n -L "module-null-sink sink_name=rt64k" \
  -L module-native-protocol-unix >"$WORK/pulse.log" 2>&1 &
PULSE_PID=$!
trap 'kill $PULSE_PID 2>/dev/null; cleanup' EXIT
for i in $(seq 50); do pactl info >/dev/null 2>&1 && break; sleep 0.1; done
pactl info >/dev/null 2>&1 || fail "pulseaudio did not start: $(cat "$WORK/pulse.log")"
launch_intro /t:$kStart /log
wait_window
sleep $kRunSeconds
intro_running || fail "intro.exe exited by itself"
tr -d '\r' <"$WORK/intro.out" >"$WORK/log.txt"
awk -v s=$kStart -v minFrames=$kMinFrames -v minAdv=$kMinAdvance '
  /^t=/ {
    split($1, t, "="); split($2, a, "="); split($3, w, "=");
    n++
    if (n == 1) next                  # the first frame shows before playback starts
    if (a[2] < 0) { bad++; next }
    music++
    if (sprintf("%.6f", t[2] - s) != sprintf("%.6f", a[2])) { off++; print "frame " n ": t=" t[2] " a=" a[2] }
    if (a[2] < last) back++
    last = a[2]
    if (music == 1) { a0 = a[2]; w0 = w[2] }
    a1 = a[2]; w1 = w[2]
  }
  END {
    rate = (w1 > w0) ? (a1 - a0) / (w1 - w0) : 0
    printf "%d frames; %d on the music clock, %d not; t = start + a off in %d; a went back %d times; music advanced %.3f s in %.3f s of wall time (%.2f)\n", n, music, bad, off, back, a1 - a0, w1 - w0, rate
    exit !(music >= minFrames && bad == 0 && off == 0 && back == 0 && rate >= minAdv)
  }' "$WORK/log.txt" || fail "the picture does not follow the music (log: $WORK/log.txt)"
escape_exits_cleanly
echo "PASS"
