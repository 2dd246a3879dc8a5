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
// ___chkstk_ms: GCC calls it in the prologue of any function whose stack
// frame is 4 kB or larger (e.g. a sample buffer on the stack). Windows grows
// a thread's stack one guard page at a time, so such a frame must be touched
// page by page from the top down before use.
//
// Not provided: _fltused (an MSVC-only marker; GCC never references it).
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

// Contract (as libgcc's): RAX = bytes the caller is about to subtract from
// RSP; every 4-kB page from the caller's RSP down to RSP - RAX is touched in
// order; all registers and flags the caller relies on are preserved (RCX and
// RAX are saved); the caller adjusts RSP itself. 24 = the return address
// and the two saved registers.
__asm__(".section .text$___chkstk_ms,\"x\"\n"
        ".globl ___chkstk_ms\n"
        "___chkstk_ms:\n"
        "  pushq %rcx\n"
        "  pushq %rax\n"
        "  cmpq $0x1000, %rax\n"
        "  leaq 24(%rsp), %rcx\n"
        "  jb 2f\n"
        "1:\n"
        "  subq $0x1000, %rcx\n"
        "  orq $0, (%rcx)\n"
        "  subq $0x1000, %rax\n"
        "  cmpq $0x1000, %rax\n"
        "  ja 1b\n"
        "2:\n"
        "  subq %rax, %rcx\n"
        "  orq $0, (%rcx)\n"
        "  popq %rax\n"
        "  popq %rcx\n"
        "  ret\n"
        ".text\n");
