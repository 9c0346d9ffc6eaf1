// Floats to OpenEXR's 16-bit half, for the HDR images' pixels (docs/session-folder.md, hdr/).
#pragma once

#include <cstddef>

#include <half.h>

namespace zbrdf {

// out[k] = half(in[k]) for k < n: the same bits as Imath's conversion (round to nearest, ties to
// even; overflow to infinity), four times faster with the CPU's F16C instructions where it has
// them (Imath's header uses them only when the whole build targets F16C; this build targets
// baseline x86-64). NaN stays NaN (its payload may differ).
void FloatsToHalf(const float* in, size_t n, half* out);

}  // namespace zbrdf
