# cmake -DEXE=intro.exe -DRAW=unpacked.exe [-DPACKER_NOTE=intro-shipped.txt]
#       -DTEMPLATE=rt64k.nfo.in -DOUT=rt64k.nfo -P nfo.cmake
# Fills the .nfo template with the shipped exe's size in bytes, whether it is
# packed (it is when it is smaller than the unpacked build RAW) and by which
# packer (PACKER_NOTE's line, written by cmake/pick-packed.cmake), and the
# build date.
file(SIZE ${EXE} RT64K_EXE_SIZE)
file(SIZE ${RAW} rawSize)
if(RT64K_EXE_SIZE LESS rawSize AND PACKER_NOTE)
  file(STRINGS "${PACKER_NOTE}" packer LIMIT_COUNT 1)
  set(RT64K_EXE_PACKING "packed (${rawSize} bytes unpacked)")
  set(RT64K_EXE_PACKER "${packer}")
else()
  set(RT64K_EXE_PACKING "not packed")
  set(RT64K_EXE_PACKER "none")
endif()
string(TIMESTAMP RT64K_BUILD_DATE "%Y-%m-%d" UTC)
configure_file(${TEMPLATE} ${OUT} @ONLY NEWLINE_STYLE CRLF)
