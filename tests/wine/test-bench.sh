#!/bin/bash
# wine.bench: `intro.exe /bench` renders its fixed frames, prints one line
# with frames per second (wall clock), the slowest frame in milliseconds and
# the process's CPU seconds (which a busy machine does not inflate) on stdout, writes the same line to rt64k-bench.txt
# next to the exe, and exits with code 0.
source "$(dirname "$0")/common.sh"
readonly kBenchTimeoutSeconds=300
setup
t0=$(now_ms)
(cd "$WORK" && timeout $kBenchTimeoutSeconds "$WINE" ./intro.exe /bench >"$WORK/intro.out" 2>"$WORK/intro.err")
rc=$?
echo "intro.exe /bench: exit code $rc after $(($(now_ms) - t0)) ms (wall, including Wine start-up)"
[ "$rc" = 0 ] || fail "exit code $rc, expected 0 (124: timed out after $kBenchTimeoutSeconds s)"
line=$(tr -d '\r' <"$WORK/intro.out")
echo "stdout: $line"
[[ "$line" =~ ^rt64k\ bench:\ ([0-9]+)\ frames\ 800x600\ on\ ([0-9]+)\ threads\ in\ ([0-9.]+)\ s\ =\ ([0-9.]+)\ fps,\ slowest\ ([0-9.]+)\ ms,\ CPU\ ([0-9.]+)\ s$ ]] ||
  fail "stdout is not the bench line: '$line'"
frames=${BASH_REMATCH[1]}
seconds=${BASH_REMATCH[3]}
fps=${BASH_REMATCH[4]}
slowest=${BASH_REMATCH[5]}
cpu=${BASH_REMATCH[6]}
[ -f "$WORK/rt64k-bench.txt" ] || fail "no rt64k-bench.txt next to the exe"
file=$(tr -d '\r' <"$WORK/rt64k-bench.txt")
[ "$file" = "$line" ] || fail "rt64k-bench.txt ('$file') differs from stdout"
awk -v f="$fps" 'BEGIN {exit !(f > 0)}' || fail "fps is $fps"
# The slowest frame lies between the mean frame time (the frames fill the
# timed span but for a few microseconds of loop between them: at least
# kMeanShare of it) and the whole span.
readonly kMeanShare=0.9
awk -v n="$frames" -v s="$seconds" -v w="$slowest" -v k=$kMeanShare 'BEGIN {
  printf "slowest frame %.2f ms; mean %.2f ms; whole run %.0f ms\n", w, 1000 * s / n, 1000 * s
  exit !(w >= k * 1000 * s / n && w <= 1000 * s) }' ||
  fail "the slowest frame ($slowest ms) is not between the mean frame and the whole run"
echo "BENCH (Wine, $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)): $fps fps, slowest $slowest ms, CPU $cpu s"
echo "PASS"
