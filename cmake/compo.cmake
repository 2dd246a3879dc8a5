# The `compo` target: build/compo/rt64k.zip with intro.exe (the shipped
# packed exe, intro-shipped.exe: the smaller of UPX's and our own packer's,
# cmake/pick-packed.cmake), rt64k.nfo
# (its size filled in) and a screenshot rendered by the rt64k tool. Included by
# the top-level CMakeLists.txt after cmake/win32.cmake.
if(NOT RT64K_HAVE_MINGW)
  return()
endif()
set(RT64K_COMPO_DIR ${CMAKE_BINARY_DIR}/compo)
set(RT64K_COMPO_ZIP ${RT64K_COMPO_DIR}/rt64k.zip)
# The screenshot: scene 2 at 44 s, full trace, captions on.
set(RT64K_COMPO_SHOT_TIME 44)
set(RT64K_COMPO_EXE ${RT64K_PACKED_EXE})
add_custom_target(compo
  COMMAND ${CMAKE_COMMAND} -E make_directory ${RT64K_COMPO_DIR}
  COMMAND ${CMAKE_COMMAND} -E copy ${RT64K_COMPO_EXE} ${RT64K_COMPO_DIR}/intro.exe
  COMMAND $<TARGET_FILE:rt64k> render --time ${RT64K_COMPO_SHOT_TIME} --mode full
          --out ${RT64K_COMPO_DIR}/screenshot.png
  COMMAND ${CMAKE_COMMAND} -DEXE=${RT64K_COMPO_DIR}/intro.exe -DRAW=${RT64K_INTRO_EXE}
          -DPACKER_NOTE=${RT64K_PACKED_NOTE} -DTEMPLATE=${CMAKE_SOURCE_DIR}/docs/rt64k.nfo.in -DOUT=${RT64K_COMPO_DIR}/rt64k.nfo
          -P ${CMAKE_SOURCE_DIR}/cmake/nfo.cmake
  COMMAND ${CMAKE_COMMAND} -E chdir ${RT64K_COMPO_DIR} ${CMAKE_COMMAND} -E tar cf rt64k.zip
          --format=zip intro.exe rt64k.nfo screenshot.png
  DEPENDS intro_exe rt64k
  BYPRODUCTS ${RT64K_COMPO_ZIP}
  COMMENT "compo: ${RT64K_COMPO_ZIP}"
  VERBATIM)

if(BUILD_TESTING)
  add_test(NAME compo_zip COMMAND ${CMAKE_COMMAND} -DBUILD=${CMAKE_BINARY_DIR}
           -DEXPECTED_EXE=${RT64K_COMPO_EXE} -DPACKER_NOTE=${RT64K_PACKED_NOTE}
           -P ${CMAKE_SOURCE_DIR}/tests/compo-test.cmake)
endif()
