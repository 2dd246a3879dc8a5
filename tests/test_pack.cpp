// The intro's own packer's codec (src/pack): round trips on generated
// inputs, the size bound on incompressible data, and damaged input decoded
// without a read past the documented bound or a write past the output.
#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cstring>
#include <random>
#include <vector>

#include "codec.h"
#include "encode.h"
#include "model.h"

namespace {

using rt64k::pack::decode;
using rt64k::pack::encode;
using rt64k::pack::kWorkBytes;
using rt64k::pack::model::max_encoded;
using Bytes = std::vector<unsigned char>;

// A readable region of exactly `n` bytes followed by an inaccessible page:
// the decoder touching byte n faults.
struct GuardedInput {
  unsigned char* base = nullptr;
  size_t mapped = 0;
  unsigned char* data = nullptr;
  explicit GuardedInput(size_t n) {
    const size_t page = static_cast<size_t>(sysconf(_SC_PAGESIZE));
    const size_t body = (n + page - 1) / page * page;
    mapped = body + page;
    void* p = mmap(nullptr, mapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) return;
    base = static_cast<unsigned char*>(p);
    mprotect(base + body, page, PROT_NONE);
    data = base + body - n;
  }
  ~GuardedInput() {
    if (base) munmap(base, mapped);
  }
};

// The codec's work memory, zeroed for each call (one buffer: a fresh
// 128 MiB allocation per call would double the suite's time).
unsigned char* zeroed_work() {
  static Bytes work(kWorkBytes);
  std::memset(work.data(), 0, work.size());
  return work.data();
}

Bytes pack(const Bytes& in) {
  Bytes out(max_encoded(static_cast<unsigned>(in.size())), 0);
  unsigned n = encode(in.data(), static_cast<unsigned>(in.size()), out.data(),
                      static_cast<unsigned>(out.size()), zeroed_work());
  out.resize(n);
  return out;
}

// Decodes `packed` with a guard page right after its readable bytes: the
// stream itself (`damaged` false: a valid stream is read exactly), or
// max_encoded(size) bytes, the stream then zeros (`damaged` true); and 64
// guard bytes after the `size` bytes of output.
Bytes unpack(const Bytes& packed, unsigned size, bool* guard_intact, bool damaged = false) {
  const size_t readable = damaged ? max_encoded(size) : packed.size();
  GuardedInput in(readable);
  EXPECT_NE(in.data, nullptr);
  if (!in.data) return {};
  std::memset(in.data, 0, readable);
  std::memcpy(in.data, packed.data(), packed.size() < readable ? packed.size() : readable);
  Bytes out(size + 64, 0xA5);
  decode(in.data, out.data(), size, zeroed_work());
  bool intact = true;
  for (unsigned i = size; i < size + 64; ++i)
    intact = intact && out[i] == 0xA5;
  if (guard_intact) *guard_intact = intact;
  out.resize(size);
  return out;
}

Bytes random_bytes(size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  Bytes b(n);
  for (auto& v : b)
    v = static_cast<unsigned char>(rng() >> 24);
  return b;
}

void expect_round_trip(const Bytes& in) {
  Bytes packed = pack(in);
  ASSERT_GT(packed.size(), 0u);
  ASSERT_LE(packed.size(), max_encoded(static_cast<unsigned>(in.size())));
  bool intact = false;
  Bytes back = unpack(packed, static_cast<unsigned>(in.size()), &intact);
  EXPECT_TRUE(intact);
  EXPECT_EQ(back, in);
}

TEST(Pack, RoundTripsSmallSizes) {
  for (unsigned n : {0u, 1u, 2u, 3u, 255u, 256u, 1000u}) {
    SCOPED_TRACE(n);
    expect_round_trip(random_bytes(n, 11 + n));
  }
}

TEST(Pack, RoundTripsUniformAndRuns) {
  expect_round_trip(Bytes(5000, 0x00));
  expect_round_trip(Bytes(5000, 0xFF));
  Bytes runs;
  std::mt19937 rng(7);
  while (runs.size() < 20000)
    runs.insert(runs.end(), 1 + rng() % 300, static_cast<unsigned char>(rng()));
  expect_round_trip(runs);
}

TEST(Pack, CompressesRedundantData) {
  // 100,000 zero bytes: the model's counters saturate near 1/4096 per bit.
  Bytes zeros(100000, 0);
  Bytes packed = pack(zeros);
  EXPECT_LT(packed.size(), 200u);
  EXPECT_EQ(unpack(packed, 100000, nullptr), zeros);
  // x86-like text: a few instruction patterns with random 32-bit operands
  // compress to well under half.
  std::mt19937 rng(3);
  Bytes code;
  const unsigned char ops[4][3] = {
      {0xF3, 0x0F, 0x10}, {0x48, 0x8B, 0x05}, {0xE8, 0, 0}, {0xC3, 0, 0}};
  while (code.size() < 30000) {
    const unsigned char* op = ops[rng() % 4];
    code.insert(code.end(), op, op + (op[0] == 0xE8 || op[0] == 0xC3 ? 1 : 3));
    if (op[0] != 0xC3)
      for (int k = 0; k < 4; ++k)
        code.push_back(static_cast<unsigned char>(k < 2 ? rng() : 0));
  }
  packed = pack(code);
  EXPECT_LT(packed.size(), code.size() * 45 / 100);
  EXPECT_EQ(unpack(packed, static_cast<unsigned>(code.size()), nullptr), code);
}

TEST(Pack, RandomDataStaysNearItsSize) {
  Bytes in = random_bytes(70000, 2026); // past 65,536
  Bytes packed = pack(in);
  ASSERT_GT(packed.size(), 0u);
  EXPECT_LE(packed.size(), in.size() + in.size() / 50); // within 2 %
  EXPECT_EQ(unpack(packed, 70000, nullptr), in);
}

TEST(Pack, EncodeReportsTooSmallOutput) {
  Bytes in = random_bytes(4000, 5);
  Bytes out(100);
  EXPECT_EQ(encode(in.data(), 4000, out.data(), 100, zeroed_work()), 0u);
}

TEST(Pack, DamagedInputStaysInBounds) {
  Bytes in(6000);
  for (size_t i = 0; i < in.size(); ++i)
    in[i] = static_cast<unsigned char>(i * i >> 5 ^ i);
  Bytes packed = pack(in);
  std::mt19937 rng(99);
  int differing = 0;
  for (int trial = 0; trial < 8; ++trial) {
    Bytes bad = packed;
    size_t bit = rng() % (bad.size() * 8);
    bad[bit / 8] ^= static_cast<unsigned char>(1u << (bit % 8));
    bool intact = false;
    Bytes back = unpack(bad, 6000, &intact, true); // a read past the bound faults
    EXPECT_TRUE(intact) << "bit " << bit;
    differing += back != in;
  }
  // The model has no redundancy check: a flipped bit changes the output.
  EXPECT_GE(differing, 6);
}

TEST(Pack, DataRegionRoundTrips) {
  // Constants then code-like bytes, as intro.exe's .text: any data region
  // (none, part, past the end) decodes.
  std::mt19937 rng(21);
  Bytes image;
  for (int i = 0; i < 1024; ++i) { // floats with short mantissas
    unsigned f = 0x3F000000u | static_cast<unsigned>(rng() % 64) << 17;
    for (int k = 0; k < 4; ++k)
      image.push_back(static_cast<unsigned char>(f >> 8 * k));
  }
  const unsigned char ops[][7] = {{0xF3, 0x0F, 0x10, 0x05, 0, 0, 0},
                                  {0x48, 0x89, 0xC1, 0, 0, 0, 0},
                                  {0xE8, 0, 0, 0, 0, 0, 0},
                                  {0xC3, 0, 0, 0, 0, 0, 0}};
  const unsigned lengths[] = {8, 3, 5, 1};
  while (image.size() < 12000) {
    unsigned op = static_cast<unsigned>(rng() % 4);
    for (unsigned k = 0; k < lengths[op]; ++k)
      image.push_back(k < 4 && ops[op][k] ? ops[op][k] : static_cast<unsigned char>(rng() % 16));
  }
  // The chosen region prices within 1 % of the better extreme (no region,
  // all data), whose prices the two passes know exactly.
  auto size_with = [&](unsigned data_end) {
    rt64k::pack::model::Params p = rt64k::pack::default_params();
    p.data_end = static_cast<unsigned short>(data_end);
    Bytes packed(max_encoded(static_cast<unsigned>(image.size())));
    return rt64k::pack::encode_with(p, image.data(), static_cast<unsigned>(image.size()),
                                    packed.data(), static_cast<unsigned>(packed.size()),
                                    zeroed_work());
  };
  const unsigned none = size_with(0), all = size_with(static_cast<unsigned>(image.size() / 4));
  const unsigned chosen = static_cast<unsigned>(pack(image).size());
  EXPECT_LE(chosen, (none < all ? none : all) * 101 / 100);
  rt64k::pack::model::Params prm = rt64k::pack::default_params();
  expect_round_trip(image);
  for (unsigned data_end : {0u, 100u, 1024u, 2999u, 3000u, 65535u}) {
    SCOPED_TRACE(data_end);
    prm.data_end = static_cast<unsigned short>(data_end);
    Bytes packed(max_encoded(static_cast<unsigned>(image.size())));
    unsigned n = rt64k::pack::encode_with(prm, image.data(), static_cast<unsigned>(image.size()),
                                          packed.data(), static_cast<unsigned>(packed.size()),
                                          zeroed_work());
    ASSERT_GT(n, 0u);
    packed.resize(n);
    EXPECT_EQ(unpack(packed, static_cast<unsigned>(image.size()), nullptr), image);
  }
}

TEST(Pack, RelativeFieldsRoundTrip) {
  // Code-like input full of CALL/JMP rel32 and RIP-relative loads (the
  // fields the coder sees as absolute), cut at every length near the end so
  // that a field crosses the last byte.
  std::mt19937 rng(8);
  Bytes code;
  while (code.size() < 3000) {
    unsigned kind = static_cast<unsigned>(rng() % 3);
    if (kind == 0) code.push_back(0xE8);
    if (kind == 1) code.insert(code.end(), {0xF3, 0x0F, 0x10, 0x05}); // movss xmm0, [rip+d]
    if (kind == 2) code.insert(code.end(), {0x0F, 0x84});             // je rel32
    unsigned v = static_cast<unsigned>(rng() % 64) - static_cast<unsigned>(code.size());
    for (int k = 0; k < 4; ++k)
      code.push_back(static_cast<unsigned char>(v >> 8 * k));
  }
  Bytes packed = pack(code);
  EXPECT_LT(packed.size(), code.size() / 4);
  EXPECT_EQ(unpack(packed, static_cast<unsigned>(code.size()), nullptr), code);
  for (unsigned cut = 1; cut <= 6; ++cut) {
    Bytes part(code.begin(), code.end() - cut);
    expect_round_trip(part);
  }
}

} // namespace

