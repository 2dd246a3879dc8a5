#!/bin/bash
# pack.bad_input: rt64k-pack refuses what the stub cannot load, with a clear
# message and exit code 1, and writes no output file. Each case is intro.exe
# with one thing changed (bytes patched in a copy), or not a PE at all. And
# `check` refuses a damaged packed exe (PACKED_EXE with a byte of its payload
# changed, or cut short) with a message and exit code 1.
#   pack-bad-input.sh RT64K_PACK INTRO_EXE WORK_DIR PACKED_EXE
set -u
readonly tool=$1 exe=$2 work=$3 packed=$4
rm -rf "$work" && mkdir -p "$work" || exit 1
failures=0

# expect NAME INPUT PHRASE: `pack INPUT` exits 1, says PHRASE, writes nothing.
expect() {
  local name=$1 input=$2 phrase=$3 out="$work/$1.s" rc
  "$tool" pack "$input" "$out" >"$work/$name.out" 2>"$work/$name.err"
  rc=$?
  if [ $rc -ne 1 ]; then
    echo "FAIL $name: exit code $rc, expected 1"; failures=$((failures + 1))
  elif ! grep -qF -- "$phrase" "$work/$name.err"; then
    echo "FAIL $name: message '$(cat "$work/$name.err")' lacks '$phrase'"; failures=$((failures + 1))
  elif [ -e "$out" ] || ls "$work" | grep -q '\.tmp'; then
    echo "FAIL $name: an output file was written"; failures=$((failures + 1))
  else
    echo "ok   $name: $(cat "$work/$name.err")"
  fi
}

# patch FILE OFFSET HEXBYTES: overwrites bytes in place.
patch() { printf "$(echo "$3" | sed 's/\(..\)/\\x\1/g')" | dd of="$1" bs=1 seek="$2" conv=notrunc status=none; }
# le32 FILE OFFSET: a little-endian 32-bit field.
le32() { od -An -t u4 -j "$2" -N 4 "$1" | tr -d ' '; }

pe=$(le32 "$exe" 60)
[ "$(od -An -c -j "$pe" -N 2 "$exe" | tr -d ' ')" = PE ] || { echo "FAIL: $exe is not a PE"; exit 1; }

echo "this is not an exe" >"$work/text.exe"
expect not_a_pe "$work/text.exe" "not a PE file"
: >"$work/empty.exe"
expect empty "$work/empty.exe" "not a PE file"
expect missing "$work/no-such.exe" "cannot open"
head -c 1024 "$exe" >"$work/truncated.exe"
expect truncated "$work/truncated.exe" "truncated"
head -c $((pe + 100)) "$exe" >"$work/truncated-header.exe"
expect truncated_header "$work/truncated-header.exe" "truncated"
cp "$exe" "$work/pe32.exe" && patch "$work/pe32.exe" $((pe + 24)) 0b01
expect pe32 "$work/pe32.exe" "PE32 (32-bit) image: only PE32+"
# Characteristics without IMAGE_FILE_RELOCS_STRIPPED (0x0001): 0x022e.
cp "$exe" "$work/relocs.exe" && patch "$work/relocs.exe" $((pe + 22)) 2e02
expect relocations "$work/relocs.exe" "relocations present"
# A base relocation directory (data directory 5) that is not empty.
cp "$exe" "$work/reloc-dir.exe" && patch "$work/reloc-dir.exe" $((pe + 24 + 112 + 5 * 8 + 4)) 08000000
expect relocation_directory "$work/reloc-dir.exe" "relocations present"
# A TLS directory (data directory 9).
cp "$exe" "$work/tls.exe" && patch "$work/tls.exe" $((pe + 24 + 112 + 9 * 8)) 0010000028000000
expect tls "$work/tls.exe" "TLS directory is present"
# The first section moved to RVA 0x2000.
sections=$((pe + 24 + $(od -An -t u2 -j $((pe + 20)) -N 2 "$exe" | tr -d ' ')))
cp "$exe" "$work/layout.exe" && patch "$work/layout.exe" $((sections + 12)) 00200000
expect section_layout "$work/layout.exe" "expected 4096"
# Another machine (i386).
cp "$exe" "$work/i386.exe" && patch "$work/i386.exe" $((pe + 4)) 4c01
expect machine "$work/i386.exe" "not an x86-64 image"

# check: a packed exe that is not ours (intro.exe itself) is refused.
"$tool" check "$exe" "$exe" >"$work/check.out" 2>"$work/check.err"
rc=$?
if [ $rc -ne 1 ] || ! grep -qF "expected 2" "$work/check.err"; then
  echo "FAIL check_not_packed: exit $rc, '$(cat "$work/check.err")'"; failures=$((failures + 1))
else
  echo "ok   check_not_packed: $(cat "$work/check.err")"
fi
# expect_check NAME PACKED PHRASE: `check intro.exe PACKED` exits 1, says PHRASE.
expect_check() {
  local name=$1 input=$2 phrase=$3 rc
  "$tool" check "$exe" "$input" >"$work/$name.out" 2>"$work/$name.err"
  rc=$?
  if [ $rc -ne 1 ] || ! grep -qF -- "$phrase" "$work/$name.err"; then
    echo "FAIL $name: exit $rc, '$(cat "$work/$name.err")' (expected 1, '$phrase')"
    failures=$((failures + 1))
  else
    echo "ok   $name: $(cat "$work/$name.err")"
  fi
}
# The payload starts at file offset 512 (the record, 16 bytes, then the
# encoded image): a byte 1000 bytes into it flipped decodes to other bytes.
cp "$packed" "$work/flipped.exe" && patch "$work/flipped.exe" $((512 + 16 + 1000)) 5a
cmp -s "$packed" "$work/flipped.exe" || expect_check damaged_payload "$work/flipped.exe" "not the encoding"
# size14's header layout (rt64k-pack finish): the decoder's 0F-opcode table
# at 0x1c0 and the import directory in the headers (its data directory
# entry at 0xd0: the PE header at 0x40, the optional header at 0x58).
cp "$packed" "$work/table.exe" && patch "$work/table.exe" $((0x1c1)) 55
expect_check header_table "$work/table.exe" "0F-opcode table"
cp "$packed" "$work/importdir.exe" && patch "$work/importdir.exe" $((0xd0)) 00500000
expect_check import_directory "$work/importdir.exe" "not in its headers"
head -c 4096 "$packed" >"$work/short.exe"
expect_check truncated_packed "$work/short.exe" "truncated"
# No arguments: usage, exit 2.
"$tool" >/dev/null 2>&1
rc=$?
[ $rc -eq 2 ] || { echo "FAIL usage: exit $rc, expected 2"; failures=$((failures + 1)); }

echo "$failures failure(s)"
[ $failures -eq 0 ]
