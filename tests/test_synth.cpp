// test_synth.cpp - the music loop: levels, seam, determinism, the WAVE tool.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

#include "audio.h"
#include "scenes.h"
#include "synth.h"

namespace {

// The loop plus 2 s of its continuation (frame kAudioFrames + k continues like
// frame k), rendered once for all tests.
constexpr int kExtraFrames = 2 * kAudioRate;

struct Track {
  std::vector<short> samples; // (kAudioFrames + kExtraFrames) * 2
  SynthReport report;
  double ms;    // wall-clock time of the render
  double cpuMs; // processor time of the render (this process; the render is single-threaded)
};

const Track& track() {
  static Track t = [] {
    Track r;
    r.samples.assign((size_t)(kAudioFrames + kExtraFrames) * 2, 0);
    std::vector<float> scratch(kSynthScratchFloats);
    auto t0 = std::chrono::steady_clock::now();
    std::clock_t c0 = std::clock();
    r.report = synth_render(r.samples.data(), kAudioFrames + kExtraFrames, scratch.data());
    r.cpuMs = 1000.0 * (double)(std::clock() - c0) / CLOCKS_PER_SEC;
    r.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return r;
  }();
  return t;
}

constexpr double kPi64 = 3.14159265358979323846;

double db(double x) { return 20 * std::log10(x); }

// RMS over both channels of frames [a, b), full scale = 1.
double rms(const std::vector<short>& s, int a, int b) {
  double sum = 0;
  for (int i = 2 * a; i < 2 * b; ++i)
    sum += (double)s[i] * s[i];
  return std::sqrt(sum / (2.0 * (b - a))) / 32767.0;
}

int frame_at(double seconds) { return (int)(seconds * kAudioRate); }

} // namespace

TEST(Synth, RenderTimeIsReported) {
  const Track& t = track();
  double seconds = (kAudioFrames + kExtraFrames) / (double)kAudioRate;
  std::printf("[ info ] synth: %.1f s of audio rendered in %.0f ms wall, %.0f ms CPU "
              "(%.0f ms CPU per 64-s loop); at most %d voices at once\n",
              seconds, t.ms, t.cpuMs, t.cpuMs * 64.0 / seconds, t.report.maxVoices);
  SUCCEED();
}

TEST(Synth, LengthIsTheTimeline) {
  EXPECT_EQ(kAudioFrames, 2822400);
  EXPECT_EQ((double)kAudioFrames, (double)kTimelineSeconds * kAudioRate);
  EXPECT_EQ(kAudioRate, 44100);
}

TEST(Synth, NoClippingAndNoGarbage) {
  const Track& t = track();
  // The float mix before conversion: finite and at most -0.5 dBFS (headroom).
  ASSERT_TRUE(std::isfinite(t.report.peak));
  EXPECT_GT(t.report.peak, 0.5f);
  EXPECT_LE(db(t.report.peak), -0.5);
  // The shorts agree with the float peak (so nothing was clamped).
  int peak = 0;
  for (short v : t.samples)
    peak = std::max(peak, std::abs((int)v));
  EXPECT_NEAR(peak / 32767.0, t.report.peak, 1.0 / 32767);
  EXPECT_LT(peak, 32767);
  // No dropout and no stuck output: every 0.5 s window has signal, and no
  // run of 1000 equal samples appears in either channel.
  for (int w = 0; w < 128; ++w) {
    int a = w * kAudioFrames / 128, b = (w + 1) * kAudioFrames / 128;
    EXPECT_GT(db(rms(t.samples, a, b)), -50.0) << "window at " << a / (double)kAudioRate << " s";
  }
  for (int c = 0; c < 2; ++c) {
    int run = 1, longest = 1;
    for (int i = 1; i < kAudioFrames; ++i) {
      run = t.samples[2 * i + c] == t.samples[2 * i - 2 + c] ? run + 1 : 1;
      longest = std::max(longest, run);
    }
    EXPECT_LT(longest, 1000) << "channel " << c;
  }
  // No voice was taken from a sounding note (that would click).
  EXPECT_EQ(t.report.stolen, 0);
}

