// model.h - the context-mixing model shared by the packer's encoder (host)
// and decoder (the packed exe's stub). Freestanding: integers only, no C
// runtime, no heap; every table lives in the caller's zeroed work memory.
//
// Ideas and formulas, from public descriptions (our own code):
// - the binary arithmetic coder with 12-bit probabilities, carry-less, a
//   32-bit range that shifts out a byte when its top bytes agree: Matt
//   Mahoney's lpaq1 (2007) Encoder/Decoder;
// - squash() (the logistic function in 12 bits; ours is a table built by
//   stepping e^(-d/256) in fixed point), stretch() as its inverse, the
//   logistic mixer (weights trained by err * input) and the APM/SSE stage:
//   lpaq1;
// - each model as a mask of which of the last 8 bytes form its context, the
//   encoder choosing the masks and storing them in the header: Crinkler
//   (Blueberry & Mentor), as described by Alexandre Mutel, "Crinkler
//   secrets, 4k intro executable compressor at its best" (2010);
// - counters as a pair of bit counts whose opposite count is halved on
//   each bit: paq8's nonstationary counters (Mahoney, "Adaptive weighing of
//   context models for lossless data compression", 2005);
// - parsing x86 instructions so that each operand byte has the opcode and
//   its position as context: paq8's exe model and kkrunchy (Fabian Giesen,
//   "x86 code compression in kkrunchy", 2011); the opcode maps from the
//   Intel SDM, vol. 2, appendix A;
// - coding rel32 fields as absolute (call/jmp targets: the E8/E9 transform
//   of paq8 and of xz's BCJ filter; here found by the parse, RIP-relative
//   displacements too): the same target then carries the same bytes.
#pragma once

