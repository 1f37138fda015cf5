#pragma once
// The comparison protocol (docs/comparison-protocol.md): 4x4 box
// downsampling, lamp pixels left out, one least-squares gain per channel, PSNR with the peak at
// the truth's 99.9th percentile, over the "all" and "shadow" masks.
#include <glm/vec3.hpp>
#include <cstdint>
#include <vector>

#include "relume/image/image.h"

namespace relume {

struct Scene;

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

// Which of a bundle's lamps and polygons hold the truth for those of a room modelled apart from
// its renders (a clicked model, `relume evaluate --geometry`). A lamp is the bundle's lamp of the
// same name, else the one whose polygon's centre is nearest (within 0.5 m). A polygon is one of
// the bundle's of the same kind in its plane (normals within 15 degrees, its centre within 5 cm of
// the plane) and within 0.5 m: the one of the same name, else of those that hold its centre the
// one nearest its size, else the nearest. -1: none.
struct BundleMatch {
  std::vector<int> lamp;     // per lamp of the model: a lamp of the bundle
  std::vector<int> polygon;  // per polygon of the model: a polygon of the bundle
};
BundleMatch matchToBundle(const Scene& model, const Scene& bundle);

}  // namespace relume
