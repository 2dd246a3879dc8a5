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
#define WIN32_LEAN_AND_MEAN
#include <windows.h>

#include "codec.h"

// What tools/pack writes at the start of the payload section (its size is
// tools/pack/pack.cpp's kPayloadHeaderBytes): RVAs are relative to the
// image base, which the packed exe shares with intro.exe.
struct Payload {
  unsigned image_bytes;   // decoded bytes, from RVA 0x1000
  unsigned entry_rva;     // intro.exe's AddressOfEntryPoint
  unsigned imports_rva;   // the import list in the decoded image (below)
  unsigned iat_rva;       // intro.exe's import address table, its first slot
  unsigned encoded_bytes; // bytes of `encoded` (read by `rt64k-pack check` only)
  unsigned char encoded[1];
};

// The image base (GNU ld's name, as MSVC's), as bytes: the RVAs index it.
extern "C" unsigned char __ImageBase[];
extern "C" const Payload rt64k_payload; // the generated payload file
static constexpr unsigned kImageRva = 0x1000;

// The codec's model memory: zero-initialised, so .bss: no file bytes (the
// linker script puts it after the image in the uninitialised section).
alignas(64) static unsigned char work[rt64k::pack::kWorkBytes];

// The hash of a function's name by which the list names it: h = 31 h + c
// over its bytes (tools/pack/pack.cpp's nameHash(), the same formula).
static unsigned name_hash(const unsigned char* s) {
  unsigned h = 0;
  while (*s != 0)
    h = h * 31 + *s++;
  return h;
}

// Returns the address to jump to: intro.exe's entry point, or null when a
// DLL or one of its functions is missing (the entry code below then returns
// 1 to the loader's thread start, which ends the thread with that code, as
// the loader's own refusal to start intro.exe would have ended the process).
//
// The imports: tools/pack replaced intro.exe's import directory by a list
// (pack.cpp, importList()): per DLL its name (without ".dll", which
// LoadLibraryA appends), NUL-terminated, the number of its functions (a
// byte) and each function's name_hash() (4 bytes); an empty DLL name ends
// the list. Each function is the DLL's first exported name with that hash
// (the export directory: PE/COFF's data directory 0, at offset 0x88 of a
// PE32+ header; its name count at 0x18, name RVAs at 0x20), and its
// address GetProcAddress's for that name (which follows forwarded exports).
// The addresses go into consecutive IAT slots, one slot skipped after each
// DLL (the null that ends its table in intro.exe's layout).
// `used`: only the asm below calls it, which link-time optimisation cannot see.
extern "C" [[gnu::used]] void* stub_main() {
  unsigned char* base = __ImageBase;
  rt64k::pack::decode(rt64k_payload.encoded, base + kImageRva, rt64k_payload.image_bytes, work);
  auto* slot = reinterpret_cast<FARPROC*>(base + rt64k_payload.iat_rva);
  for (unsigned char* p = base + rt64k_payload.imports_rva; *p != 0; ++slot) {
    auto* dll = reinterpret_cast<unsigned char*>(LoadLibraryA(reinterpret_cast<char*>(p)));
    if (dll == nullptr) return nullptr;
    while (*p++ != 0) {
    }
    const unsigned char* exports =
        dll + *reinterpret_cast<unsigned*>(dll + *reinterpret_cast<unsigned*>(dll + 0x3c) + 0x88);
    const unsigned count = *reinterpret_cast<const unsigned*>(exports + 0x18);
    const auto* names =
        reinterpret_cast<const unsigned*>(dll + *reinterpret_cast<const unsigned*>(exports + 0x20));
    for (unsigned n = *p++; n != 0; --n, p += 4) {
      unsigned wanted;
      __builtin_memcpy(&wanted, p, 4);
      unsigned i = 0;
      for (;; ++i) {
        if (i == count) return nullptr;
        if (name_hash(dll + names[i]) == wanted) break;
      }
      *slot =
          GetProcAddress(reinterpret_cast<HMODULE>(dll), reinterpret_cast<char*>(dll + names[i]));
      if (*slot++ == nullptr) return nullptr;
    }
  }
  return base + rt64k_payload.entry_rva;
}

// The entry point (asm: C++ cannot leave the stack as it found it before a
// jump). The loader calls it with RSP = 8 mod 16; stub_main, a Win64
// function, needs RSP = 0 mod 16 before its call and 32 bytes of shadow
// space above its return address: 40 bytes. After it, RSP is the loader's
// again and the jump enters intro_entry as if the loader had called it.
__asm__(".section .text$stub_start,\"x\"\n"
        ".globl stub_start\n"
        "stub_start:\n"
        "  subq $40, %rsp\n"
        "  call stub_main\n"
        "  addq $40, %rsp\n"
        "  testq %rax, %rax\n"
        "  jz 1f\n"
        "  jmp *%rax\n"
        "1:\n"
        "  movl $1, %eax\n"
        "  ret\n"
        ".text\n");

// The packed exe's own import table, written here instead of taken from
// MinGW's libkernel32.a (whose lookup table repeats the address table and
// whose names are padded): one descriptor without a lookup table
// (OriginalFirstThunk 0: the loader reads the names through the address
// table itself, as the PE format allows), the address table of the two
// functions (their `__imp_` symbols are what the calls above go through),
// their hint/name entries (hint 0; each entry starts on an even address)
// and the DLL's name. stub.ld adds the null descriptor and places these
// sections in the import format's order.
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
