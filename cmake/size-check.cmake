# size-check: intro.exe's size against the project's budget and hard limit.
#   cmake -DEXE=intro.exe -DOBJDUMP=x86_64-w64-mingw32-objdump
#         [-DUPX=/path/to/upx -DPACKED=intro-upx.exe] -P cmake/size-check.cmake
# Prints the file size, the 16,384-byte budget, each section's size (from
# objdump -h) and, where UPX was found, the packed copy's size. Fails only
# above the 65,536-byte limit (of the packed copy when there is one, else of
# the unpacked exe); over the budget it warns.
set(kBudgetBytes 16384)
set(kLimitBytes 65536)

if(NOT EXISTS "${EXE}")
  message(FATAL_ERROR "size-check: ${EXE} does not exist (build the intro_exe target first)")
endif()
file(SIZE "${EXE}" exeBytes)

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
  math(EXPR sectionBytes "${sectionBytes} + ${bytes}")
  string(LENGTH "${name}" nameLength)
  math(EXPR pad "10 - ${nameLength}")
  string(REPEAT " " ${pad} spaces)
  string(APPEND report "    ${name}${spaces}${bytes} bytes\n")
endforeach()
math(EXPR overheadBytes "${exeBytes} - ${sectionBytes}")

message("size-check: intro.exe is ${exeBytes} bytes unpacked "
        "(budget ${kBudgetBytes}, hard limit ${kLimitBytes})")
message("  sections (virtual size):\n${report}"
        "    headers, padding to the 512-byte file alignment: ${overheadBytes} bytes")

set(judgedBytes ${exeBytes})
set(judged "unpacked exe")
if(UPX)
  if(NOT EXISTS "${PACKED}")
    message(FATAL_ERROR "size-check: UPX is at ${UPX} but ${PACKED} is missing")
  endif()
  file(SIZE "${PACKED}" packedBytes)
  math(EXPR percent "100 * (${exeBytes} - ${packedBytes}) / ${exeBytes}")
  message("  UPX (${UPX}): packed copy ${PACKED} is ${packedBytes} bytes (-${percent} %)")
  set(judgedBytes ${packedBytes})
  set(judged "UPX-packed copy")
else()
  message("  UPX is absent (not on PATH at configure time): judging the unpacked exe")
endif()

if(judgedBytes GREATER kLimitBytes)
  message(FATAL_ERROR "size-check: FAIL: the ${judged} is ${judgedBytes} bytes, "
                      "over the ${kLimitBytes}-byte limit")
endif()
if(judgedBytes GREATER kBudgetBytes)
  math(EXPR over "${judgedBytes} - ${kBudgetBytes}")
  message(WARNING "size-check: the ${judged} is ${over} bytes over the ${kBudgetBytes}-byte budget "
                  "(still under the ${kLimitBytes}-byte limit)")
else()
  math(EXPR spare "${kBudgetBytes} - ${judgedBytes}")
  message("size-check: PASS: the ${judged} (${judgedBytes} bytes) is within the budget, "
          "${spare} bytes to spare")
endif()
