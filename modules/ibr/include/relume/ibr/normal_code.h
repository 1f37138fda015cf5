#pragma once
// Normal coding for image-based objects (Dinh, Metoyer, Turk §3, after Glassner's "Normal
// Coding", Graphics Gems 1990): a 17 x 17 grid over the unit circle of the view plane; the centres
// of the 225 cells inside the circle, lifted onto the hemisphere facing the viewer
// (z = sqrt(1 - x^2 - y^2)), are the normals an 8-bit code stands for. Denser towards the viewer,
// sparser at the rim, where shading changes are hard to see.
#include <array>
#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <span>

namespace relume::ibr {

inline constexpr int kNormalCodes = 225;
inline constexpr int kNormalGrid = 17;
// The code of a pixel outside the object's silhouette (never a normal).
inline constexpr uint8_t kNoNormal = 255;

// ByteToNormal: the unit normal each code 0..224 stands for (view frame: x right, y up, z towards
// the viewer), codes in row-major order of the grid, bottom row first.
const std::array<glm::vec3, kNormalCodes>& byteToNormal();

// The code whose normal is nearest (largest dot product) to the unit normal with these x, y
// components (z >= 0 implied; |(x, y)| > 1 is taken as on the rim). Exact: a search of the grid
// cells the orthographic projection leaves possible (it never lengthens a distance).
uint8_t encodeNormal(glm::vec2 xy);

// A normal image coded pixel by pixel. `normals` holds x, y per pixel (row-major, width x height);
// pixels with mask[i] == 0 get kNoNormal. Without dithering each pixel gets encodeNormal. With
// dithering (Floyd-Steinberg, the paper's §3.1, which dithers x and y), each pixel takes the code
// nearest its normal plus the error carried to it, and its own error — in x, y and z, so that the
// mean shade is kept and not only the mean x and y — is spread over the neighbours still to be
// coded (7/16 right, 3/16 down-left, 5/16 down, 1/16 down-right; only onto pixels inside the
// mask), so that the mean normal over a small area is kept and the bands of equal codes break up.
void encodeNormalImage(std::span<const glm::vec2> normals, std::span<const uint8_t> mask, int width, int height,
                       bool dither, std::span<uint8_t> codes);

// Banding, as the longest run of one code along a row of a coded image (pixels of kNoNormal break
// runs and are not counted): every row, or only row `onlyRow`.
int longestCodeRun(std::span<const uint8_t> codes, int width, int height, int onlyRow = -1);

}  // namespace relume::ibr
