// test_adaptive_group.cpp - round eleven's paths of the adaptive renderer
// (adaptive.cpp): a band's base blocks processed in groups (until kBaseGroup
// = 8 of them split or are traced per pixel, their column arrays from a
// ring of 17), the records compared with the count in the first vector,
// adaptive_estimate in SSE2, a scratch per running band, and the 2-px
// blocks' own paths (interpolate_exact, trace_block), which a frame rendered
// with a kinds map does not take: the pictures with and without one are the
// same, bit for bit.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <thread>
#include <vector>

#include "adaptive.h"
#include "frame.h"
#include "scenes.h"

namespace {

struct Lcg {
  uint32_t seed;
  uint32_t next() {
    seed = seed * 1664525u + 1013904223u;
    return seed >> 8;
  }
};

// The renderer marks every pixel copied, interpolated or traced; a split
// block marks none of its own, so kSplit is "unset".
constexpr uint8_t kUnset = kSplit;

// Base blocks of band `band` that are not one copied or interpolated block
// (all their pixels of one kind, copied or interpolated): at least the
// blocks that split or were traced per pixel (a block split into children
// that were all interpolated counts as not split here).
int held_blocks(const std::vector<uint8_t>& kinds, int w, int h, int block, int band) {
  int y0 = band * block, y1 = y0 + block < h ? y0 + block : h, held = 0;
  for (int x0 = 0; x0 < w; x0 += block) {
    int x1 = x0 + block < w ? x0 + block : w;
    uint8_t first = kinds[size_t(y0) * size_t(w) + size_t(x0)] & kKindMask;
    bool one = first == kCopied || first == kInterpolated;
    for (int y = y0; y < y1 && one; ++y)
      for (int x = x0; x < x1 && one; ++x)
        one = (kinds[size_t(y) * size_t(w) + size_t(x)] & kKindMask) == first;
    held += !one;
  }
  return held;
}

// The caller's buffer for a w x h frame of base block `block` (adaptive.cpp):
// gridH lines of `w` samples, one scratch per band, the queue (two counters,
// a done and a busy flag per band) last; sizes in samples.
struct Layout {
  int bands;
  size_t count, lines, queue, scratch; // scratch: one band's
};

Layout buffer_layout(int w, int h, int block) {
  Layout l;
  int gridH = (h - 1 + block - 1) / block + 1;
  l.bands = gridH - 1;
  l.count = size_t(adaptive_corner_count(w, h, block));
  l.lines = size_t(gridH) * size_t(w);
  l.queue = (8 + 2 * size_t(l.bands) + sizeof(CornerSample) - 1) / sizeof(CornerSample);
  l.scratch = (l.count - l.lines - l.queue) / size_t(l.bands);
  return l;
}

// An adaptive frame of `s` into img over the caller's buffer, begun.
AdaptiveFrame begun_frame(const Scene& s, Image& img, CornerSample* corners, int block) {
  AdaptiveFrame f{};
  f.scene = &s;
  f.fb = img.pixels.data();
  f.width = f.stride = img.width;
  f.height = img.height;
  f.baseBlock = block;
  f.minBlock = 2;
  f.mode = kModeAdaptive;
  f.corners = corners;
  adaptive_begin(f);
  return f;
}

} // namespace

