#!/bin/bash
# wine.first_run: the README's first command, tools/run-intro.sh, as a new
# user runs it: no Wine prefix yet, no X display (Xvfb), no sound card (the
# test hides any PulseAudio; on a machine with an ALSA card that part is
# only reported). Issue 11: the first run saved a black screenshot because
# the intro joined the display-less session wineboot had started and exited
# with code 1; and it printed a page of ALSA errors. Checks: the script
# exits 0 after seeing the intro still running; its screenshot of the
# window equals rt64k render at the /t: time (/hold); its output has one
# line saying the intro runs silent and no ALSA error.
source "$(dirname "$0")/common.sh"
: "${RT64K_SOURCE_DIR:?set by ctest}" "${RT64K_BUILD_DIR:?set by ctest}"
readonly kTime=12
readonly kRunSeconds=6
find_tools
WORK="$RT64K_WINE_DIR/work/$TEST_NAME"
rm -rf "$WORK"
mkdir -p "$WORK"
export PULSE_SERVER="unix:$WORK/no-such-pulse-server"
t0=$(now_ms)
env -u DISPLAY -u WINEPREFIX -u WINEDLLOVERRIDES BUILD_DIR="$RT64K_BUILD_DIR" \
  RT64K_WINEPREFIX="$WORK/prefix" RT64K_SECONDS=$kRunSeconds RT64K_SCREENSHOT="$WORK/shot.png" \
  "$RT64K_SOURCE_DIR/tools/run-intro.sh" /t:$kTime /hold >"$WORK/run.out" 2>&1
rc=$?
echo "tools/run-intro.sh from no prefix: exit code $rc after $(($(now_ms) - t0)) ms; its output:"
sed 's/^/  | /' "$WORK/run.out"
[ "$rc" = 0 ] || fail "run-intro.sh exited with code $rc"
grep -q "^creating a Wine prefix" "$WORK/run.out" || fail "the script did not create a prefix"
grep -q "still running" "$WORK/run.out" || fail "the script did not see the intro running"
# The intro's own output (Wine's and ALSA's messages) goes to a log when it
# runs headless, and to the terminal when there is a display: neither may
# hold ALSA errors.
cp "$RT64K_BUILD_DIR/intro-run.log" "$WORK/intro-run.log" || fail "no intro-run.log"
alsa=$(grep -ci "ALSA" "$WORK/run.out" "$WORK/intro-run.log" | awk -F: '{n += $2} END {print n}')
echo "ALSA lines in the script's output and the intro's: $alsa (without the sound check: 16)"
[ "$alsa" = 0 ] || fail "ALSA messages in the output"
if [ -r /proc/asound/cards ] && grep -q '^ *[0-9]' /proc/asound/cards; then
  echo "this machine has an ALSA sound card: the 'runs silent' line is not expected"
else
  n=$(grep -c "runs silent" "$WORK/run.out")
  [ "$n" = 1 ] || fail "$n lines say the intro runs silent, expected 1"
fi
[ -f "$WORK/shot.png" ] || fail "no screenshot"
size=$(identify -format '%wx%h' "$WORK/shot.png")
[ "$size" = 800x600 ] || fail "the screenshot is $size, not the 800x600 window"
render_ref $kTime "$WORK/ref.png"
same_frame "$WORK/shot.png" "$WORK/ref.png" ||
  fail "the screenshot differs from rt64k render --time $kTime: max channel diff $MAX_DIFF/255, $DIFF_PIXELS pixels, PSNR $PSNR dB"
echo "screenshot vs rt64k render --time $kTime: max channel diff $MAX_DIFF/255, $DIFF_PIXELS pixels differ, PSNR $PSNR dB"
rm -rf "$WORK/prefix"
echo "PASS"
