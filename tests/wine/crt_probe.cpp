// crt_probe.cpp - crt_probe.exe, built with intro.exe's flags and
// src/win32/crt.cpp, run under Wine by the wine.crt test: each replacement
// of a C runtime symbol gives the right result on Windows. The exit code
// is 0 when all pass, else the sum of the failed checks' bits.
#define WIN32_LEAN_AND_MEAN
#include <windows.h>

extern "C" float sqrtf(float);
extern "C" double sqrt(double);

namespace {

constexpr int kProbeBytes = 256 * 1024; // 64 pages: far past the guard page
constexpr unsigned kFailStack = 1, kFailMemset = 2, kFailMemcpy = 4, kFailSqrt = 8;

// A frame of kProbeBytes: GCC calls ___chkstk_ms in the prologue, which must
// return with RAX and RCX intact. On Windows, without the page-by-page probe
// the first write below the guard page is an access violation; Wine maps
// the whole stack at once, so under Wine this checks the calling contract
// only, not the probing (a ___chkstk_ms that just returns passes too).
__attribute__((noinline)) int deep_frame(int seed) {
  volatile unsigned char big[kProbeBytes];
  for (int i = 0; i < kProbeBytes; i += 4096)
    big[i] = (unsigned char)(seed + i / 4096);
  int sum = 0;
  for (int i = 0; i < kProbeBytes; i += 4096)
    sum += big[i];
  return sum;
}

struct Blob {
  unsigned char bytes[3000]; // large enough that GCC calls memset/memcpy
};

// Sizes and inputs pass through volatiles, so GCC cannot inline or fold
// the calls: memset, memcpy, sqrtf and sqrt are really called.
volatile unsigned long long g_blobBytes = sizeof(Blob::bytes);
volatile float g_minusOne = -1.0f, g_floatSquare = 2.25f;
volatile double g_doubleSquare = 6.25;

} // namespace

extern "C" [[noreturn]] void probe_entry() {
  unsigned failed = 0;
  int expected = 0;
  for (int i = 0; i < kProbeBytes / 4096; ++i)
    expected += (unsigned char)(7 + i);
  if (deep_frame(7) != expected) failed |= kFailStack;

  static Blob a, b; // static: the stack stays small here
  __builtin_memset(a.bytes, 0x5a, g_blobBytes);
  for (unsigned char c : a.bytes)
    if (c != 0x5a) failed |= kFailMemset;
  a.bytes[1234] = 1;
  __builtin_memcpy(b.bytes, a.bytes, g_blobBytes);
  for (int i = 0; i < (int)sizeof a.bytes; ++i)
    if (b.bytes[i] != (i == 1234 ? 1 : 0x5a)) failed |= kFailMemcpy;

  // sqrtf/sqrt are reached only for negative input (see crt.cpp); call them
  // directly too.
  float nan = __builtin_sqrtf(g_minusOne);
  if (sqrtf(g_floatSquare) != 1.5f || sqrt(g_doubleSquare) != 2.5 || nan == nan)
    failed |= kFailSqrt;
  ExitProcess(failed);
}
