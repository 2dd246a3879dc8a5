# CMake toolchain file: cross-compile for 64-bit Windows with MinGW-w64 on
# Linux (Debian/Ubuntu package g++-mingw-w64-x86-64). Used by the intro.exe
# sub-build that cmake/win32.cmake sets up; usable on its own too:
#   cmake -S src/win32 -B build-win32 -DCMAKE_TOOLCHAIN_FILE=cmake/mingw-w64-x86_64.cmake
set(CMAKE_SYSTEM_NAME Windows)
set(CMAKE_SYSTEM_PROCESSOR x86_64)

set(RT64K_MINGW_PREFIX x86_64-w64-mingw32)
# Debian ships the compiler in two thread models; the "-win32" one needs no
# winpthread DLL. intro.exe links no runtime at all, so either works; prefer
# the plain name, which the alternatives system points at one of them.
find_program(CMAKE_CXX_COMPILER NAMES ${RT64K_MINGW_PREFIX}-g++ ${RT64K_MINGW_PREFIX}-g++-win32
             ${RT64K_MINGW_PREFIX}-g++-posix REQUIRED)
find_program(CMAKE_RC_COMPILER NAMES ${RT64K_MINGW_PREFIX}-windres)
find_program(RT64K_MINGW_OBJDUMP NAMES ${RT64K_MINGW_PREFIX}-objdump)

set(CMAKE_FIND_ROOT_PATH /usr/${RT64K_MINGW_PREFIX})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
