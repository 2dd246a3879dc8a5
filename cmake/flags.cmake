# Flags shared by every build of src/core and scenes/ (native and MinGW).
# Freestanding: no exceptions, no RTTI, no C runtime calls may be generated.
set(RT64K_FP_FLAGS -ffp-contract=off -fno-math-errno -fno-fast-math -mfpmath=sse -msse2)
set(RT64K_CORE_FLAGS ${RT64K_FP_FLAGS} -ffreestanding -fno-exceptions -fno-rtti
    -fno-tree-loop-distribute-patterns -O2)
