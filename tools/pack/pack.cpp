// rt64k-pack - our own exe packer's host tool (docs/win32.md "Round eight:
// our own packer"). `pack` reads intro.exe, lays its sections out as the
// loader would, encodes the image with the codec (src/pack/codec.h) and
// writes an assembler file that src/win32/CMakeLists.txt links with the
// start-up stub (src/pack/stub.cpp, src/pack/stub.ld) into intro-packed.exe.
// `check` reads a packed exe back, decodes its payload natively and compares
// the result with intro.exe's image, byte for byte, and prints the bytes of
// each part of the packed exe.
//
// Only what the stub can load is accepted: a PE32+ x86-64 exe at the fixed
// base 0x140000000 without relocations, with imports by name and no other
// data directory (no TLS, resources, exception tables...), its sections
// inside the image from RVA 0x1000 on. Anything else: a message, exit 1.
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

#include "codec.h"
#include "model.h"

namespace {

using Bytes = std::vector<unsigned char>;

// The stub is linked at this base and decodes to this RVA (stub.ld).
constexpr unsigned long long kImageBase = 0x140000000ull;
constexpr unsigned kImageRva = 0x1000;
// PE/COFF constants (Microsoft's PE format specification).
constexpr unsigned kMachineAmd64 = 0x8664;
constexpr unsigned kMagicPe32 = 0x10b, kMagicPe32Plus = 0x20b;
constexpr unsigned kRelocsStripped = 0x0001;
constexpr unsigned kDynamicBase = 0x0040;
constexpr unsigned kDirImport = 1, kDirIat = 12;
constexpr unsigned kScnUninitialised = 0x80;
constexpr unsigned kScnRwx = 0xe0000000; // MEM_EXECUTE | MEM_READ | MEM_WRITE
constexpr unsigned long long kOrdinalFlag = 1ull << 63;
// The payload record stub.cpp reads: four 32-bit fields, then the encoded
// bytes (struct Payload).
constexpr unsigned kPayloadHeaderBytes = 16;
// More than any image the packed exe could hold (the 64 kB limit).
constexpr unsigned kMaxImageBytes = 1u << 24;

struct Error {
  std::string message;
};

[[noreturn]] void fail(const std::string& what) { throw Error{what}; }

unsigned read16(const Bytes& b, size_t at) {
  if (at + 2 > b.size())
    fail("truncated: a header field at offset " + std::to_string(at) + " is past the end of the " +
         std::to_string(b.size()) + "-byte file");
  return b[at] | b[at + 1] << 8;
}

unsigned read32(const Bytes& b, size_t at) {
  if (at + 4 > b.size())
    fail("truncated: a header field at offset " + std::to_string(at) + " is past the end of the " +
         std::to_string(b.size()) + "-byte file");
  return b[at] | b[at + 1] << 8 | b[at + 2] << 16 | unsigned(b[at + 3]) << 24;
}

// Writes a little-endian 32-bit field inside the file (the caller has
// checked the offset against the layout it parsed).
void write32(Bytes& b, size_t at, unsigned v) {
  for (unsigned i = 0; i < 4; ++i)
    b[at + i] = (unsigned char)(v >> 8 * i);
}

unsigned long long read64(const Bytes& b, size_t at) {
  return read32(b, at) | (unsigned long long)read32(b, at + 4) << 32;
}

struct Section {
  std::string name;
  unsigned virtualSize, rva, rawSize, rawOffset, characteristics;
};

// The header fields the packer needs or copies, and the sections.
struct Pe {
  unsigned characteristics, subsystem, dllCharacteristics;
  unsigned long long imageBase, stackReserve, stackCommit, heapReserve, heapCommit;
  unsigned entryRva, sizeOfImage, sizeOfHeaders, sectionAlignment;
  unsigned dirRva[16] = {}, dirSize[16] = {};
  std::vector<Section> sections;
};

Bytes readFile(const char* path) {
  FILE* f = std::fopen(path, "rb");
  if (!f) fail(std::string("cannot open ") + path + ": " + std::strerror(errno));
  Bytes b;
  unsigned char chunk[65536];
  size_t n;
  while ((n = std::fread(chunk, 1, sizeof chunk, f)) > 0) {
    b.insert(b.end(), chunk, chunk + n);
    if (b.size() > kMaxImageBytes) {
      std::fclose(f);
      fail(std::string(path) + " is larger than " + std::to_string(kMaxImageBytes) + " bytes");
    }
  }
  bool bad = std::ferror(f);
  std::fclose(f);
  if (bad) fail(std::string("cannot read ") + path);
  return b;
}

// Parses the headers (any PE32+ x86-64 image; what the packer accepts is
// decided by validate()).
Pe parse(const Bytes& b) {
  if (b.size() < 64 || b[0] != 'M' || b[1] != 'Z') fail("not a PE file (no MZ header)");
  const unsigned pe = read32(b, 0x3c);
  if (read32(b, pe) != 0x4550) // "PE\0\0"
    fail("not a PE file (no PE signature at offset " + std::to_string(pe) + ")");
  if (read16(b, pe + 4) != kMachineAmd64)
    fail("not an x86-64 image (machine " + std::to_string(read16(b, pe + 4)) + ")");
  const unsigned sectionCount = read16(b, pe + 6);
  const unsigned optionalBytes = read16(b, pe + 20);
  Pe p;
  p.characteristics = read16(b, pe + 22);
  const size_t opt = pe + 24;
  const unsigned magic = read16(b, opt);
  if (magic == kMagicPe32) fail("a PE32 (32-bit) image: only PE32+ is handled");
  if (magic != kMagicPe32Plus) fail("unknown optional header magic " + std::to_string(magic));
  if (optionalBytes < 112 + 16 * 8)
    fail("optional header too short (" + std::to_string(optionalBytes) + " bytes)");
  p.entryRva = read32(b, opt + 16);
  p.imageBase = read64(b, opt + 24);
  p.sectionAlignment = read32(b, opt + 32);
  p.sizeOfImage = read32(b, opt + 56);
  p.sizeOfHeaders = read32(b, opt + 60);
  p.subsystem = read16(b, opt + 68);
  p.dllCharacteristics = read16(b, opt + 70);
  p.stackReserve = read64(b, opt + 72);
  p.stackCommit = read64(b, opt + 80);
  p.heapReserve = read64(b, opt + 88);
  p.heapCommit = read64(b, opt + 96);
  const unsigned dirCount = read32(b, opt + 108);
  for (unsigned i = 0; i < 16 && i < dirCount; ++i) {
    p.dirRva[i] = read32(b, opt + 112 + 8 * i);
    p.dirSize[i] = read32(b, opt + 116 + 8 * i);
  }
  const size_t table = opt + optionalBytes;
  for (unsigned i = 0; i < sectionCount; ++i) {
    const size_t s = table + 40 * i;
    read32(b, s + 36); // the whole header is in the file
    Section sec;
    sec.name.assign(reinterpret_cast<const char*>(&b[s]),
                    strnlen(reinterpret_cast<const char*>(&b[s]), 8));
    sec.virtualSize = read32(b, s + 8);
    sec.rva = read32(b, s + 12);
    sec.rawSize = read32(b, s + 16);
    sec.rawOffset = read32(b, s + 20);
    sec.characteristics = read32(b, s + 36);
    if (sec.rawSize != 0 && sec.rawOffset != 0 &&
        (sec.rawOffset > b.size() || sec.rawSize > b.size() - sec.rawOffset))
      fail("truncated: section " + sec.name + "'s " + std::to_string(sec.rawSize) +
           " file bytes at offset " + std::to_string(sec.rawOffset) + " are past the end of the " +
           std::to_string(b.size()) + "-byte file");
    p.sections.push_back(sec);
  }
  return p;
}

// The image as the loader maps it: SizeOfImage bytes, each section's file
// bytes (at most its virtual size) at its RVA, zeros elsewhere.
Bytes layOut(const Bytes& file, const Pe& p, unsigned* initialisedEnd) {
  Bytes image(p.sizeOfImage, 0);
  *initialisedEnd = kImageRva;
  for (const Section& s : p.sections) {
    const unsigned n = s.rawSize < s.virtualSize ? s.rawSize : s.virtualSize;
    std::memcpy(&image[s.rva], &file[s.rawOffset], n);
    if (n > 0 && s.rva + n > *initialisedEnd) *initialisedEnd = s.rva + n;
  }
  return image;
}

// What the stub can load (see the file comment); everything checked here
// is a message, not a crash, further on.
void validate(const Pe& p, const Bytes& file) {
  if (!(p.characteristics & kRelocsStripped) || p.dirSize[5] != 0)
    fail("relocations present: the stub decodes the image at its fixed base and does not relocate "
         "(link with --disable-reloc-section)");
  if (p.dllCharacteristics & kDynamicBase)
    fail("dynamic base (ASLR) requested: the image must load at its fixed base");
  if (p.imageBase != kImageBase) fail("image base is not 0x140000000 (the stub's own base)");
  if (p.sectionAlignment != 0x1000) fail("section alignment is not 4096");
  static const char* kDirNames[16] = {
      "export",      "import",       "resource",     "exception",      "security",
      "relocation",  "debug",        "architecture", "global pointer", "TLS",
      "load config", "bound import", "IAT",          "delay import",   "CLR",
      "reserved"};
  for (unsigned i = 0; i < 16; ++i)
    if (i != kDirImport && i != kDirIat && (p.dirRva[i] != 0 || p.dirSize[i] != 0))
      fail(std::string("a ") + kDirNames[i] +
           " directory is present: the stub handles imports only");
  if (p.sizeOfImage <= kImageRva || p.sizeOfImage > kMaxImageBytes)
    fail("SizeOfImage " + std::to_string(p.sizeOfImage) + " out of range");
  if (p.sections.empty()) fail("no sections");
  unsigned next = kImageRva;
  for (const Section& s : p.sections) {
    if (s.rva != next)
      fail("section " + s.name + " at RVA " + std::to_string(s.rva) + ", expected " +
           std::to_string(next) + " (sections must follow each other from RVA 0x1000)");
    const unsigned long long span = (s.virtualSize + 0xfffull) & ~0xfffull;
    if (s.virtualSize == 0 || span > p.sizeOfImage - s.rva)
      fail("section " + s.name + " lies outside the image");
    if (s.rawSize != 0 && s.rawOffset == 0)
      fail("section " + s.name + " has file bytes at offset 0");
    next = s.rva + unsigned(span);
  }
  if (next != p.sizeOfImage) fail("SizeOfImage does not end at the last section");
  if (p.entryRva < kImageRva || p.entryRva >= p.sizeOfImage)
    fail("the entry point lies outside the sections");
  (void)file;
}

// One imported function: the IAT slot the loader would fill, its DLL and name.
struct Import {
  unsigned slot;
  std::string dll, name;
  unsigned hash = 0; // nameHash(name), in what walkList() reads back
};

// The import directory as the loader reads it: every descriptor, DLL name,
// lookup and address table entry must lie in the image's file bytes, every
// import by name. `zero` marks every byte these structures occupy.
std::vector<Import> readImports(const Bytes& image, unsigned end, unsigned directory,
                                std::vector<bool>& zero) {
  zero.assign(image.size(), false);
  auto in = [&](unsigned long long rva, unsigned long long bytes) {
    return rva >= kImageRva && rva + bytes <= end;
  };
  auto mark = [&](unsigned long long rva, unsigned long long bytes) {
    for (unsigned long long i = rva; i < rva + bytes; ++i)
      zero[i] = true;
  };
  auto name = [&](unsigned long long rva, const char* what) {
    if (!in(rva, 1))
      fail(std::string("an import's ") + what + " lies outside the image's file bytes");
    for (unsigned long long i = rva; i < end; ++i)
      if (image[i] == 0) {
        mark(rva, i + 1 - rva);
        return std::string(reinterpret_cast<const char*>(&image[rva]));
      }
    fail(std::string("an import's ") + what + " is not terminated");
  };
  std::vector<Import> imports;
  for (unsigned d = directory;; d += 20) {
    if (!in(d, 20)) fail("the import directory lies outside the image's file bytes");
    mark(d, 20);
    unsigned lookup, dll, iat;
    std::memcpy(&lookup, &image[d], 4);
    std::memcpy(&dll, &image[d + 12], 4);
    std::memcpy(&iat, &image[d + 16], 4);
    if (dll == 0) return imports;
    const std::string dllName = name(dll, "DLL name");
    if (dllName.empty()) fail("an empty DLL name");
    for (unsigned i = 0;; ++i) {
      if (!in(lookup + 8ull * i, 8) || !in(iat + 8ull * i, 8))
        fail("an import lookup or address table lies outside the image's file bytes");
      mark(lookup + 8ull * i, 8);
      mark(iat + 8ull * i, 8);
      unsigned long long entry;
      std::memcpy(&entry, &image[lookup + 8ull * i], 8);
      if (entry == 0) break;
      if (entry & kOrdinalFlag) fail("an import by ordinal: the stub imports by name only");
      if (!in(entry, 2)) fail("an import's hint lies outside the image's file bytes");
      mark(entry, 2);
      imports.push_back({iat + 8 * i, dllName, name(entry + 2, "function name")});
      if (imports.back().name.empty()) fail("an empty function name");
    }
  }
}

// LoadLibraryA appends ".dll" to a name without an extension (Microsoft's
// LoadLibraryA documentation; Wine does the same): "GDI32.dll" -> "gdi32".
std::string shortDllName(const std::string& dll) {
  std::string s;
  for (char c : dll)
    s += (c >= 'A' && c <= 'Z') ? char(c - 'A' + 'a') : c;
  if (s.size() > 4 && s.compare(s.size() - 4, 4, ".dll") == 0 && s.find('.') == s.size() - 4)
    s.resize(s.size() - 4);
  return s;
}

// The hash by which the stub finds a function among its DLL's exported
// names (stub.cpp's name_hash(), the same formula): h = 31 h + c over the
// name's bytes, 32 bits.
unsigned nameHash(const std::string& name) {
  unsigned h = 0;
  for (unsigned char c : name)
    h = h * 31 + c;
  return h;
}

// The compact import list the stub walks instead of the import directory:
// per DLL, its name (NUL-terminated), the number of its functions (one
// byte) and each function's nameHash() (4 bytes, little-endian); an empty
// DLL name ends the list. The stub fills the IAT slots in order from the
// first, skipping one (the terminator of each DLL's address table) after
// each DLL: the tool checks that the IAT has this layout, and that no two
// functions of a DLL in the list share a hash. A hash could still equal
// that of another name the DLL exports before the wanted one: with 32 bits
// and ~1,600 names per DLL, about 4e-7 per function; not checkable here
// (the DLLs are Windows's).
std::string importList(const std::vector<Import>& imports) {
  std::string list;
  unsigned slot = imports.empty() ? 0 : imports[0].slot;
  size_t countAt = 0;
  for (size_t i = 0; i < imports.size(); ++i) {
    const bool first = i == 0 || imports[i].dll != imports[i - 1].dll;
    if (first) {
      if (i > 0) slot += 8; // the previous DLL's terminator
      list += shortDllName(imports[i].dll) + '\0';
      countAt = list.size();
      list += '\0';
    }
    if (imports[i].slot != slot)
      fail("the import address tables are not consecutive (one per DLL, each ended by a null "
           "slot): the stub fills them in one run");
    if ((unsigned char)list[countAt] == 255) fail("more than 255 functions from one DLL");
    ++list[countAt];
    for (size_t j = i; j-- > 0 && imports[j].dll == imports[i].dll;)
      if (nameHash(imports[j].name) == nameHash(imports[i].name))
        fail(imports[i].name + " and " + imports[j].name + " have the same hash");
    const unsigned h = nameHash(imports[i].name);
    for (unsigned k = 0; k < 4; ++k)
      list += char(h >> 8 * k);
    slot += 8;
  }
  list += '\0';
  return list;
}

// The stub's walk of `list` (at `at` in `image`), as in stub.cpp: the
// (slot, DLL, function's hash) it would fill. For `check`.
std::vector<Import> walkList(const Bytes& image, unsigned at, unsigned slot) {
  std::vector<Import> out;
  auto byte = [&]() {
    if (at >= image.size()) fail("the import list runs past the image");
    return image[at++];
  };
  while (true) {
    std::string dll;
    for (unsigned char c; (c = byte()) != 0;)
      dll += char(c);
    if (dll.empty()) return out;
    for (unsigned n = byte(); n != 0; --n, slot += 8) {
      unsigned h = 0;
      for (unsigned k = 0; k < 4; ++k)
        h |= unsigned(byte()) << 8 * k;
      out.push_back({slot, dll, "", h});
    }
    slot += 8;
  }
}

struct Image {
  Pe pe;
  Bytes image;
  unsigned end; // RVA after the last initialised byte: the decoded part is [0x1000, end)
  std::vector<Import> imports;
  // What the stub decodes: the image with every byte of the import
  // directory's structures zeroed (intro.exe never reads them; the IAT is
  // filled by the stub) and the compact import list (importList()) written
  // right after the IAT, at listRva.
  Bytes packed;
  unsigned listRva, iatRva;
};

// Runs f, prefixing any error's message with `path`.
template <class F> auto about(const char* path, F f) {
  try {
    return f();
  } catch (const Error& e) {
    fail(std::string(path) + ": " + e.message);
  }
}

Image load(const char* path) {
  return about(path, [&] {
    Bytes file = readFile(path);
    Image im;
    im.pe = parse(file);
    validate(im.pe, file);
    im.image = layOut(file, im.pe, &im.end);
    if (im.pe.dirRva[kDirImport] == 0) fail("no import directory (the stub expects one)");
    std::vector<bool> zero;
    im.imports = readImports(im.image, im.end, im.pe.dirRva[kDirImport], zero);
    if (im.imports.empty()) fail("no imported function (the stub expects some)");
    const std::string list = importList(im.imports);
    im.packed = im.image;
    for (size_t i = 0; i < zero.size(); ++i)
      if (zero[i]) im.packed[i] = 0;
    im.iatRva = im.imports[0].slot;
    im.listRva = im.imports.back().slot + 16; // after the last DLL's terminator
    for (size_t i = 0; i < list.size(); ++i) {
      const size_t at = im.listRva + i;
      if (at >= im.end || (!zero[at] && im.image[at] != 0))
        fail("no room for the import list after the import address table");
      im.packed[at] = (unsigned char)list[i];
    }
    return im;
  });
}

// `path` appears whole or not at all: written beside it, then renamed.
// `executable`: mode 0755 (an exe), else 0644.
void writeFile(const std::string& path, const std::string& text, bool executable = false) {
  const std::string temp = path + ".tmp" + std::to_string(getpid());
  FILE* f = std::fopen(temp.c_str(), "wb");
  if (!f) fail("cannot create " + temp + ": " + std::strerror(errno));
  bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  ok = std::fclose(f) == 0 && ok;
  ok = chmod(temp.c_str(), executable ? 0755 : 0644) == 0 && ok;
  if (!ok || std::rename(temp.c_str(), path.c_str()) != 0) {
    std::remove(temp.c_str());
    fail("cannot write " + path);
  }
}

// Decodes `bytes` bytes from the `available` bytes at `encoded`. On damaged
// input the decoder may read up to model::max_encoded(bytes) bytes (codec.h):
// it gets a zero-padded copy that long, so it never reads past the buffer.
Bytes decodeNative(const unsigned char* encoded, size_t available, unsigned bytes) {
  Bytes in(encoded, encoded + available);
  if (in.size() < rt64k::pack::model::max_encoded(bytes))
    in.resize(rt64k::pack::model::max_encoded(bytes), 0);
  Bytes out(bytes), work(rt64k::pack::kWorkBytes, 0);
  rt64k::pack::decode(in.data(), out.data(), bytes, work.data());
  return out;
}

// The PE header's CheckSum of `file` (the field itself counted as zero):
// 16-bit little-endian words summed with the carries folded back in, plus the
// file's length (the algorithm of Microsoft's CheckSumMappedFile; it gives
// the value GNU ld wrote into intro.exe). Windows checks it only for drivers
// and boot files; `finish` keeps it right after changing a header.
unsigned peChecksum(const Bytes& file) {
  const size_t field = read32(file, 0x3c) + 24 + 64;
  unsigned long long sum = 0;
  for (size_t i = 0; i < file.size(); i += 2) {
    unsigned word = file[i] | (i + 1 < file.size() ? file[i + 1] << 8 : 0);
    if (i == field || i == field + 2) word = 0;
    sum += word;
    sum = (sum & 0xffff) + (sum >> 16);
  }
  sum = (sum & 0xffff) + (sum >> 16);
  return unsigned(sum + file.size());
}

// The encoded image of `im` (what the stub decodes): the codec is
// deterministic, so `check` encodes again to find the payload's length.
Bytes encodeImage(const Image& im) {
  const unsigned bytes = im.end - kImageRva;
  Bytes encoded(bytes + bytes / 4 + 4096), work(rt64k::pack::kWorkBytes, 0);
  const unsigned n = rt64k::pack::encode(&im.packed[kImageRva], bytes, encoded.data(),
                                         unsigned(encoded.size()), work.data());
  if (n == 0) fail("the codec's output did not fit " + std::to_string(encoded.size()) + " bytes");
  encoded.resize(n);
  return encoded;
}

int pack(const char* inPath, const char* outPath) {
  const Image im = load(inPath);
  const unsigned bytes = im.end - kImageRva;
  const unsigned char* body = &im.packed[kImageRva];
  const Bytes encoded = encodeImage(im);
  const unsigned n = unsigned(encoded.size());
  // The stub must get back what went in: decode here first, natively.
  if (decodeNative(encoded.data(), n, bytes) != Bytes(body, body + bytes))
    fail("internal error: the codec does not round-trip this image");
  std::string s;
  s += "# Generated by rt64k-pack from " + std::string(inPath) + ": do not edit.\n";
  s += "# " + std::to_string(bytes) + " image bytes encoded into " + std::to_string(n) + ".\n";
  s += "  .section .rt64k_image,\"bwx\"\n";
  s += "  .space " + std::to_string(im.pe.sizeOfImage - kImageRva) + "\n";
  s += "  .section .rt64k_payload,\"dr\"\n  .globl rt64k_payload\nrt64k_payload:\n";
  s += "  .long " + std::to_string(bytes) + ", " + std::to_string(im.pe.entryRva) + ", " +
       std::to_string(im.listRva) + ", " + std::to_string(im.iatRva) + "\n";
  for (unsigned i = 0; i < n; i += 32) {
    s += "  .byte ";
    for (unsigned j = i; j < n && j < i + 32; ++j)
      s += std::to_string(encoded[j]) + (j + 1 < n && j + 1 < i + 32 ? "," : "");
    s += "\n";
  }
  writeFile(outPath, s);
  std::printf("rt64k-pack: %s: %u image bytes -> %u encoded (%.1f %%)\n", inPath, bytes, n,
              100.0 * n / bytes);
  return 0;
}

// Reads the packed exe back: its headers copy the original's, its first
// section is the uninitialised RWX room for the image at RVA 0x1000, its
// second holds the payload at its start, and the payload decodes to the
// original's image. Prints the bytes of each part.
int check(const char* originalPath, const char* packedPath) {
  const Image im = load(originalPath);
  // Every failure below is about the packed exe.
  return about(packedPath, [&] {
    const Bytes file = readFile(packedPath);
    const Pe p = parse(file);
    const Pe& o = im.pe;
    if (p.imageBase != o.imageBase || p.subsystem != o.subsystem ||
        p.stackReserve != o.stackReserve || p.stackCommit != o.stackCommit ||
        p.heapReserve != o.heapReserve || p.heapCommit != o.heapCommit ||
        p.characteristics != o.characteristics || p.dllCharacteristics != o.dllCharacteristics)
      fail("the packed exe's header fields (base, subsystem, stack, heap, characteristics) differ "
           "from the original's");
    if (p.dirSize[5] != 0 || p.dirSize[3] != 0 || p.dirSize[9] != 0)
      fail("the packed exe has relocations, exception data or TLS");
    if (p.sections.size() != 2)
      fail("the packed exe has " + std::to_string(p.sections.size()) + " sections, expected 2");
    const Section& room = p.sections[0];
    const Section& packed = p.sections[1];
    if (room.rva != kImageRva || room.rawSize != 0 ||
        room.characteristics != (kScnRwx | kScnUninitialised) ||
        room.virtualSize < o.sizeOfImage - kImageRva + rt64k::pack::kWorkBytes ||
        (room.characteristics & kScnRwx) != kScnRwx)
      fail("the packed exe's first section is not an uninitialised RWX section at RVA 0x1000 "
           "covering the image and the model memory");
    if (packed.rawOffset == 0 || packed.rawOffset != p.sizeOfHeaders ||
        packed.rawSize < kPayloadHeaderBytes)
      fail("the packed exe's second section does not follow the headers");
    const unsigned char* payload = &file[packed.rawOffset];
    auto field = [&](unsigned i) { return read32(file, packed.rawOffset + 4 * i); };
    const unsigned bytes = field(0), entry = field(1), list = field(2), iat = field(3);
    if (bytes != im.end - kImageRva || entry != o.entryRva || list != im.listRva ||
        iat != im.iatRva)
      fail("the payload record (size, entry, import list, IAT) does not match the original");
    // The record does not hold the payload's length: the same encoding
    // again gives it, and the payload must be those bytes.
    const Bytes expected = encodeImage(im);
    const unsigned encodedBytes = unsigned(expected.size());
    if (kPayloadHeaderBytes + encodedBytes > packed.rawSize)
      fail("the payload runs past its section");
    if (std::memcmp(payload + kPayloadHeaderBytes, expected.data(), encodedBytes) != 0)
      fail("the payload is not the encoding of the original's image");
    const Bytes decoded = decodeNative(payload + kPayloadHeaderBytes, encodedBytes, bytes);
    // Byte for byte the original except for its import directory's
    // structures: zero, the IAT to be filled by the stub, and the list.
    Bytes image = im.image;
    std::memcpy(&image[kImageRva], decoded.data(), bytes);
    unsigned differing = 0;
    for (unsigned i = kImageRva; i < im.end; ++i)
      if (image[i] != im.image[i]) {
        if (image[i] != im.packed[i])
          fail("the decoded image differs from the packed one at RVA " + std::to_string(i));
        ++differing;
      }
    // The stub's walk of the decoded list fills exactly the original's IAT
    // slots with the original's functions.
    const std::vector<Import> walked = walkList(image, list, iat);
    if (walked.size() != im.imports.size())
      fail("the import list names " + std::to_string(walked.size()) + " functions, the original " +
           std::to_string(im.imports.size()));
    for (size_t i = 0; i < walked.size(); ++i)
      if (walked[i].slot != im.imports[i].slot || walked[i].hash != nameHash(im.imports[i].name) ||
          walked[i].dll != shortDllName(im.imports[i].dll))
        fail("import " + std::to_string(i) + " (" + walked[i].dll + ", hash " +
             std::to_string(walked[i].hash) + ") is not the original's " + im.imports[i].name);
    // The import directory and names in the headers (rt64k-pack finish),
    // the address table at the second section's end.
    const unsigned importDir = p.dirRva[kDirImport], iatRva = p.dirRva[kDirIat];
    if (importDir == 0 || importDir + p.dirSize[kDirImport] > p.sizeOfHeaders)
      fail("the packed exe's import directory is not in its headers");
    if (iatRva < packed.rva || iatRva + p.dirSize[kDirIat] != packed.rva + packed.virtualSize)
      fail("the packed exe's import address table does not end its second section");
    const unsigned payloadBytes = kPayloadHeaderBytes + encodedBytes;
    const unsigned importBytes = p.dirSize[kDirIat];
    const unsigned stubBytes = packed.virtualSize - payloadBytes - importBytes;
    const int padding = int(packed.rawSize) - int(packed.virtualSize);
    std::printf("rt64k-pack check: %s decodes to %s's %u image bytes: identical but for %u bytes "
                "of its import directory, replaced by a list of its %zu imports, which give the "
                "same functions' hashes for the same IAT slots\n",
                packedPath, originalPath, bytes, differing, walked.size());
    std::printf("  %zu bytes = headers %u + payload %u (record %u, encoded %u) + stub code and "
                "constants %u + imports %u + padding %d (the import directory and names in the "
                "headers, the address table's last zeros not in the file)\n",
                file.size(), p.sizeOfHeaders, payloadBytes, kPayloadHeaderBytes, encodedBytes,
                stubBytes, importBytes, padding);
    if (std::memcmp(&file[rt64k::pack::model::kTwoByteHeaderOffset], rt64k::pack::model::kTwoByte,
                    sizeof rt64k::pack::model::kTwoByte) != 0)
      fail("the packed exe's headers do not hold the decoder's 0F-opcode table");
    if (read32(file, read32(file, 0x3c) + 24 + 64) != peChecksum(file))
      fail("the packed exe's CheckSum field is not its checksum");
    if (p.sizeOfHeaders + packed.rawSize != file.size())
      fail("the packed exe has bytes after its last section");
    return 0;
  });
}

// GNU ld writes an executable uninitialised section (the image's room) as
// code with file bytes: SizeOfRawData = its virtual size at file offset 0,
// characteristics CNT_CODE. The PE format wants 0 raw bytes and
// CNT_UNINITIALIZED_DATA for it (what ld writes for .bss, and UPX for its
// UPX0); ld has no way to say so, so this step rewrites the first section's
// header of the linked exe `in` into `out`.
// size14: the headers' free bytes take what the loader and the stub only
// read. stub.ld puts the import directory, its null entry and the names at
// the end of the second section, after the import address table; here the
// DOS stub goes (the PE header moves to offset 0x40: the loader reads only
// e_magic and e_lfanew of the DOS header), the names go into the DOS
// header's unused bytes (0x02-0x3b), the directory right after the section
// table, the decoder's 0F-opcode table after it (model.h's
// kTwoByteHeaderOffset, where stub.ld puts its symbol), and the section ends
// at its last non-zero byte before the moved part (the loader zero-fills the
// rest of its virtual size). The directory's RVA is its file offset (the
// headers are mapped at RVA 0); the address table stays in the writable
// section. Fails, with nothing written, on any other layout.
void moveImports(Bytes& file, const Pe& p) {
  const unsigned oldPe = read32(file, 0x3c);
  const size_t tableEnd = oldPe + 24 + read16(file, oldPe + 20) + 40 * p.sections.size();
  constexpr unsigned kNewPe = 0x40, kNames = 0x02, kNamesEnd = 0x3c;
  if (oldPe < kNewPe || tableEnd > p.sizeOfHeaders) fail("unexpected PE header layout");
  std::memmove(&file[kNewPe], &file[oldPe], tableEnd - oldPe);
  std::memset(&file[kNewPe + (tableEnd - oldPe)], 0, oldPe - kNewPe);
  std::memset(&file[kNames], 0, kNamesEnd - kNames);
  write32(file, 0x3c, kNewPe);
  const unsigned opt = kNewPe + 24, free = unsigned(tableEnd - oldPe + kNewPe + 3) & ~3u;
  const Section& sec = p.sections[1];
  const size_t secHeader = kNewPe + 24 + read16(file, kNewPe + 20) + 40;
  const unsigned dir = p.dirRva[kDirImport], iat = p.dirRva[kDirIat];
  const unsigned end = sec.rva + sec.virtualSize; // the moved part: [dir, end)
  if (dir < sec.rva || dir >= end || sec.rawSize < sec.virtualSize || iat < sec.rva ||
      iat + p.dirSize[kDirIat] > dir)
    fail("the import directory is not at the end of the second section, after the address table");
  const size_t from = sec.rawOffset + (dir - sec.rva);
  // The descriptors up to the null entry; the names after them.
  unsigned dirBytes = 0;
  for (;; dirBytes += 20) {
    if (dir + dirBytes + 20 > end) fail("the import directory has no null entry");
    if (read32(file, from + dirBytes + 12) == 0 && read32(file, from + dirBytes + 16) == 0) break;
  }
  dirBytes += 20;
  const unsigned names = dir + dirBytes, nameBytes = end - names;
  if (free + dirBytes > rt64k::pack::model::kTwoByteHeaderOffset || kNames + nameBytes > kNamesEnd)
    fail("the import directory (" + std::to_string(dirBytes) + " bytes) or its names (" +
         std::to_string(nameBytes) + ") do not fit into the headers' free bytes");
  std::memcpy(&file[free], &file[from], dirBytes);
  std::memcpy(&file[kNames], &file[from + dirBytes], nameBytes);
  std::memcpy(&file[rt64k::pack::model::kTwoByteHeaderOffset], rt64k::pack::model::kTwoByte,
              sizeof rt64k::pack::model::kTwoByte);
  if (rt64k::pack::model::kTwoByteHeaderOffset + sizeof rt64k::pack::model::kTwoByte >
      p.sizeOfHeaders)
    fail("no room for the 0F-opcode table in the headers");
  auto moved = [&](unsigned rva) {
    if (rva < names || rva >= end) fail("an import name outside the moved part");
    return rva - names + kNames;
  };
  // Descriptors: the names move; the lookup table must be absent (0).
  for (unsigned d = free; d + 20 < free + dirBytes; d += 20) {
    if (read32(file, d) != 0) fail("an import lookup table (the stub's has none)");
    const unsigned thunk = read32(file, d + 16);
    if (thunk < iat || thunk >= dir) fail("an import descriptor's address table outside its own");
    write32(file, d + 12, moved(read32(file, d + 12)));
  }
  // The address table's entries (RVAs of hint/name entries) move too.
  for (unsigned slot = iat; slot + 8 <= dir; slot += 8) {
    const size_t at = sec.rawOffset + (slot - sec.rva);
    if (read32(file, at) != 0) write32(file, at, moved(read32(file, at)));
  }
  write32(file, opt + 112 + 8 * kDirImport, free);
  // The section's file bytes end at its last non-zero byte before `dir`.
  unsigned kept = dir - sec.rva;
  while (kept > 0 && file[sec.rawOffset + kept - 1] == 0)
    --kept;
  const unsigned align = read32(file, opt + 36); // FileAlignment
  const unsigned raw = (kept + align - 1) / align * align;
  write32(file, secHeader + 8, dir - sec.rva); // VirtualSize: up to the address table's end
  write32(file, secHeader + 16, raw);          // SizeOfRawData
  file.resize(sec.rawOffset + raw);
  std::memset(&file[sec.rawOffset + kept], 0, raw - kept);
}

int finish(const char* inPath, const char* outPath) {
  return about(inPath, [&] {
    Bytes file = readFile(inPath);
    const Pe p = parse(file);
    if (p.sections.size() != 2 || p.sections[0].rva != kImageRva || p.sections[0].rawOffset != 0 ||
        (p.sections[0].characteristics & kScnRwx) != kScnRwx)
      fail("not a linked stub (two sections, the first at RVA 0x1000 without file bytes, RWX)");
    const unsigned pe = read32(file, 0x3c);
    const size_t header = pe + 24 + read16(file, pe + 20);
    write32(file, header + 16, 0);                           // SizeOfRawData
    write32(file, header + 36, kScnRwx | kScnUninitialised); // characteristics
    moveImports(file, p);
    const unsigned pe2 = read32(file, 0x3c);
    write32(file, pe2 + 24 + 64, peChecksum(file));
    std::string text(file.begin(), file.end());
    writeFile(outPath, text, true);
    return 0;
  });
}

const char* kUsage =
    "rt64k-pack - the intro's own exe packer (docs/win32.md \"Round eight: our own packer\")\n"
    "\n"
    "usage:\n"
    "  rt64k-pack pack IN.exe OUT.s\n"
    "      encodes IN.exe's image (PE32+, fixed base 0x140000000, no relocations, imports by\n"
    "      name) and writes the assembler file the stub is linked with\n"
    "  rt64k-pack finish LINKED.exe PACKED.exe\n"
    "      marks the linked stub's first section uninitialised (no file bytes), as ld cannot\n"
    "  rt64k-pack check IN.exe PACKED.exe\n"
    "      decodes PACKED.exe's payload and compares it with IN.exe's image; prints the bytes\n"
    "      of each part of PACKED.exe\n";

} // namespace

int main(int argc, char** argv) {
  try {
    if (argc == 4 && std::strcmp(argv[1], "pack") == 0) return pack(argv[2], argv[3]);
    if (argc == 4 && std::strcmp(argv[1], "finish") == 0) return finish(argv[2], argv[3]);
    if (argc == 4 && std::strcmp(argv[1], "check") == 0) return check(argv[2], argv[3]);
    std::fputs(kUsage, stderr);
    return 2;
  } catch (const Error& e) {
    std::fprintf(stderr, "rt64k-pack: %s\n", e.message.c_str());
    return 1;
  }
}
