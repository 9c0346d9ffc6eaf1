// Network material files (brdf/nbrdf.h): ReadNbrdfNetwork; a network read is then evaluated
// and sampled at a few directions.
#include <cstddef>
#include <cstdint>

#include "brdf/nbrdf.h"
#include "fuzz/brdf_probe.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = zbrdf::fuzz::WriteScratchFile("material.json", data, size);
  zbrdf::fuzz::ExpectOnlyInputErrors([&] {
    const zbrdf::NbrdfBrdf brdf(zbrdf::ReadNbrdfNetwork(path), "file:" + path);
    zbrdf::fuzz::ProbeBrdf(brdf);
  });
  return 0;
}
