// MERL .binary tables (brdf/merl_table.h): ReadMerlBinary. A full table is 33 MB, longer
// than fuzz inputs get, so this exercises the header and size checks.
#include <cstddef>
#include <cstdint>

#include "brdf/merl_table.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = zbrdf::fuzz::WriteScratchFile("material.binary", data, size);
  zbrdf::fuzz::ExpectOnlyInputErrors([&] { (void)zbrdf::ReadMerlBinary(path); });
  return 0;
}
