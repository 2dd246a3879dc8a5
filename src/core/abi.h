// abi.h - the calling convention of the hot core's out-of-line functions.
//
// RT64K_HOT_ABI marks the declarations of the functions the renderer calls
// per ray, per sample or per band and that stay out of line in intro.exe
// (trace, trace_hit, intersect_t, hit_normal, the adaptive renderer's
// functions, the primary-ray and camera functions), and the adaptive
// renderer's entry points that src/win32 calls. On Win64 (intro.exe) it is
// GCC's sysv_abi: the System V AMD64 convention, in which xmm6-xmm15, rsi and
// rdi are the caller's to save, so these functions save none of them in
// their prologues; six integer and eight float arguments travel in
// registers, and a Vec3 in two xmm registers instead of through memory.
// A call across the two conventions is correct either way (each call site
// sees its callee's declaration); a Win64 function that calls a System V one
// keeps what it needs across the call itself. rt_sin, rt_cos, rt_exp... keep
// the Win64 convention: the scenes and the synth (Win64 code) call them many
// times. Measured in docs/win32.md ("Round seven: the calling convention").
//
// Elsewhere (the Linux tool and tests) the macro is empty: System V is the
// platform's own convention, so nothing changes there. For measurement only,
// RT64K_HOT_ABI_MS (defined) gives these functions the Win64 convention, as
// intro.exe had them before: in intro.exe (tests/wine/measure-flags.sh prices
// it) and on a native x86-64 build (ms_abi), where callgrind counts what the
// convention costs the renderer.
#pragma once

#if defined(_WIN64) && !defined(RT64K_HOT_ABI_MS)
#define RT64K_HOT_ABI __attribute__((sysv_abi))
#elif defined(RT64K_HOT_ABI_MS) && defined(__x86_64__) && !defined(_WIN64)
#define RT64K_HOT_ABI __attribute__((ms_abi))
#else
#define RT64K_HOT_ABI
#endif