namespace rt64k::pack::model {

using u8 = unsigned char;
using u16 = unsigned short;
using u32 = unsigned int;
using u64 = unsigned long long;
using i64 = long long;

// Up to kMaxModels hashed context models; each has 2^kSlotBits counters.
constexpr int kMaxModels = 14;
constexpr int kSlotBits = 22;
constexpr u32 kSlots = 1u << kSlotBits;
constexpr int kMixInputs = kMaxModels + 1; // the models and a bias
constexpr int kBias = 512;                 // the mixer's bias input (p())
constexpr int kApmCells = 33;              // stretch(p) in 33 steps of 128 from -2048

// Model mask bits: bits 0-7 put byte -1..-8 in the context; the others
// add derived contexts.
// (bit 8, position & 3 for 4-byte tables, went when the data region came:
// the mask search stopped using it)
constexpr u32 kMaskX86Op = 1u << 9;     // x86 parse: the next byte's role, the opcode
constexpr u32 kMaskX86Modrm = 1u << 10; // x86 parse: the role and the ModRM byte
constexpr u32 kMaskX86Prev = 1u << 11;  // x86 parse: the previous instruction's opcode

// Header flags: which rel32 fields the coder sees as absolute (the field's
// value plus its offset), so that references to one target carry the same
// bytes. Which bytes form such a field depends only on the opcode and ModRM
// bytes before it, which the transform leaves alone.
constexpr u8 kFlagBranch = 1; // CALL/JMP rel32 (E8, E9) and Jcc rel32 (0F 80-8F)
constexpr u8 kFlagRip = 2;    // RIP-relative disp32 (ModRM mod 00, r/m 101)

// A counter: two bytes n[0], n[1], the zeros and ones seen in its context
// (at most 255), the opposite count halved (kept above 1) on each bit so
// that it follows change (paq8's nonstationary counters).
// P(1) = (4 n1 + 1) / (4 n0 + 4 n1 + 2):
// a context seen once or twice is already trusted (tuned on intro.exe:
// factor 4 beat 2, 3 and 6; the counts beat 16-bit probabilities adapting
// at 1/(n+1.5) by 200 bytes).
inline int counter_p12(const u8* n) { return ((4 * n[1] + 1) * 4096) / (4 * (n[0] + n[1]) + 2); }
inline void counter_update(u8* n, int y) {
  if (n[y] < 255) ++n[y];
  if (n[!y] > 2) n[!y] = static_cast<u8>(n[!y] / 2 + 1);
}

// The parameters the encoder chooses and stores in the stream's header:
// [n][flags][data lo, data hi][mask lo, mask hi] * n.
struct Params {
  u8 n;         // models in use, 1..kMaxModels
  u8 flags;     // kFlag*
  u16 data_end; // the data region: bytes [0, 4 * data_end)
  u16 mask[kMaxModels];
};

struct Tables {
  u8 slot[kMaxModels][kSlots][2];      // counters
  int weight[256 + 65536][kMixInputs]; // mixer weights (16.16): weights_a(), weights_b()
  u16 apm[128 * 256 * kApmCells];      // SSE by the x86 role, operand index and c0
  short stretch[4096];
  short squash[4095]; // squash(d) at d + 2047
};

// x86-64 opcode classes for the instruction parse: one-byte opcodes in
// nibbles (bit 3: a ModRM byte follows; bits 0-2: the immediate, 0 none,
// 1 imm8, 2 imm32, 3 imm16, 4 imm16+imm8, 5 moffs64, 6 imm32 (MOV r, imm:
// imm64 with REX.W, which the parse does not track: 6 bytes on intro.exe
// for ~20 bytes of decoder; nor the 66 prefix's imm16: 10 bytes), 7 a
// prefix); 0F xx in 2-bit fields (0 ModRM, 1 nothing, 2 rel32,
// 3 ModRM + imm8). From the Intel SDM's opcode maps (vol. 2, appendix A).
// alignas(1): read a byte at a time, so no need for the 16 bytes the x86-64
// ABI gives arrays of 16 bytes or more (in the stub: up to 15 bytes of fill
// after the payload).
alignas(1) inline const u8 kOneByte[128] = {
    0x88, 0x88, 0x21, 0x00, 0x88, 0x88, 0x21, 0x00, 0x88, 0x88, 0x21, 0x00, 0x88, 0x88, 0x21, 0x00,
    0x88, 0x88, 0x21, 0x07, 0x88, 0x88, 0x21, 0x07, 0x88, 0x88, 0x21, 0x07, 0x88, 0x88, 0x21, 0x07,
    0x77, 0x77, 0x77, 0x77, 0x77, 0x77, 0x77, 0x77, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
    0x00, 0x80, 0x77, 0x77, 0xA2, 0x91, 0x00, 0x00, 0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x11,
    0xA9, 0x99, 0x88, 0x88, 0x88, 0x88, 0x88, 0x88, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
    0x55, 0x55, 0x00, 0x00, 0x21, 0x00, 0x00, 0x00, 0x11, 0x11, 0x11, 0x11, 0x66, 0x66, 0x66, 0x66,
    0x99, 0x03, 0x00, 0xA9, 0x04, 0x03, 0x10, 0x00, 0x88, 0x88, 0x00, 0x00, 0x88, 0x88, 0x88, 0x88,
    0x11, 0x11, 0x11, 0x11, 0x22, 0x10, 0x00, 0x00, 0x07, 0x77, 0x00, 0xA9, 0x00, 0x00, 0x00, 0x88};
alignas(1) inline const u8 kTwoByte[64] = {
    0x00, 0x54, 0x45, 0x10, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x55, 0x55, 0x00, 0x00,
    0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xFF, 0x40, 0x00, 0x00,
    0xAA, 0xAA, 0xAA, 0xAA, 0x00, 0x00, 0x00, 0x00, 0x15, 0x03, 0x15, 0x03, 0x00, 0x00, 0x30, 0x00,
    0x30, 0x3F, 0x55, 0x55, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00};
// In the packed exe the stub reads kTwoByte from the headers' free bytes,
// where `rt64k-pack finish` writes it (kTwoByteHeaderOffset, which stub.ld
// gives the symbol; `rt64k-pack check` compares the bytes): 64 bytes of the
// stub's section less (size14).
constexpr u32 kTwoByteHeaderOffset = 0x1C0;
#ifdef RT64K_PACK_STUB
extern "C" const u8 rt64k_two_byte[64];
#define RT64K_TWO_BYTE rt64k_two_byte
#else
#define RT64K_TWO_BYTE kTwoByte
#endif

// The next byte's role in the x86-64 instruction stream: an opcode or a
// prefix, the opcode after 0F, a ModRM or SIB byte, or one of the `left`
// displacement and immediate bytes. (0F 38 and 0F 3A, three-byte opcodes,
// are SSSE3 and later: intro.exe, SSE2 only, has none, so the parse takes
// them as two-byte opcodes with ModRM; handling them cost ~25 decoder bytes.)
enum : u8 { kOp, kOp0F, kModrm, kSib, kOperand };

// Follows the byte stream as x86-64 code (paq8's exe model and kkrunchy
// parse instructions to give operand bytes their own contexts). In data it
// parses nonsense, consistently on both sides.
struct X86 {
  u32 role, left, op, prev, modrm, imm;
  u32 rel; // the next 4 bytes are a rel32 field: kFlagBranch or kFlagRip

