#!/bin/bash
# wine.fullscreen_*: `intro.exe /f` covers the whole screen with a borderless
# window and shows the picture at the largest 4:3 size that fits the screen,
# centred, black bars filling the rest. Usage: test-fullscreen.sh WxH [scaled]
#   (default) the picture is rendered at that size (the screen's own
#             resolution): the screenshot of the 4:3 rectangle equals
#             `rt64k render --size PWxPH` (tolerance as for the window:
#             common.sh same_frame).
#   scaled    `/f /scaled`: the 800x600 picture stretched by StretchDIBits
#             (COLORONCOLOR), the switch for slow machines; checked against
#             the envelope below.
export RT64K_SCREEN="$1x24"  # read by common.sh: the Xvfb screen size
source "$(dirname "$0")/common.sh"
readonly kTime=44  # scene 2: bright, so the picture's own edges are not black
mode=${2:-native}
# The scaled picture's content. StretchDIBits (COLORONCOLOR) takes each screen
# pixel from one source pixel; which one, at the edges between source pixels,
# depends on how the scaler rounds (and a filtering scaler would blend
# neighbours). Either way every channel of a screen pixel lies between the
# minimum and maximum of that channel over the 3x3 source pixels around the
# ideal nearest one. So: rt64k render at 800x600, its 3x3 minimum and maximum
# (ImageMagick erode/dilate), both scaled with the point filter; no channel of
# any picture pixel may leave that envelope (kMaxOutside = 0). A frame 0.1 s
# away leaves it at ~63,000 pixels. Also printed: how many pixels equal the
# point-filtered render exactly (measured: all).
readonly kMaxOutside=0
TEST_NAME="$TEST_NAME-$1-$mode"
sw=${1%x*}
sh=${1#*x}
setup
case $mode in
  native) launch_intro /f /t:$kTime /hold ;;
  scaled) launch_intro /f /scaled /t:$kTime /hold ;;
  *) fail "unknown mode '$mode' (native or scaled)" ;;
esac
wait_window
window_geometry
echo "window: ${WIN_W}x${WIN_H} at +${WIN_X}+${WIN_Y} on a ${sw}x${sh} screen"
[ "${WIN_W}x${WIN_H}+${WIN_X}+${WIN_Y}" = "${sw}x${sh}+0+0" ] || fail "the window does not cover the screen"
# Expected picture: the largest 4:3 rectangle, centred.
if [ $((sw * 3)) -le $((sh * 4)) ]; then pw=$sw; ph=$((sw * 3 / 4)); else ph=$sh; pw=$((sh * 4 / 3)); fi
px=$(((sw - pw) / 2)); py=$(((sh - ph) / 2))
ref="$WORK/ref.png"
if [ $mode = native ]; then
  render_ref $kTime "$ref" "${pw}x${ph}"
else
  render_ref $kTime "$WORK/ref800.png"
  convert "$WORK/ref800.png" -filter point -resize "${pw}x${ph}!" "$ref"
  convert "$WORK/ref800.png" -morphology Erode Square:1 -filter point -resize "${pw}x${ph}!" "$WORK/low.png"
  convert "$WORK/ref800.png" -morphology Dilate Square:1 -filter point -resize "${pw}x${ph}!" "$WORK/high.png"
fi
# outside_envelope PICTURE: pixels with a channel below low or above high.
outside_envelope() {
  convert \( "$1" "$WORK/low.png" -compose Minus_Dst -composite \) \
    \( "$WORK/high.png" "$1" -compose Minus_Dst -composite \) -compose Lighten -composite \
    -separate -evaluate-sequence Max -threshold 0 -format '%[fx:round(mean*w*h)]' info:
}
# picture_ok: the content test of this mode on $WORK/picture.png.
picture_ok() {
  if [ $mode = native ]; then
    same_frame "$WORK/picture.png" "$ref"
  else
    outside=$(outside_envelope "$WORK/picture.png")
    [ "$outside" -le $kMaxOutside ]
  fi
}
sleep 3  # the first frames
for try in 1 2 3 4 5 6 7 8 9 10; do
  import -window root "$WORK/shot.png" || fail "screenshot failed"
  # The bounding box of everything not black: a 1-pixel black border first,
  # so that -trim trims black and not, say, a uniform sky along the top.
  geom=$(convert "$WORK/shot.png" -bordercolor black -border 1 -trim -format '%w %h %X %Y' info:)
  read -r bw bh bx by <<<"${geom//+/}"
  bx=$((bx - 1)); by=$((by - 1))
  convert "$WORK/shot.png" -crop "${pw}x${ph}+${px}+${py}" +repage "$WORK/picture.png"
  picture_ok && [ "$bw $bh $bx $by" = "$pw $ph $px $py" ] && ok=1 && break
  ok=0
  sleep 1
done
echo "non-black area: ${bw}x${bh}+${bx}+${by}; expected picture ${pw}x${ph}+${px}+${py} (aspect $((bw * 1000 / bh))/1000, 4:3 = 1333/1000)"
[ "$bw $bh $bx $by" = "$pw $ph $px $py" ] || fail "the picture is not the centred 4:3 rectangle"
[ $(((bw * 3 - bh * 4) * (bw * 3 - bh * 4))) -le 9 ] || fail "aspect ratio is not 4:3 within a pixel"
if [ $mode = native ]; then
  same_frame "$WORK/picture.png" "$ref"
  echo "content: rendered at the screen's resolution: vs rt64k render --size ${pw}x${ph}: max channel" \
    "diff $MAX_DIFF/255, $DIFF_PIXELS of $((pw * ph)) pixels differ, PSNR $PSNR dB (limits:" \
    "$kMaxChannelDiff, $kMaxDifferentPixels)"
  [ "$ok" = 1 ] || fail "the picture differs from rt64k render --size ${pw}x${ph} (see $WORK)"
else
  exact=$(compare -metric AE "$WORK/picture.png" "$ref" null: 2>&1 | awk '{printf "%d", $1}')
  psnr=$(compare -metric PSNR "$WORK/picture.png" "$ref" null: 2>&1 | awk '{print $1}')
  echo "content: /scaled: $outside of $((pw * ph)) pixels outside the 3x3 envelope of the scaled rt64k render (limit $kMaxOutside);" \
    "$exact differ from the point-filtered render at all, PSNR $psnr dB"
  [ "$outside" -le $kMaxOutside ] || fail "the picture differs from rt64k render scaled ($outside pixels outside the envelope)"
fi
intro_running || fail "intro.exe exited by itself"
echo "PASS"
