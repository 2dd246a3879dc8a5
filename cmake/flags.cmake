# Flags shared by every build of src/core and scenes/ (native and MinGW).
# Freestanding: no exceptions, no RTTI, no C runtime calls may be generated.
# Order matters: -fno-fast-math resets -fmath-errno, so it comes first and
# -fno-math-errno after it (with errno maths on, GCC follows each sqrtss with
# a call to libm's sqrtf for negative input).
set(RT64K_FP_FLAGS -fno-fast-math -ffp-contract=off -fno-math-errno -mfpmath=sse -msse2)
set(RT64K_CORE_FLAGS ${RT64K_FP_FLAGS} -ffreestanding -fno-exceptions -fno-rtti
    -fno-tree-loop-distribute-patterns -O2)