  void operands(u32 n) {
    left = n;
    role = kOperand;
    if (n == 0) role = kOp;
  }

  void step(u32 b) {
    u32 r = role;
    rel = 0;
    if (r == kOperand) {
      if (--left == 0) role = kOp;
      return;
    }
    if (r >= kModrm) {
      if (r == kModrm) {
        modrm = b;
        if ((op | 1) == 0xF7 && (b & 0x30)) imm = 0; // F6/F7: only TEST has an immediate
        if (b >> 6 != 3 && (b & 7) == 4) {
          role = kSib;
          return;
        }
      }
      u32 mod = modrm >> 6, base = b & 7; // rm or the SIB's base: 5 with mod 0 is disp32
      u32 disp = 0x410 >> mod * 4 & 15;   // mod 0, 1, 2, 3: 0, 1, 4, 0 bytes
      if (mod == 0 && base == 5) {
        disp = 4;
        if (r == kModrm) rel = kFlagRip;
      }
      operands(disp + imm);
      return;
    }
    u32 c; // the opcode's class as in kOneByte
    if (r == kOp) {
      if (b == 0x0F) {
        role = kOp0F;
        return;
      }
      c = kOneByte[b >> 1] >> (b & 1) * 4 & 15;
      if (c == 7) return; // a prefix
    } else {              // kOp0F
      // The 2-bit field's class: 0 ModRM (8), 1 nothing (0), 2 rel32 (2),
      // 3 ModRM + imm8 (9).
      c = 0x9208u >> (RT64K_TWO_BYTE[b >> 2] >> (b & 3) * 2 & 3) * 4 & 15;
      b |= 0x100;
    }
    rel = (b | 1) == 0xE9 || (b & 0x1F0) == 0x180 ? kFlagBranch : 0; // CALL, JMP, Jcc rel32
    prev = op;
    op = b;
    imm = 0x4832410u >> (c & 7) * 4 & 15; // classes 0-6: 0, 1, 4, 2, 3, 8, 4 bytes
    if (c & 8)
      role = kModrm;
    else
      operands(imm);
  }
};

// The context-mixing predictor: p() gives P(next bit = 1) in 1..4095;
// update(bit) learns it. Both sides call them in the same order.
struct Predictor {
  // Scalars first: their offsets fit in a byte, which keeps the stub's
  // instructions short.
  Tables* t;
  int n;           // models in use
  u32 flags;       // kFlag*
  const u8* masks; // n little-endian 16-bit masks (the header's)
  u64 hist;        // the last 8 bytes, byte -1 lowest
  u32 c0;          // 1, then the bits of the current byte behind a leading 1
  int* wa;         // the mixer's weight sets in use
  int* wb;
  u16* apm; // the SSE cell update() moves: the nearer of the two p() used
  int pmix; // mixer output (12 bits)
  X86 x86;
  u32 hash[kMaxModels];
  int in[kMixInputs];
  u8* cur[kMaxModels];

