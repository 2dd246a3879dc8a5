// crt.cpp - the few C runtime symbols GCC may call by itself in a -nostdlib
// build: it emits memset/memcpy for large aggregate initialisation and
// copies (a Scene is ~1.8 kB) even with -ffreestanding. Each function sits
// in its own section, so --gc-sections drops whichever the exe never calls.
//
// sqrtf and sqrt: RT64K_FP_FLAGS put -fno-fast-math after -fno-math-errno,
// and -fno-fast-math switches errno maths back on, so GCC follows each
// inline sqrtss/sqrtsd by a call to the library function for negative
// input (to set errno). That call returns the same NaN the instruction
// already gave; here it is the instruction again, in asm so that it cannot
// become a call to itself.
//
// Not provided, because GCC for x86_64-w64-mingw32 never references them in
// this program (the link would fail if it did): _fltused (an MSVC-only
// marker) and ___chkstk_ms (stack probes, emitted only for frames of 4 kB
// or more; no function here or in the core has one).
typedef unsigned long long size_t;

// Contract as in C: regions of n bytes, no overlap for memcpy. `rep stosb`
// and `rep movsb` are a few bytes each and fast on every CPU since Ivy
// Bridge (ERMSB). Written in asm so the compiler cannot turn the loop back
// into a call to itself.
extern "C" void* memset(void* dst, int value, size_t n) {
  void* d = dst;
  __asm__ volatile("rep stosb" : "+D"(d), "+c"(n) : "a"(value) : "memory");
  return dst;
}

extern "C" void* memcpy(void* dst, const void* src, size_t n) {
  void* d = dst;
  __asm__ volatile("rep movsb" : "+D"(d), "+S"(src), "+c"(n) : : "memory");
  return dst;
}

extern "C" float sqrtf(float x) {
  float r;
  __asm__("sqrtss %1, %0" : "=x"(r) : "x"(x));
  return r;
}

extern "C" double sqrt(double x) {
  double r;
  __asm__("sqrtsd %1, %0" : "=x"(r) : "x"(x));
  return r;
}
