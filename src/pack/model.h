// model.h - the context-mixing model shared by the packer's encoder (host)
// and decoder (the packed exe's stub). Freestanding: integers only, no C
// runtime, no heap; every table lives in the caller's zeroed work memory.
//
// Ideas and formulas, from public descriptions (our own code):
// - the binary arithmetic coder with 12-bit probabilities, carry-less, a
//   32-bit range that shifts out a byte when its top bytes agree: Matt
//   Mahoney's lpaq1 (2007) Encoder/Decoder;
// - the squash() interpolation table, stretch() as its inverse, the logistic
//   mixer (weights trained by err * input) and the APM/SSE stage: lpaq1;
// - each model as a mask of which of the last 8 bytes form its context, the
//   encoder choosing the masks and storing them in the header: Crinkler
//   (Blueberry & Mentor, "Crinkler" notes and Assembly 2007 seminar);
// - counters whose learning rate falls as 1/(n+1.5) up to a limit: lpaq1's
//   StateMap adaptation rate;
// - the E8/E9 call transform (call/jmp rel32 -> absolute): paq8's exe
//   model and the BCJ filter of xz/LZMA; kkrunchy (ryg) notes that relative
//   call targets compress badly because the same target gets other bytes.
#pragma once

namespace rt64k::pack::model {

using u8 = unsigned char;
using u16 = unsigned short;
using u32 = unsigned int;
using u64 = unsigned long long;
using i64 = long long;

// Up to kMaxModels hashed context models; each has 2^kSlotBits counters.
constexpr int kMaxModels = 14;
constexpr int kSlotBits = 20;
constexpr u32 kSlots = 1u << kSlotBits;
// The mixer's weights are selected by the partial byte c0 (1..255).
constexpr int kMixInputs = kMaxModels + 1;
constexpr int kApmCells = 33; // stretch(p) in 33 steps of 128 from -2048

// Model mask bits: bits 0-7 put byte -1..-8 in the context; the others
// add derived contexts.
constexpr u32 kMaskColumn = 1u << 8; // position & 3 (4-byte float tables)

// Header flags.
constexpr u8 kFlagCallTransform = 1; // E8/E9 rel32 -> absolute

// The parameters the encoder chooses and stores in the stream's header:
// [n][flags][limit][rate][mask lo, mask hi] * n.
struct Params {
  u8 n;     // models in use, 1..kMaxModels
  u8 flags; // kFlag*
  u8 limit; // counters' adaptation count limit (rate 1/(n+1.5))
  u8 rate;  // mixer learning rate: weight += input * err * rate >> 14
  u16 mask[kMaxModels];
};

struct Tables {
  u32 slot[kMaxModels][kSlots]; // counters: p16 ^ 0x8000 << 16 | count
  int weight[256][kMixInputs];  // mixer weights (16.16), by c0
  u16 apm0[256][kApmCells];     // SSE by c0
  u16 apm1[65536][kApmCells];   // SSE by c0 and the last byte
  short stretch[4096];
};

// squash(d) = 4096 / (1 + e^(-d/256)), d in stretch units, by interpolation
// of 33 points (lpaq1's table).
inline int squash(int d) {
  static const short t[33] = {1,    2,    3,    6,    10,   16,   27,   45,   73,   120,  194,
                              310,  488,  747,  1101, 1546, 2047, 2549, 2994, 3348, 3607, 3785,
                              3901, 3975, 4022, 4050, 4068, 4079, 4085, 4089, 4092, 4093, 4094};
  if (d > 2047) return 4095;
  if (d < -2047) return 1;
  int w = d & 127;
  d = (d >> 7) + 16;
  return (t[d] * (128 - w) + t[d + 1] * w + 64) >> 7;
}

// The context-mixing predictor: p() gives P(next bit = 1) in 1..4095;
// update(bit) learns it. Both sides call them in the same order.
struct Predictor {
  Tables* t;
  Params prm;
  u32 hash[kMaxModels];
  u32* cur[kMaxModels];
  int in[kMixInputs];
  u64 hist;   // the last 8 bytes, byte -1 lowest
  u32 c0;     // 1, then the bits of the current byte behind a leading 1
  u32 pos;    // bytes done
  int pmix;   // mixer output (12 bits)
  int dot;    // mixer output in stretch units
  int a0, a1; // APM cells in use (index of the lower one)
  int aw;     // APM interpolation weight (0..127)

  void init(void* work, const Params& p) {
    t = static_cast<Tables*>(work);
    prm = p;
    hist = 0;
    c0 = 1;
    pos = 0;
    // stretch = squash^-1 over 0..4095.
    int pi = 0;
    for (int x = -2047; x <= 2047; ++x) {
      int v = squash(x);
      for (int j = pi; j <= v; ++j)
        t->stretch[j] = static_cast<short>(x);
      pi = v + 1;
    }
    for (int j = pi; j < 4096; ++j)
      t->stretch[j] = 2047;
    // APMs start as the identity: cell k holds squash((k - 16) * 128) * 16.
    for (int c = 0; c < 256 * kApmCells; ++c) {
      u16 v = static_cast<u16>(squash((c % kApmCells - 16) * 128) * 16);
      (&t->apm0[0][0])[c] = v;
      for (int b = 0; b < 256; ++b)
        (&t->apm1[0][0])[b * 256 * kApmCells + c] = v;
    }
    rehash();
  }