// The count is a byte followed by three bytes of padding that a record's
// copy carries along (trace_primary4 writes only the count): the comparison
// must ignore them. Seeded records as in RecordsCompareAsSamePath, every
// record's padding random: the decision splits exactly where same_path()
// finds a record differing from c00's.
TEST(AdaptiveDecide, RecordsCompareIgnoringThePaddingAfterTheCount) {
  static_assert(sizeof(PathRecord) == 32, "count, three bytes of padding, seven nodes");
  Lcg rng{4242};
  int splits = 0, kept = 0, paddingDiffers = 0;
  for (int iter = 0; iter < 200000; ++iter) {
    CornerSample c[4];
    std::memset(c, 0, sizeof c);
    c[0].packed = 0xff405060u;
    c[0].path.count = (u8)(rng.next() % (kMaxPathNodes + 1));
    for (u32& node : c[0].path.node)
      node = rng.next() % 3;
    for (int k = 1; k < 4; ++k) {
      c[k] = c[0];
      c[k].packed = rng.next() % 2 ? c[0].packed : 0xff405061u;
      for (int i = c[0].path.count; i < kMaxPathNodes; ++i) // garbage past the count
        c[k].path.node[i] = rng.next();
      switch (rng.next() % 8) {
      case 0:
        c[k].path.count = (u8)(rng.next() % (kMaxPathNodes + 1));
        break;
      case 1:
        c[k].path.node[rng.next() % kMaxPathNodes] ^= 1u << (rng.next() % 32);
        break;
      default:
        break;
      }
    }
    for (CornerSample& s : c) { // the padding bytes after the count
      uint8_t* bytes = reinterpret_cast<uint8_t*>(&s.path);
      for (int b = 1; b < 4; ++b)
        bytes[b] = (uint8_t)rng.next();
    }
    paddingDiffers += std::memcmp(reinterpret_cast<uint8_t*>(&c[0].path) + 1,
                                  reinterpret_cast<uint8_t*>(&c[1].path) + 1, 3) != 0;
    bool same = same_path(c[0].path, c[1].path) && same_path(c[0].path, c[2].path) &&
                same_path(c[0].path, c[3].path);
    BlockKind kind = adaptive_decide(c[0], c[1], c[2], c[3], kModeAdaptive);
    ASSERT_EQ(kind == kSplit, !same) << "iter " << iter;
    BlockKind expect =
        !same ? kSplit
        : c[0].packed == c[1].packed && c[0].packed == c[2].packed && c[0].packed == c[3].packed
            ? kCopied
            : kInterpolated;
    ASSERT_EQ(kind, expect) << "iter " << iter;
    (same ? kept : splits)++;
  }
  EXPECT_GT(splits, 20000);
  EXPECT_GT(kept, 20000);
  EXPECT_GT(paddingDiffers, 190000);
}

// Frames whose bands hold many more than kBaseGroup base blocks that split
// or are traced per pixel (several groups a band, the last column of a
// group carried to the next through the ring): no sample is traced twice, the
// primary rays are the samples, every traced pixel is the full trace's, the
// picture is the same for 1 and 3 threads, and the same without a kinds map
// (the 2-px paths) as with one (the general paths). Fails with a ring of 14
// columns (15 needed by a group of 8 blocks none next to another, and the
// column carried).
TEST(AdaptiveFrame, ManySplitBaseBlocksPerBand) {
  struct Case {
    double t;
    int w, h, block;
  };
  for (Case c : {Case{44.0, 400, 300, 4}, Case{58.75, 400, 300, 4}, Case{38.5, 301, 203, 2},
                 Case{29.0, 400, 300, 8}}) {
    Scene s;
    build_timeline_scene(s, c.t);
    Image full(c.w, c.h), adaptive(c.w, c.h), plain(c.w, c.h), threaded(c.w, c.h);
    RenderOptions fo;
    fo.mode = Mode::Full;
    fo.threads = 2;
    render_frame(s, full, fo, nullptr);
    std::vector<uint8_t> kinds(size_t(c.w) * size_t(c.h), kUnset);
    RenderOptions opt;
    opt.block = c.block;
    opt.threads = 1;
    opt.kinds = kinds.data();
    RayStats stats;
    render_frame(s, adaptive, opt, &stats);
    opt.kinds = nullptr;
    render_frame(s, plain, opt, nullptr);
    opt.threads = 3;
    render_frame(s, threaded, opt, nullptr);

    int bands = (c.h - 1 + c.block - 1) / c.block, most = 0;
    for (int b = 0; b < bands; ++b) {
      int held = held_blocks(kinds, c.w, c.h, c.block, b);
      most = held > most ? held : most;
    }
    uint64_t samples = 0, twice = 0, traced = 0, mismatched = 0, unset = 0;
    for (size_t i = 0; i < kinds.size(); ++i) {
      int count = kinds[i] >> kSampleCountShift;
      samples += uint64_t(count);
      twice += count > 1;
      uint8_t kind = kinds[i] & kKindMask;
      unset += kind == kUnset;
      if (kind != kTraced) continue;
      ++traced;
      mismatched += full.pixels[i] != adaptive.pixels[i];
    }
    EXPECT_GT(most, 4 * 8) << "t=" << c.t << ": base blocks held in one band";

    EXPECT_EQ(twice, 0u) << "t=" << c.t;
    EXPECT_EQ(samples, stats.primary) << "t=" << c.t;
    EXPECT_EQ(unset, 0u) << "t=" << c.t;
    EXPECT_GT(traced, uint64_t(c.w * c.h / 50)) << "t=" << c.t;
    EXPECT_EQ(mismatched, 0u) << "t=" << c.t << " of " << traced << " traced pixels";
    EXPECT_EQ(adaptive.pixels, plain.pixels) << "t=" << c.t << ": with and without kinds map";
    EXPECT_EQ(plain.pixels, threaded.pixels) << "t=" << c.t << ": 1 and 3 threads";
  }
}

