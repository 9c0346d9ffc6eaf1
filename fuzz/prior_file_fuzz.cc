// BRDF prior files (brdf/brdf_prior.h): ReadPriorFile; a prior read is then hashed, and its
// first material's atoms, as a TabulatedBrdf, evaluated and sampled at a few directions.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "brdf/brdf_prior.h"
#include "brdf/tabulated_brdf.h"
#include "fuzz/brdf_probe.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = zbrdf::fuzz::WriteScratchFile("prior.exr", data, size);
  zbrdf::fuzz::ExpectOnlyInputErrors([&] {
    const zbrdf::BrdfPrior prior = zbrdf::ReadPriorFile(path);
    (void)prior.Hash();
    (void)prior.MaterialIndex(prior.materials.front());
    std::vector<zbrdf::Rgb> table(prior.grid.size());
    for (int n = 0; n < prior.grid.size(); ++n) {
      table[n] = {prior.atoms(n, 0), prior.atoms(n, 1), prior.atoms(n, 2)};
    }
    const zbrdf::TabulatedBrdf brdf(prior.grid, std::move(table), {}, prior.materials.front());
    zbrdf::fuzz::ProbeBrdf(brdf);
  });
  return 0;
}
