// audio.cpp - waveOut playback of the music loop (see audio.h). Win32 API
// only: no C runtime call, every struct field set explicitly.
#define WIN32_LEAN_AND_MEAN
#include <windows.h>
// mmsystem.h needs windows.h first.
#include <mmsystem.h>

#include "audio.h"
#include "synth.h"

namespace {

// The one mutable global of the exe. Zero-initialised, it goes to .bss (no
// file bytes; src/win32/intro.ld) as long as the exe is built without
// -fdata-sections, which would give it a .data$ section with file bytes.
struct Player {
  HWAVEOUT device;
  WAVEHDR header;
  DWORD lastFrame; // last position within the loop, in frames
  int passes;      // completed passes through the loop
} g;

} // namespace

// 16-bit stereo PCM at kAudioRate: tag, channels, rate, bytes per second,
// bytes per frame, bits per sample, no extra bytes.
const WAVEFORMATEX kFormat = {WAVE_FORMAT_PCM, 2, kAudioRate, kAudioRate * 4, 4, 16, 0};

bool audio_start(const short* samples) {
  if (waveOutOpen(&g.device, WAVE_MAPPER, &kFormat, 0, 0, CALLBACK_NULL) == MMSYSERR_NOERROR) {
    g.header.lpData = (LPSTR)samples;
    g.header.dwBufferLength = (DWORD)kAudioFrames * 4;
    g.header.dwFlags = 0; // waveOutPrepareHeader wants 0; the loop flags come after
    g.header.dwLoops = 0;
    g.lastFrame = 0;
    g.passes = 0;
    if (waveOutPrepareHeader(g.device, &g.header, sizeof g.header) == MMSYSERR_NOERROR) {
      g.header.dwFlags |= WHDR_BEGINLOOP | WHDR_ENDLOOP;
      g.header.dwLoops = 0xFFFFFFFF;
      if (waveOutWrite(g.device, &g.header, sizeof g.header) == MMSYSERR_NOERROR) return true;
    }
    // A device that refused the buffer stays open, silent, until the process
    // exits (which closes it): no waveOutUnprepareHeader, waveOutClose imports.
  }
  g.device = nullptr; // audio_stop then does nothing
  return false;
}

double audio_seconds() {
  MMTIME t;
  t.wType = TIME_SAMPLES;
  t.u.sample = 0;
  waveOutGetPosition(g.device, &t, sizeof t);
  // A driver without TIME_SAMPLES answers in another format (usually bytes).
  DWORD frame = (t.wType == TIME_BYTES ? t.u.cb / 4 : t.u.sample) % (DWORD)kAudioFrames;
  if (frame + kAudioFrames / 2 < g.lastFrame)
    ++g.passes; // wrapped to the loop's start
  else if (frame < g.lastFrame)
    frame = g.lastFrame; // jitter: never step back
  g.lastFrame = frame;
  return g.passes * (double)kAudioSeconds + (double)frame * (1.0 / kAudioRate);
}

void audio_stop() {
  if (!g.device) return;
  // Silence now; the exit that always follows (quit) closes the device with
  // its prepared header (docs/win32.md, round seven: two imports fewer).
  waveOutReset(g.device);
}
