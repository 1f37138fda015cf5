// The intrinsics JSON of `relume calibrate`: any bytes give intrinsics or a relume::Error, never a
// crash, a leak or a hang.
#include <string>

#include "relume/geometry/error.h"
#include "relume/reconstruct/photos.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    (void)relume::recon::parseIntrinsics(std::string(reinterpret_cast<const char*>(data), size), "intrinsics.json");
  } catch (const relume::Error&) {
  }
  return 0;
}