  int squash(int d) const { return t->squash[(d < -2047 ? -2047 : d > 2047 ? 2047 : d) + 2047]; }

  // `header`: the stream's header (Params); a damaged n counts as 1.
  void init(void* work, const u8* header) {
    t = static_cast<Tables*>(work);
    n = header[0];
    if (n < 1 || n > kMaxModels) n = 1;
    flags = header[1];
    // The data region: bytes before 4 * the header's 16-bit count.
    const u32 data_end = (header[2] | header[3] << 8) * 4u;
    masks = header + 4;
    hist = 0;
    x86 = X86{};
    c0 = 1;
    // The data region (the constants before the code) is one long operand
    // to the parse: no instructions, and left & 3 is the column in 4-byte
    // tables (a kData role with no parse cost 16 bytes more and 32 decoder
    // bytes more).
    if (data_end) x86.operands(data_end);
    // squash(d) = 4096 / (1 + e^(-d/256)) for d in -2047..2047, stretch
    // units (lpaq1's squash, which interpolates 33 points; here e^(-d/256)
    // steps down from e^(2047/256) in 16.16 fixed point with rounding, for
    // d <= 0, and squash(-d) = 4096 - squash(d); integers only).
    u64 e = 194598426; // e^(2047/256) * 2^16
    for (int i = 0; i < 2048; ++i) {
      int v = static_cast<int>((1u << 28) / (65536 + static_cast<u32>(e)));
      t->squash[i] = static_cast<short>(v);
      t->squash[4094 - i] = static_cast<short>(4096 - v);
      e = (e * 4278222805u + (1u << 31)) >> 32; // * e^(-1/256)
    }
    // stretch = squash^-1 over 0..4095.
    int pi = 0;
    for (int x = -2047; x <= 2047; ++x) {
      int v = t->squash[x + 2047];
      for (int j = pi; j <= v; ++j)
        t->stretch[j] = static_cast<short>(x);
      pi = v + 1;
    }
    // No tail to fill: squash(2047) = 4095 (e^(-2047/256) * 4096 < 1.5), so
    // the loop above ends with pi = 4096 (Codec.StretchCoversEveryProbability).
    // APMs start as the identity: cell k holds squash((k - 16) * 128) * 16.
    for (u32 c = 0; c < sizeof t->apm / sizeof t->apm[0]; ++c)
      t->apm[c] = static_cast<u16>(squash((static_cast<int>(c % kApmCells) - 16) * 128) * 16);
    // Every mixer weight starts at 1/16 (two sets: 1/8 per input; tuned:
    // 0 cost 74 bytes, 1/32 31, 1/8 336).
    for (u32 c = 0; c < sizeof t->weight / sizeof(int); ++c)
      (&t->weight[0][0])[c] = 1 << 12;
    rehash();
  }

  void rehash() {
    for (int i = 0; i < n; ++i) {
      u32 m = masks[2 * i] | masks[2 * i + 1] << 8;
      u32 h = (m + 1) * 0x9E3779B1u;
      u64 bytes = hist;
      for (u32 j = 0, bits = m; j < 8; ++j, bits >>= 1, bytes >>= 8)
        if (bits & 1) h = (h ^ static_cast<u32>(bytes & 255)) * 0x01000193u + j;
      if (m & kMaskX86Op) h = (h ^ (x86.role | (x86.left & 7) << 3 | x86.op << 7)) * 0x2F0B4A13u;
      if (m & kMaskX86Modrm) h = (h ^ (x86.role | x86.modrm << 3)) * 0x6F4F2A35u;
      if (m & kMaskX86Prev) h = (h ^ x86.prev) * 0x2F0B4A13u;
      hash[i] = h;
    }
  }