// Stated levels: each scene's RMS within [-22, -16] dBFS; scene 1 (dark) is
// the quieter one, scene 2 (bright) carries more of its energy above 2 kHz.
TEST(Synth, LevelsAndMoodPerScene) {
  const Track& t = track();
  int half = kAudioFrames / 2;
  double rms1 = db(rms(t.samples, 0, half)), rms2 = db(rms(t.samples, half, kAudioFrames));
  std::printf("[ info ] RMS scene 1 %.2f dBFS, scene 2 %.2f dBFS, peak %.2f dBFS\n", rms1, rms2,
              db(t.report.peak));
  EXPECT_GE(rms1, -22.0);
  EXPECT_LE(rms1, -16.0);
  EXPECT_GE(rms2, -22.0);
  EXPECT_LE(rms2, -16.0);
  EXPECT_LT(rms1, rms2);
  // Share of energy above ~2 kHz: a 2-pole high-pass (RBJ biquad, Q 0.707)
  // over the mid signal (L + R) / 2.
  auto bright_share = [&](int a, int b) {
    double w0 = 2 * kPi64 * 2000.0 / kAudioRate, alpha = std::sin(w0) / (2 * 0.70710678);
    double cw = std::cos(w0), n = 1 + alpha;
    double c0 = (1 + cw) / 2 / n, c1 = -(1 + cw) / n, c2 = c0, d1 = -2 * cw / n,
           d2 = (1 - alpha) / n;
    double x1 = 0, x2 = 0, y1 = 0, y2 = 0, hi = 0, all = 0;
    for (int i = a; i < b; ++i) {
      double x = (t.samples[2 * i] + t.samples[2 * i + 1]) * 0.5;
      double y = c0 * x + c1 * x1 + c2 * x2 - d1 * y1 - d2 * y2;
      x2 = x1, x1 = x, y2 = y1, y1 = y;
      hi += y * y;
      all += x * x;
    }
    return hi / all;
  };
  double b1 = bright_share(0, half), b2 = bright_share(half, kAudioFrames);
  std::printf("[ info ] energy above 2 kHz: scene 1 %.1f%%, scene 2 %.1f%%\n", 100 * b1, 100 * b2);
  EXPECT_GT(b2, 2 * b1);
}

// No DC offset: the mean of each channel over each scene is within 1e-3 of
// full scale (-60 dB).
TEST(Synth, NoDcOffset) {
  const Track& t = track();
  for (int half = 0; half < 2; ++half)
    for (int c = 0; c < 2; ++c) {
      double sum = 0;
      for (int i = half * kAudioFrames / 2; i < (half + 1) * kAudioFrames / 2; ++i)
        sum += t.samples[2 * i + c];
      double mean = sum / (kAudioFrames / 2) / 32767.0;
      EXPECT_LT(std::fabs(mean), 1e-3) << "scene " << half + 1 << " channel " << c;
    }
}

// The knock in scene 1 (9 s) is an accent: the 0.25 s after it are at least
// 6 dB louder than the 0.5 s before.
TEST(Synth, KnockAccentAtNineSeconds) {
  const Track& t = track();
  double before = rms(t.samples, frame_at(8.5), frame_at(9.0));
  double after = rms(t.samples, frame_at(9.0), frame_at(9.25));
  std::printf("[ info ] knock: %.1f dB before, %.1f dB after\n", db(before), db(after));
  EXPECT_GT(db(after) - db(before), 6.0);
}

// The seam: the sample after the last one is sample 0. The step across it
// is within the 99.9th percentile of all steps (no click), and the rendered
// continuation repeats the loop's start (within 1 LSB).
TEST(Synth, LoopSeamHasNoClick) {
  const Track& t = track();
  const std::vector<short>& s = t.samples;
  for (int c = 0; c < 2; ++c) {
    std::vector<int> steps;
    steps.reserve(kAudioFrames);
    for (int i = 0; i + 1 < kAudioFrames; ++i)
      steps.push_back(std::abs(s[2 * (i + 1) + c] - s[2 * i + c]));
    std::sort(steps.begin(), steps.end());
    int seam = std::abs(s[c] - s[2 * (kAudioFrames - 1) + c]);
    int p999 = steps[steps.size() * 999 / 1000], p50 = steps[steps.size() / 2];
    std::printf("[ info ] channel %d: seam step %d; elsewhere median %d, 99.9%% %d, max %d\n", c,
                seam, p50, p999, steps.back());
    EXPECT_LE(seam, steps.back());
    EXPECT_LE(seam, p999);
  }
  int worst = 0;
  for (int k = 0; k < 2 * kExtraFrames; ++k)
    worst = std::max(worst, std::abs(s[2 * kAudioFrames + k] - s[k]));
  EXPECT_LE(worst, 1);
}