// The decoder leans on two facts of its tables (model.h, size13): init()'s
// stretch loop reaches the last probability by itself (squash(2047) = 4095,
// so it has no tail to fill), and p() never exceeds 4095 with only its
// lower clamp (mixer and SSE both at most 4095). Checked on the built tables
// and on p() over a seeded stream, including runs that push it to the top.
TEST(Pack, TablesCoverEveryProbability) {
  using namespace rt64k::pack::model;
  unsigned char* work = zeroed_work();
  const unsigned char header[4 + 2] = {1, 0, 0, 0, 0x01, 0x00};
  Predictor m;
  m.init(work, header);
  const Tables* t = static_cast<const Tables*>(static_cast<void*>(work));
  EXPECT_EQ(t->squash[4094], 4095); // squash(2047)
  EXPECT_EQ(t->squash[0], 1);       // squash(-2047)
  // stretch[j] is the least d with squash(d) >= j, for every j in 0..4095:
  // the entries past the loop's last write would still be 0 (the work is
  // zeroed), and squash reaches 4095 at d = 1952 already.
  int d = -2047;
  for (int j = 0; j < 4096; ++j) {
    while (t->squash[d + 2047] < j)
      ++d;
    ASSERT_EQ(t->stretch[j], d) << j;
  }
  EXPECT_EQ(t->stretch[4095], 1952);
  // p() in 1..4095 on 200,000 bits: 100,000 ones (p driven to the top),
  // then seeded random bits.
  std::mt19937 rng(13);
  int lo = 4096, hi = 0;
  for (int i = 0; i < 200000; ++i) {
    const int p = m.p();
    lo = p < lo ? p : lo;
    hi = p > hi ? p : hi;
    m.update(i < 100000 ? 1 : static_cast<int>(rng() & 1));
  }
  EXPECT_GE(lo, 1);
  EXPECT_LE(hi, 4095);
  EXPECT_GE(hi, 4000); // the run of ones reached the top range
}
