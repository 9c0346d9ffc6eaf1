// Tabulated BRDF files (brdf/tabulated_file.h): ReadTabulatedFileInfo and ReadTabulatedFile; a
// table read is then evaluated (its uncertainty too) and sampled at a few directions.
#include <cstddef>
#include <cstdint>
#include <memory>

#include "brdf/tabulated_file.h"
#include "fuzz/brdf_probe.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = zbrdf::fuzz::WriteScratchFile("fit-prior.exr", data, size);
  zbrdf::fuzz::ExpectOnlyInputErrors([&] { (void)zbrdf::ReadTabulatedFileInfo(path); });
  zbrdf::fuzz::ExpectOnlyInputErrors([&] {
    const std::unique_ptr<zbrdf::TabulatedBrdf> brdf = zbrdf::ReadTabulatedFile(path);
    zbrdf::fuzz::ProbeBrdf(*brdf);
    (void)brdf->EvalSigma(zbrdf::Vec3{0, 0, 1}, zbrdf::Normalize(zbrdf::Vec3{0.5, 0.2, 0.6}));
  });
  return 0;
}
