#!/bin/sh
# cli_test.sh - the rt64k command-line tool from the outside (ctest: cli).
# Usage: cli_test.sh path/to/rt64k
# Checks: --help exits 0; render writes a valid PNG of the requested size
# (signature, chunk CRCs, IHDR, inflated scanlines); scene prints valid JSON
# with camera, lights and objects; every bad argument gives exactly one line
# on stderr, nothing on stdout, and exit code 2; control characters and bytes
# that are not UTF-8 in an argument come back escaped in that line; finite
# denormal times are accepted. Needs python3 (PNG and JSON checks use only its
# standard library). Output files: tests/output_test.sh.
set -u
RT64K=${1:?usage: cli_test.sh path/to/rt64k}
. "$(dirname "$0")/check-lib.sh"

# A PNG is valid: signature, every chunk's CRC, IHDR of W x H, 8-bit RGB or
# RGBA, IDAT inflating to exactly H rows of filter byte + W pixels, IEND last.
png_ok() {
  python3 - "$1" "$2" "$3" <<'EOF'
import struct, sys, zlib
path, w, h = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
data = open(path, 'rb').read()
assert data[:8] == b'\x89PNG\r\n\x1a\n', 'signature'
pos, chunks, idat = 8, [], b''
while pos < len(data):
    n, kind = struct.unpack('>I4s', data[pos:pos + 8])
    body = data[pos + 8:pos + 8 + n]
    crc, = struct.unpack('>I', data[pos + 8 + n:pos + 12 + n])
    assert zlib.crc32(kind + body) & 0xffffffff == crc, 'crc of ' + kind.decode()
    chunks.append(kind)
    if kind == b'IHDR':
        iw, ih, depth, ctype = struct.unpack('>IIBB', body[:10])
        assert (iw, ih) == (w, h), 'size %dx%d, wanted %dx%d' % (iw, ih, w, h)
        assert depth == 8 and ctype in (2, 6), 'depth %d type %d' % (depth, ctype)
        channels = 3 if ctype == 2 else 4
    if kind == b'IDAT':
        idat += body
    pos += 12 + n
assert chunks[0] == b'IHDR' and chunks[-1] == b'IEND', 'chunk order'
raw = zlib.decompress(idat)
assert len(raw) == h * (1 + w * channels), 'scanlines %d bytes' % len(raw)
assert all(raw[y * (1 + w * channels)] <= 4 for y in range(h)), 'filter types'
EOF
}

# Runs the tool; expects exit code 2, exactly one non-empty line on stderr,
# nothing on stdout.
expect_usage_error() {
  what=$1
  shift
  "$RT64K" "$@" >"$TMP/out" 2>"$TMP/err"
  code=$?
  lines=$(wc -l <"$TMP/err")
  if [ "$code" -ne 2 ]; then
    fail "$what: exit code $code, wanted 2 ($*)"
  elif [ "$lines" -ne 1 ] || [ ! -s "$TMP/err" ]; then
    fail "$what: $lines lines on stderr, wanted 1 ($*)"
  elif [ -s "$TMP/out" ]; then
    fail "$what: wrote to stdout ($*)"
  else
    pass
  fi
}

# --help
if "$RT64K" --help >"$TMP/out" 2>"$TMP/err" && grep -q "usage" "$TMP/out" && [ ! -s "$TMP/err" ]; then
  pass
else
  fail "--help: not exit 0 with usage on stdout"
fi