// adaptive_estimate with SSE2 (the records as in adaptive_decide, the
// channels' differences as saturating byte differences) against its
// definition: same_path() and |difference| <= 8 on each colour channel,
// then the midpoint's record is a's and each channel (a + b + 1) / 2, alpha
// 255; else false and `mid` untouched. Seeded pairs: channels within 12 of
// each other (so both sides of the limit), records as above, padding random.
TEST(AdaptiveEstimate, SameAsItsDefinition) {
  Lcg rng{99};
  int estimated = 0, byColour = 0, byRecord = 0;
  for (int iter = 0; iter < 200000; ++iter) {
    CornerSample a, b, mid, before;
    std::memset(&a, 0, sizeof a);
    a.packed = 0xff000000u | (rng.next() & 0xffffffu);
    b = a;
    for (int sh = 0; sh < 24; sh += 8) {
      int ch = int(a.packed >> sh & 255) + int(rng.next() % 25) - 12;
      ch = ch < 0 ? 0 : ch > 255 ? 255 : ch;
      b.packed = (b.packed & ~(255u << sh)) | uint32_t(ch) << sh;
    }
    a.path.count = (u8)(rng.next() % (kMaxPathNodes + 1));
    for (u32& node : a.path.node)
      node = rng.next() % 3;
    b.path = a.path;
    for (int i = a.path.count; i < kMaxPathNodes; ++i)
      b.path.node[i] = rng.next();
    if (rng.next() % 4 == 0) b.path.node[rng.next() % kMaxPathNodes] ^= 1u;
    if (rng.next() % 8 == 0) b.path.count = (u8)(rng.next() % (kMaxPathNodes + 1));
    for (CornerSample* s : {&a, &b})
      for (int k = 1; k < 4; ++k)
        reinterpret_cast<uint8_t*>(&s->path)[k] = (uint8_t)rng.next();
    std::memset(&mid, 0x5a, sizeof mid);
    before = mid;
    bool close = true;
    uint32_t mean = 0xff000000u;
    for (int sh = 0; sh < 24; sh += 8) {
      int ca = int(a.packed >> sh & 255), cb = int(b.packed >> sh & 255);
      close = close && ca - cb <= 8 && cb - ca <= 8;
      mean |= uint32_t((ca + cb + 1) / 2) << sh;
    }
    bool same = same_path(a.path, b.path), expect = same && close;
    ASSERT_EQ(adaptive_estimate(a, b, mid), expect) << "iter " << iter;
    if (expect) {
      ASSERT_EQ(mid.packed, mean) << "iter " << iter;
      ASSERT_TRUE(same_path(mid.path, a.path)) << "iter " << iter;
      ++estimated;
    } else {
      ASSERT_EQ(std::memcmp(&mid, &before, sizeof mid), 0) << "iter " << iter;
      byColour += same && !close;
      byRecord += !same;
    }
  }
  EXPECT_GT(estimated, 20000);
  EXPECT_GT(byColour, 20000);
  EXPECT_GT(byRecord, 20000);
}

