# cmake -DEXE=intro.exe -DRAW=unpacked.exe -DTEMPLATE=rt64k.nfo.in -DOUT=rt64k.nfo -P nfo.cmake
# Fills the .nfo template with the shipped exe's size in bytes, whether it is
# packed (it is when it is smaller than the unpacked build RAW), and the build date.
file(SIZE ${EXE} RT64K_EXE_SIZE)
file(SIZE ${RAW} rawSize)
if(RT64K_EXE_SIZE LESS rawSize)
  set(RT64K_EXE_PACKING "packed with UPX 3.94 (${rawSize} bytes unpacked)")
else()
  set(RT64K_EXE_PACKING "not packed (no UPX at build time)")
endif()
string(TIMESTAMP RT64K_BUILD_DATE "%Y-%m-%d" UTC)
configure_file(${TEMPLATE} ${OUT} @ONLY NEWLINE_STYLE CRLF)
