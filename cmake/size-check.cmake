# size-check: intro.exe's size, unpacked and packed, against the project's
# budget and hard limit.
#   cmake -DEXE=intro.exe -DOBJDUMP=x86_64-w64-mingw32-objdump
#         [-DUPX=/path/to/upx -DPACKED=intro-upx.exe]
#         [-DOURS=intro-packed.exe -DPACK_TOOL=rt64k-pack]
#         [-DSHIPPED=intro-shipped.exe -DSHIPPED_NOTE=intro-shipped.txt]
#         -P cmake/size-check.cmake
# Prints the unpacked exe's bytes and sections (objdump -h); where UPX was
# found, UPX's packed exe's bytes and the UPX version; our own packer's exe's
# bytes and parts (`rt64k-pack check`, which also decodes it natively and
# compares it with intro.exe); and which packed exe ships (the smaller).
# Fails above the 65,536-byte limit on any of them; the budget (16,384, and
# the 20,480 of the thesis's packed intro) is judged on the shipped exe, and
# only warns.
set(kBudgetBytes 16384)
set(kLimitBytes 65536)
set(kTargetBytes 20480) # the thesis's intro after UPX (no music, no captions)

if(NOT EXISTS "${EXE}")
  message(FATAL_ERROR "size-check: ${EXE} does not exist (build the intro_exe target first)")
endif()
file(SIZE "${EXE}" exeBytes)
file(TIMESTAMP "${EXE}" exeTime "%s" UTC)

execute_process(COMMAND "${OBJDUMP}" -h "${EXE}" OUTPUT_VARIABLE headers RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "size-check: ${OBJDUMP} -h failed")
endif()
# Lines look like: "  0 .text         00005a70  0000000140001000  ...".
string(REGEX MATCHALL "\n +[0-9]+ [^ ]+ +[0-9a-f]+" rows "${headers}")
set(report "")
set(sectionBytes 0)
foreach(row IN LISTS rows)
  string(REGEX REPLACE "\n +[0-9]+ ([^ ]+) +([0-9a-f]+)" "\\1;\\2" fields "${row}")
  list(GET fields 0 name)
  list(GET fields 1 hex)
  math(EXPR bytes "0x${hex}")
  if(NOT name STREQUAL ".bss") # no file bytes
    math(EXPR sectionBytes "${sectionBytes} + ${bytes}")
  endif()
  string(LENGTH "${name}" nameLength)
  math(EXPR pad "10 - ${nameLength}")
  string(REPEAT " " ${pad} spaces)
  string(APPEND report "    ${name}${spaces}${bytes} bytes\n")
endforeach()
math(EXPR overheadBytes "${exeBytes} - ${sectionBytes}")

message("size-check: intro.exe is ${exeBytes} bytes unpacked "
        "(hard limit ${kLimitBytes})")
message("  sections (virtual size):\n${report}"
        "    headers, padding to the 512-byte file alignment: ${overheadBytes} bytes (.bss takes none)")
if(exeBytes GREATER kLimitBytes)
  message(FATAL_ERROR "size-check: FAIL: the unpacked exe is ${exeBytes} bytes, "
                      "over the ${kLimitBytes}-byte limit")
endif()

# A packed exe at `path`, made from ${EXE} by `packer`: it exists, is not
# older than ${EXE}, is at most kLimitBytes; prints its bytes. Sets
# `outBytes` in the caller to its size.
function(check_packed path packer outBytes)
  if(NOT EXISTS "${path}")
    message(FATAL_ERROR "size-check: ${path} is missing (the exe packed by ${packer})")
  endif()
  file(TIMESTAMP "${path}" packedTime "%s" UTC)
  if(packedTime LESS exeTime)
    message(FATAL_ERROR "size-check: ${path} is older than ${EXE} (the packing step did not run)")
  endif()
  file(SIZE "${path}" bytes)
  get_filename_component(name "${path}" NAME)
  math(EXPR percent "100 * (${exeBytes} - ${bytes}) / ${exeBytes}")
  message("size-check: ${name} (packed by ${packer}) is ${bytes} bytes "
          "(-${percent} %; hard limit ${kLimitBytes})")
  if(bytes GREATER kLimitBytes)
    message(FATAL_ERROR "size-check: FAIL: ${name} is ${bytes} bytes, "
                        "over the ${kLimitBytes}-byte limit")
  endif()
  set(${outBytes} ${bytes} PARENT_SCOPE)
endfunction()

set(judgedBytes ${exeBytes})
set(judged "unpacked exe")
if(UPX)
  execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=UPX "${UPX}" --version
                  OUTPUT_VARIABLE version RESULT_VARIABLE rc)
  string(REGEX MATCH "^[^\n]*" version "${version}")
  check_packed("${PACKED}" "${version}" packedBytes)
  if(NOT version STREQUAL "upx 3.94")
    message(WARNING "size-check: packed by '${version}', not the pinned upx 3.94 "
                    "(tools/install-deps.sh): sizes differ from docs/win32.md")
  endif()
  set(judgedBytes ${packedBytes})
  set(judged "packed exe")
else()
  message(WARNING "size-check: UPX is absent (tools/install-deps.sh intro puts it into "
                  "build-tools/): judging the unpacked exe")
endif()

if(OURS)
  check_packed("${OURS}" "our own packer, rt64k-pack" oursBytes)
  execute_process(COMMAND "${PACK_TOOL}" check "${EXE}" "${OURS}" OUTPUT_VARIABLE parts
                  ERROR_VARIABLE parts RESULT_VARIABLE rc)
  message("${parts}")
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "size-check: FAIL: rt64k-pack check refused intro-packed.exe")
  endif()
endif()
if(SHIPPED)
  file(SIZE "${SHIPPED}" judgedBytes)
  file(STRINGS "${SHIPPED_NOTE}" packer LIMIT_COUNT 1)
  set(judged "shipped packed exe (${packer})")
  message("size-check: the compo zip ships the smaller packed exe: ${packer}, ${judgedBytes} bytes")
endif()

if(judgedBytes GREATER kLimitBytes)
  message(FATAL_ERROR "size-check: FAIL: the ${judged} is ${judgedBytes} bytes, "
                      "over the ${kLimitBytes}-byte limit")
endif()
if(judgedBytes GREATER kTargetBytes)
  math(EXPR over "${judgedBytes} - ${kTargetBytes}")
  message(WARNING "size-check: the ${judged} is ${over} bytes over the ${kTargetBytes}-byte target "
                  "(the thesis's packed intro; budget ${kBudgetBytes}; still under the "
                  "${kLimitBytes}-byte limit)")
elseif(judgedBytes GREATER kBudgetBytes)
  math(EXPR over "${judgedBytes} - ${kBudgetBytes}")
  message("size-check: PASS: the ${judged} (${judgedBytes} bytes) is within the ${kTargetBytes}-byte "
          "target, ${over} bytes over the ${kBudgetBytes}-byte budget")
else()
  math(EXPR spare "${kBudgetBytes} - ${judgedBytes}")
  message("size-check: PASS: the ${judged} (${judgedBytes} bytes) is within the budget, "
          "${spare} bytes to spare")
endif()
