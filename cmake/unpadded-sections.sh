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
# With --data first (the packer's stub, src/pack: its constants are byte
# tables), each constant's section (.rdata$NAME) gets an alignment of 2^0
# too: GNU as padded the decoder's 4- and 7-byte tables to 16 bytes each
# (docs/win32.md "Round eight: the shipped exe under the next step"). A
# constant that needs alignment still says so with its own .align, which
# raises its section's.
set -euo pipefail
data=0
if [ "${1:-}" = --data ]; then
  data=1
  shift
fi
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
if [ "$data" = 1 ]; then
  sed -i -E 's/^([[:space:]]*\.section[[:space:]]+\.rdata\$[^,]*),"dr"$/\1,"dr0"/' "$asm"
fi
# The compiler's own assembler, as the driver would run it.
"${args[0]}" -c -x assembler -o "$out" "$asm"
rm -f "$asm"