// A band runs in the first scratch no running band holds (adaptive_run):
// with T threads only the first T of the caller's per-band scratches are
// written, the rest of the buffer keeps its bytes. The buffer's layout
// (adaptive.cpp): gridH lines of `width` samples, one scratch per band, the
// queue (two counters, a done and a busy flag per band) last. Rendered by 1
// and by 2 threads into a buffer of a seeded byte pattern: no byte past the
// lines and the first T scratches changes but the queue's, and the picture
// is the one rendered into zeros.
TEST(AdaptiveFrame, OnlyTheFirstScratchesPerThreadAreWritten) {
  const int w = 400, h = 300, block = 8;
  Scene s;
  build_timeline_scene(s, 44.0);
  Layout L = buffer_layout(w, h, block);
  size_t count = L.count, lines = L.lines, queue = L.queue, scratch = L.scratch;
  ASSERT_EQ(lines + scratch * size_t(L.bands) + queue, count);
  std::vector<CornerSample> corners(count);
  auto render = [&](int threads) {
    Image img(w, h);
    AdaptiveFrame f = begun_frame(s, img, corners.data(), block);
    auto work = [&f] {
      RayStats stats{0, 0, 0};
      for (int b; (b = adaptive_take(f)) != kAdaptiveDone;)
        if (b == kAdaptiveWait)
          std::this_thread::yield();
        else
          adaptive_run(f, b, &stats);
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t)
      pool.emplace_back(work);
    work();
    for (std::thread& t : pool)
      t.join();
    return img;
  };
  std::memset(corners.data(), 0, count * sizeof(CornerSample));
  Image ref = render(1);
  for (int threads : {1, 2}) {
    auto* bytes = reinterpret_cast<uint8_t*>(corners.data());
    Lcg rng{uint32_t(threads)};
    for (size_t i = 0; i < count * sizeof(CornerSample); ++i)
      bytes[i] = (uint8_t)rng.next();
    std::vector<uint8_t> before(bytes, bytes + count * sizeof(CornerSample));
    Image img = render(threads);
    EXPECT_EQ(img.pixels, ref.pixels) << threads << " threads";
    size_t from = (lines + scratch * size_t(threads)) * sizeof(CornerSample);
    size_t to = (count - queue) * sizeof(CornerSample), changed = 0;
    for (size_t i = from; i < to; ++i)
      changed += bytes[i] != before[i];
    EXPECT_EQ(changed, 0u) << threads << " threads";
    size_t firstChanged = 0; // the first scratch is used
    for (size_t i = lines * sizeof(CornerSample); i < from; ++i)
      firstChanged += bytes[i] != before[i];
    EXPECT_GT(firstChanged, 1000u) << threads << " threads";
  }
}

