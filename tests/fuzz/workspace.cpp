// A reconstruction workspace's workspace.json: any bytes give its description or a
// relume::Error, never a crash, a leak or a hang.
#include <string>

#include "relume/geometry/error.h"
#include "relume/reconstruct/colmap_driver.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    (void)relume::recon::parseWorkspaceInfo(std::string(reinterpret_cast<const char*>(data), size), "workspace.json");
  } catch (const relume::Error&) {
  }
  return 0;
}
