# check-lib.sh - what the shell test scripts (cli_test.sh, output_test.sh)
# share; sourced with `.` after they set RT64K. Gives TMP (a fresh folder,
# removed at exit), fail MESSAGE (counts a failure and prints it), pass
# (counts a passed check) and finish NAME (prints the counts; its status is
# the script's: 0 when nothing failed).
set -u
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
checks=0
failures=0

fail() {
  failures=$((failures + 1))
  echo "FAIL: $*"
}
pass() { checks=$((checks + 1)); }

finish() {
  echo "$1: $checks checks passed, $failures failed"
  [ "$failures" -eq 0 ]
}
