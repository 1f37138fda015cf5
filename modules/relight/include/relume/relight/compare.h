#pragma once
// The comparison protocol (docs/comparison-protocol.md): 4x4 box
// downsampling, lamp pixels left out, one least-squares gain per channel, PSNR with the peak at
// the truth's 99.9th percentile, over the "all" and "shadow" masks.
#include <glm/vec3.hpp>
#include <cstdint>
#include <vector>

#include "relume/image/image.h"

namespace relume {

struct CompareMasks {
  int width = 0, height = 0;          // downsampled size
  std::vector<uint8_t> all, shadow;   // per downsampled pixel
};

struct Comparison {
  double psnr = 0;
  glm::dvec3 gain{1.0};  // rendering -> truth
  size_t pixels = 0;
};

ImageRGB boxDownsample(const ImageRGB& img, int factor);
// Masks from the main photo (lamp pixels) and the truth without occluder shadows.
CompareMasks benchmarkMasks(const ImageRGB& photo, const ImageRGB& unoccludedTruth);
// Gain-corrected PSNR of `rendering` against `truth` (full-size linear images) over one mask.
Comparison compareImages(const ImageRGB& rendering, const ImageRGB& truth, const std::vector<uint8_t>& mask);

}  // namespace relume
