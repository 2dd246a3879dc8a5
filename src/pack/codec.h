// codec.h - the intro's own packer: the contract between its encoder (the
// Linux build tool that packs intro.exe) and its decoder (the start-up stub
// inside the packed exe).
//
// The codec is a context-mixing compressor: one model predicts each bit of
// the image from what came before, and a binary arithmetic coder spends
// -log2(p) bits on it. The encoder and the decoder run the same model code,
// so they stay in step by construction; the model uses integers only (no
// floating point), so the native tool and the MinGW-built stub compute the
// same predictions bit for bit.
//
// The decoder is freestanding (no C runtime, no heap, no OS calls): the
// caller gives it the model's memory, kWorkBytes zeroed bytes (in the
// packed exe: an uninitialised section, which costs no file bytes).
#pragma once

namespace rt64k::pack {

// Bytes of model memory decode() and encode() need, zeroed by the caller
// (the model's tables; the packed exe reserves them in its uninitialised
// section, so the figure is fixed at compile time).
// 128 MiB: 14 context models of 2^22 16-bit counters (117 MB; 2^21 would
// cost 26 bytes more on intro.exe), the mixer's weights and the SSE table.
constexpr unsigned kWorkBytes = 1u << 27;

// Decodes `size` bytes of `in` (what encode() wrote) into `out`.
// `work`: kWorkBytes zeroed bytes. It writes out[0 .. size) only. It reads
// exactly the encoded length of `in` when `in` is what encode() wrote; on
// damaged input it reads at most model::max_encoded(size) bytes (reads
// past that see zeros), so a caller that cannot trust its payload gives
// that many readable bytes. It never fails: damaged input decodes to other
// bytes. `out` must not overlap `in` (the model reads the header's masks
// from `in` throughout).
void decode(const unsigned char* in, unsigned char* out, unsigned size, void* work);

// Encodes `size` bytes of `in` into `out`, which has room for `capacity`
// bytes; returns the encoded length (at most model::max_encoded(size)), or
// 0 if `out` is too small.
// `work`: kWorkBytes zeroed bytes. Host only (the packer tool and tests).
unsigned encode(const unsigned char* in, unsigned size, unsigned char* out, unsigned capacity,
                void* work);

} // namespace rt64k::pack
