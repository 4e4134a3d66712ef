// A camera response on the GPU: g(Z) as a 256 x 1 RGB32F texture (RGB order).
#pragma once

#include "gl/objects.h"
#include "hdr/response_curve.h"

namespace hdribr::render {

// Texel z holds g(z) of the R, G and B channels (the curve is BGR); linear filtering. Throws
// UsageError when the curve is not valid.
gl::Texture MakeResponseLut(const ResponseCurve& response);

}  // namespace hdribr::render
