#pragma once
// A calibrated fisheye lens kept as JSON (what `relume calibrate --fisheye` writes, what a daylight
// room's sky names as its "fisheye_lens"): {"model": "OPENCV_FISHEYE", "width", "height", "fx",
// "fy", "cx", "cy", "k1".."k4", "rms_pixels", optional "circle": {"cx", "cy", "radius"}}.
#include <string>

#include "relume/geometry/scene.h"

namespace relume {

// Throws relume::Error naming `name` and the field when the bytes are not such a lens (model
// OPENCV_FISHEYE, whole positive image size, positive focal lengths, numbers throughout, a
// positive circle radius when a circle is given).
FisheyeLens parseFisheyeLens(const std::string& jsonBytes, const std::string& name);
FisheyeLens readFisheyeLens(const std::string& jsonPath);
std::string fisheyeLensJson(const FisheyeLens& lens);                  // the JSON's bytes
void writeFisheyeLens(const FisheyeLens& lens, const std::string& jsonPath);  // atomically

}  // namespace relume
