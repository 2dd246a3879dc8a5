// decode.cpp - the packer's decoder: runs in the packed exe's stub, so it is
// freestanding (no C runtime, no heap, no OS calls) and small.
#include "codec.h"
#include "model.h"

namespace rt64k::pack {

static_assert(sizeof(model::Tables) <= kWorkBytes, "the model tables exceed kWorkBytes");

void decode(const unsigned char* in, unsigned char* out, unsigned size, void* work) {
  using namespace model;
  const u32 bound = max_encoded(size);
  Predictor m;
  m.init(work, in); // the header: at most 4 + 2 * kMaxModels bytes, within bound
  const u8* at = in + 4 + 2 * m.n;
  const u8* end = in + bound;
  auto next = [&]() -> u32 { return at < end ? *at++ : 0u; };
  // x2 starts at 0: the shift loop before the first bit reads the stream's
  // first four bytes (x2 becomes 0xFFFFFFFF), so no loop of its own.
  u32 x1 = 0, x2 = 0, x = 0;
  u32 field = 0; // 1 + the offset of a rel32 field being decoded
  for (u32 k = 0; k < size; ++k) {
    if ((m.x86.rel & m.flags) && k + 4 <= size) field = k + 1;
    u32 c = 1;
    while (c < 256) {
      while (((x1 ^ x2) & 0xFF000000u) == 0) { // as the encoder did after the last bit
        x1 <<= 8;
        x2 = x2 << 8 | 255;
        x = x << 8 | next();
      }
      u32 xmid = x1 + ((x2 - x1) >> 12) * static_cast<u32>(m.p());
      int y = x <= xmid;
      if (y)
        x2 = xmid;
      else
        x1 = xmid + 1;
      m.update(y);
      c = c << 1 | static_cast<u32>(y);
    }
    out[k] = static_cast<u8>(c);
    if (field && k == field + 2) { // the field's last byte: back to relative
      u8* f = out + field - 1;
      u32 v; // little-endian, as x86 is (4-byte copies compile to moves)
      __builtin_memcpy(&v, f, 4);
      v -= field - 1;
      __builtin_memcpy(f, &v, 4);
      field = 0;
    }
  }
}

} // namespace rt64k::pack
