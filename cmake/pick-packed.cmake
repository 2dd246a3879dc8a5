# pick-packed: the packed exe that ships, the smaller of UPX's and ours.
#   cmake -DUPX_EXE=intro-upx.exe [-DUPX=upx] -DOURS_EXE=intro-packed.exe
#         -DOUT=intro-shipped.exe -DNOTE=intro-shipped.txt -P cmake/pick-packed.cmake
# Copies the smaller one (ours on a tie: it needs no third-party tool) to OUT
# and writes NOTE, one line naming its packer, which cmake/nfo.cmake puts into
# the .nfo. Without UPX, ours. Both files appear whole or not at all
# (written beside, then renamed).
if(NOT EXISTS "${OURS_EXE}")
  message(FATAL_ERROR "pick-packed: ${OURS_EXE} does not exist")
endif()
file(SIZE "${OURS_EXE}" oursBytes)
set(pick "${OURS_EXE}")
set(note "rt64k-pack, the intro's own context-mixing packer")
if(UPX)
  if(NOT EXISTS "${UPX_EXE}")
    message(FATAL_ERROR "pick-packed: UPX is at ${UPX} but ${UPX_EXE} is missing")
  endif()
  file(SIZE "${UPX_EXE}" upxBytes)
  if(upxBytes LESS oursBytes)
    set(pick "${UPX_EXE}")
    set(note "UPX 3.94")
  endif()
endif()
file(COPY_FILE "${pick}" "${OUT}.tmp")
file(RENAME "${OUT}.tmp" "${OUT}")
file(WRITE "${NOTE}.tmp" "${note}\n")
file(RENAME "${NOTE}.tmp" "${NOTE}")
get_filename_component(name "${pick}" NAME)
message(STATUS "pick-packed: shipping ${name} (${note})")
