// audio.h - intro.exe's music: the synth's pre-rendered loop played through
// winmm waveOut, and the playback position as the intro's clock.
//
// One looping buffer (WHDR_BEGINLOOP | WHDR_ENDLOOP, dwLoops = 0xFFFFFFFF)
// holds the whole 64-s loop, so playback never needs the program again and
// the picture can follow the sound on any machine.
#pragma once

// Opens the default output device (44.1 kHz stereo 16-bit) and starts
// playing `samples`, kAudioFrames stereo frames, over and over: one whole
// loop of synth_render's music, which may begin anywhere in the loop (intro.exe
// passes a window into two copies of the loop that starts at its /t: time). The samples must stay
// alive until audio_stop. False when there is no device (waveOutOpen fails) or it refuses the
// buffer: then nothing plays and the caller keeps its own clock.
bool audio_start(const short* samples);

// Seconds of music played since audio_start, from waveOutGetPosition. Never
// decreases: each pass through the loop adds 64 s (a wrap is recognised when
// the position within the loop falls by more than half a loop, whether the
// driver counts on or restarts at each pass; smaller jitter backwards is held).
// Must be called at least once per 32 s. The driver's 32-bit sample counter
// overflows after 27 h of play, which moves the clock once by < 64 s.
// Only meaningful after audio_start returned true.
double audio_seconds();

// Stops playback at once (waveOutReset); the device stays open for the
// process's exit to close, which must follow (intro.exe's quit). Does nothing
// when audio_start was never called or returned false.
void audio_stop();
