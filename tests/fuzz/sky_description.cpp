// A daylight bundle's fisheye description in words ("equidistant, 180 deg, looking up (+Z), image
// up = +Y") and its image size: any bytes give a lens model or a relume::Error, never a crash, a
// leak or a hang.
#include <string>

#include "relume/daylight/sky.h"
#include "relume/geometry/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 2) return 0;
  const int w = 1 + data[0], h = 1 + data[1];
  try {
    const auto m = relume::daylight::fisheyeFromDescription(std::string(reinterpret_cast<const char*>(data + 2), size - 2), w, h,
                                                            "scene.json");
    (void)relume::daylight::pixelDirection(m, w / 2.0, 0.5);
  } catch (const relume::Error&) {
  }
  return 0;
}
