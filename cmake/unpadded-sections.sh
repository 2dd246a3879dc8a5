#!/bin/bash
# unpadded-sections.sh - compiler launcher of intro.exe's sub-build
# (src/win32/CMakeLists.txt, RT64K_UNPADDED_SECTIONS): runs the compile
# command it is given, except that an object compiled without LTO (the hot
# core, crt.cpp) is compiled to assembly first and every function's section
# (.text$NAME, from -ffunction-sections) is given an alignment of 2^0 ("x0",
# the COFF section flag GNU as reads as a power-of-two alignment) before it
# is assembled. GNU as aligns each PE section to 16 bytes and pads its end
# to 16 by default, whatever -falign-functions=1 says, so every hot function
# carried up to 15 bytes of nops (docs/win32.md "Round four"). The code is
# the same instructions; the native (ELF) build has no such padding anyway.
# LTO compiles (GIMPLE, no assembly) and everything else run unchanged.
set -euo pipefail
args=("$@")
lto=0
out=""
for ((i = 0; i < ${#args[@]}; i++)); do
  case "${args[$i]}" in
  -flto) lto=1 ;;
  -fno-lto) lto=0 ;;
  -o) out=${args[$((i + 1))]:-} ;;
  esac
done
if [ "$lto" = 1 ] || [ -z "$out" ]; then exec "$@"; fi
asm="$out.unpadded.s"
compile=()
for ((i = 0; i < ${#args[@]}; i++)); do
  case "${args[$i]}" in
  -c) compile+=(-S) ;;
  -o)
    compile+=(-o "$asm")
    i=$((i + 1))
    ;;
  *) compile+=("${args[$i]}") ;;
  esac
done
"${compile[@]}"
# Only the function sections' directives: .section .text$NAME,"x"
sed -i -E 's/^([[:space:]]*\.section[[:space:]]+\.text\$[^,]*),"x"$/\1,"x0"/' "$asm"
# The compiler's own assembler, as the driver would run it.
"${args[0]}" -c -x assembler -o "$out" "$asm"
rm -f "$asm"
