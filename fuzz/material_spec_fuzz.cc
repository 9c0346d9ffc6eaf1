// Material specs (brdf/material_spec.h): MakeBrdf on a --material string; the BRDF made is
// then evaluated and sampled at a few directions. Specs of the "file:" model are skipped: they
// name files, whose readers have targets of their own (and the fuzzer must not read /dev/zero).
#include <algorithm>
#include <cctype>
#include <cstddef>
#include <cstdint>
#include <string>

#include "brdf/material_spec.h"
#include "fuzz/brdf_probe.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string spec(reinterpret_cast<const char*>(data), size);
  std::string lower = spec;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (lower.find("file") != std::string::npos) return 0;
  zbrdf::fuzz::ExpectOnlyInputErrors([&] { zbrdf::fuzz::ProbeBrdf(*zbrdf::MakeBrdf(spec)); });
  return 0;
}
