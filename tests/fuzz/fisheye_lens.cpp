// A calibrated fisheye lens's JSON (`relume calibrate --fisheye`, a daylight room's fisheye_lens):
// any bytes give a lens, and a lens a model whose mapping is evaluated, or a relume::Error — never
// a crash, a leak or a hang.
#include <string>

#include "relume/daylight/sky.h"
#include "relume/geometry/error.h"
#include "relume/project/fisheye_lens.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const relume::FisheyeLens lens = relume::parseFisheyeLens(std::string(reinterpret_cast<const char*>(data), size), "lens.json");
    const auto m = relume::daylight::fisheyeCalibrated(lens, 180, "lens.json");
    for (const auto& [x, y] : {std::pair{lens.cx, lens.cy}, {0.5, 0.5}, {lens.width - 0.5, lens.height / 2.0}})
      if (const auto d = relume::daylight::pixelDirection(m, x, y)) (void)relume::daylight::directionPixel(m, *d);
    (void)relume::daylight::pixelSolidAngle(m, lens.width / 2, lens.height / 2);
  } catch (const relume::Error&) {
  }
  return 0;
}
