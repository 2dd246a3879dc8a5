#!/bin/bash
# wine.audio: with a PulseAudio null sink standing in for a sound card, the
# exe plays its music through waveOut (Wine's winepulse) and the picture
# follows the music's position, not the system clock. With /log each frame
# prints the time it shows (t), the music's position the clock read (a, -1
# when not from the music) and the wall clock (w).
#
# 1. Playing (`/t:30 /log`, across the scene cut at 32 s): Wine's stream is on
#    the null sink; from the second frame on every frame's time comes from the
#    music (a >= 0) and equals 30 + a to the printed digits; a never goes back;
#    the music advances with the wall clock (at least kMinAdvance: the null
#    sink's clock runs slow on a loaded machine, 0.6-0.9 seen); a screenshot
#    taken while it plays is the rt64k render of a logged (music) time.
# 2. The music stops: the sound server is frozen (SIGSTOP), so the stream's
#    position stops where the music stopped. Frames keep coming, all at that
#    one time (a system clock would have moved on by kFreezeSeconds), and a
#    screenshot then equals rt64k render at exactly that audio time.
# 3. The music goes on (SIGCONT): the picture continues from the frozen time
#    (the next time is less than kMaxResumeStep later, not kFreezeSeconds).
# 4. /mute with the sound card present: no stream is opened, every frame is on
#    the system clock (a = -1), and the first two frames follow each other
#    without the synth's precalc.
source "$(dirname "$0")/common.sh"
readonly kStart=30
readonly kPlaySeconds=3
readonly kMinAdvance=0.5      # music seconds per wall second while playing, at least
readonly kFreezeSettleSeconds=1
readonly kFreezeSeconds=2
readonly kMinFrozenFrames=5   # frames rendered while the music stood still
readonly kMaxResumeStep=0.3   # seconds from the frozen time to the next frame's
readonly kMaxNoPrecalcSeconds=0.4  # first to second frame under /mute (precalc ~0.8 s)
readonly kMusicTimeoutSeconds=15

command -v pulseaudio >/dev/null && command -v pactl >/dev/null ||
  skip "PulseAudio not installed (packages pulseaudio pulseaudio-utils): the music cannot be heard by this test"
[ -n "$(ls /usr/lib/wine/*/winepulse.drv* /usr/lib/*/wine/*/winepulse.drv* 2>/dev/null)" ] ||
  skip "Wine's winepulse driver not found: Wine cannot play to PulseAudio here"
setup

# A private PulseAudio: its own runtime folder and home (the user's are not
# touched), a null sink as the only card, anonymous clients (Wine needs no
# cookie). Ended by its pid.
PULSE_DIR="$WORK/pulse"
mkdir -p "$PULSE_DIR/home"
chmod 700 "$PULSE_DIR"
export XDG_RUNTIME_DIR="$PULSE_DIR" PULSE_SERVER="unix:$PULSE_DIR/native"
HOME="$PULSE_DIR/home" pulseaudio -n --daemonize=no --exit-idle-time=-1 --system=false \
  -L "module-null-sink sink_name=rt64k_null" \
  -L "module-native-protocol-unix auth-anonymous=1 socket=$PULSE_DIR/native" \
  >"$WORK/pulse.log" 2>&1 &
PULSE_PID=$!
end_pulse() {
  kill -CONT "$PULSE_PID" 2>/dev/null
  kill "$PULSE_PID" 2>/dev/null
  wait "$PULSE_PID" 2>/dev/null
}
trap 'kill -CONT "$PULSE_PID" 2>/dev/null; cleanup; end_pulse' EXIT
for i in $(seq 50); do pactl info >/dev/null 2>&1 && break; sleep 0.1; done
pactl info >/dev/null 2>&1 || fail "pulseaudio did not start: $(cat "$WORK/pulse.log")"
streams() { pactl list short sink-inputs | wc -l; }

# 1. Playing.
launch_intro /t:$kStart /log
wait_window
t0=$(now_ms)
until log_lines | awk '$2 >= 0 {found = 1} END {exit !found}'; do
  [ $(($(now_ms) - t0)) -le $((kMusicTimeoutSeconds * 1000)) ] ||
    fail "no frame on the music clock within $kMusicTimeoutSeconds s: waveOut did not play (log: $WORK/intro.out, $WORK/intro.err)"
  intro_running || fail "intro.exe exited"
  sleep 0.2
done
[ "$(streams)" -ge 1 ] || fail "no stream on the null sink"
echo "music playing: $(streams) stream(s) on the null sink"
sleep $kPlaySeconds
match_logged_frame
awk -v a="$MATCHED_A" 'BEGIN {exit !(a >= 0)}' || fail "the matched frame's time was not the music's"

