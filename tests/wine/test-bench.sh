#!/bin/bash
# wine.bench: `intro.exe /bench` renders its fixed frames, prints one line
# with frames per second (wall clock) and the process's CPU seconds (which a
# busy machine does not inflate) on stdout, writes the same line to rt64k-bench.txt
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
[[ "$line" =~ ^rt64k\ bench:\ ([0-9]+)\ frames\ 800x600\ on\ ([0-9]+)\ threads\ in\ ([0-9.]+)\ s\ =\ ([0-9.]+)\ fps,\ CPU\ ([0-9.]+)\ s$ ]] ||
  fail "stdout is not the bench line: '$line'"
fps=${BASH_REMATCH[4]}
cpu=${BASH_REMATCH[5]}
[ -f "$WORK/rt64k-bench.txt" ] || fail "no rt64k-bench.txt next to the exe"
file=$(tr -d '\r' <"$WORK/rt64k-bench.txt")
[ "$file" = "$line" ] || fail "rt64k-bench.txt ('$file') differs from stdout"
awk -v f="$fps" 'BEGIN {exit !(f > 0)}' || fail "fps is $fps"
echo "BENCH (Wine, $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)): $fps fps, CPU $cpu s"
echo "PASS"
