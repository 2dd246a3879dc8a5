// encode.h - the encoder's host-side extras: encoding with given model
// parameters (for measuring and searching them).
#pragma once

#include "codec.h"
#include "model.h"

namespace rt64k::pack {

// The parameters encode() uses.
model::Params default_params();

// encode() with `prm` instead of the defaults (same contract).
unsigned encode_with(const model::Params& prm, const unsigned char* in, unsigned size,
                     unsigned char* out, unsigned capacity, void* work);

} // namespace rt64k::pack
