// stub.cpp - the entry point of intro-packed.exe, the intro packed by our
// own packer (tools/pack/, docs/win32.md "Round eight: our own packer").
//
// The packed exe has two sections (src/pack/stub.ld): an uninitialised
// read+write+execute one at RVA 0x1000, as large as intro.exe's image, into
// which this stub decodes intro.exe's sections; and one file-backed section
// with the payload (what tools/pack wrote: a Payload record, then the
// encoded image), this stub's code and its own import table (kernel32's
// LoadLibraryA and GetProcAddress, filled in by the system's loader).
//
// At start-up: decode the image into place (it was linked at the same fixed
// base, 0x140000000, without relocations, so it runs where it lands), fill
// in the image's import address table the way the loader would have (from a
// compact list of DLL names and function name hashes decoded with the image), then jump to
// intro.exe's entry point with the stack as the loader left it. Freestanding: no C runtime, no
// heap.
#include "codec.h"

// What tools/pack writes at the start of the payload section (its size is
// tools/pack/pack.cpp's kPayloadHeaderBytes): RVAs are relative to the
// image base, which the packed exe shares with intro.exe.
struct Payload {
  unsigned image_bytes; // decoded bytes, from RVA 0x1000
  unsigned entry_rva;   // intro.exe's AddressOfEntryPoint
  unsigned imports_rva; // the import list in the decoded image (below)
  unsigned iat_rva;     // intro.exe's import address table, its first slot
  unsigned char encoded[1];
};

// The codec's model memory: zero-initialised, so .bss: no file bytes (the
// linker script puts it after the image in the uninitialised section).
// Global: the asm below names it.
extern "C" {
alignas(64) unsigned char rt64k_work[rt64k::pack::kWorkBytes];
}

// The field offsets the asm below reads.
static_assert(__builtin_offsetof(Payload, image_bytes) == 0);
static_assert(__builtin_offsetof(Payload, entry_rva) == 4);
static_assert(__builtin_offsetof(Payload, imports_rva) == 8);
static_assert(__builtin_offsetof(Payload, iat_rva) == 12);
static_assert(__builtin_offsetof(Payload, encoded) == 16);

