// audio.h - `rt64k audio`: the intro's music loop as a WAVE file.
#pragma once
#include <string>
#include <vector>

// `rt64k audio --out FILE.wav`: renders the 64-s loop (the same samples
// intro.exe plays) and writes it as RIFF WAVE, 44.1 kHz stereo 16-bit PCM.
// Prints one summary line on stdout. Returns 0; 2 on bad arguments or an
// output that cannot be written (one line on stderr).
int cmd_audio(int argc, char** argv);

// Writes interleaved stereo 16-bit samples as a RIFF WAVE file, whole or not
// at all (output.h); false with a one-line `error` if it cannot be written.
bool write_wav(const std::string& path, const std::vector<short>& stereo, int rate,
               std::string& error);
