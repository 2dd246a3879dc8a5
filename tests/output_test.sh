#!/bin/sh
# output_test.sh - every file rt64k writes appears whole or not at all, and no
# name it is given is ever run (ctest: output). Usage: output_test.sh path/to/rt64k
#
# For each output (render --out, sheet --out, audio --out, bench --csv, bench
# --plot): hostile names land under their exact names and run nothing; a write
# failing on a file-size limit (ulimit -f, SIGXFSZ ignored) exits 2 with one
# line and leaves the old file byte for byte and no temporary; a kill during
# the write (RT64K_TEST_STOP_IN_WRITE stops the tool inside it) leaves the old
# file and no temporary. Devices: a copy of /dev/full (mknod, as root) and then
# /dev/full itself exit 2 and stay device nodes; /dev/null and FIFOs are
# written in place; block devices, sockets, dangling links are refused. Paths
# are checked before the work (under a memory limit the work cannot even
# start). gnuplot runs with no arguments, its errors come back in one line.
# stdout on /dev/full exits 2. Needs python3 (standard library only).
set -u
ulimit -c 0 # SIGQUIT below must leave no core file in the folders it checks
RT64K=${1:?usage: output_test.sh path/to/rt64k}
case $RT64K in /*) ;; *) RT64K=$(pwd)/$RT64K ;; esac
. "$(dirname "$0")/check-lib.sh"
is_root() { [ "$(id -u)" -eq 0 ]; }

SIDE_CSV=$TMP/side.csv # the CSV of bench runs whose --plot is under test
BENCH="bench --step 32 --size 16x12 --modes full,adaptive8 --scaling off --threads 2"

# run KIND OUT: the command that writes OUT as its output of kind KIND,
# prefixed by the words in $PRE (e.g. "exec env ...").
PRE=
# shellcheck disable=SC2086
run() {
  case $1 in
  render) $PRE "$RT64K" render --time 3 --size 64x48 --threads 2 --out "$2" ;;
  sheet) $PRE "$RT64K" sheet --threads 2 --out "$2" ;;
  audio) $PRE "$RT64K" audio --out "$2" ;;
  csv) $PRE "$RT64K" $BENCH --csv "$2" ;;
  plot) $PRE "$RT64K" $BENCH --csv "$SIDE_CSV" --plot "$2" ;;
  esac
}

# valid KIND FILE [DIR NAME]: FILE is a whole output of KIND (PNG chunks and
# CRCs and size, WAV header and length, CSV rows); with DIR and NAME, DIR also
# holds NAME and nothing else (one python start for both: the machine is slow).
valid() {
  python3 - "$@" <<'EOF'
import os, struct, sys, zlib
kind, path = sys.argv[1], sys.argv[2]
if len(sys.argv) > 3:
    names = os.listdir(sys.argv[3])
    assert names == [sys.argv[4]], 'folder holds %r' % names
data = open(path, 'rb').read()
if kind in ('render', 'sheet', 'plot'):
    w, h = {'render': (64, 48), 'sheet': (980, 740), 'plot': (900, 600)}[kind]
    assert data[:8] == b'\x89PNG\r\n\x1a\n', 'signature'
    pos, idat, kinds = 8, b'', []
    while pos < len(data):
        n, k = struct.unpack('>I4s', data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        assert zlib.crc32(k + body) & 0xffffffff == struct.unpack('>I', data[pos + 8 + n:pos + 12 + n])[0]
        kinds.append(k)
        if k == b'IHDR':
            assert struct.unpack('>II', body[:8]) == (w, h), 'size'
        if k == b'IDAT':
            idat += body
        pos += 12 + n
    assert kinds[0] == b'IHDR' and kinds[-1] == b'IEND' and pos == len(data)
    zlib.decompress(idat)
elif kind == 'audio':
    assert data[:4] == b'RIFF' and data[8:16] == b'WAVEfmt '
    assert struct.unpack('<I', data[4:8])[0] == len(data) - 8
    assert struct.unpack('<I', data[40:44])[0] == 64 * 44100 * 4 == len(data) - 44
elif kind == 'csv':
    lines = data.decode().splitlines()
    assert lines[0].startswith('time,mode,ms,'), 'header'
    assert len(lines) == 1 + 2 * 2, '%d lines' % len(lines)
EOF
}

# only_names DIR NAME...: DIR holds exactly these names (no temporary, no canary).
only_names() {
  python3 -c 'import os, sys; sys.exit(sorted(os.listdir(sys.argv[1])) != sorted(sys.argv[2:]))' "$@"
}

# A whole old output of each kind, to be kept intact.
mkdir "$TMP/old"
for kind in render sheet audio csv plot; do
  run $kind "$TMP/old/$kind" >/dev/null 2>&1 || fail "$kind: cannot make a reference output"
  valid $kind "$TMP/old/$kind" || fail "$kind: reference output not valid"
done
# The old file to protect must differ from what the next run writes: for the
# render, an earlier frame; for the others, the same bytes are still compared
# byte for byte against a copy, which is what "intact" means.
"$RT64K" render --time 9 --size 64x48 --threads 2 --out "$TMP/old/render" || fail "old render"

# ---- 1. hostile names: written under the exact name, nothing run ----------
nl='
'
ALL_IN_ONE="-a b'c\"d;touch CANARY;\$(touch CANARY)\`touch CANARY\`${nl}e|f<g"
for kind in render sheet audio csv plot; do
  names="ALL_IN_ONE"
  case $kind in render | csv | plot) names="ALL_IN_ONE QUOTE SEMI SUBST NEWLINE DASH SPACE GNU PIPE LT" ;; esac
  for which in $names; do
    case $which in
    ALL_IN_ONE) name=$ALL_IN_ONE ;;
    QUOTE) name="it's \"here\".out" ;;
    SEMI) name="x';touch CANARY;'.out" ;;
    SUBST) name="\$(touch CANARY)\`touch CANARY\`.out" ;;
    NEWLINE) name="two${nl}lines.out" ;;
    DASH) name="--help" ;;
    SPACE) name=" lead and trail " ;;
    GNU) name="p'; system('touch CANARY'); print '.out" ;;
    PIPE) name="|touch CANARY" ;;
    LT) name="<touch CANARY" ;;
    esac
    d=$TMP/hostile
    rm -rf "$d" && mkdir "$d"
    (cd "$d" && run $kind "$name" >"$TMP/out" 2>"$TMP/err" </dev/null)
    code=$?
    if [ $code -ne 0 ]; then
      fail "$kind, name $which: exit code $code ($(tail -1 "$TMP/err"))"
    elif ! valid $kind "$d/$name" "$d" "$name" 2>"$TMP/py"; then
      fail "$kind, name $which: $(tail -1 "$TMP/py")"
    elif [ $which = NEWLINE ] && { grep -q '^lines.out' "$TMP/out" ||
      { [ $kind = csv ] && ! grep -q '^CSV: two\\nlines.out$' "$TMP/out"; }; }; then
      fail "$kind, name $which: name printed raw on stdout: $(cat "$TMP/out")"
    else
      pass
    fi
  done
done
# The issue's two injections at once, through the real gnuplot: a --csv name
# that broke out of the shell command, a --plot name that broke out of the
# gnuplot script.
# hostile_pair CSV PNG: both land under their names, whole, and nothing runs.
hostile_pair() {
  d=$TMP/hostile
  rm -rf "$d" && mkdir "$d"
  # shellcheck disable=SC2086
  if ! (cd "$d" && "$RT64K" $BENCH --csv "$1" --plot "$2" >/dev/null 2>"$TMP/err" </dev/null); then
    fail "bench with hostile --csv and --plot: $(tail -1 "$TMP/err")"
  elif ! only_names "$d" "$1" "$2"; then
    fail "bench with hostile --csv and --plot: folder holds $(ls -A "$d" | tr '\n' '/')"
  elif ! valid csv "$d/$1" || ! valid plot "$d/$2"; then
    fail "bench with hostile --csv and --plot: outputs not whole"
  else
    pass
  fi
}
hostile_pair "x';touch CANARY;'.csv" "p'; system('touch CANARY'); print '.png"
hostile_pair "$ALL_IN_ONE.csv" "$ALL_IN_ONE.png"
[ -e CANARY ] && fail "a CANARY appeared in $(pwd)"

# ---- 2. a write over the file-size limit ----------------------------------
# ulimit -f in the subshell only; stderr through a pipe (the limit would stop
# the message itself from reaching a file). A limit of 0 fails the first write;
# for the plot, 8 blocks (dash: 512 bytes each) let the CSV through and stop
# gnuplot's PNG.
for kind in render sheet audio csv plot; do
  d=$TMP/limit
  rm -rf "$d" && mkdir "$d"
  cp "$TMP/old/$kind" "$d/target"
  limit=0
  [ $kind = plot ] && limit=8
  err=$( (
    ulimit -f $limit
    trap '' XFSZ
    cd "$d" && run $kind target 2>&1 >/dev/null
  ))
  code=$?
  lines=$(printf '%s\n' "$err" | grep -c '^rt64k:')
  others=$(printf '%s\n' "$err" | grep -v '^bench: frame' | grep -vc '^rt64k:')
  if [ $code -ne 2 ]; then
    fail "$kind over ulimit -f $limit: exit code $code, wanted 2"
  elif [ "$lines" -ne 1 ] || [ "$others" -ne 0 ]; then
    fail "$kind over ulimit -f $limit: wanted one error line, got: $err"
  elif ! printf '%s' "$err" | grep -q 'File too large\|File size limit exceeded'; then
    fail "$kind over ulimit -f $limit: the line does not name the cause: $err"
  elif ! cmp -s "$d/target" "$TMP/old/$kind"; then
    fail "$kind over ulimit -f $limit: the old file changed"
  elif ! only_names "$d" target; then
    fail "$kind over ulimit -f $limit: left $(ls -A "$d" | tr '\n' ' ')"
  else
    pass
  fi
done

# ---- 3. killed during the write -------------------------------------------
# stopped_in_write PID: waits (up to 15 s) until PID is stopped (T).
stopped_in_write() {
  i=0
  while [ $i -lt 150 ]; do
    state=$(cut -d' ' -f3 "/proc/$1/stat" 2>/dev/null) || return 1
    [ "$state" = T ] && return 0
    sleep 0.1
    i=$((i + 1))
  done
  return 1
}
for case_ in render:TERM render:INT render:HUP sheet:TERM audio:TERM audio:INT csv:TERM \
  csv:INT plot:TERM plot:QUIT render:KILL; do
  kind=${case_%%:*}
  sig=${case_#*:}
  d=$TMP/kill
  rm -rf "$d" && mkdir "$d"
  cp "$TMP/old/$kind" "$d/target"
  # Background jobs of a non-interactive shell start with SIGINT and SIGQUIT
  # ignored (and rt64k keeps what it inherits ignored): env restores them.
  (cd "$d" && export RT64K_TEST_STOP_IN_WRITE=target && PRE="exec env --default-signal=INT,QUIT" &&
    run $kind target >/dev/null 2>&1) &
  pid=$!
  # The subshell execs env, which execs rt64k: one pid.
  if ! stopped_in_write $pid; then
    fail "$kind: never stopped inside its write"
    kill -KILL $pid 2>/dev/null
    wait $pid 2>/dev/null
    continue
  fi
  temps=$(ls -A "$d" | grep -c '^\.target\.rt64k-')
  kill -$sig $pid
  kill -CONT $pid 2>/dev/null
  wait $pid
  code=$?
  case $sig in HUP) num=1 ;; INT) num=2 ;; QUIT) num=3 ;; KILL) num=9 ;; TERM) num=15 ;; esac
  want=$((128 + num))
  if [ "$temps" -ne 1 ]; then
    fail "$kind, SIG$sig: $temps temporaries while stopped in the write, wanted 1"
  elif [ $code -ne $want ]; then
    fail "$kind, SIG$sig: exit status $code, wanted $want (killed by the signal)"
  elif ! cmp -s "$d/target" "$TMP/old/$kind"; then
    fail "$kind, SIG$sig: the old file changed"
  elif [ $sig = KILL ]; then
    # SIGKILL cannot be caught: the old file is intact, the temporary stays.
    if [ "$(ls -A "$d" | grep -c '^\.target\.rt64k-')" -eq 1 ]; then pass; else
      fail "$kind, SIGKILL: expected the uncatchable kill to leave its temporary"
    fi
  elif ! only_names "$d" target; then
    fail "$kind, SIG$sig: left $(ls -A "$d" | tr '\n' ' ')"
  else
    pass
  fi
done

# Interrupted while measuring (3 s of CPU at least): the CSV's temporary,
# open since the start, goes; the old CSV stays.
d=$TMP/midbench
mkdir "$d"
cp "$TMP/old/csv" "$d/target"
env --default-signal=INT "$RT64K" bench --step 0.25 --size 160x120 --modes full --scaling off \
  --threads 1 --csv "$d/target" >/dev/null 2>&1 &
pid=$!
sleep 0.5
temps=$(ls -A "$d" | grep -c '^\.target\.rt64k-')
kill -INT $pid
wait $pid
code=$?
if [ "$temps" -eq 1 ] && [ $code -eq 130 ] && cmp -s "$d/target" "$TMP/old/csv" &&
  only_names "$d" target; then
  pass
else
  fail "bench interrupted mid-run: $temps temporaries, exit $code, left $(ls -A "$d" | tr '\n' ' ')"
fi

# Kills at arbitrary moments (audio: 0.1 to 1.5 s spans its synth and its
# 11-MB write): the target is always the old file or a whole new one, and no
# temporary stays.
d=$TMP/anytime
mkdir "$d"
for delay in 0.1 0.4 0.7 0.8 0.9 1.2; do
  cp "$TMP/old/audio" "$d/target"
  # A distinct old file: the new one must be whole, or else the old one.
  printf 'old' >>"$d/target"
  cp "$d/target" "$TMP/old-anytime"
  env --default-signal=INT "$RT64K" audio --out "$d/target" >/dev/null 2>&1 &
  pid=$!
  sleep $delay
  kill -INT $pid 2>/dev/null
  wait $pid
  if ! only_names "$d" target; then
    fail "audio killed after $delay s: left $(ls -A "$d" | tr '\n' ' ')"
  elif cmp -s "$d/target" "$TMP/old-anytime" || valid audio "$d/target" 2>/dev/null; then
    pass
  else
    fail "audio killed after $delay s: the target is neither the old file nor a whole new one"
  fi
done

# ---- 4. devices, FIFOs, sockets, links --------------------------------------
# is_chr PATH MAJOR MINOR: PATH is still that character device.
is_chr() {
  [ -c "$1" ] && [ "$(stat -c '%t:%T' "$1")" = "$(printf '%x:%x' "$2" "$3")" ]
}
# expect_error WHAT PATTERN CMD...: exit 2, one stderr line matching PATTERN
# (bench progress lines aside).
expect_error() {
  what=$1
  pattern=$2
  shift 2
  "$@" >"$TMP/out" 2>"$TMP/err" </dev/null
  code=$?
  grep -v '^bench: frame' "$TMP/err" >"$TMP/err1"
  if [ $code -ne 2 ]; then
    fail "$what: exit code $code, wanted 2"
  elif [ "$(wc -l <"$TMP/err1")" -ne 1 ]; then
    fail "$what: $(wc -l <"$TMP/err1") error lines, wanted 1: $(cat "$TMP/err1")"
  elif ! grep -q "$pattern" "$TMP/err1"; then
    fail "$what: '$(cat "$TMP/err1")' does not say '$pattern'"
  else
    pass
  fi
}

d=$TMP/dev
mkdir "$d"
copy_ok=no
if is_root && mknod "$d/full" c 1 7 2>/dev/null && mknod "$d/null" c 1 3 2>/dev/null; then
  copy_ok=yes
  for kind in render sheet audio csv; do
    expect_error "$kind to a copy of /dev/full" 'No space left on device' run $kind "$d/full"
    if is_chr "$d/full" 1 7; then pass; else
      fail "$kind: the /dev/full copy is no longer that device"
      copy_ok=no
    fi
    if run $kind "$d/null" >/dev/null 2>&1 && is_chr "$d/null" 1 3; then pass; else
      fail "$kind to a copy of /dev/null: not exit 0 with the node kept"
      copy_ok=no
    fi
  done
  if run plot "$d/null" >/dev/null 2>&1 && is_chr "$d/null" 1 3; then pass; else
    fail "plot to a copy of /dev/null"
  fi
  expect_error "plot to a copy of /dev/full" 'gnuplot\|No space' run plot "$d/full"
  if is_chr "$d/full" 1 7; then pass; else fail "plot: the /dev/full copy changed"; fi
  # A block device (0:0, no driver: even a write would go nowhere) is refused.
  if mknod "$d/blk" b 0 0 2>/dev/null; then
    expect_error "render to a block device" 'block device' run render "$d/blk"
    [ -b "$d/blk" ] && pass || fail "the block device node changed"
  else
    fail "mknod of a block device failed as root"
  fi
elif is_root; then
  fail "mknod failed as root: device copies not tested"
else
  echo "note: not root, device-node copies not tested"
fi
# /dev/full itself, only once its copy came through unharmed.
if [ $copy_ok = yes ] || ! is_root; then
  if is_chr /dev/full 1 7; then
    for kind in render csv audio; do
      expect_error "$kind to /dev/full" 'No space left on device' run $kind /dev/full
      if is_chr /dev/full 1 7; then pass; else fail "$kind removed or replaced /dev/full"; fi
    done
  fi
fi
# stdout on /dev/full: the lost output is an error.
expect_error "scene > /dev/full" 'standard output: No space left' \
  sh -c '"$0" scene --time 1 >/dev/full' "$RT64K"
expect_error "--help > /dev/full" 'standard output' sh -c '"$0" --help >/dev/full' "$RT64K"
expect_error "bench table > /dev/full" 'standard output' \
  sh -c '"$0" '"$BENCH"' --csv "$1" >/dev/full' "$RT64K" "$TMP/dev/table.csv"
# /dev/stdout is a link to /proc/self/fd/1; the same link made here keeps any
# harm in this folder.
ln -s /proc/self/fd/1 "$d/stdout"
expect_error "render --out stdout > /dev/full" 'No space left' \
  sh -c '"$0" render --time 1 --size 8x6 --out "$1" >/dev/full' "$RT64K" "$d/stdout"

# A FIFO is written in place, whole.
mkfifo "$d/fifo"
cat "$d/fifo" >"$d/from-fifo.png" &
reader=$!
if run render "$d/fifo" >/dev/null 2>&1 && wait $reader && valid render "$d/from-fifo.png" &&
  [ -p "$d/fifo" ]; then pass; else fail "render to a FIFO"; fi
# stdout on a pipe is a FIFO.
if "$RT64K" render --time 3 --size 64x48 --threads 2 --out "$d/stdout" | cat >"$d/piped.png" &&
  valid render "$d/piped.png"; then pass; else fail "render --out /dev/stdout | cat"; fi
# A socket and a dangling link are refused; a link to a file replaces the file.
python3 -c 'import socket, sys; socket.socket(socket.AF_UNIX).bind(sys.argv[1])' "$d/sock"
expect_error "render to a socket" 'not a regular file' run render "$d/sock"
ln -s "$d/nothing-here" "$d/dangling"
expect_error "render to a dangling link" 'symbolic link to nothing' run render "$d/dangling"
[ -L "$d/dangling" ] && [ ! -e "$d/nothing-here" ] && pass || fail "dangling link changed"
mkdir "$d/real"
cp "$TMP/old/render" "$d/real/frame.png"
chmod 640 "$d/real/frame.png"
ln -s real/frame.png "$d/link.png"
if run render "$d/link.png" >/dev/null 2>&1 && [ -L "$d/link.png" ] &&
  [ "$(readlink "$d/link.png")" = real/frame.png ] && valid render "$d/real/frame.png" &&
  ! cmp -s "$d/real/frame.png" "$TMP/old/render" &&
  [ "$(stat -c %a "$d/real/frame.png")" = 640 ] && only_names "$d/real" frame.png; then
  pass
else
  fail "render through a link: the link must stay, the file it names replaced (mode kept)"
fi
expect_error "render to a path ending in /" 'names a folder' run render "$d/real/"
expect_error "render to an empty path" 'empty' run render ""
expect_error "render under a file" 'Not a directory' run render "$d/real/frame.png/x.png"
if ! is_root; then
  mkdir "$d/ro" && chmod 555 "$d/ro"
  expect_error "render into a read-only folder" 'not writable' run render "$d/ro/x.png"
fi

# ---- 5. paths checked before any work ---------------------------------------
# Under a 400-MB address-space limit a 16384x16384 frame (1 GiB) cannot even
# be allocated: the path error must come first.
expect_error "render: bad folder before the frame" "nothing-here" sh -c \
  'ulimit -v 400000; exec "$0" render --time 1 --size 16384x16384 --out "$1"' \
  "$RT64K" "$TMP/nothing-here/x.png"
expect_error "bench: bad --csv folder before the bench" "nothing-here" sh -c \
  'ulimit -v 400000; exec "$0" bench --size 16384x16384 --csv "$1"' "$RT64K" "$TMP/nothing-here/b.csv"
expect_error "bench: bad --plot folder before the bench" "nothing-here" sh -c \
  'ulimit -v 400000; exec "$0" bench --size 16384x16384 --csv "$1" --plot "$2"' \
  "$RT64K" "$TMP/b.csv" "$TMP/nothing-here/b.png"
[ -e "$TMP/b.csv" ] && fail "a bench refused for its --plot wrote its CSV" || pass
expect_error "bench: --plot is a folder" "is a folder" "$RT64K" $BENCH --csv "$TMP/b.csv" --plot "$TMP"
expect_error "bench: --csv and --plot the same" "same file" \
  "$RT64K" $BENCH --csv "$TMP/same" --plot "$TMP/same"
expect_error "bench: no gnuplot in PATH, before the bench" "not in PATH" sh -c \
  'ulimit -v 400000; PATH=$3 exec "$0" bench --size 16384x16384 --csv "$1" --plot "$2"' \
  "$RT64K" "$TMP/b.csv" "$TMP/b.png" "$TMP/empty-path"
expect_error "sheet: bad folder" "nothing-here" "$RT64K" sheet --out "$TMP/nothing-here/s.png"
cp "$TMP/old/audio" "$TMP/keep.wav"
expect_error "audio: bad folder" "nothing-here" "$RT64K" audio --out "$TMP/nothing-here/a.wav"

# ---- 6. gnuplot: no arguments, no user string, its error in one line --------
fake=$TMP/fakebin
mkdir "$fake"
# A gnuplot that records its arguments and script, then fails like gnuplot.
cat >"$fake/gnuplot" <<EOF
#!/bin/sh
printf '%s\n' "\$#" >"$TMP/fake-argc"
/bin/cat >"$TMP/fake-stdin"
echo 'gnuplot> plot foo(x)' >&2
echo '                   ^' >&2
echo '         line 0: undefined function: foo' >&2
echo >&2
exit 1
EOF
chmod +x "$fake/gnuplot"
d=$TMP/gp
mkdir "$d"
cp "$TMP/old/plot" "$d/p'; system('touch CANARY'); print '.png"
ORIG=$(pwd)
cd "$d" && expect_error "a failing gnuplot" '^rt64k: gnuplot failed (exit code 1): line 0: undefined function: foo' \
  env PATH="$fake" "$RT64K" $BENCH --csv "x';touch CANARY;'.csv" --plot "p'; system('touch CANARY'); print '.png"
cd "$ORIG" || exit 1
if grep -qi install "$TMP/err1"; then fail "advice to install gnuplot, which is installed"; else pass; fi
if [ "$(cat "$TMP/fake-argc")" = 0 ]; then pass; else fail "gnuplot got $(cat "$TMP/fake-argc") arguments"; fi
if grep -q "CANARY\|system\|$TMP\|set output" "$TMP/fake-stdin" || ! grep -q '^plot \$modes' "$TMP/fake-stdin"; then
  fail "gnuplot's script holds a path or lacks the plot: $(cat "$TMP/fake-stdin")"
else
  pass
fi
if cmp -s "$d/p'; system('touch CANARY'); print '.png" "$TMP/old/plot" &&
  only_names "$d" "p'; system('touch CANARY'); print '.png" "x';touch CANARY;'.csv"; then
  pass
else
  fail "a failing gnuplot: old plot changed or files left: $(ls -A "$d" | tr '\n' ' ')"
fi
# A gnuplot that exits 0 with half a PNG; one killed by a signal.
printf '#!/bin/sh\nhead -c 100 "%s"\nexit 0\n' "$TMP/old/plot" >"$fake/gnuplot"
expect_error "gnuplot with half a PNG" 'no complete PNG' \
  env PATH="$fake" "$RT64K" $BENCH --csv "$SIDE_CSV" --plot "$d/half.png"
[ -e "$d/half.png" ] && fail "half a PNG was kept" || pass
printf '#!/bin/sh\nkill -SEGV $$\n' >"$fake/gnuplot"
expect_error "gnuplot killed" 'killed by signal 11' \
  env PATH="$fake" "$RT64K" $BENCH --csv "$SIDE_CSV" --plot "$d/killed.png"
[ -e CANARY ] || [ -e "$d/CANARY" ] && fail "a CANARY appeared" || pass

finish output_test