// The entry point, in asm: its code is not compressed, and GCC's -Os took
// 301 bytes for it in C++ (an asm stub_start calling a C++ function), this 256.
//
// 1. Decode the image into place: decode(rt64k_payload.encoded, __ImageBase
//    + 0x1000, rt64k_payload.image_bytes, rt64k_work), a Win64 call (RSP 16-
//    byte aligned, 32 bytes of shadow space: the loader enters with RSP = 8
//    mod 16; seven pushes and 32 bytes make it 0).
// 2. The imports: tools/pack replaced intro.exe's import directory by a list
//    (pack.cpp, importList()): per DLL its name (without ".dll", which
//    LoadLibraryA appends), NUL-terminated, the number of its functions (a
//    byte, at least 1) and each function's name hash (4 bytes, h = 31 h + c
//    over the name's bytes, pack.cpp's nameHash()); an empty DLL name ends
//    the list. Each function is the first name in the DLL's export
//    directory (PE/COFF data directory 0, at offset 0x88 of a PE32+ header;
//    its name count at 0x18, its name RVAs at 0x20) with that hash, and its
//    address what GetProcAddress gives for that name (which follows
//    forwarded exports). The addresses go into consecutive IAT slots
//    (stosq: the direction flag is clear in the Win64 convention), one slot
//    skipped after each DLL (scasq: the null that ends its table in
//    intro.exe's layout).
// 3. Jump to intro.exe's entry point with RSP as the loader left it (the
//    pushed registers need no restoring: intro_entry never returns; every
//    way out is ExitProcess).
// A missing DLL, function name or address: the registers and RSP restored,
// return 1 to the loader's thread start, which ends the thread with that
// code, as the loader's own refusal to start intro.exe ends the process.
__asm__(".section .text$stub_start,\"x\"\n"
        ".globl stub_start\n"
        "stub_start:\n"
        "  pushq %rbx\n"
        "  pushq %rbp\n"
        "  pushq %rdi\n"
        "  pushq %rsi\n"
        "  pushq %r12\n"
        "  pushq %r13\n"
        "  pushq %r14\n"
        "  subq $32, %rsp\n"
        "  leaq __ImageBase(%rip), %rbp\n"
        "  leaq rt64k_payload(%rip), %rsi\n" // the record (rsi kept by decode)
        "  leaq 16(%rsi), %rcx\n"
        "  leaq 0x1000(%rbp), %rdx\n"
        "  movl (%rsi), %r8d\n"
        "  leaq rt64k_work(%rip), %r9\n"
        "  call _ZN5rt64k4pack6decodeEPKhPhjPv\n"
        "  movl 8(%rsi), %ebx\n"
        "  addq %rbp, %rbx\n" // rbx: the list
        "  movl 12(%rsi), %edi\n"
        "  addq %rbp, %rdi\n" // rdi: the next IAT slot
        "1:\n"                // a DLL
        "  cmpb $0, (%rbx)\n"
        "  je 7f\n"
        "  movq %rbx, %rcx\n"
        "  call *__imp_LoadLibraryA(%rip)\n"
        "  testq %rax, %rax\n"
        "  jz 8f\n"
        "  movq %rax, %rsi\n" // rsi: the DLL's base
        "2:\n"
        "  incq %rbx\n"
        "  cmpb $0, -1(%rbx)\n"
        "  jne 2b\n"
        "  movzbl (%rbx), %r12d\n" // r12: functions left
        "  incq %rbx\n"
        "  movl 0x3c(%rsi), %eax\n"
        "  movl 0x88(%rsi,%rax), %eax\n"
        "  movl 0x18(%rsi,%rax), %r14d\n" // r14: exported names
        "  movl 0x20(%rsi,%rax), %r13d\n"
        "  addq %rsi, %r13\n" // r13: their RVAs
        "3:\n"                // a function
        "  decl %r12d\n"      // from at most 255: negative after the last
        "  js 6f\n"
        "  xorl %ecx, %ecx\n"
        "4:\n" // the next exported name
        "  cmpl %r14d, %ecx\n"
        "  je 8f\n"
        "  movl (%r13,%rcx,4), %edx\n"
        "  addq %rsi, %rdx\n"
        "  incl %ecx\n"
        "  xorl %eax, %eax\n"
        "  movq %rdx, %r8\n"
        "5:\n" // its hash
        "  movzbl (%r8), %r9d\n"
        "  incq %r8\n"
        "  testl %r9d, %r9d\n"
        "  jz 9f\n"
        "  imull $31, %eax, %eax\n"
        "  addl %r9d, %eax\n"
        "  jmp 5b\n"
        "9:\n"
        "  cmpl (%rbx), %eax\n"
        "  jne 4b\n"
        "  movq %rsi, %rcx\n"
        "  call *__imp_GetProcAddress(%rip)\n"
        "  testq %rax, %rax\n"
        "  jz 8f\n"
        "  stosq\n"
        "  addq $4, %rbx\n"
        "  jmp 3b\n"
        "6:\n"
        "  scasq\n"
        "  jmp 1b\n"
        "7:\n"
        "  movl rt64k_payload+4(%rip), %eax\n"
        "  addq %rbp, %rax\n"
        "  addq $88, %rsp\n"
        "  jmp *%rax\n"
        "8:\n"
        "  addq $32, %rsp\n"
        "  popq %r14\n"
        "  popq %r13\n"
        "  popq %r12\n"
        "  popq %rsi\n"
        "  popq %rdi\n"
        "  popq %rbp\n"
        "  popq %rbx\n"
        "  pushq $1\n" // eax = 1 in 3 bytes (movl: 5)
        "  popq %rax\n"
        "  ret\n"
        ".text\n");

// The packed exe's own import table, written here instead of taken from
// MinGW's libkernel32.a (whose lookup table repeats the address table and
// whose names are padded): one descriptor without a lookup table
// (OriginalFirstThunk 0: the loader reads the names through the address
// table itself, as the PE format allows), the address table of the two
// functions (their `__imp_` symbols are what the calls above go through),
// their hint/name entries (hint 0; each entry starts on an even address)
// and the DLL's name. stub.ld adds the null descriptor and puts the address
// table first, then the directory and the names at the section's end, which
// `rt64k-pack finish` moves into the headers' free bytes (size14).
__asm__(".section .idata$2,\"w\"\n"
        "  .long 0, 0, 0\n"
        "  .rva rt64k_kernel32\n"
        "  .rva __imp_LoadLibraryA\n"
        ".section .idata$5,\"w\"\n"
        ".globl __imp_LoadLibraryA\n"
        "__imp_LoadLibraryA:\n"
        "  .rva rt64k_load_library\n"
        "  .long 0\n"
        ".globl __imp_GetProcAddress\n"
        "__imp_GetProcAddress:\n"
        "  .rva rt64k_get_proc_address\n"
        "  .long 0\n"
        "  .quad 0\n"
        ".section .idata$6,\"w\"\n"
        "rt64k_load_library:\n"
        "  .short 0\n"
        "  .asciz \"LoadLibraryA\"\n"
        "  .byte 0\n"
        "rt64k_get_proc_address:\n"
        "  .short 0\n"
        "  .asciz \"GetProcAddress\"\n"
        ".section .idata$7,\"w\"\n"
        "rt64k_kernel32:\n"
        "  .asciz \"KERNEL32.dll\"\n"
        ".text\n");
