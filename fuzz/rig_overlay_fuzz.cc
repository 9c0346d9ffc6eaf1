// Rig overlays ("faults" files, rig/rig.h): ApplyRigOverlayText on the thesis rig.
#include <cstddef>
#include <cstdint>
#include <string>

#include "basis/data_path.h"
#include "fuzz/fuzz_util.h"
#include "rig/rig.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const zbrdf::Rig base = zbrdf::LoadRig(zbrdf::DataPath("rig/rigs/thesis.yaml"));
  const std::string text(reinterpret_cast<const char*>(data), size);
  zbrdf::fuzz::ExpectOnlyInputErrors(
      [&] { (void)zbrdf::ApplyRigOverlayText(base, text, "fuzz-faults.yaml"); });
  return 0;
}
