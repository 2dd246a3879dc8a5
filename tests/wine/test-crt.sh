#!/bin/bash
# wine.crt: crt_probe.exe (tests/wine/crt_probe.cpp) exits 0: the project's
# memset, memcpy, sqrtf, sqrt and ___chkstk_ms (src/win32/crt.cpp) work
# without the C runtime. The exit code's bits name the failed checks:
# 1 stack probe, 2 memset, 4 memcpy, 8 sqrt.
source "$(dirname "$0")/common.sh"
: "${RT64K_CRT_PROBE_EXE:?set by ctest}"
setup
cp "$RT64K_CRT_PROBE_EXE" "$WORK/crt_probe.exe"
(cd "$WORK" && timeout 60 "$WINE" ./crt_probe.exe)
rc=$?
echo "crt_probe.exe: exit code $rc"
[ "$rc" = 0 ] || fail "crt_probe.exe exit code $rc (bits: 1 stack, 2 memset, 4 memcpy, 8 sqrt)"
echo "PASS"
