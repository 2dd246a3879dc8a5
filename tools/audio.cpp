// audio.cpp - `rt64k audio --out FILE.wav`.
#include "audio.h"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include "synth.h"

namespace {

void put16(std::string& s, uint16_t v) {
  s += (char)(v & 255);
  s += (char)(v >> 8);
}
void put32(std::string& s, uint32_t v) {
  put16(s, (uint16_t)(v & 0xffff));
  put16(s, (uint16_t)(v >> 16));
}

} // namespace

bool write_wav(const std::string& path, const std::vector<short>& stereo, int rate) {
  uint32_t dataBytes = (uint32_t)(stereo.size() * 2);
  std::string h = "RIFF";
  put32(h, 36 + dataBytes);
  h += "WAVEfmt ";
  put32(h, 16); // fmt chunk size
  put16(h, 1);  // PCM
  put16(h, 2);  // channels
  put32(h, (uint32_t)rate);
  put32(h, (uint32_t)rate * 4); // bytes per second
  put16(h, 4);                  // block align
  put16(h, 16);                 // bits per sample
  h += "data";
  put32(h, dataBytes);
  std::string body;
  body.reserve(dataBytes);
  for (short v : stereo)
    put16(body, (uint16_t)v); // little-endian on any host
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return false;
  bool ok = std::fwrite(h.data(), 1, h.size(), f) == h.size() &&
            std::fwrite(body.data(), 1, body.size(), f) == body.size();
  ok = (std::fclose(f) == 0) && ok;
  return ok;
}

int cmd_audio(int argc, char** argv) {
  std::string out;
  for (int i = 2; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--out" && i + 1 < argc && out.empty()) {
      out = argv[++i];
    } else {
      std::fprintf(stderr, "rt64k audio: bad argument '%s' (usage: rt64k audio --out FILE.wav)\n",
                   a.c_str());
      return 2;
    }
  }
  if (out.empty()) {
    std::fprintf(
        stderr, "rt64k audio: missing required option --out (usage: rt64k audio --out FILE.wav)\n");
    return 2;
  }
  // Fail before the render if the path cannot be written.
  FILE* probe = std::fopen(out.c_str(), "wb");
  if (!probe) {
    std::fprintf(stderr, "rt64k audio: cannot write '%s'\n", out.c_str());
    return 2;
  }
  std::fclose(probe);
  std::vector<short> samples((size_t)kAudioFrames * 2);
  std::vector<float> scratch(kSynthScratchFloats);
  auto t0 = std::chrono::steady_clock::now();
  SynthReport rep = synth_render(samples.data(), scratch.data());
  double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (!write_wav(out, samples, kAudioRate)) {
    std::fprintf(stderr, "rt64k audio: cannot write '%s'\n", out.c_str());
    return 2;
  }
  double sum = 0;
  for (short v : samples)
    sum += (double)v * v;
  double rms = std::sqrt(sum / (double)samples.size()) / 32767.0;
  std::printf("%s: %d s, %d Hz stereo 16-bit; peak %.2f dBFS, RMS %.2f dBFS; rendered in %.0f ms\n",
              out.c_str(), kAudioSeconds, kAudioRate, 20 * std::log10(rep.peak),
              20 * std::log10(rms), ms);
  return 0;
}