  void rehash() {
    for (int i = 0; i < prm.n; ++i) {
      u32 m = prm.mask[i];
      u32 h = (m + 1) * 0x9E3779B1u;
      for (int j = 0; j < 8; ++j)
        if (m >> j & 1) h = (h ^ static_cast<u32>(hist >> (8 * j) & 255)) * 0x01000193u + j;
      if (m & kMaskColumn) h = (h ^ (pos & 3)) * 0x2F0B4A13u;
      hash[i] = h;
    }
  }

  int p() {
    i64 sum = 0;
    int* w = t->weight[c0];
    for (int i = 0; i < prm.n; ++i) {
      u32 h = (hash[i] + c0 * 0x6F4F2A35u) * 0x9E3779B1u;
      cur[i] = &t->slot[i][h >> (32 - kSlotBits)];
      int x = t->stretch[((*cur[i] >> 16) ^ 0x8000) >> 4];
      in[i] = x;
      sum += static_cast<i64>(w[i]) * x;
    }
    in[prm.n] = 256;
    sum += static_cast<i64>(w[prm.n]) * 256;
    int d = static_cast<int>(sum >> 16);
    if (d > 2047) d = 2047;
    if (d < -2047) d = -2047;
    dot = d;
    pmix = squash(d);
    // SSE: interpolate between the two cells around stretch(pmix).
    int s = (d + 2048) * 4; // 0..16380 -> cells of 512
    a0 = s >> 9;
    aw = s & 511;
    int c1 = static_cast<int>(hist & 255);
    const u16* r0 = t->apm0[c0];
    const u16* r1 = t->apm1[c1 << 8 | c0];
    int q0 = (r0[a0] * (512 - aw) + r0[a0 + 1] * aw) >> 13;
    int q1 = (r1[a0] * (512 - aw) + r1[a0 + 1] * aw) >> 13;
    int pr = (pmix * 2 + q0 + q1) >> 2;
    if (pr < 1) pr = 1;
    if (pr > 4095) pr = 4095;
    return pr;
  }

  void update(int y) {
    // Counters.
    for (int i = 0; i < prm.n; ++i) {
      u32 s = *cur[i];
      int p16 = static_cast<int>((s >> 16) ^ 0x8000);
      int n = static_cast<int>(s & 255);
      p16 += (((y << 16) - y - p16) * 2) / (2 * n + 3);
      if (n < prm.limit) ++n;
      *cur[i] = static_cast<u32>(p16 ^ 0x8000) << 16 | static_cast<u32>(n);
    }
    // Mixer.
    int err = ((y << 12) - pmix) * prm.rate;
    int* w = t->weight[c0];
    for (int i = 0; i <= prm.n; ++i)
      w[i] += (in[i] * err) >> 14;
    // SSE: move the nearer cell toward the bit.
    int c1 = static_cast<int>(hist & 255);
    int k = a0 + (aw >> 8);
    u16* r0 = &t->apm0[c0][k];
    u16* r1 = &t->apm1[c1 << 8 | c0][k];
    int target = (y << 16) - y;
    *r0 = static_cast<u16>(*r0 + ((target - *r0) >> 6));
    *r1 = static_cast<u16>(*r1 + ((target - *r1) >> 6));
    // Next bit.
    c0 = c0 << 1 | static_cast<u32>(y);
    if (c0 >= 256) {
      hist = hist << 8 | (c0 & 255);
      c0 = 1;
      ++pos;
      rehash();
    }
  }
};

// The call transform: E8/E9 followed by a rel32 becomes E8/E9 followed by
// (rel32 + offset of the next instruction), so calls to one function carry
// the same four bytes. Which bytes are opcodes depends only on bytes the
// transform leaves alone, so `forward` false undoes it exactly.
inline void call_transform(u8* b, u32 n, bool forward) {
  for (u32 i = 0; i + 5 <= n;) {
    if ((b[i] & 0xFE) == 0xE8) {
      u32 v = b[i + 1] | b[i + 2] << 8 | b[i + 3] << 16 | static_cast<u32>(b[i + 4]) << 24;
      v = forward ? v + i + 5 : v - (i + 5);
      b[i + 1] = static_cast<u8>(v);
      b[i + 2] = static_cast<u8>(v >> 8);
      b[i + 3] = static_cast<u8>(v >> 16);
      b[i + 4] = static_cast<u8>(v >> 24);
      i += 5;
    } else {
      ++i;
    }
  }
}

// Header bytes for `p`.
inline u32 header_bytes(const Params& p) { return 4 + 2 * p.n; }

// decode() reads at most this many bytes of its input for `size` output
// bytes, whatever they hold (reads past it see 0); encode() fails rather
// than write more.
inline u32 max_encoded(u32 size) { return 4 + 2 * kMaxModels + size + (size >> 4) + 16; }

} // namespace rt64k::pack::model
