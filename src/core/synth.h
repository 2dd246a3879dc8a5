// synth.h - rt64k's softsynth: renders the intro's 64-s music loop at start-up.
//
// Freestanding like the rest of src/core: no C runtime, no heap, no OS calls.
// The caller owns every buffer. The result is a pure function of the code and
// its note data: the same samples from the Linux tool and from intro.exe, on
// any machine, as long as both compile synth.cpp with RT64K_CORE_FLAGS (IEEE
// single precision on SSE, no fast-math, no FP contraction).
//
// The loop is seamless: rendering starts kSynthPrerollSeconds before t = 0
// with the notes of the loop's end, so every voice, echo and filter that
// sounds across the seam is already running when sample 0 is written; the
// sample after the last one continues into sample 0.
#pragma once
#include "rtmath.h"

constexpr int kAudioRate = 44100;
constexpr int kAudioSeconds = 64;                        // = kTimelineSeconds in scenes/scenes.h
constexpr int kAudioFrames = kAudioSeconds * kAudioRate; // stereo frames in the loop

// Floats of caller-owned scratch synth_render needs (about 237 KiB); its
// contents on entry do not matter.
constexpr int kSynthScratchFloats = 5 * 5520 + 2 * 16544;

constexpr float kSynthPrerollSeconds = 8.0f;

struct SynthReport {
  float peak;    // largest |sample| of the float mix before conversion; full scale = 1
  int stolen;    // voices taken from a still-sounding note (each one a click): 0 by design
  int maxVoices; // most voices sounding at once
};

// Renders `frames` stereo frames (interleaved L, R; 16-bit PCM) of the music
// loop into `out`. frames = kAudioFrames gives the loop; more frames keep
// playing the loop (frame kAudioFrames + k continues like frame k: the tests
// use this to check the seam). Samples are not clamped: the mix never
// reaches full scale (SynthReport::peak, asserted <= -0.5 dBFS by
// tests/test_synth, which also checks the shorts against it), and a clamp
// that never acts cost 16 packed bytes (docs/win32.md "Round seven").
SynthReport synth_render(short* out, int frames, float* scratch /* kSynthScratchFloats */);

// The loop, as intro.exe uses it: out holds kAudioFrames * 2 shorts.
inline SynthReport synth_render(short* out, float* scratch) {
  return synth_render(out, kAudioFrames, scratch);
}
