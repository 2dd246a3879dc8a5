#!/usr/bin/env bash
# Builds everything (native tool and tests, and intro.exe with MinGW) and runs
# every test with ctest, the Wine end-to-end tests included. Installs missing
# Debian packages first. The last line is "N passed, N failed".
set -uo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh test || { echo "0 passed, 1 failed"; exit 1; }
build=${BUILD_DIR:-build}
# In CI a Wine test that cannot run is a failure, not a skip.
required=OFF
[ "${CI:-}" = true ] && required=ON
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DRT64K_WINE_TESTS_REQUIRED=$required >/dev/null ||
  { echo "0 passed, 1 failed"; exit 1; }
cmake --build "$build" -j"$(nproc)" || { echo "0 passed, 1 failed"; exit 1; }
log=$(mktemp)
(cd "$build" && ctest --output-on-failure -j1 "$@") 2>&1 | tee "$log"
status=${PIPESTATUS[0]}
summary=$(grep -E '[0-9]+% tests passed, [0-9]+ tests? failed out of [0-9]+' "$log" | tail -n 1)
rm -f "$log"
if [ -n "$summary" ]; then
  failed=$(echo "$summary" | sed -E 's/.* ([0-9]+) tests? failed out of ([0-9]+).*/\1/')
  total=$(echo "$summary" | sed -E 's/.* failed out of ([0-9]+).*/\1/')
  echo "$((total - failed)) passed, $failed failed"
else
  echo "0 passed, 1 failed"
  status=1
fi
exit "$status"
