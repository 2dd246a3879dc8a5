# Flags shared by every build of src/core and scenes/ (native and MinGW).
# Freestanding: no exceptions, no RTTI, no C runtime calls may be generated.
# Order matters: -fno-fast-math resets -fmath-errno, so it comes first and
# -fno-math-errno after it (with errno maths on, GCC follows each sqrtss with
# a call to libm's sqrtf for negative input).
set(RT64K_FP_FLAGS -fno-fast-math -ffp-contract=off -fno-math-errno -mfpmath=sse -msse2)
# -O2 without the parts of it that grow the code and buy no measured speed
# in this renderer (docs/win32.md "A smaller exe": each flag's bytes in the
# packed exe, callgrind instruction counts and render times of the native
# tool; pixels identical). None changes a computed value. Code that relies on
# one of them (say, loops written for GCC's auto-vectoriser) must be
# measured again with and without it.
set(RT64K_CODE_SIZE_FLAGS
    -fno-tree-vectorize            # GCC 12 vectorises at -O2: scalar code here
    -fno-inline-functions          # -O2's inlining of non-small functions
    -fno-schedule-insns2 -fno-reorder-blocks # scheduling, block reordering
    -falign-functions=1 -falign-jumps=1 -falign-loops=1 -falign-labels=1 # no padding
    # Issue 11, round three: each of these made the packed exe smaller and
    # the renderer's instruction count (callgrind, render_frame at 12, 44 and
    # 58.75 s) no larger, the same PNGs (docs/win32.md "Round three"): the
    # first six -610 bytes packed (no padding), -1.0 to -1.3 % instructions;
    # the last two -80 bytes more, a further -1.3 to -1.9 %.
    -fno-tree-fre -fno-code-hoisting -fno-tree-scev-cprop -fno-strict-aliasing
    -fno-move-loop-invariants -fira-region=one
    -fno-tree-forwprop -fno-tree-tail-merge
    # Round five (docs/win32.md "Round five: each measure"): -144 bytes of
    # UPX1 alone, instructions -0.33 / 0.00 / -0.49 % (adaptive8 at 12 and
    # 44 s, full at 12 s), the same PNGs.
    -fno-tree-dominator-opts)
set(RT64K_CORE_FLAGS ${RT64K_FP_FLAGS} -ffreestanding -fno-exceptions -fno-rtti
    -fno-tree-loop-distribute-patterns -O2 ${RT64K_CODE_SIZE_FLAGS})

# The hot sources of intro.exe (everything in src/core the renderer runs per
# pixel; src/core/packet/ is the native tool's alternative to scalar/). Each
# may carry flags of its own after RT64K_CORE_FLAGS, RT64K_HOT_FLAGS_<stem>
# (<stem>: the file's name without .cpp), in every build; measurement builds
# add RT64K_HOT_EXTRA_<stem> on the command line (-D...), after them.
set(RT64K_HOT_SOURCES src/core/adaptive.cpp src/core/rtmath.cpp src/core/shapes.cpp
    src/core/trace.cpp src/core/scalar/primary.cpp)
# Round five, per file (docs/win32.md "Round five: each measure"): each flag
# priced on its file alone in the exe and by callgrind in the native tool;
# the same flag on another hot file cost bytes or instructions (PRE on
# trace.cpp +2 %). rtmath.cpp's functions (rt_pow, rt_exp, rt_sin, rt_cos...)
# cost no measurable instruction at -Os.
# Round seven (docs/win32.md "Round seven: flags under System V"), priced
# again after the hot core took the System V convention (src/core/abi.h):
# on every hot file -fno-gcse -fno-tree-pta, and one to five flags per file;
# together UPX1 -416 bytes (normalised: timestamp and checksum zeroed; -448
# with the scene builders' flags below), the packed file 24,576 -> 24,064,
# renderer instructions -0.22 / -0.78 % (adaptive8 at 12 and 44 s), the same
# PNGs. Each flag is free alone or on top of the others but adaptive.cpp's
# -fno-tree-ch: +0.19 / +0.15 % against the set without it, -96 UPX1 bytes,
# the ones that cross the step. Re-price after a change to a hot file.
set(RT64K_HOT_FLAGS_ALL -fno-gcse -fno-tree-pta)
set(RT64K_HOT_FLAGS_adaptive -fno-tree-pre ${RT64K_HOT_FLAGS_ALL} -fno-caller-saves -fno-tree-sink
    -fno-tree-ch -fno-tree-coalesce-vars)
