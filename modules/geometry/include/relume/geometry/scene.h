#pragma once
// The scene model: polygons, groups, materials, lamps, cameras and photos, lighting variants.
#include <glm/vec3.hpp>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "relume/geometry/camera.h"
#include "relume/geometry/photometry.h"
#include "relume/geometry/polygon.h"

namespace relume {

struct Lamp {
  std::string name;
  int polygon = -1;         // index into Scene::polygons (a polygon of kind Light)
  glm::dvec3 radiance{0.0};  // emitted radiance, linear RGB; exitance = pi * radiance
  // Emits from both faces (an emissive panel seen from above and below, as Cycles mesh lamps
  // do), the same radiance per face; otherwise from the face its normal points to only.
  bool twoSided = false;
  // A photometric distribution (IES LM-63 or EULUMDAT file, relative to Scene::baseDir; empty:
  // none): the shape of the lamp's emission over all directions, its nadir along the polygon's
  // normal and its C0 plane through the polygon's first edge. Its exitance is then the lamp's
  // whole flux over its area, whatever the faces (`twoSided` no longer matters); the file's
  // lumens are reported, never used for the scale.
  std::string photometryFile;
  std::shared_ptr<const PhotometricDistribution> photometry;
};

struct Photo {
  std::string name;
  std::string file;  // relative to Scene::baseDir (LDR, sRGB)
  std::string hdr;   // relative, linear radiance (EXR); may be empty
  Camera camera;
};

struct VirtualBox {
  std::string name;
  glm::dvec3 boxMin{0.0}, boxMax{0.0};
  glm::dvec3 albedo{0.5};
  std::vector<std::vector<glm::dvec3>> mesh;  // an OBJ mesh's polygons instead of the box, if any
  // An image-based object instead (relume::ibr): its fan file (relative to the file that names
  // it), where the bottom centre of its mesh's bounding box stands, its scale and its turn about
  // +Z (degrees). Empty: a box or mesh object.
  std::string fan;
  glm::dvec3 position{0.0};
  double scale = 1.0;
  double rotationDegrees = 0.0;
};

struct Variant {
  std::string name;
  std::map<std::string, glm::dvec3> lampScale;  // per lamp name, RGB multiplier (1 if absent)
  std::vector<Lamp> virtualLamps;                // with polygon vertices in virtualLampPolygons
  std::vector<std::vector<glm::dvec3>> virtualLampPolygons;
  std::vector<VirtualBox> virtualObjects;
  std::string sky;        // the sky it is lit by (a SkyCapture's name; empty: the photos' own)
  std::string file, hdr;  // truth images, relative
};

// A calibrated fisheye: OpenCV's fisheye model (Kannala-Brandt; COLMAP's OPENCV_FISHEYE) as
// `relume calibrate --fisheye` measures it. A point at angle theta from the axis lies at theta_d =
// theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8) focal lengths from the principal
// point (cx, cy); pixel centres at +0.5. The image circle (where the lens's light ends on the
// sensor) beside it when it was measured (circleRadius 0: not). fx == 0: no lens.
struct FisheyeLens {
  int width = 0, height = 0;  // the images it was calibrated on
  double fx = 0, fy = 0, cx = 0, cy = 0;
  double k[4] = {0, 0, 0, 0};
  double rms = 0;  // the calibration's reprojection error, pixels
  double circleX = 0, circleY = 0, circleRadius = 0;
};

// A measured sky (daylight rooms): an HDR fisheye taken outside, and optionally a panorama.
struct SkyCapture {
  std::string name;
  std::string fisheye;       // relative path of the HDR fisheye
  std::string fisheyeModel;  // its lens and orientation in words, e.g. "equidistant, 180 deg,
                             // looking up (+Z), image up = +Y" (relume::daylight parses it)
  FisheyeLens lens;          // a calibrated lens (fx > 0): the projection, the words the orientation
  glm::dvec3 fisheyePosition{0.0};
  std::string panorama;      // relative path of an equirectangular HDR, or empty
  glm::dvec3 panoramaPosition{0.0};
};

struct Scene {
  std::string baseDir;     // folder the relative paths start from
  std::string sourceFile;  // the file the scene was read from (for error messages)
  std::vector<Polygon> polygons;
  std::vector<Lamp> lamps;
  std::vector<Photo> photos;
  std::string mainPhoto;
  std::vector<Variant> variants;
  std::vector<SkyCapture> skies;  // daylight rooms: the measured skies
  std::string photoSky;           // the sky the photos were taken under (a SkyCapture's name)
  // What reading found and did that the user should hear about (an interrupted save's
  // leftovers, a project put back from its backup); front ends show them.
  std::vector<std::string> notes;

  int findPolygon(const std::string& name) const;
  int findLamp(const std::string& name) const;
  const Photo* findPhoto(const std::string& name) const;
  const SkyCapture* findSky(const std::string& name) const;
  // Index of the lamp whose polygon is `polygon`, or -1.
  int lampOfPolygon(int polygon) const;
};

}  // namespace relume