// The same samples on every run, whatever the scratch held before.
TEST(Synth, Deterministic) {
  const Track& t = track();
  std::vector<short> again((size_t)kAudioFrames * 2, 0x5a5a);
  std::vector<float> scratch(kSynthScratchFloats, std::nanf(""));
  SynthReport r = synth_render(again.data(), scratch.data());
  EXPECT_EQ(r.peak, t.report.peak);
  EXPECT_TRUE(std::equal(again.begin(), again.end(), t.samples.begin()));
}

// rt_sin_turns (rtmath.h), the oscillators' sine: |error| <= 1e-3 against
// libm's sin over +-8 turns, and never outside [-1, 1].
TEST(Synth, FastSineErrorBound) {
  double worst = 0;
  for (int i = -800000; i <= 800000; ++i) {
    float p = (float)i * 1e-5f;
    float s = rt_sin_turns(p);
    ASSERT_LE(std::fabs(s), 1.0f) << p;
    worst = std::max(worst, std::fabs(s - std::sin(2 * kPi64 * (double)p)));
  }
  std::printf("[ info ] rt_sin_turns max |error| %.2e\n", worst);
  EXPECT_LE(worst, 1e-3);
}

namespace {

std::vector<unsigned char> read_file(const std::string& path) {
  std::vector<unsigned char> data;
  FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return data;
  unsigned char buf[65536];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0)
    data.insert(data.end(), buf, buf + n);
  std::fclose(f);
  return data;
}

uint32_t le32(const std::vector<unsigned char>& d, size_t at) {
  return d[at] | d[at + 1] << 8 | d[at + 2] << 16 | (uint32_t)d[at + 3] << 24;
}
uint16_t le16(const std::vector<unsigned char>& d, size_t at) {
  return (uint16_t)(d[at] | d[at + 1] << 8);
}

int run_audio(std::vector<std::string> args) {
  args.insert(args.begin(), {"rt64k", "audio"});
  std::vector<char*> argv;
  for (auto& a : args)
    argv.push_back(a.data());
  return cmd_audio((int)argv.size(), argv.data());
}

} // namespace

TEST(AudioTool, WritesTheLoopAsRiffWave) {
  std::string path = ::testing::TempDir() + "rt64k_track.wav";
  ASSERT_EQ(run_audio({"--out", path}), 0);
  std::vector<unsigned char> d = read_file(path);
  ASSERT_EQ(d.size(), 44u + (size_t)kAudioFrames * 4);
  EXPECT_EQ(std::memcmp(d.data(), "RIFF", 4), 0);
  EXPECT_EQ(le32(d, 4), d.size() - 8);
  EXPECT_EQ(std::memcmp(d.data() + 8, "WAVEfmt ", 8), 0);
  EXPECT_EQ(le32(d, 16), 16u);    // fmt chunk size
  EXPECT_EQ(le16(d, 20), 1);      // PCM
  EXPECT_EQ(le16(d, 22), 2);      // stereo
  EXPECT_EQ(le32(d, 24), 44100u); // rate
  EXPECT_EQ(le32(d, 28), 176400u);
  EXPECT_EQ(le16(d, 32), 4);
  EXPECT_EQ(le16(d, 34), 16);
  EXPECT_EQ(std::memcmp(d.data() + 36, "data", 4), 0);
  EXPECT_EQ(le32(d, 40), (uint32_t)kAudioFrames * 4);
  // Sample for sample what the synth (and so intro.exe) renders.
  const Track& t = track();
  bool same = true;
  for (int i = 0; i < 2 * kAudioFrames && same; ++i)
    same = (short)le16(d, 44 + 2 * (size_t)i) == t.samples[i];
  EXPECT_TRUE(same);
  std::remove(path.c_str());
}

TEST(AudioTool, BadArgumentsAndUnwritablePathReturn2) {
  EXPECT_EQ(run_audio({}), 2);
  EXPECT_EQ(run_audio({"--out"}), 2);
  EXPECT_EQ(run_audio({"--bogus", "x.wav"}), 2);
  EXPECT_EQ(run_audio({"--out", "a.wav", "--out", "b.wav"}), 2);
  EXPECT_EQ(run_audio({"--out", "/nonexistent-dir/x/track.wav"}), 2);
}
