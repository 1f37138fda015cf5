#pragma once
// Photo textures (Loscos et al. 2000 §2.2): each polygon's part of a photo de-warped onto the
// polygon's plane, at about the photo's own resolution there, with a per-texel record of where
// each value came from. Layers share one grid: the original texture, the unoccluded one made by
// preprocessing, and the reflectance map derived from it.
#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "relume/geometry/polygon.h"
#include "relume/geometry/progress.h"

namespace relume {

class RayScene;
struct Scene;
struct Camera;
struct ImageRGB;

enum class TexelSource : uint8_t {
  Outside = 0,    // outside the polygon (padding, extrapolated so that filtering stays clean)
  MainPhoto = 1,  // seen by the chosen photo
  OtherPhoto = 2, // hidden from the chosen photo, seen by another one
  Smooth = 3,     // seen by no photo: filled smoothly from the texels around
  // Seen at a pixel next to another polygon's image (or the glow kept for a lamp): the camera's
  // pixel filter mixed the neighbour into its value, so it shows the photo but does not measure
  // this polygon alone. A 4 cm strip of a table top seen from 3 m is all outline.
  MainPhotoOutline = 4,
  OtherPhotoOutline = 5,
};

// Was the texel seen by a photo (main or other), rather than filled or outside?
inline bool fromPhoto(TexelSource s) { return s != TexelSource::Outside && s != TexelSource::Smooth; }
inline bool fromMainPhoto(TexelSource s) { return s == TexelSource::MainPhoto || s == TexelSource::MainPhotoOutline; }
inline bool fromOtherPhoto(TexelSource s) { return s == TexelSource::OtherPhoto || s == TexelSource::OtherPhotoOutline; }
// Seen by a photo away from the polygon's outline there: the texel measures this polygon alone.
inline bool photographedInside(TexelSource s) { return s == TexelSource::MainPhoto || s == TexelSource::OtherPhoto; }

struct PolygonTexture {
  int polygon = -1;
  PlaneFrame frame;          // the polygon's plane frame (as the radiosity engine uses it)
  glm::dvec2 origin{0.0};    // uv of texel (0,0)'s corner
  double texel = 0.01;       // metres per texel
  int width = 0, height = 0;
  std::vector<TexelSource> source;
  std::vector<glm::vec3> original;    // linear radiance as photographed
  std::vector<glm::vec3> unoccluded;  // T_final: real shadows removed (empty until preprocessed)
  std::vector<glm::vec3> albedo;      // reflectance map (empty until preprocessed)

  size_t index(int x, int y) const { return size_t(y) * width + x; }
  // Does any photo show part of the polygon?
  bool photographed() const;
  glm::dvec2 uvOf(double x, double y) const { return origin + texel * glm::dvec2(x, y); }
  // Where the texel containing plane coordinates uv (clamped to the grid) came from.
  TexelSource sourceAt(glm::dvec2 uv) const;
  // Bilinear lookup of a layer at plane coordinates uv (clamped to the grid).
  glm::vec3 sample(const std::vector<glm::vec3>& layer, glm::dvec2 uv) const;
  // Mean of a layer over the texels whose centres lie in the rectangle and in the polygon (or the
  // value at its centre when none does); `seen` receives the fraction seen by the main photo.
  glm::vec3 mean(const std::vector<glm::vec3>& layer, glm::dvec2 lo, glm::dvec2 hi, double* seen = nullptr) const;
  // Mean of a layer over the texels some photo shows (main or other) away from the polygon's
  // outline in it, or over all it shows when every one is on the outline; `count` gets their
  // number (0: none, and the mean is 0).
  glm::dvec3 photographedMean(const std::vector<glm::vec3>& layer, size_t* count = nullptr) const;
};

struct DewarpStats {
  size_t texels = 0, fromMain = 0, fromOther = 0, smooth = 0;
  // Per other photo that filled texels, in the order used: its radiance scale to the main photo's
  // exposure (1 with fewer than 64 texels both show) and how many texels both show.
  std::vector<float> exposureScale;
  std::vector<size_t> exposureOverlap;
};

// De-warps photo `photoIndex` of the scene onto every polygon. Texels hidden from that camera by
// other polygons, behind the polygon or outside the frame are taken from another photo that sees
// them, scaled to the main photo's exposure (the median ratio over the texels both show), else
// filled smoothly. Photos are read as linear radiance (the EXR when there is one).
std::vector<PolygonTexture> dewarpPhotos(const Scene& scene, const RayScene& rays, int photoIndex,
                                         DewarpStats* stats = nullptr, Progress& progress = silentProgress());

// Pixels of `cam` around a lamp's image (not on it) where the lamp's glow (antialiasing, lens
// bloom) mixes into the surface behind: the index into scene.lamps of the nearest lamp, or -1.
// The radius is 2.5 % of the image width (at least 2 pixels).
std::vector<int> lampGlowRing(const Scene& scene, const RayScene& rays, const Camera& cam);

// Fills texels of a layer from the others (pull-push over a pyramid): those no photo saw and the
// padding outside the polygon, or (outsideOnly) the padding alone.
void fillSmoothly(PolygonTexture& t, std::vector<glm::vec3>& layer, bool outsideOnly);

// CIE L*a*b* (D65) of a linear sRGB colour whose white is (1,1,1).
glm::dvec3 linearRgbToLab(const glm::dvec3& rgb);

}  // namespace relume
