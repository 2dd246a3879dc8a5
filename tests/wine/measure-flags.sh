#!/bin/bash
# measure-flags.sh - what each build flag of intro.exe saves or costs, in bytes
# (and, with --bench, in frames per second under Wine). Not a ctest test: it
# rebuilds the MinGW sub-project (src/win32) once per variant, each with one
# flag changed against the shipped set, and prints a Markdown table for
# docs/win32.md.
#
# usage: tests/wine/measure-flags.sh [--bench] [WORK_DIR]   (default /tmp/rt64k-flags)
#        (--bench uses $WINEPREFIX, else build/wine/prefix, else WORK_DIR/prefix)
# needs: cmake, ninja or make, g++-mingw-w64-x86-64; --bench also wine and xvfb-run
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
bench=0
if [ "${1:-}" = --bench ]; then
  bench=1
  shift
fi
work=${1:-/tmp/rt64k-flags}
mkdir -p "$work"
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)

# configure_and_build NAME [-DVAR=VALUE ...]: builds variant NAME and prints
# "FILE_BYTES SECTION_BYTES": the exe's size (a multiple of the 512-byte
# file alignment) and the sum of its sections' sizes (objdump -h), which
# shows changes smaller than 512 bytes.
configure_and_build() {
  local name=$1
  shift
  cmake -S "$root/src/win32" -B "$work/$name" "${generator[@]}" \
    -DCMAKE_TOOLCHAIN_FILE="$root/cmake/mingw-w64-x86_64.cmake" "$@" >"$work/$name.log" 2>&1
  cmake --build "$work/$name" --target intro >>"$work/$name.log" 2>&1 || {
    echo "build of $name failed, see $work/$name.log" >&2
    return 1
  }
  local sections=0 hex
  for hex in $(x86_64-w64-mingw32-objdump -h "$work/$name/intro.exe" | awk '/^ +[0-9]+ / {print $3}'); do
    sections=$((sections + 16#$hex))
  done
  echo "$(stat -c %s "$work/$name/intro.exe") $sections"
}

# cache_list NAME VAR: the value of a list variable in a configured build.
cache_list() { sed -n "s/^$2:STRING=//p" "$work/$1/CMakeCache.txt"; }

# without LIST ITEM...: LIST (;-separated) with the items removed.
without() {
  local list=";$1;"
  shift
  local item
  for item in "$@"; do list=${list//;$item;/;}; done
  list=${list#;}
  echo "${list%;}"
}

# "fps (CPU s)" of /bench for the exe of variant $1 (empty without --bench).
# On a shared machine compare the CPU seconds: wall-clock fps varies with load.
fps() {
  [ $bench = 1 ] || return 0
  local prefix="${WINEPREFIX:-$root/build/wine/prefix}"  # the tests' prefix, if built
  [ -d "$prefix" ] || prefix="$work/prefix"
  (cd "$work/$1" && WINEPREFIX="$prefix" WINEDEBUG=-all xvfb-run -a wine ./intro.exe /bench |
    tr -d '\r' | sed -n 's/.* = \([0-9.]*\) fps, CPU \([0-9.]*\) s/\1 (\2 s)/p')
}

read -r base baseSections < <(configure_and_build shipped)
sizeFlags=$(cache_list shipped RT64K_SIZE_FLAGS)
linkFlags=$(cache_list shipped RT64K_LINK_FLAGS)
baseFps=$(fps shipped)

echo "shipped: $base bytes, sections $baseSections bytes${baseFps:+, /bench $baseFps fps}"
echo
if [ $bench = 1 ]; then
  echo "| variant (one change against the shipped flags) | exe bytes | change | sections bytes | change | /bench fps (CPU s) |"
  echo "|---|---:|---:|---:|---:|---:|"
else
  echo "| variant (one change against the shipped flags) | exe bytes | change | sections bytes | change |"
  echo "|---|---:|---:|---:|---:|"
fi
row() {
  local label=$1 name=$2
  shift 2
  local bytes sections
  read -r bytes sections < <(configure_and_build "$name" "$@") || true
  [ -n "${bytes:-}" ] || return 0
  local line="| $label | $bytes | $((bytes - base)) | $sections | $((sections - baseSections)) |"
  [ $bench = 1 ] && line+=" $(fps "$name") |"
  echo "$line"
}
row "shipped (src/win32 -Os, core -O2 as in flags.cmake)" shipped
row "src/win32 at -O2 instead of -Os" win32_O2 -DRT64K_WIN32_OPT=-O2
row "core (src/core, scenes) at -Os instead of -O2" core_Os -DRT64K_CORE_EXTRA=-Os
# Unwind tables (.pdata) and no --gc-sections keep every function alive.
# (winmm is linked anyway since the music plays; -lwinmm is kept for builds
# with RT64K_MUSIC=0, where audio.cpp is left out.)
row "without -fno-asynchronous-unwind-tables -fno-unwind-tables (+ -lwinmm)" unwind \
  "-DRT64K_SIZE_FLAGS=$(without "$sizeFlags" -fno-asynchronous-unwind-tables -fno-unwind-tables)" \
  -DRT64K_EXTRA_LIBS=winmm
row "without -ffunction-sections -fdata-sections" sections \
  "-DRT64K_SIZE_FLAGS=$(without "$sizeFlags" -ffunction-sections -fdata-sections)"
row "without -fno-ident" ident "-DRT64K_SIZE_FLAGS=$(without "$sizeFlags" -fno-ident)"
row "without -fno-stack-protector" protector \
  "-DRT64K_SIZE_FLAGS=$(without "$sizeFlags" -fno-stack-protector)"
row "with -fmerge-all-constants" merge "-DRT64K_SIZE_FLAGS=$sizeFlags;-fmerge-all-constants"
row "without -s (symbols kept)" strip "-DRT64K_LINK_FLAGS=$(without "$linkFlags" -s)"
row "without -Wl,--gc-sections (+ -lwinmm)" gc \
  "-DRT64K_LINK_FLAGS=$(without "$linkFlags" -Wl,--gc-sections)" -DRT64K_EXTRA_LIBS=winmm
row "without --disable-reloc-section (relocations, ASLR on)" reloc \
  "-DRT64K_LINK_FLAGS=$(without "$linkFlags" -Wl,--disable-reloc-section -Wl,--disable-dynamicbase -Wl,--disable-high-entropy-va)"
# Features (src/win32/switches.h), one switched off at a time.
row "feature off: adaptive renderer (every pixel traced)" no_adaptive -DRT64K_FEATURES=RT64K_ADAPTIVE=0
row "feature off: music (synth, waveOut, winmm, /mute)" no_music -DRT64K_FEATURES=RT64K_MUSIC=0
row "feature off: /f fullscreen" no_fullscreen -DRT64K_FEATURES=RT64K_FULLSCREEN=0
row "feature off: /mute (music kept)" no_mute -DRT64K_FEATURES=RT64K_MUTE=0
row "feature off: /once" no_once -DRT64K_FEATURES=RT64K_ONCE=0
row "feature off: /log" no_log -DRT64K_FEATURES=RT64K_LOG=0
