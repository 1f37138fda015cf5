#pragma once
// Image fans (Dinh, Metoyer, Turk §1-3): an object rendered by Relume itself (Embree ray casting)
// from rings of views around it; per pixel its coverage (alpha), normal code, depth and albedo.
//
// Views are orthographic: a view sees the object's bounding sphere (centre c, radius R) from
// direction d, its image the square [-R, R]^2 of the plane through c across d. The paper renders
// perspective views from a fixed distance and notes that the object looks wrong when seen much
// closer or farther; an orthographic view has no distance, every pixel's 3-D point follows from
// its depth exactly, and the silhouette from a lamp's direction is a parallel projection.
#include <cstdint>
#include <glm/vec3.hpp>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "relume/geometry/progress.h"
#include "relume/ibr/mesh.h"

namespace relume::ibr {

struct FanOptions {
  int viewsPerRing = 96;
  int size = 256;                                      // pixels across a view
  std::vector<double> ringElevations{15.0, 45.0, 75.0};  // degrees above the object's horizon
  bool dither = true;                                  // Floyd-Steinberg on the normals (§3.1)
  int samplesPerAxis = 2;                              // rays per pixel: its square (alpha = coverage)
  bool yUp = false;                                    // the mesh's up is +Y (turned so that it is +Z)
};

// One view: size x size pixels, row 0 at the top.
struct FanView {
  std::vector<uint8_t> alpha;    // coverage, 0..255
  std::vector<uint8_t> code;     // normal code (kNoNormal where alpha is 0), view frame
  std::vector<uint16_t> depth;   // distance from the view's front plane (c + R d), 0..2R in 0..65534; 65535: none
  std::vector<uint8_t> colour;   // albedo, RGB, sRGB-encoded
  // Per cell of a kTableCells x kTableCells grid over the image, the mean depth (m) of its
  // covered pixels (the centre's depth, R, where none is): where the lamps' tables are aimed.
  std::vector<float> cellDepth;
  // Per block of kNearBlock x kNearBlock pixels (row-major, ceil(size / kNearBlock) across), the
  // depth (m) of its nearest covered pixel, infinity where none is: a ray marched through the
  // view skips a block it crosses wholly in front of that depth (see ibr_object.cpp).
  std::vector<float> nearBlock;
};

inline constexpr int kTableCells = 4;
inline constexpr int kNearBlock = 8;

inline constexpr uint16_t kNoDepth = 65535;
inline constexpr uint32_t kFanVersion = 1;

class ImageFan {
 public:
  // --- what the fan file's header holds ---
  int size = 0, viewsPerRing = 0;
  std::vector<double> ringElevations;  // degrees
  bool dithered = false;
  glm::dvec3 centre{0.0};  // bounding sphere, object frame (metres, +Z up)
  double radius = 0;
  glm::dvec3 boundsMin{0.0}, boundsMax{0.0};  // the mesh's bounding box
  uint64_t meshTriangles = 0;
  std::string meshName;
  std::string source;  // the fan file it was read from (for messages; the mesh's name when built)

  int viewCount() const { return viewsPerRing * int(ringElevations.size()); }
  // View k = ring * viewsPerRing + j, at azimuth 2 pi j / viewsPerRing.
  glm::dvec3 toCamera(int view) const;  // unit, from the centre towards the view's camera
  glm::dvec3 right(int view) const;     // image x
  glm::dvec3 up(int view) const;        // image -y
  int nearestView(const glm::dvec3& toCameraDirection) const;
  // The views that can be nearest or next-nearest to a direction, in increasing order: on each
  // ring the four whose azimuths lie around the direction's (a ring's view is the nearer the
  // nearer its azimuth, when its elevation lies within +-90 degrees), else every view. Searching
  // these finds what searching all views finds, with a handful of evaluations instead of hundreds.
  std::vector<int> viewsAround(const glm::dvec3& toCameraDirection) const;
  // The three at once (a view's frame: x right, y up, z towards its camera).
  struct Axes {
    glm::dvec3 right, up, toCamera;
  };
  Axes axes(int view) const;
  // The object-frame point at pixel coordinates (x, y) (pixel centres at + 0.5) and depth (m).
  glm::dvec3 pointAt(int view, double x, double y, double depth) const;
  // The same with the view's axes computed once (a loop over a view's pixels: each axis costs
  // sines and cosines).
  glm::dvec3 pointAt(const Axes& axes, double x, double y, double depth) const;
  // (A product, not a quotient: the march reads it at every step of every ray.)
  double depthMetres(uint16_t code) const { return double(code) * (2.0 / 65534.0) * radius; }

  // A view's pixels, decoded on first use (thread-safe). Throws relume::Error naming `source`
  // for a view that does not exist or whose pixels are damaged.
  const FanView& view(int k) const;

  // --- storage ---
  std::vector<std::vector<uint8_t>> compressed;  // per view, deflated

 private:
  mutable std::mutex mutex_;
  mutable std::vector<std::unique_ptr<FanView>> decoded_;
};

// Renders the fan: views per ring x rings images, progress per view; Cancel throws Cancelled.
std::unique_ptr<ImageFan> buildFan(const Mesh& mesh, const FanOptions& options, Progress& progress = silentProgress());

// Fan files: "RELUMEFN", version, header, the views deflated, a CRC-32 of all before it.
// Written atomically (a temporary file renamed into place).
void writeFan(const ImageFan& fan, const std::string& path);
std::vector<uint8_t> fanBytes(const ImageFan& fan);
// Throws relume::Error naming the file: not a fan file, another version, truncated, damaged.
std::unique_ptr<ImageFan> readFan(const std::string& path);
std::unique_ptr<ImageFan> parseFan(const std::vector<uint8_t>& bytes, const std::string& name);

}  // namespace relume::ibr