# render: requested sizes, default size, ids view, negative and huge finite times
for args in "--time 3 --size 64x48:64:48" "--time 40.5 --size 1x1:1:1" \
            "--time 10:800:600" "--time 50 --size 97x31 --view ids:97:31" \
            "--time -1e9 --size 32x24:32:24" "--time 1e12 --size 32x24:32:24"; do
  opts=${args%%:*}
  rest=${args#*:}
  w=${rest%%:*}
  h=${rest#*:}
  rm -f "$TMP/f.png"
  # shellcheck disable=SC2086
  if ! "$RT64K" render $opts --threads 2 --out "$TMP/f.png" >"$TMP/out" 2>"$TMP/err"; then
    fail "render $opts: exit code $? ($(cat "$TMP/err"))"
  elif ! png_ok "$TMP/f.png" "$w" "$h" 2>"$TMP/py"; then
    fail "render $opts: invalid PNG: $(tail -1 "$TMP/py")"
  else
    pass
  fi
done

# scene: valid JSON with camera, lights, objects, for times in both scenes,
# negative and huge
for t in 5 40 -3.5 1e15; do
  if ! "$RT64K" scene --time "$t" >"$TMP/scene.json" 2>"$TMP/err"; then
    fail "scene --time $t: exit code $?"
  elif ! python3 -m json.tool "$TMP/scene.json" >/dev/null 2>"$TMP/py"; then
    fail "scene --time $t: invalid JSON: $(tail -1 "$TMP/py")"
  elif ! python3 - "$TMP/scene.json" <<'EOF' 2>"$TMP/py"; then
import json, math, sys
s = json.load(open(sys.argv[1]))
cam = s['camera']
for key in ('position', 'target', 'up'):
    assert len(cam[key]) == 3 and all(math.isfinite(v) for v in cam[key]), key
assert 0 < cam['fov_y_degrees'] < 180
assert (cam['width'], cam['height']) == (800, 600)
assert len(s['lights']) >= 1 and all(len(l['position']) == 3 for l in s['lights'])
assert len(s['objects']) >= 1
for o in s['objects']:
    assert o['shape']['kind'] in ('sphere', 'plane', 'cylinder', 'cone', 'triangle')
    assert 'material' in o and 'background' in o and 'ids_color' in o
assert 0 <= s['timeline_time'] < 64
EOF
    fail "scene --time $t: $(tail -1 "$TMP/py")"
  else
    pass
  fi
done

# Bad arguments: one line on stderr, exit code 2.
OUT="$TMP/bad.png"
expect_usage_error "no command"
expect_usage_error "unknown command" frobnicate
expect_usage_error "unknown option" render --time 1 --out "$OUT" --bogus 3
expect_usage_error "unknown option (scene)" scene --time 1 --colour red
expect_usage_error "missing value" render --out "$OUT" --time
expect_usage_error "missing value (size)" render --time 1 --out "$OUT" --size
expect_usage_error "missing --time" render --out "$OUT"
expect_usage_error "missing --out" render --time 1
expect_usage_error "non-numeric time" render --time abc --out "$OUT"
expect_usage_error "trailing junk in time" scene --time 1.5x
expect_usage_error "empty time" scene --time ""
expect_usage_error "nan time" render --time nan --out "$OUT"
expect_usage_error "inf time" scene --time inf
expect_usage_error "-inf time" scene --time -inf
expect_usage_error "overflowing time" scene --time 1e999
expect_usage_error "zero width" render --time 1 --size 0x600 --out "$OUT"
expect_usage_error "zero height" render --time 1 --size 800x0 --out "$OUT"
expect_usage_error "negative size" render --time 1 --size -5x10 --out "$OUT"
expect_usage_error "huge size" render --time 1 --size 100000x100000 --out "$OUT"
expect_usage_error "overflowing size" render --time 1 --size 99999999999999999999x10 --out "$OUT"
expect_usage_error "nan size" render --time 1 --size nanx10 --out "$OUT"
expect_usage_error "malformed size" render --time 1 --size 800 --out "$OUT"
expect_usage_error "malformed size (no height)" render --time 1 --size 800x --out "$OUT"
expect_usage_error "unknown view" render --time 1 --view depth --out "$OUT"
expect_usage_error "unwritable path" render --time 1 --size 8x8 --out /nonexistent-dir/x.png
expect_usage_error "directory as path" render --time 1 --size 8x8 --out "$TMP"
expect_usage_error "repeated option" render --time 1 --time 2 --out "$OUT"
if [ -e "$OUT" ]; then fail "a rejected render wrote $OUT"; else pass; fi

# Captions appear at their times in rendered frames (4 s: the title) and
# nowhere else (9 s: no caption), and --overlay off leaves them out.
for t in 4 9; do
  "$RT64K" render --time $t --size 200x150 --mode full --out "$TMP/on-$t.png" &&
    "$RT64K" render --time $t --size 200x150 --mode full --overlay off --out "$TMP/off-$t.png" ||
    fail "render with/without captions at $t s"
done
if cmp -s "$TMP/on-4.png" "$TMP/off-4.png"; then fail "no caption drawn at 4 s"; else pass; fi
if cmp -s "$TMP/on-9.png" "$TMP/off-9.png"; then pass; else fail "a caption drawn at 9 s"; fi
expect_usage_error "bad overlay value" render --time 1 --overlay maybe --out "$OUT"

# Finite denormal and underflowing times are times: 1e-310 is kept as given,
# 1e-400 rounds to 0.
for t in 1e-310 -1e-310 1e-400; do
  if "$RT64K" scene --time "$t" >"$TMP/scene.json" 2>"$TMP/err" &&
    python3 -c 'import json, sys; s = json.load(open(sys.argv[1])); sys.exit(s["time"] != float(sys.argv[2]))' \
      "$TMP/scene.json" "$t"; then
    pass
  else
    fail "scene --time $t: not accepted as the time it is ($(cat "$TMP/err"))"
  fi
done
rm -f "$TMP/tiny.png"
if "$RT64K" render --time 1e-310 --size 8x6 --out "$TMP/tiny.png" && png_ok "$TMP/tiny.png" 8 6; then
  pass
else
  fail "render --time 1e-310"
fi

# Control characters in an argument are escaped in the one error line.
expect_usage_error "newline in a time" scene --time "1
2"
if grep -qF "'1\\n2'" "$TMP/err"; then pass; else fail "newline not escaped"; fi
esc=$(printf '\033]0;title\007\033[31mred')
expect_usage_error "escape sequences in an option" render --time 1 --out "$OUT" "$esc" 1
if grep -qF "'\\x1b]0;title\\x07\\x1b[31mred'" "$TMP/err" && ! grep -q "$(printf '\033')" "$TMP/err"; then
  pass
else
  fail "escape sequence not escaped: $(od -c "$TMP/err" | head -3)"
fi
expect_usage_error "carriage return and tab in a view" render --time 1 --out "$OUT" --view "$(printf 'a\rb\tc')"
if grep -qF "'a\\rb\\tc'" "$TMP/err"; then pass; else fail "CR/tab not escaped"; fi
# UTF-8 text is kept; a byte that is not UTF-8, and a C1 control, are escaped.
expect_usage_error "UTF-8 and bad bytes" scene --time "$(printf 'caf\303\251\377\302\233')"
if grep -qF "'caf$(printf '\303\251')\\xff\\xc2\\x9b'" "$TMP/err"; then pass; else
  fail "UTF-8 handling: $(od -c "$TMP/err" | head -3)"
fi

# audio: a repeated --out is refused like the other commands' repeats, and
# neither file is written.
expect_usage_error "repeated --out (audio)" audio --out "$TMP/a1.wav" --out "$TMP/a2.wav"
if grep -q "given twice" "$TMP/err" && [ ! -e "$TMP/a1.wav" ] && [ ! -e "$TMP/a2.wav" ]; then
  pass
else
  fail "audio --out twice: $(cat "$TMP/err")"
fi
expect_usage_error "repeated --out (sheet)" sheet --out "$TMP/s1.png" --out "$TMP/s2.png"
expect_usage_error "repeated --csv (bench)" bench --csv "$TMP/b1.csv" --csv "$TMP/b2.csv"
expect_usage_error "bench --repeat 0" bench --repeat 0 --csv "$TMP/b.csv"
expect_usage_error "bench --repeat 33" bench --repeat 33 --csv "$TMP/b.csv"
expect_usage_error "bench --repeat x" bench --repeat x --csv "$TMP/b.csv"
# --repeat times each frame more often and changes nothing but the ms
# columns (2 and 3 of the CSV): same error, rays and flicker as one pass.
for n in 1 3; do
  "$RT64K" bench --step 32 --size 40x30 --modes full,adaptive8 --threads 2 --repeat $n \
    --csv "$TMP/r$n.csv" >/dev/null 2>"$TMP/err" || fail "bench --repeat $n: $(tail -1 "$TMP/err")"
  cut -d, -f1,2,5- "$TMP/r$n.csv" >"$TMP/r$n.cut"
done
if [ "$(wc -l <"$TMP/r1.cut")" -eq 5 ] && cmp -s "$TMP/r1.cut" "$TMP/r3.cut"; then
  pass
else
  fail "bench --repeat 3 changed more than the ms columns"
fi
expect_usage_error "audio without a value" audio --out
expect_usage_error "audio, unknown option" audio --out "$TMP/a.wav" --rate 8000

finish cli_test
