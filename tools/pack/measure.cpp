// measure.cpp - pack-measure: the codec's bytes on given files (concatenated),
// with a round-trip check. Usage:
//   pack-measure FILE... [--flags N] [--data BYTES] [--masks m,m,...] [--search PASSES]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "encode.h"

namespace {

bool read_file(const char* path, std::vector<unsigned char>& data) {
  FILE* f = std::fopen(path, "rb");
  if (!f) return false;
  unsigned char buf[65536];
  size_t got;
  while ((got = std::fread(buf, 1, sizeof buf, f)) > 0)
    data.insert(data.end(), buf, buf + got);
  bool ok = !std::ferror(f);
  std::fclose(f);
  return ok;
}

} // namespace

int main(int argc, char** argv) {
  using namespace rt64k::pack;
  model::Params prm = default_params();
  std::vector<unsigned char> data;
  int search = 0;
  long data_bytes = -1; // the data region's bytes; -1: chosen as encode() does
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto value = [&]() -> long {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "pack-measure: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return std::strtol(argv[++i], nullptr, 0);
    };
    if (a == "--search")
      search = static_cast<int>(value());
    else if (a == "--data")
      data_bytes = value();
    else if (a == "--flags")
      prm.flags = static_cast<unsigned char>(value());
    else if (a == "--masks") {
      if (i + 1 >= argc) return 2;
      const char* s = argv[++i];
      prm.n = 0;
      while (*s && prm.n < model::kMaxModels) {
        char* end;
        prm.mask[prm.n++] = static_cast<unsigned short>(std::strtoul(s, &end, 16));
        s = *end == ',' ? end + 1 : end;
        if (end == s && *end) break;
      }
    } else if (!read_file(argv[i], data)) {
      std::fprintf(stderr, "pack-measure: cannot read %s\n", argv[i]);
      return 1;
    }
  }
  if (data.empty()) {
    std::fprintf(stderr, "usage: pack-measure FILE... [--flags N] "
                         "[--masks m,m,...]\n");
    return 2;
  }
  const unsigned size = static_cast<unsigned>(data.size());
  std::vector<unsigned char> work(kWorkBytes), packed(model::max_encoded(size) + 64, 0);
  if (data_bytes >= 0)
    prm.data_end = static_cast<unsigned short>(data_bytes / 4);
  else
    prm = choose_data_region(prm, data.data(), size, work.data());
  if (search) {
    // Coordinate descent over the models' masks (Crinkler's approach):
    // each slot in turn takes the candidate mask that gives the fewest bytes.
    auto cost = [&](const model::Params& p) {
      std::fill(work.begin(), work.end(), 0);
      return encode_with(p, data.data(), size, packed.data(), static_cast<unsigned>(packed.size()),
                         work.data());
    };
    // Candidates: short and sparse byte masks, the x86 parse's contexts
    // alone and with the last bytes.
    const std::vector<unsigned short> cands = {
        0x000, 0x001, 0x003, 0x007, 0x00F, 0x01F, 0x03F, 0x07F, 0x0FF, 0x002, 0x004, 0x005, 0x006,
        0x00E, 0x00C, 0x008, 0x010, 0x030, 0x009, 0x00B, 0x00D, 0x200, 0x201, 0x203, 0x207, 0x202,
        0x204, 0x400, 0x401, 0x403, 0x600, 0x601, 0x800, 0x801, 0xA00, 0xA01, 0xE00, 0xE01, 0xC00,
        0xC01, 0x011, 0x020, 0x040, 0x080, 0x0F0, 0x00A, 0x205, 0x209,
        // size14: more sparse byte masks and x86 contexts with bytes -2..-4
        // (0x013, 0x019 and 0x20A were chosen on round ten's image).
        0x013, 0x019, 0x021, 0x041, 0x081, 0x012, 0x014, 0x018, 0x210, 0x211, 0x212, 0x220, 0xA02,
        0xA03, 0x603, 0xC03, 0x803, 0xE03, 0x402, 0x404, 0x20A, 0x20B, 0x20F, 0x206, 0x802, 0xA04,
        0xC02, 0x015, 0x01B, 0x0C0, 0x0E0, 0x0FE};
    std::printf("drop-one:");
    for (int i = 0; i < prm.n; ++i) {
      model::Params p = prm;
      for (int j = i; j + 1 < p.n; ++j)
        p.mask[j] = p.mask[j + 1];
      --p.n;
      std::printf(" %x:%u", prm.mask[i], cost(p));
      std::fflush(stdout);
    }
    std::printf("\n");
    unsigned best = cost(prm);
    std::printf("start %u\n", best);
    std::fflush(stdout);
    for (int pass = 0; pass < search; ++pass) {
      for (int slot = 0; slot < model::kMaxModels; ++slot) {
        if (slot > prm.n) break;
        model::Params p = prm;
        if (slot == prm.n) p.n = static_cast<unsigned char>(prm.n + 1);
        for (unsigned short m : cands) {
          p.mask[slot] = m;
          unsigned c = cost(p);
          if (c < best) {
            best = c;
            prm = p;
          }
        }
        std::printf("pass %d slot %d: %u bytes, masks", pass, slot, best);
        for (int i = 0; i < prm.n; ++i)
          std::printf("%s%x", i ? "," : " ", prm.mask[i]);
        std::printf("\n");
        std::fflush(stdout);
      }
    }
    std::fill(work.begin(), work.end(), 0);
  }
  auto t0 = std::chrono::steady_clock::now();
  unsigned n = encode_with(prm, data.data(), size, packed.data(),
                           static_cast<unsigned>(packed.size()), work.data());
  auto t1 = std::chrono::steady_clock::now();
  if (n == 0) {
    std::fprintf(stderr, "pack-measure: encode failed\n");
    return 1;
  }
  std::fill(work.begin(), work.end(), 0);
  std::fill(packed.begin() + n, packed.end(), 0xEE); // decode reads the n bytes only
  std::vector<unsigned char> back(size);
  auto t2 = std::chrono::steady_clock::now();
  decode(packed.data(), back.data(), size, work.data());
  auto t3 = std::chrono::steady_clock::now();
  bool ok = back == data;
  std::printf("data region %u bytes; ", 4u * prm.data_end);
  std::printf("%u -> %u bytes (%.4f bpc), encode %.0f ms, decode %.0f ms, round trip %s\n", size, n,
              8.0 * n / size, std::chrono::duration<double, std::milli>(t1 - t0).count(),
              std::chrono::duration<double, std::milli>(t3 - t2).count(), ok ? "ok" : "FAILED");
  return ok ? 0 : 1;
}