# 2. The music stops.
kill -STOP "$PULSE_PID"
sleep $kFreezeSettleSeconds
frozenFrom=$(log_count)
frozenT=$(log_lines | tail -n1 | cut -d' ' -f1)
sleep $kFreezeSeconds
screenshot_client "$WORK/shot-frozen.png"
frozenTo=$(log_count)
log_lines | sed -n "$((frozenFrom + 1)),${frozenTo}p" >"$WORK/frozen.txt"
frozenFrames=$(wc -l <"$WORK/frozen.txt")
moved=$(awk -v t="$frozenT" '$1 != t' "$WORK/frozen.txt" | wc -l)
echo "music stopped: $frozenFrames frames rendered in $kFreezeSeconds s; $moved of them not at the frozen time t=$frozenT"
[ "$frozenFrames" -ge $kMinFrozenFrames ] || fail "only $frozenFrames frames while the music stood still: the intro should keep rendering"
[ "$moved" = 0 ] || fail "the picture's time moved while the music stood still (see $WORK/frozen.txt)"
render_ref "$frozenT" "$WORK/ref-frozen.png"
same_frame "$WORK/shot-frozen.png" "$WORK/ref-frozen.png" ||
  fail "while the music stood at t=$frozenT the screen differs from rt64k render: max channel diff $MAX_DIFF/255, $DIFF_PIXELS pixels, PSNR $PSNR dB"
echo "the frozen picture is rt64k render at t=$frozenT: max channel diff $MAX_DIFF/255, $DIFF_PIXELS pixels differ, PSNR $PSNR dB"

# 3. The music goes on.
kill -CONT "$PULSE_PID"
sleep $kPlaySeconds
intro_running || fail "intro.exe exited by itself"
log_lines | sed -n "$((frozenTo + 1)),\$p" | awk -v t="$frozenT" '$1 != t' | head -n1 >"$WORK/resumed.txt"
resumedT=$(cut -d' ' -f1 "$WORK/resumed.txt")
[ -n "$resumedT" ] || fail "the picture did not move again after the music went on"
awk -v r="$resumedT" -v f="$frozenT" -v m=$kMaxResumeStep 'BEGIN {
  printf "music on again: the next frame shows t=%s, %.3f s after the frozen time (limit %.2f; %d s of wall time passed)\n", r, r - f, m, '"$kFreezeSeconds"'
  exit !(r > f && r - f <= m) }' || fail "the picture did not continue from where the music stopped"

# The whole run's log: every frame after the first on the music clock, t = start + a,
# a never back, and the music's pace while it played (before the freeze).
log_lines >"$WORK/log.txt"
awk -v s=$kStart -v minAdv=$kMinAdvance -v frozenFrom=$frozenFrom '
  {
    n++
    if (n == 1) next                  # the first frame shows before playback starts
    if ($2 < 0) { bad++; next }
    music++
    if (sprintf("%.6f", $1 - s) != sprintf("%.6f", $2)) { off++; print "frame " n ": t=" $1 " a=" $2 }
    if ($2 < last) back++
    last = $2
    if (music == 1) { a0 = $2; w0 = $3 }
    if (n <= frozenFrom) { a1 = $2; w1 = $3 }
  }
  END {
    rate = (w1 > w0) ? (a1 - a0) / (w1 - w0) : 0
    printf "%d frames; %d on the music clock, %d not; t = start + a off in %d; a went back %d times; before the freeze the music advanced %.3f s in %.3f s of wall time (%.2f, limit %.2f)\n", n, music, bad, off, back, a1 - a0, w1 - w0, rate, minAdv
    exit !(bad == 0 && off == 0 && back == 0 && rate >= minAdv)
  }' "$WORK/log.txt" || fail "the picture does not follow the music (log: $WORK/log.txt)"
escape_exits_cleanly

# 4. /mute, the sound card still there.
launch_intro /t:12 /mute /log
wait_window
sleep $kPlaySeconds
intro_running || fail "intro.exe /mute exited by itself"
[ "$(streams)" = 0 ] || fail "/mute opened a stream on the sound card"
log_lines | awk -v pre=$kMaxNoPrecalcSeconds '
  { n++; if ($2 != -1) music++; if (n == 1) w0 = $3; if (n == 2) w1 = $3; tl = $1 }
  END {
    printf "/mute: no stream; %d frames, %d with a music position; first to second frame %.3f s (no precalc; limit %.2f); t reached %s\n", n, music, w1 - w0, pre, tl
    exit !(n >= 2 && music == 0 && w1 - w0 <= pre && tl > 12) }' ||
  fail "/mute: music clock used, or the synth ran (log: $WORK/intro.out)"
escape_exits_cleanly
echo "PASS"
