// Rig files (rig/rig.h): ParseRig, the parser behind LoadRig, on arbitrary YAML text.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz/fuzz_util.h"
#include "rig/rig.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  zbrdf::fuzz::ExpectOnlyInputErrors([&] {
    const zbrdf::Rig rig = zbrdf::ParseRig(text, "fuzz.yaml");
    (void)zbrdf::WriteRigYaml(rig);
  });
  return 0;
}
