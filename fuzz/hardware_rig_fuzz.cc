// Hardware rig files (drivers/hardware_rig.h): ParseHardwareRig, the parser behind
// LoadHardwareRig, and the camera options derived from the parsed rig.
#include <cstddef>
#include <cstdint>
#include <string>

#include "drivers/hardware_rig.h"
#include "fuzz/fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  zbrdf::fuzz::ExpectOnlyInputErrors([&] {
    const zbrdf::HardwareRig rig = zbrdf::ParseHardwareRig(text, "fuzz-hardware.yaml");
    (void)zbrdf::CameraOptionsFromRig(rig);
  });
  return 0;
}