// The children of split blocks go through process_group in groups of up to
// kGroup = 32 (round eleven, adapt15; was 16): a band's scratch holds, per
// level, the inner lines of 32 split blocks. Base blocks of 64 px always
// split down to 8 px (kMaxInterpolated), so the groups of 32 px and 16 px
// children are full of split blocks. Rendered by 1 thread into a buffer of
// a seeded byte pattern: the scratch is written past what groups of 16
// needed (17 columns of 65, 8 base blocks' lines, 16 blocks' lines a level),
// no byte past the first scratch changes but the queue's, the picture is
// render_frame's with 3 threads, no sample is traced twice and every traced
// pixel is the full trace's. Fails with band_scratch sized for groups of 16
// (the scratch runs into the second one) and with kGroup = 16 (not written
// past that size).
TEST(AdaptiveFrame, ChildGroupsOfThirtyTwoStayInTheirScratch) {
  const int w = 400, h = 300, block = 64;
  Layout L = buffer_layout(w, h, block);
  size_t count = L.count, lines = L.lines, queue = L.queue, scratch = L.scratch;
  ASSERT_EQ(lines + scratch * size_t(L.bands) + queue, count);
  size_t sixteen = 17 * (block + 1) + 8 * 2 * (block + 1); // columns, base level
  for (int s = (block + 1) / 2; s >= 2; s = (s + 1) / 2)
    sixteen += 16 * 2 * size_t(s + 1);
  for (double t : {13.0, 44.0}) {
    Scene s;
    build_timeline_scene(s, t);
    std::vector<CornerSample> corners(count);
    auto* bytes = reinterpret_cast<uint8_t*>(corners.data());
    Lcg rng{uint32_t(t * 4)};
    for (size_t i = 0; i < count * sizeof(CornerSample); ++i)
      bytes[i] = (uint8_t)rng.next();
    std::vector<uint8_t> before(bytes, bytes + count * sizeof(CornerSample));
    Image img(w, h);
    AdaptiveFrame f = begun_frame(s, img, corners.data(), block);
    RayStats stats{0, 0, 0};
    for (int b; (b = adaptive_take(f)) != kAdaptiveDone;)
      if (b != kAdaptiveWait) adaptive_run(f, b, &stats);

    size_t first = lines * sizeof(CornerSample), end = (lines + scratch) * sizeof(CornerSample);
    size_t last = 0, past = 0;
    for (size_t i = first; i < end; ++i)
      if (bytes[i] != before[i]) last = i;
    for (size_t i = end; i < (count - queue) * sizeof(CornerSample); ++i)
      past += bytes[i] != before[i];
    EXPECT_GT(last, first + sixteen * sizeof(CornerSample)) << "t=" << t;
    EXPECT_EQ(past, 0u) << "t=" << t;

    Image threaded(w, h), full(w, h), marked(w, h);
    RenderOptions opt;
    opt.block = block;
    opt.threads = 3;
    render_frame(s, threaded, opt, nullptr);
    EXPECT_EQ(img.pixels, threaded.pixels) << "t=" << t;
    std::vector<uint8_t> kinds(size_t(w) * size_t(h), kUnset);
    opt.threads = 1;
    opt.kinds = kinds.data();
    RayStats marks;
    render_frame(s, marked, opt, &marks);
    RenderOptions fo;
    fo.mode = Mode::Full;
    fo.threads = 2;
    render_frame(s, full, fo, nullptr);
    uint64_t samples = 0, twice = 0, traced = 0, mismatched = 0;
    for (size_t i = 0; i < kinds.size(); ++i) {
      int n = kinds[i] >> kSampleCountShift;
      samples += uint64_t(n);
      twice += n > 1;
      if ((kinds[i] & kKindMask) != kTraced) continue;
      ++traced;
      mismatched += full.pixels[i] != marked.pixels[i];
    }
    EXPECT_EQ(twice, 0u) << "t=" << t;
    EXPECT_EQ(samples, marks.primary) << "t=" << t;
    EXPECT_EQ(samples, stats.primary) << "t=" << t;
    EXPECT_GT(traced, uint64_t(w * h / 50)) << "t=" << t;
    EXPECT_EQ(mismatched, 0u) << "t=" << t << " of " << traced << " traced pixels";
    EXPECT_EQ(marked.pixels, img.pixels) << "t=" << t << ": with and without kinds map";
  }
}

// The bands' order on one thread (25 bands): even bands from the bottom up,
// each odd band as soon as both neighbours ran, until only the last 5 even
// bands (adaptive.cpp: kTailEvens; 8, 6, 4, 2, 0) are left: then the ready
// odd band (11) is held back and the last even bands come in a row, the odd
// bands after them. Fails with odd bands handed out as soon as they are
// ready (kTailEvens 0: ..., 10, 11, 8, 9, ...).
TEST(AdaptiveFrame, BandsQueueKeepsOddBandsForTheEnd) {
  Scene s;
  build_timeline_scene(s, 44.0);
  constexpr int kW = 64, kH = 200;
  Image ref(kW, kH), img(kW, kH);
  RenderOptions opt;
  opt.threads = 1;
  render_frame(s, ref, opt, nullptr);
  std::vector<CornerSample> corners(size_t(adaptive_corner_count(kW, kH, 8)));
  AdaptiveFrame f = begun_frame(s, img, corners.data(), 8);
  ASSERT_EQ(adaptive_items(f), 25);
  std::vector<int> order;
  RayStats stats{0, 0, 0};
  for (int b; (b = adaptive_take(f)) != kAdaptiveDone;) {
    ASSERT_NE(b, kAdaptiveWait); // one thread: every band it waits for has run
    order.push_back(b);
    adaptive_run(f, b, &stats);
  }
  std::vector<int> want = {24, 22, 23, 20, 21, 18, 19, 16, 17, 14, 15, 12, 13,
                           10, 8,  6,  4,  2,  0,  11, 9,  7,  5,  3,  1};
  EXPECT_EQ(order, want);
  EXPECT_EQ(img.pixels, ref.pixels);
}
