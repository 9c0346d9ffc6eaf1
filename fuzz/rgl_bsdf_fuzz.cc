// RGL .bsdf materials (brdf/rgl_bsdf.h): RglBrdf::FromFile; a material read is then evaluated
// and sampled at a few directions.
#include <cstddef>
#include <cstdint>

#include "brdf/rgl_bsdf.h"
#include "fuzz/brdf_probe.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = zbrdf::fuzz::WriteScratchFile("material.bsdf", data, size);
  zbrdf::fuzz::ExpectOnlyInputErrors(
      [&] { zbrdf::fuzz::ProbeBrdf(*zbrdf::RglBrdf::FromFile(path)); });
  return 0;
}
