// A clicks.json (clicked corners, polygons, measurements): any bytes give clicks or a
// relume::Error, never a crash, a leak or a hang. Read as a finished file and as a draft.
#include <string>

#include "relume/geometry/error.h"
#include "relume/reconstruct/clicks.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  for (bool draft : {false, true}) {
    try {
      (void)relume::recon::parseClicks(bytes, "clicks.json", draft);
    } catch (const relume::Error&) {
    }
  }
  return 0;
}
