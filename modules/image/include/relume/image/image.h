#pragma once
// Float RGB images and the one place where files are read and written (OpenImageIO).
#include <glm/vec3.hpp>
#include <string>
#include <utility>
#include <vector>

namespace relume {

struct ImageRGB {
  int width = 0, height = 0;
  std::vector<float> pixels;  // linear RGB, row-major, top row first

  ImageRGB() = default;
  ImageRGB(int w, int h) : width(w), height(h), pixels(size_t(w) * h * 3, 0.f) {}
  glm::vec3 at(int x, int y) const {
    const float* p = &pixels[(size_t(y) * width + x) * 3];
    return {p[0], p[1], p[2]};
  }
  void set(int x, int y, const glm::vec3& c) {
    float* p = &pixels[(size_t(y) * width + x) * 3];
    p[0] = c.x;
    p[1] = c.y;
    p[2] = c.z;
  }
};

float srgbToLinear(float v);
float linearToSrgb(float v);

// Reads an image as linear RGB: float formats (EXR, HDR) as they are, 8/16-bit ones through
// the inverse sRGB curve. Throws relume::Error naming the file when it cannot be read.
ImageRGB readImageLinear(const std::string& path);
// Reads only the header; throws relume::Error when the file is missing or unreadable.
void imageSize(const std::string& path, int& width, int& height);
// Writes by extension: .exr as linear half floats, .png/.jpg as sRGB 8-bit (scaled by
// `exposure` first). Atomic: a temporary file renamed into place, so no half-written file.
void writeImage(const std::string& path, const ImageRGB& img, float exposure = 1.f);

// Is this a radiance file (.exr / .hdr, any case) rather than an 8-bit photo?
bool isRadianceFile(const std::string& path);

// An 8-bit image exactly as stored (no curve applied), RGB interleaved: what exposure merging,
// calibration and matching read.
struct Image8 {
  int width = 0, height = 0;
  std::vector<unsigned char> pixels;
};
// Throws relume::Error naming the file when it is missing, unreadable, truncated or not 8-bit.
Image8 readImage8(const std::string& path);
// Bilinear resampling to width x height (pixel centres at +0.5 in both: the image keeps its
// extent, so a point at x in the input lies at x * width / input width in the output).
Image8 resizeImage8(const Image8& image, int width, int height);
// Metadata to store with an image, by OpenImageIO's names ("ExposureTime", "Exif:...").
struct ImageMetadata {
  std::vector<std::pair<std::string, float>> floats;
  std::vector<std::pair<std::string, int>> ints;
  std::vector<std::pair<std::string, std::string>> strings;
};
// Writes an 8-bit image as it is; atomic like writeImage.
void writeImage8(const std::string& path, const Image8& image, const ImageMetadata& metadata = {});

}  // namespace relume
