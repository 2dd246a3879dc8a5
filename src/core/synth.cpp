// synth.cpp - the softsynth and the intro's music (see docs/music.md).
//
// Structure: 13 channels, each one fixed instrument (a ChannelDef of bytes).
// A channel plays 16-step patterns (one per bar) chosen by its row in
// kSong. Notes go to a shared pool of voices; a voice is two oscillators
// (saws, or a sine with FM), noise, a state-variable filter with an
// envelope, a pitch envelope and an attack-decay-sustain-release amplifier.
// Voices mix into two stereo buses (instruments, ducked by each kick; drums)
// and a send to one ping-pong delay.
//
// Time: 120 BPM, a 16th-note step is 5512.5 samples, a bar 16 steps (2 s);
// 32 bars make the 64-s loop: bars 0-15 scene 1, bars 16-31 scene 2.
#include "synth.h"

namespace {

// ---------------------------------------------------------------- timing
constexpr int kStepsPerLoop = 512; // 32 bars x 16 steps; a power of two (step & 511)
constexpr int kPrerollSteps = 64;  // kSynthPrerollSeconds at 8 steps a second
static_assert(kPrerollSteps * 5512.5f == kSynthPrerollSeconds * kAudioRate, "preroll");
// First sample of step k (k >= -kPrerollSteps): 5512.5 k, rounded down.
// kPrerollSteps is even, so the preroll is a whole number of samples.
inline int sample_of_step(int k) {
  return ((k + kPrerollSteps) * 11025 >> 1) - kPrerollSteps * 11025 / 2;
}

constexpr int kBlockMax = 5520;  // >= the longest step (5513 samples)
constexpr int kDelayLen = 16538; // 3 steps (a dotted eighth), rounded
constexpr int kDelayAlloc = 16544;
static_assert(kSynthScratchFloats == 5 * kBlockMax + 2 * kDelayAlloc, "scratch layout");

constexpr float kFeedback = 0.42f; // ping-pong echo gain per repeat
constexpr float kDamp = 0.35f;     // one-pole low-pass in the echo loop: repeats darken
constexpr float kMaster = 0.5f;
constexpr float kDuckDepth = 0.5f; // each kick ducks the other instruments (and echoes) by half,
constexpr int kDuckRelease = 120;  // recovering with this half-life (time code: 88 ms)
constexpr float kMaxCut = 0.8f;    // SVF stable for f^2 + 2 f q < 4: holds for f <= 0.8, q < 2
constexpr float kSilentLevel = 0.5f / 32768; // a released voice stops below half an LSB
constexpr int kVoices = 32;

// ---------------------------------------------------------------- instruments
enum Kind : u8 {
  kPlain = 0,
  kChord = 1,  // plays the bar's 4 chord tones (plus base + note field - 1)
  kRoot = 2,   // note is relative to the bar's chord root
  kDrum = 4,   // the pattern's length bits are a velocity (1..8)/8; gate is one step
  kPhase0 = 8, // oscillators start at phase 0 (others at a random phase, so that
               // chord tones and coinciding hits do not add up in phase)
};

// Byte codes: a "time" t is a half-life (or a linear attack time) of
// 2^((t - 176) / 16) seconds: 176 = 1 s, 160 = 0.5 s, 128 = 125 ms, 64 = 7.8 ms,
// 0 = 0.5 ms. A "cutoff" c is the SVF coefficient 2^(c/32 - 8) (~ 2 pi fc / fs):
// 150 ~ 700 Hz, 192 ~ 1.75 kHz, 224 ~ 3.5 kHz; capped at kMaxCut (~5.8 kHz).
struct ChannelDef {
  u8 kind, base; // base: MIDI note of pattern note field 1 (chord channels: added to the chord)
  u8 patterns;   // number of patterns before this channel's pattern 'a' in kGrids
  u8 wave;       // 0 sine, phase-modulated by osc 2 (FM); 1 two saws
  u8 osc2;       // wave 0: modulator ratio osc2/16; else osc 2 detuned by ratio 1 + osc2/2048
  u8 fm;         // wave 0: modulation index fm/32 turns, scaled by the amplitude envelope
  u8 noise;      // share of white noise in the source, /256
  u8 attack, decay, sustain, release; // times; sustain level /256
  u8 cutoff;                          // filter cutoff (code above)
  signed char fenv; // cutoff * (1 + fenv/8 * e), e falls 1 -> 0 with half-life fdecay
  u8 fdecay;
  u8 filter; // bits 0-1: 0 low-pass, 1 band-pass, 2 high-pass, 3 none; bits 2-7: damping q*32 - 1
  u8 pitch, pdecay; // frequency * (1 + pitch/8 * e), e falls 1 -> 0 with half-life pdecay
  u8 volume;        // /256
  signed char pan;  // /128, < 0 is left; chord tones spread +-0.3 around it
  u8 send;          // to the delay, /256
};

enum Channel {
  PAD,
  STAB,
  SUB,
  BASS,
  LEAD,
  BELL,
  METAL,
  KICK,
  SNARE,
  HAT,
  OHAT,
  CRASH,
  RISER,
  kChannels
};

// clang-format off
const ChannelDef kChannelDefs[kChannels] = {
  //kind        base pat wave osc2 fm noise  att  dec sus  rel  cut fenv fdec filter      pitch pdec vol pan send
  {kChord,        0,  0,  1,  12,   0,   0, 176, 200, 160, 140, 150, -6, 192, 31 << 2 | 0,  0,  0,  40,   0,  90}, // PAD dark saw pad
  {kChord,       12,  2,  1,  16,   0,   0,   0, 104,   0, 104, 200,  8, 112, 21 << 2 | 0,  0,  0,  58,   0, 110}, // STAB offbeat pluck
  {kRoot,         0,  4,  0,  16,   8,   0, 168, 200, 200, 150, 255,  0,   0, 31 << 2 | 3,  0,  0,  72,   0,   0}, // SUB sine sub bass
  {kRoot,         0,  5,  1,   4,   0,   0,   0, 128, 100,  96, 150, 16, 112, 15 << 2 | 0,  0,  0, 112,   0,   0}, // BASS rolling saw bass
  {kPlain,       69,  8,  1,  10,   0,   0,  64, 160, 170, 112, 215,  4, 128, 31 << 2 | 0,  0,  0,  92, -10, 100}, // LEAD saw lead
  {kPlain,       57, 17,  0,  56,   6,   0,   0, 152,   0, 152, 192,  0,   0, 31 << 2 | 0,  0,  0,  72,  20, 150}, // BELL FM glass bell
  {kPlain,       57, 28,  0,  23,  40,   0,   0, 140,   0, 140, 255,  0,   0, 31 << 2 | 3,  0,  0, 255,   0, 140}, // METAL the knock's clank
  {kDrum|kPhase0,28, 29,  0,   0,   0,   0,   0, 112,   0, 112, 255,  0,   0, 31 << 2 | 3, 32, 80, 215,   0,   0}, // KICK
  {kDrum,        53, 35,  0,   0,   0, 140,   0, 100,   0, 100, 240,  0,   0, 31 << 2 | 0,  4, 64, 215,   8,  40}, // SNARE
  {kDrum,        60, 40,  0,   0,   0, 255,   0,  64,   0,  64, 250,  0,   0, 31 << 2 | 2,  0,  0,  93,  30,  20}, // HAT closed
  {kDrum,        60, 42,  0,   0,   0, 255,   0, 112,   0, 112, 250,  0,   0, 31 << 2 | 2,  0,  0,  55, -30,  20}, // OHAT open
  {kDrum,        60, 43,  0,   0,   0, 255,   0, 148,   0, 148, 200,  0,   0, 44 << 2 | 2,  0,  0,  44, -15,  60}, // CRASH
  {kPlain,       57, 45,  0,   0,   0, 255, 205, 255, 255, 112, 220, -7, 176, 15 << 2 | 1,  0,  0,  88,   0,  80}, // RISER noise sweep
};

// A pattern is one bar: a grid of the steps that start a note (kGrids,
// bit k = step k) and one note byte per such step, in step order, in
// kNotes (pattern p's notes follow those of patterns 0..p-1). Note byte:
// bits 0-4 note field (1-31), bits 5-7 length code (kLength) or, on drum
// channels, velocity code.
constexpr u16 grid(const char (&g)[17]) {
  u16 m = 0;
  for (int k = 0; k < 16; ++k)
    m |= (u16)((g[k] == 'x') << k);
  return m;
}
const u16 kGrids[] = {
  grid("x..............."), // PAD a
  grid("x..............."), // PAD b
  grid("..x...x...x..x.."), // STAB a
  grid("..x...x...x.x.x."), // STAB b
  grid("x..............."), // SUB a
  grid("..xx..xx..xx..xx"), // BASS a
  grid("..xx..xx..xx.xxx"), // BASS b
  grid("x..............."), // BASS c
  grid("x..x..x.x.x.x..."), // LEAD a
  grid("x..x..x.x.x.x..."), // LEAD b
  grid("x..x..x.x.x.x.x."), // LEAD c
  grid("x..x..x...x.x..."), // LEAD d
  grid("x.x.x...x.x.x..."), // LEAD e
  grid("x..x..x.x.x.x..."), // LEAD f
  grid("x..x..x.x.x.x..."), // LEAD g
  grid("x.....x.x...x.x."), // LEAD h
  grid("x.x.x.......x..."), // LEAD i
  grid("x.....x........."), // BELL a
  grid("x...........x..."), // BELL b
  grid("x..............."), // BELL c
  grid("x.....x.x......."), // BELL d
  grid("....x...x......."), // BELL e
  grid("x.......x......."), // BELL f
  grid("x.......x...x..."), // BELL g
  grid("x.......x...x..."), // BELL h
  grid("x.......x......."), // BELL i
  grid("x.......x......."), // BELL j
  grid("x...x...x......."), // BELL k
  grid("........x......."), // METAL a
  grid("........x......."), // KICK a
  grid("x.x............."), // KICK b
  grid("x.x.....x.x....."), // KICK c
  grid("x...x...x...x.x."), // KICK d
  grid("x...x...x...x..."), // KICK e
  grid("x...x...x......."), // KICK f
  grid("........x......."), // SNARE a
  grid("xxxxxxxxxxxxxxxx"), // SNARE b
  grid("....x.......x..."), // SNARE c
  grid("....x.......x.xx"), // SNARE d
  grid("....x..........."), // SNARE e
  grid("..x...x...x...x."), // HAT a
  grid("xxxxxxxxxxxxxxxx"), // HAT b
  grid("..x...x...x...x."), // OHAT a
  grid("........x......."), // CRASH a
  grid("x..............."), // CRASH b
  grid("x..............."), // RISER a
};
constexpr u8 n(int field, int code) { return (u8)(code << 5 | field); }
enum Len { l1, l2, l3, l4, l6, l8, l16, l32 };
const u8 kLength[8] = {1, 2, 3, 4, 6, 8, 16, 32};

enum Note {
  A4 = 69, Bb4, B4, C5, Cs5, D5, Eb5, E5, F5, Fs5, G5, Ab5, A5, Bb5, B5, C6, Cs6, D6, Eb6, E6,
  F6, Fs6, G6, Ab6, A6,
};
constexpr u8 ld(int midi, int len) { return n(midi - 68, len); }  // LEAD, base 69
constexpr u8 bl(int midi, int len) { return n(midi - 56, len); }  // BELL and METAL, base 57

const u8 kNotes[] = {
  // PAD: a, whole chord for two bars; b, one bar an octave up
  n(1, l32),
  n(13, l16),
  // STAB: a, offbeats and a push; b, offbeats and an extra
  n(1,l1), n(1,l1), n(1,l1), n(1,l2),
  n(1,l1), n(1,l1), n(1,l1), n(1,l1), n(1,l1),
  // SUB: a, the root for two bars
  n(1, l32),
  // BASS: a, rolling offbeat 16ths (root, octave 13, fifth 8); b, with the seventh (11); c, held
  1, 1, 13, 1, 1, 1, 13, 8,
  1, 1, 13, 1, 13, 1, 11, 13, 8,
  n(1, l16),
  // LEAD: a-d over D A Bm G; e-h over D F#m G A; i the last bar (A7)
  ld(A5,l3), ld(Fs5,l3), ld(D6,l2), ld(Cs6,l2), ld(A5,l2), ld(Fs5,l4),
  ld(E5,l3), ld(A5,l3), ld(Cs6,l2), ld(B5,l2), ld(A5,l2), ld(E5,l4),
  ld(Fs5,l3), ld(B5,l3), ld(D6,l2), ld(Cs6,l2), ld(B5,l2), ld(Fs5,l2), ld(A5,l2),
  ld(G5,l3), ld(B5,l3), ld(D6,l4), ld(B5,l2), ld(A5,l4),
  ld(D6,l2), ld(E6,l2), ld(Fs6,l4), ld(E6,l2), ld(D6,l2), ld(A5,l4),
  ld(Cs6,l3), ld(A5,l3), ld(Fs5,l2), ld(A5,l2), ld(Cs6,l2), ld(E6,l4),
  ld(D6,l3), ld(B5,l3), ld(G5,l2), ld(B5,l2), ld(D6,l2), ld(G6,l4),
  ld(E6,l6), ld(Cs6,l2), ld(A5,l4), ld(E5,l2), ld(G5,l2),
  ld(Cs6,l2), ld(E6,l2), ld(A6,l8), ld(G6,l4),
  // BELL: a-k, bars 5-15 of scene 1 (Gm A7 A7 Dm Dm Bb Bb Eb Eb A7 A7)
  bl(D5,l4), bl(Bb4,l4),
  bl(Cs5,l8), bl(E5,l4),
  bl(A4,l16),
  bl(F5,l6), bl(E5,l2), bl(D5,l8),
  bl(A4,l4), bl(C5,l8),
  bl(D5,l8), bl(F5,l8),
  bl(A5,l8), bl(G5,l4), bl(F5,l4),
  bl(G5,l8), bl(Bb5,l4), bl(G5,l4),
  bl(F5,l8), bl(Eb5,l8),
  bl(E5,l8), bl(Cs5,l8),
  bl(E5,l4), bl(G5,l4), bl(Cs6,l8),
  // METAL: a, the knock at 9 s (bar 4, step 8)
  bl(A5,l2),
  // KICK (field 5 the kick, field 1 the knock's lower boom): a knock; b, c heartbeat;
  // d build; e four to the floor; f the last bar
  n(1,7),
  n(5,4), n(5,2),
  n(5,4), n(5,2), n(5,4), n(5,2),
  n(5,4), n(5,4), n(5,5), n(5,6), n(5,5),
  n(5,7), n(5,7), n(5,7), n(5,7),
  n(5,7), n(5,7), n(5,7),
  // SNARE: a soft half-time; b roll; c backbeat; d backbeat and fill; e last bar
  n(1,2),
  n(1,0), n(1,0), n(1,1), n(1,1), n(1,2), n(1,2), n(1,3), n(1,3), n(1,4), n(1,4), n(1,5), n(1,5), n(1,6), n(1,6), n(1,7), n(1,7),
  n(1,7), n(1,7),
  n(1,7), n(1,7), n(1,3), n(1,5),
  n(1,7),
  // HAT: a soft offbeat 8ths; b 16ths with accented offbeats
  n(1,3), n(1,3), n(1,3), n(1,3),
  n(1,2), n(1,1), n(1,6), n(1,1), n(1,2), n(1,1), n(1,6), n(1,2), n(1,2), n(1,1), n(1,6), n(1,1), n(1,2), n(1,1), n(1,6), n(1,3),
  // OHAT: a offbeats
  n(1,4), n(1,4), n(1,4), n(1,4),
  // CRASH: a soft, at the knock; b downbeat
  n(1,6),
  n(1,7),
  // RISER: a, two bars
  n(1, l32),
};

// Chords: root (for kRoot channels) and four tones, MIDI notes.
const u8 kChords[][5] = {
  {38, 50, 57, 60, 65},  // a Dm7
  {34, 50, 57, 58, 65},  // b Bbmaj7/D
  {31, 50, 55, 58, 65},  // c Gm7/D
  {33, 49, 55, 57, 64},  // d A7/C#
  {39, 50, 55, 58, 63},  // e Ebmaj7/D
  {38, 57, 62, 66, 69},  // f D
  {33, 57, 61, 64, 69},  // g A
  {35, 57, 62, 66, 71},  // h Bm7
  {31, 59, 62, 67, 71},  // i G
  {42, 57, 61, 66, 69},  // j F#m
  {33, 55, 61, 64, 69},  // k A7
};

// One letter per bar, 32 bars a row: the chord, then each channel's pattern
// ('.' = none). kSong[32 * (1 + channel) + bar].
//              scene 1 (dark)  | scene 2 (bright)
const char kSong[] =
  /* chord */ "aabbccddaabbeedd" "fghifghifjigfgik"
  /* PAD   */ "a.a.a.a.a.a.a.a." ".........bb....."
  /* STAB  */ "................" "aaabaaabaaabaaab"
  /* SUB   */ "..a.a.a.a.a.a.a." "................"
  /* BASS  */ "................" "aaabaaabaccbaaab"
  /* LEAD  */ "................" "....abcdefghabdi"
  /* BELL  */ ".....abcdefghijk" "................"
  /* METAL */ "....a..........." "................"
  /* KICK  */ "....a...bbbbcccd" "eeeeeeeee..eeeef"
  /* SNARE */ "............aaab" "cccdcccdc..dccce"
  /* HAT   */ "............aaaa" "bbbbbbbbbaabbbba"
  /* OHAT  */ "................" "....aaaa....aaa."
  /* CRASH */ "....a..........." "b...b...b..bb..."
  /* RISER */ "..............a." ".........a......";
// clang-format on

// ---------------------------------------------------------------- voices
struct Voice {
  float ph, ph2, inc, inc2;                    // oscillator phases and increments, in turns
  float amp, over, atk, dec, sus, rel, silent; // amplifier envelope; over = amp - sus
  float penv, pamt, pdec;                      // pitch envelope
  float fenv, famt, fdec, cut, q;              // filter envelope and coefficients
  float low, band;                             // SVF state
  float noise, fm;
  float gl, gr, gs;                      // gains: left, right, delay send
  int gate;                              // samples until release
  u32 seed;                              // noise generator
  u8 wave, mode, attacking, active, bus; // bus 0: ducked by the kick; 1: drums
};

// Half-life (or attack time) code -> 1 / (time in samples).
float rate(int code) { return rt_exp2((float)(176 - code) * (1.0f / 16)) * (1.0f / kAudioRate); }
float halflife_coef(int code) { return rt_exp2(-rate(code)); }

void note_on(Voice* pool, const ChannelDef& d, int midi, float vel, int steps, u32 seed, float pan,
             SynthReport& rep) {
  // A free voice; failing that the quietest (a steal: the data is laid out never to need one).
  Voice* v = pool;
  for (int i = 0; i < kVoices; ++i) {
    if (!pool[i].active) {
      v = pool + i;
      goto found;
    }
    if (pool[i].amp < v->amp) v = pool + i;
  }
  ++rep.stolen;
found:
  *v = Voice{};
  float inc = rt_exp2((float)(midi - 69) * (1.0f / 12)) * (440.0f / kAudioRate);
  v->inc = inc;
  v->inc2 = inc * (d.wave ? 1.0f + d.osc2 * (1.0f / 2048) : d.osc2 * (1.0f / 16));
  v->atk = rate(d.attack);
  v->dec = halflife_coef(d.decay);
  v->sus = d.sustain * (1.0f / 256);
  v->rel = halflife_coef(d.release);
  v->penv = v->fenv = 1.0f;
  v->pamt = d.pitch * (1.0f / 8);
  v->pdec = halflife_coef(d.pdecay);
  v->famt = d.fenv * (1.0f / 8);
  v->fdec = halflife_coef(d.fdecay);
  v->cut = rt_min(rt_exp2(d.cutoff * (1.0f / 32) - 8.0f), kMaxCut);
  v->q = ((d.filter >> 2) + 1) * (1.0f / 32);
  v->noise = d.noise * (1.0f / 256);
  v->fm = d.fm * (1.0f / 32);
  float g = d.volume * (1.0f / 256) * vel;
  v->gl = g * (1.0f - pan);
  v->gr = g * (1.0f + pan);
  v->gs = g * d.send * (1.0f / 256);
  // Stop when the voice's louder side is below half an LSB of the output:
  // the step at the cut is then inaudible (and smaller than any real step).
  v->silent = kSilentLevel / (g * (1.0f + rt_abs(pan)) * kMaster);
  v->gate = steps * 11025 >> 1;
  v->seed = seed;
  if (!(d.kind & kPhase0)) {
    // A random start. The FM modulator keeps its phase relation to the
    // carrier (as if both had started together earlier): with ratio 1 an
    // offset between them would put DC into sin(ph + k sin(ph2)).
    v->ph = (float)(seed >> 8) * (1.0f / 16777216);
    float ph2 = v->ph * d.osc2 * (1.0f / 16);
    v->ph2 = d.wave ? (float)(seed & 0xffffff) * (1.0f / 16777216) : ph2 - rt_floor(ph2);
  }
  v->wave = d.wave;
  v->mode = d.filter & 3;
  v->bus = d.kind >> 2 & 1; // kDrum
  v->attacking = v->active = 1;
}

// Starts the notes of loop step `song` (0..511); true if a kick starts.
bool trigger(int song, Voice* pool, SynthReport& rep) {
  bool kick = false;
  int bar = song >> 4, pos = song & 15;
  const u8* chord = kChords[kSong[bar] - 'a'];
  for (int c = 0; c < kChannels; ++c) {
    char o = kSong[32 * (1 + c) + bar];
    if (o == '.') continue;
    const ChannelDef& d = kChannelDefs[c];
    int p = d.patterns + o - 'a', at = 16 * p + pos, i = 0;
    if (!(kGrids[p] >> pos & 1)) continue; // no note at this step
    for (int q = 0; q < at; ++q)           // the notes before it, in all patterns
      i += kGrids[q >> 4] >> (q & 15) & 1;
    int b = kNotes[i];
    kick |= c == KICK;
    int code = b >> 5, note = d.base + (b & 31) - 1, steps = kLength[code];
    float vel = 1.0f;
    if (d.kind & kDrum) {
      vel = (float)(code + 1) * 0.125f;
      steps = 1;
    }
    if (d.kind & kRoot) note += chord[0];
    float pan = d.pan * (1.0f / 128);
    int tones = d.kind & kChord ? 4 : 1;
    for (int j = 0; j < tones; ++j) {
      u32 seed = (u32)(song * kChannels + c) * 4 + j + 1; // the same noise every loop
      note_on(pool, d, tones > 1 ? note + chord[1 + j] : note, vel, steps, seed * 2654435761u,
              tones > 1 ? pan + (j & 1 ? 0.3f : -0.3f) : pan, rep);
    }
  }
  return kick;
}

// Adds n samples of voice v to its bus's stereo pair and the delay send.
// mix: 5 blocks of kBlockMax: left, right of bus 0; left, right of bus 1; send.
void render_voice(Voice& v, float* mix, int n) {
  // restrict: the mix buffers never alias the voice, so its fields stay in registers.
  float* __restrict L = mix + v.bus * 2 * kBlockMax;
  float* __restrict R = L + kBlockMax;
  float* __restrict S = mix + 4 * kBlockMax;
  for (int i = 0; i < n; ++i) {
    if (v.gate > 0) {
      --v.gate;
      if (v.attacking) {
        v.amp += v.atk;
        if (v.amp >= 1.0f) {
          v.amp = 1.0f;
          v.over = 1.0f - v.sus;
          v.attacking = 0;
        }
      } else {
        v.over *= v.dec; // decay: the excess over the sustain level halves every half-life
        v.amp = v.sus + v.over;
      }
    } else {
      v.amp *= v.rel;
      if (v.amp < v.silent) {
        v.active = 0;
        break;
      }
    }
    float bend = 1.0f + v.pamt * v.penv;
    v.penv *= v.pdec;
    v.ph += v.inc * bend; // increments stay below 1 turn, so one wrap suffices
    if (v.ph >= 1.0f) v.ph -= 1.0f;
    v.ph2 += v.inc2 * bend;
    if (v.ph2 >= 1.0f) v.ph2 -= 1.0f;
    float x = v.wave ? v.ph + v.ph2 - 1.0f // two saws
                     : rt_sin_turns(v.ph + v.fm * v.amp * rt_sin_turns(v.ph2));
    // Noise, on every voice: with a share of 0 it adds a zero (x is unchanged
    // but for the sign of a zero, which no output sample keeps).
    v.seed = v.seed * 1664525u + 1013904223u;
    x += ((float)(i32)v.seed * (1.0f / 2147483648.0f) - x) * v.noise;
    float y = x;
    if (v.mode != 3) {
      // Chamberlin state-variable filter (low += f band; band += f (x - low - q band)),
      // rearranged so each state depends on the old states by one multiply-add.
      // famt >= -1 and fenv in [0, 1] keep f in [0, kMaxCut]: stable for q < 2.
      float f = rt_min(v.cut * (1.0f + v.famt * v.fenv), kMaxCut);
      v.fenv *= v.fdec;
      float low = v.low + f * v.band;
      float band = v.band * (1.0f - f * (f + v.q)) + f * (x - v.low);
      y = v.mode == 0 ? low : v.mode == 1 ? band : x - low - v.q * v.band;
      v.low = low;
      v.band = band;
    }
    y *= v.amp;
    L[i] += y * v.gl;
    R[i] += y * v.gr;
    S[i] += y * v.gs;
  }
}

} // namespace

