// audio.cpp - `rt64k audio --out FILE.wav`.
#include "audio.h"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include "output.h"
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

bool write_wav(const std::string& path, const std::vector<short>& stereo, int rate,
               std::string& error) {
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
  OutputFile out;
  if (!out.open(path, error)) return false;
  std::fwrite(h.data(), 1, h.size(), out.stream());
  std::fwrite(body.data(), 1, body.size(), out.stream());
  return out.commit(error); // any failed write above is reported here
}

int cmd_audio(int argc, char** argv) {
  const std::string usage = " (usage: rt64k audio --out FILE.wav)";
  std::string out;
  bool haveOut = false;
  for (int i = 2; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--out" && haveOut) {
      report_error("audio: option --out given twice" + usage);
      return 2;
    } else if (a == "--out" && i + 1 < argc) {
      out = argv[++i];
      haveOut = true;
    } else if (a == "--out") {
      report_error("audio: option --out needs a value" + usage);
      return 2;
    } else {
      report_error("audio: unknown option '" + a + "'" + usage);
      return 2;
    }
  }
  if (!haveOut) {
    report_error("audio: missing required option --out" + usage);
    return 2;
  }
  // Fail before the render if the path cannot be written; the file itself is
  // not touched until the samples are ready (output.h).
  std::string error;
  if (!check_output_path(out, error)) {
    report_error("audio: " + error);
    return 2;
  }
  std::vector<short> samples((size_t)kAudioFrames * 2);
  std::vector<float> scratch(kSynthScratchFloats);
  auto t0 = std::chrono::steady_clock::now();
  SynthReport rep = synth_render(samples.data(), scratch.data());
  double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (!write_wav(out, samples, kAudioRate, error)) {
    report_error("audio: " + error);
    return 2;
  }
  double sum = 0;
  for (short v : samples)
    sum += (double)v * v;
  double rms = std::sqrt(sum / (double)samples.size()) / 32767.0;
  std::printf("%s: %d s, %d Hz stereo 16-bit; peak %.2f dBFS, RMS %.2f dBFS; rendered in %.0f ms\n",
              printable(out).c_str(), kAudioSeconds, kAudioRate, 20 * std::log10(rep.peak),
              20 * std::log10(rms), ms);
  return 0;
}