  // The mixer's two weight sets, whose sums weigh the inputs: one by the
  // x86 role, the bit's position in the byte and the operand byte's index,
  // one by the role, the operand byte's index and the last byte (tuned:
  // 16,825 bytes with the first alone, 16,534 with both; the first alone
  // by c0 gave 17,173 on an older model).
  int* weights_a() const {
    return t->weight[x86.role << 3 | (31 - __builtin_clz(c0)) | (x86.left & 3) << 6];
  }
  int* weights_b() const {
    return t->weight[256 + ((hist & 255) << 8 | x86.role | (x86.left & 7) << 3)];
  }
  u16* apm_row() const { return &t->apm[((x86.role | (x86.left & 7) << 3) << 8 | c0) * kApmCells]; }

  int p() {
    i64 sum = 0;
    int* w = wa = weights_a();
    int* v = wb = weights_b();
    for (int i = 0; i < n; ++i) {
      u32 h = (hash[i] + c0 * 0x6F4F2A35u) * 0x9E3779B1u;
      cur[i] = t->slot[i][h >> (32 - kSlotBits)];
      in[i] = t->stretch[counter_p12(cur[i])];
      sum += static_cast<i64>(w[i] + v[i]) * in[i];
    }
    // The bias input: 512 (size13 on round nine's image: 256 -12 bytes,
    // 384 and 416 -2 and 0 against 512, 1024 +100; no decoder byte).
    in[n] = kBias;
    sum += static_cast<i64>(w[n] + v[n]) * kBias;
    int d = static_cast<int>(sum >> 16);
    if (d > 2047) d = 2047;
    if (d < -2047) d = -2047;
    pmix = t->squash[d + 2047];
    // SSE: interpolate between the two cells around stretch(pmix), then
    // average with the mixer (1:3; 1:1 and the mixer alone cost more).
    int s = (d + 2048) * 4;              // 0..16380: 32 cells of 512
    const int at = s >> 9, w1 = s & 511; // the lower cell, the upper's weight
    u16* r = apm_row() + at;
    apm = r + (w1 >> 8);
    int q = (r[0] * (512 - w1) + r[1] * w1) >> 13;
    int pr = (pmix + q * 3) >> 2;
    // pmix <= 4095 and q <= 65535 * 512 >> 13 = 4095, so pr <= 4095 as it
    // is; pmix 1 with q 0 gives 0, hence the lower bound alone.
    if (pr < 1) pr = 1;
    return pr;
  }

  void update(int y) {
    for (int i = 0; i < n; ++i)
      counter_update(cur[i], y);
    int err =
        (y << 12) - pmix; // the learning rate: 1/2048 (tuned: 6/16384 +10 bytes, 10/16384 +15)
    for (int i = 0; i <= n; ++i) {
      wa[i] += (in[i] * err) >> 11;
      wb[i] += (in[i] * err) >> 11;
    }
    // SSE: move the nearer cell toward the bit (rate 1/32; 1/16 and 1/64 cost more).
    *apm = static_cast<u16>(*apm + ((((y << 16) - y) - *apm) >> 5));
    c0 = c0 << 1 | static_cast<u32>(y);
    if (c0 >= 256) {
      hist = hist << 8 | (c0 & 255);
      x86.step(c0 & 255);
      c0 = 1;
      rehash();
    }
  }
};

// Header bytes for `p`.
inline u32 header_bytes(const Params& p) { return 4 + 2 * p.n; }

// decode() reads at most this many bytes of its input for `size` output
// bytes, whatever they hold (reads past it see 0); encode() fails rather
// than write more.
inline u32 max_encoded(u32 size) { return 4 + 2 * kMaxModels + size + (size >> 4) + 16; }

} // namespace rt64k::pack::model
