# Flags shared by every build of src/core and scenes/ (native and MinGW).
# Freestanding: no exceptions, no RTTI, no C runtime calls may be generated.
# Order matters: -fno-fast-math resets -fmath-errno, so it comes first and
# -fno-math-errno after it (with errno maths on, GCC follows each sqrtss with
# a call to libm's sqrtf for negative input).
set(RT64K_FP_FLAGS -fno-fast-math -ffp-contract=off -fno-math-errno -mfpmath=sse -msse2)
set(RT64K_CORE_FLAGS ${RT64K_FP_FLAGS} -ffreestanding -fno-exceptions -fno-rtti
    -fno-tree-loop-distribute-patterns -O2)

# Sources that run once per frame or once per run (scene building, captions,
# the synth at start-up): compiled at -Os instead of -O2 in every build, to
# save bytes where speed does not matter. An optimisation level changes no
# computed value under RT64K_FP_FLAGS (no fast-math, no contraction), so the
# tests still test what ships. Paths relative to the repository root.
set(RT64K_COLD_SOURCES scenes/scenes.cpp src/core/scene.cpp src/core/shapes_build.cpp
    src/core/overlay.cpp src/core/synth.cpp)
set(RT64K_COLD_FLAGS -Os)
