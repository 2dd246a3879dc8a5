// encode.h - the encoder's host-side extras: encoding with given model
// parameters (for measuring and searching them).
#pragma once

#include "codec.h"
#include "model.h"

namespace rt64k::pack {

// The parameters encode() uses.
model::Params default_params();

// encode() with `prm` instead of the defaults (same contract). With
// `byte_bits` (size zeroed doubles), adds each byte's cost in bits.
unsigned encode_with(const model::Params& prm, const unsigned char* in, unsigned size,
                     unsigned char* out, unsigned capacity, void* work,
                     double* byte_bits = nullptr);

// `prm` with the data region (the constants before the code, one long
// operand to the x86 parse) that two pricing passes find cheapest; none for
// inputs under 4,096 bytes. `work`: kWorkBytes zeroed bytes, zeroed again
// on return.
model::Params choose_data_region(model::Params prm, const unsigned char* in, unsigned size,
                                 void* work);

} // namespace rt64k::pack
