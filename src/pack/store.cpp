// store.cpp - a stand-in codec that stores the bytes unchanged: the packer's
// pipeline (stub, tool, tests) was developed against it before the
// context-mixing codec existed. Not part of any build once the real codec
// (decode.cpp, encode.cpp) is merged.
#include "codec.h"

namespace rt64k::pack {

void decode(const unsigned char* in, unsigned char* out, unsigned size, void*) {
  for (unsigned i = 0; i < size; ++i)
    out[i] = in[i];
}

unsigned encode(const unsigned char* in, unsigned size, unsigned char* out, unsigned capacity,
                void*) {
  if (size > capacity) return 0;
  for (unsigned i = 0; i < size; ++i)
    out[i] = in[i];
  return size;
}

} // namespace rt64k::pack
