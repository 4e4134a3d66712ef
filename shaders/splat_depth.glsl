// Step-1 splat depth as stored (R32UI): the bits of the positive camera z, which order like
// the floats, so the nearest splat wins through atomicMin (compute rasterisation) or a plain
// store behind the depth test (graphics pipeline); kNoSplat marks pixels no splat covers.
const uint kNoSplat = 0xFFFFFFFFu;

uint EncodeSplatDepth(float z) { return floatBitsToUint(z); }

// Camera z of a stored splat depth, 0 where no splat covers the pixel.
float DecodeSplatDepth(uint bits) { return bits == kNoSplat ? 0.0 : uintBitsToFloat(bits); }
