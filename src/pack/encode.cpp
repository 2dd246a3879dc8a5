// encode.cpp - the packer's encoder (host only): the same model as
// decode.cpp, driving the arithmetic coder the other way.
#include "encode.h"

#include <cmath>
#include <cstring>
#include <vector>

namespace rt64k::pack {

using namespace model;

unsigned encode_with(const Params& prm, const unsigned char* in, unsigned size, unsigned char* out,
                     unsigned capacity, void* work, double* byte_bits) {
  const u32 limit = capacity < max_encoded(size) ? capacity : max_encoded(size);
  std::vector<u8> src(in, in + size);
  u32 n = 0;
  bool overflow = false;
  auto put = [&](u32 b) {
    if (n < limit)
      out[n++] = static_cast<u8>(b);
    else
      overflow = true;
  };
  if (prm.n < 1 || prm.n > kMaxModels) return 0;
  u8 header[4 + 2 * kMaxModels] = {prm.n, prm.flags, static_cast<u8>(prm.data_end),
                                   static_cast<u8>(prm.data_end >> 8)};
  for (int i = 0; i < prm.n; ++i) {
    header[4 + 2 * i] = static_cast<u8>(prm.mask[i]);
    header[5 + 2 * i] = static_cast<u8>(prm.mask[i] >> 8);
  }
  for (u32 i = 0; i < header_bytes(prm); ++i)
    put(header[i]);
  Predictor m;
  m.init(work, header);
  u32 x1 = 0, x2 = 0xFFFFFFFFu;
  for (u32 k = 0; k < size && !overflow; ++k) {
    if ((m.x86.rel & prm.flags) && k + 4 <= size) { // a rel32 field: code it as absolute
      u32 v = src[k] | src[k + 1] << 8 | src[k + 2] << 16 | static_cast<u32>(src[k + 3]) << 24;
      v += k;
      for (int i = 0; i < 4; ++i, v >>= 8)
        src[k + i] = static_cast<u8>(v);
    }
    for (int j = 7; j >= 0; --j) {
      int y = src[k] >> j & 1;
      const int p1 = m.p();
      if (byte_bits) byte_bits[k] -= std::log2((y ? p1 : 4096 - p1) / 4096.0);
      u32 xmid = x1 + ((x2 - x1) >> 12) * static_cast<u32>(p1);
      if (y)
        x2 = xmid;
      else
        x1 = xmid + 1;
      m.update(y);
      while (((x1 ^ x2) & 0xFF000000u) == 0) {
        put(x2 >> 24);
        x1 <<= 8;
        x2 = x2 << 8 | 255;
      }
    }
  }
  // x1's four bytes end the stream: the decoder's window then lies in
  // [x1, x2], and it has read at most the n bytes written (it shifts before
  // each bit, not after, so it skips the reads of the last shifts). One
  // byte that relied on zeros after the stream would save 3 bytes but bind
  // the caller to them.
  for (int i = 0; i < 4; ++i, x1 <<= 8)
    put(x1 >> 24);
  if (overflow) return 0;
  return n;
}

Params default_params() {
  Params p{};
  // Found by pack-measure --search on intro.exe's .text + .idata (coordinate
  // descent over 48 candidates per slot, from orders 0-4, 6, sparse, column
  // and x86 masks; five rounds as the model changed): 16,498 -> 16,037 bytes;
  // a sixth on round eight's merged exe (the image the packer encodes, 42,672
  // bytes): 15,699 -> 15,682; a seventh on round nine's (size13: three
  // passes, the same 42,672 bytes): 15,861 -> 15,846 (0x00C -> 0x004,
  // 0x007 -> 0x011, 0x209 -> 0x00D), and a pass on size13's image: 15,737
  // -> 15,731 (0x011 -> 0x00A); an eighth on round ten's (size14: two
  // passes on adapt13's image, 16,037 -> 16,026: 0x00A -> 0x011, 0x00D ->
  // 0x209; after the cold sources' -fno-jump-tables, one pass with 33 more
  // candidates, 15,985 -> 15,948: 0x011 -> 0x013, 0x209 -> 0x20A, 0x202 ->
  // 0x019, 0x07F -> 0x201; a second pass found nothing).
  const u16 masks[] = {0x000, 0x001, 0xA01, 0x003, 0x004, 0x204, 0xC01,
                       0x002, 0x013, 0x20A, 0x019, 0x201, 0x200, 0xC00};
  p.n = sizeof masks / sizeof masks[0];
  for (int i = 0; i < p.n; ++i)
    p.mask[i] = masks[i];
  p.flags = kFlagBranch | kFlagRip;
  return p;
}

Params choose_data_region(Params prm, const unsigned char* in, unsigned size, void* work) {
  prm.data_end = 0;
  if (size < 4096) return prm;
  // Two passes price every byte as code (no data region) and as data (all
  // of it, up to the header's limit); bytes before a split cost what the
  // data pass says exactly, bytes after it about what the code pass says.
  std::vector<double> as_code(size, 0.0), as_data(size, 0.0);
  std::vector<u8> scratch(max_encoded(size));
  const u32 cap = static_cast<u32>(scratch.size());
  encode_with(prm, in, size, scratch.data(), cap, work, as_code.data());
  std::memset(work, 0, kWorkBytes);
  Params all = prm;
  all.data_end = static_cast<u16>(size / 4 < 65535 ? size / 4 : 65535);
  encode_with(all, in, size, scratch.data(), cap, work, as_data.data());
  std::memset(work, 0, kWorkBytes);
  double code_after = 0, data_before = 0;
  for (u32 k = 0; k < size; ++k)
    code_after += as_code[k];
  double best = code_after;
  for (u32 k = 0; k < 4u * all.data_end; ++k) {
    data_before += as_data[k];
    code_after -= as_code[k];
    if ((k + 1) % 4 == 0 && data_before + code_after < best) {
      best = data_before + code_after;
      prm.data_end = static_cast<u16>((k + 1) / 4);
    }
  }
  return prm;
}

unsigned encode(const unsigned char* in, unsigned size, unsigned char* out, unsigned capacity,
                void* work) {
  return encode_with(choose_data_region(default_params(), in, size, work), in, size, out, capacity,
                     work);
}

} // namespace rt64k::pack