SynthReport synth_render(short* out, int frames, float* scratch) {
  // Flush denormals to zero while the synth runs (envelopes decay towards 0);
  // the same mode on Linux and Windows, so the samples stay identical.
  unsigned csr = __builtin_ia32_stmxcsr();
  __builtin_ia32_ldmxcsr(csr | 0x8040); // FTZ | DAZ

  float* mix = scratch; // see render_voice
  float* dL = scratch + 5 * kBlockMax;
  float* dR = dL + kDelayAlloc;
  for (int i = 0; i < 2 * kDelayAlloc; ++i)
    dL[i] = 0.0f;
  Voice pool[kVoices] = {};
  SynthReport rep{0.0f, 0, 0};
  int pos = 0;
  float lpL = 0.0f, lpR = 0.0f, duck = 0.0f, duckCoef = halflife_coef(kDuckRelease);

  for (int step = -kPrerollSteps;; ++step) {
    int start = sample_of_step(step), end = sample_of_step(step + 1);
    if (start >= frames) break;
    if (end > frames) end = frames;
    int n = end - start;
    if (trigger(step & (kStepsPerLoop - 1), pool, rep)) duck = 1.0f;
    for (int i = 0; i < 5 * kBlockMax; ++i)
      mix[i] = 0.0f;
    int sounding = 0;
    for (Voice& v : pool) {
      if (!v.active) continue;
      ++sounding;
      render_voice(v, mix, n);
    }
    if (sounding > rep.maxVoices) rep.maxVoices = sounding;
    for (int i = 0; i < n; ++i) {
      // Ping-pong: the send enters on the left, each echo crosses to the other side.
      float el = dL[pos], er = dR[pos];
      lpL += (er - lpL) * kDamp;
      lpR += (el - lpR) * kDamp;
      dL[pos] = mix[i + 4 * kBlockMax] + kFeedback * lpL;
      dR[pos] = kFeedback * lpR;
      if (++pos == kDelayLen) pos = 0;
      float g = (1.0f - kDuckDepth * duck) * kMaster;
      duck *= duckCoef;
      int t = start + i;
      if (t < 0) continue; // preroll
      float echo[2] = {el, er};
      for (int c = 0; c < 2; ++c) { // left, right
        float y = (mix[i + c * kBlockMax] + echo[c]) * g + mix[i + (2 + c) * kBlockMax] * kMaster;
        rep.peak = rt_max(rep.peak, rt_abs(y));
        out[2 * t + c] = (short)rt_round(y * 32767.0f); // |y| < 1: see synth.h
      }
    }
  }
  __builtin_ia32_ldmxcsr(csr);
  return rep;
}
