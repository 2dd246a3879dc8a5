# cmake -DEXE=intro.exe -DTEMPLATE=rt64k.nfo.in -DOUT=rt64k.nfo -P nfo.cmake
# Fills the .nfo template with the exe's size in bytes and the build date.
file(SIZE ${EXE} RT64K_EXE_SIZE)
string(TIMESTAMP RT64K_BUILD_DATE "%Y-%m-%d" UTC)
configure_file(${TEMPLATE} ${OUT} @ONLY NEWLINE_STYLE CRLF)