set(RT64K_HOT_FLAGS_shapes -fno-tree-sink ${RT64K_HOT_FLAGS_ALL} -fno-tree-ch -fno-shrink-wrap
    -fno-expensive-optimizations)
set(RT64K_HOT_FLAGS_rtmath -Os ${RT64K_HOT_FLAGS_ALL})
set(RT64K_HOT_FLAGS_trace ${RT64K_HOT_FLAGS_ALL} -fno-ivopts)
set(RT64K_HOT_FLAGS_primary ${RT64K_HOT_FLAGS_ALL} -fno-caller-saves -fno-tree-pre)

# The packet sources (src/core/packet/*.cpp: the native tool's alone, never
# in intro.exe), after RT64K_CORE_FLAGS. Round fourteen (shade21) priced the
# code-size flags' opposites on them alone by callgrind (13 s adaptive8:
# docs/tracer-speed.md "Round fourteen"): none lowered the instructions by
# more than 0.02 %, all ten together +0.43 %; so none here. Measurement
# builds add RT64K_PACKET_EXTRA (-D..., a list) after them, say
# -fschedule-insns2 and -freorder-blocks, which move no instruction count
# (callgrind cannot price them) and are left to a timed A/B.
set(RT64K_PACKET_FLAGS)

# Sources that run once per frame or once per run (scene building, captions,
# the synth at start-up): compiled at -Os instead of -O2 in every build, to
# save bytes where speed does not matter. An optimisation level changes no
# computed value under RT64K_FP_FLAGS (no fast-math, no contraction), so the
# tests still test what ships. Paths relative to the repository root.
set(RT64K_COLD_SOURCES scenes/scenes.cpp src/core/scene.cpp src/core/shapes_build.cpp
    src/core/overlay.cpp src/core/synth.cpp)
# The -fno flags: each makes the packed exe smaller here (docs/win32.md
# "Round three"); the synth's time and samples unchanged.
# Round ten (size14): -fno-jump-tables, -40 bytes of our packer's payload
# (shapes_build.cpp's switch over the shape kinds as compares, once per shape
# and frame; the other cold objects compile to the same bytes with it).
set(RT64K_COLD_FLAGS -Os -fno-move-loop-invariants -fno-code-hoisting -fno-tree-dominator-opts
    -fno-caller-saves -fno-jump-tables)
# Per cold file, after RT64K_COLD_FLAGS: RT64K_COLD_FLAGS_<stem>. Round seven
# (docs/win32.md "Round seven: flags under System V"): the scene builders
# without loop optimisation (run once per frame, ~4,000 instructions).
set(RT64K_COLD_FLAGS_LOOPS -fno-tree-sink -fno-tree-ch -fno-tree-loop-im -fno-tree-loop-optimize)
set(RT64K_COLD_FLAGS_scenes ${RT64K_COLD_FLAGS_LOOPS})
set(RT64K_COLD_FLAGS_scene ${RT64K_COLD_FLAGS_LOOPS})
set(RT64K_COLD_FLAGS_shapes_build ${RT64K_COLD_FLAGS_LOOPS})
# Round nine (docs/win32.md "Round nine: the packed exe under the next step
# again"): the captions without loop-invariant motion and loop
# optimisation, -15 and -31 bytes of our packer's payload; overlay_draw()
# +12.9 % instructions (240,000 -> 271,000 a frame, callgrind over 256
# times: about 0.06 % of the cheapest frame's render), the same pixels.
set(RT64K_COLD_FLAGS_overlay -fno-tree-loop-im -fno-tree-loop-optimize)
