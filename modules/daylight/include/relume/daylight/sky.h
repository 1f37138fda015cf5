#pragma once
// The measured sky (Grosch, Eble, Mueller 2007, §5 and §6.1): an HDR fisheye image taken outside,
// looking up, with its lens model; the upper hemisphere cut into N regions of about equal solid
// angle; each region's mean radiance from the image, and the sun found and kept apart, since its
// light is concentrated in a few pixels rather than spread over a region.
//
// Directions are unit vectors in the room's frame (metres, +Z up), pointing from the room to the
// sky. A fisheye's image frame: x to the right, y down, pixel centres at (x + 0.5, y + 0.5).
#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <optional>
#include <string>
#include <vector>

#include "relume/image/image.h"

#include "relume/geometry/scene.h"

namespace relume::daylight {

// Rec. 709 luminance of a linear RGB value.
inline double luminance(const glm::dvec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

enum class FisheyeProjection {
  Equidistant,  // r = f * theta (the common "f-theta" fisheye)
  Equisolid,    // r = 2 f * sin(theta / 2)
  // A full panorama, 360 x 180 degrees: column x at azimuth (1/2 - (x + 1/2) / width) x 360
  // degrees from `axes` column 0 towards column 1 (the centre column looks along column 0, the
  // left edge behind it, +90 degrees a quarter of the way in), row y at elevation
  // (1/2 - (y + 1/2) / height) x 180 degrees towards column 2 (the zenith at the top row). What a
  // viewer turning round sees; day101's panoramas with the identity axes (centre along +X, +Z up).
  Equirectangular,
  // A calibrated fisheye: OpenCV's fisheye model (Kannala-Brandt, COLMAP's OPENCV_FISHEYE), as
  // `relume calibrate --fisheye` measures it from checkerboard photos. A point at angle theta from
  // the optical axis lies at theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8)
  // from the principal point `centre`, in units of the focal lengths `focal` (pixels, per axis).
  // The view ends at fovDeg / 2 from the axis and, when `radius` > 0, at the image circle of that
  // radius around `circleCentre` (where the lens's light ends on the sensor).
  OpenCvFisheye,
};

struct FisheyeModel {
  FisheyeProjection projection = FisheyeProjection::Equidistant;
  double fovDeg = 180;     // full field of view across the image circle
  glm::dvec2 centre{0.0};  // the image circle's centre (pixels)
  double radius = 0;       // the image circle's radius (pixels): theta = fov / 2 there
  // Columns: the room-frame directions of the image's +x (right), of its up (-y) and of the
  // optical axis. Looking up with image up = +Y: (-X, +Y, +Z) (seen from below, +X is on the
  // left). (Equirectangular: see above.)
  glm::dmat3 axes{1.0};
  int width = 0, height = 0;  // the image's size (equirectangular; the fisheye needs only the circle)
  // OpenCvFisheye only: focal lengths (pixels), distortion k1..k4, and the image circle's centre
  // (its radius is `radius`; 0: no circle, the field of view alone bounds the view).
  glm::dvec2 focal{0.0};
  double k[4] = {0, 0, 0, 0};
  glm::dvec2 circleCentre{0.0};
};

// A calibrated fisheye (FisheyeProjection::OpenCvFisheye) looking up with image up = +Y (as
// fisheyeLookingUp), limited to `fovDeg` and to the lens's image circle when it has one. Throws
// relume::Error naming `file` when the focal lengths are not positive or the distortion does not
// map angles to radii monotonically up to fovDeg / 2 (no lens does: it would fold the image over
// itself).
FisheyeModel fisheyeCalibrated(const FisheyeLens& lens, double fovDeg, const std::string& file);
// The angle from the axis (radians) of a calibrated fisheye at distorted radius theta_d (focal
// units), and the distorted radius of an angle: the model's own mapping (Newton's method back).
double fisheyeTheta(const FisheyeModel& m, double thetaD);
double fisheyeThetaD(const FisheyeModel& m, double theta);

// The image circle of a fisheye photo: the edge between the lit disc and the dark border around
// it, found along 720 rays from the image's centre (sub-pixel, where the luminance crosses a level
// between the border's and the disc's) and fitted by a circle (least squares, points more than
// three robust deviations off dropped, in up to three rounds). `rms` is the fitted points'
// distance from it (pixels).
// Throws relume::Error naming `file` when there is no dark border (the circle fills or overflows
// the image), when the edge is found over too little of the circle, or when it is no circle.
struct ImageCircle {
  glm::dvec2 centre{0.0};
  double radius = 0, rms = 0;
  int points = 0;  // edge points the fit kept
};
ImageCircle findImageCircle(const ImageRGB& image, const std::string& file);

// An equirectangular panorama of width x height pixels: the centre column along `axes` column 0
// (default +X), +Z up (see FisheyeProjection::Equirectangular).
FisheyeModel equirectangular(int width, int height, const glm::dmat3& axes = glm::dmat3(1.0));

// The day101 convention: equidistant (or `projection`), `fovDeg`, looking up (+Z), image up = +Y,
// the circle filling the image (centre at its centre, radius half its smaller side).
FisheyeModel fisheyeLookingUp(int width, int height, FisheyeProjection projection = FisheyeProjection::Equidistant,
                              double fovDeg = 180);

// A fisheye described in words, as daylight bundles do ("equidistant, 180 deg, looking up (+Z),
// image up = +Y"): the projection (equidistant or equisolid), the field of view in degrees, looking
// up, and which room axis is the image's up (+X, -X, +Y or -Y); the circle fills the
// width x height image. With a calibrated `lens` (fx > 0) the lens is the projection (the words
// need name none; the field of view is 180 degrees unless they give one) and must have been
// calibrated on width x height images. Throws relume::Error naming `file` and what is missing or
// not understood.
FisheyeModel fisheyeFromDescription(const std::string& text, int width, int height, const std::string& file,
                                    const FisheyeLens& lens = {});

// The direction seen at image point (px, py), or nothing outside the image circle.
std::optional<glm::dvec3> pixelDirection(const FisheyeModel& m, double px, double py);
// The image point where `direction` is seen, or nothing outside the field of view.
std::optional<glm::dvec2> directionPixel(const FisheyeModel& m, const glm::dvec3& direction);
// The solid angle (sr) pixel (x, y) covers (0 outside the circle), integrated over the pixel.
double pixelSolidAngle(const FisheyeModel& m, int x, int y);

struct SkyImage {
  ImageRGB image;  // linear radiance (W / (m^2 sr) per channel, or any consistent unit)
  FisheyeModel model;
  std::string file;  // for messages
};
// Reads an HDR fisheye and checks it: finite, non-negative radiance; the circle inside the image;
// a view that sees the upper hemisphere (not only what lies below the horizon). Throws
// relume::Error naming the file and what is wrong.
SkyImage readSkyImage(const std::string& path, const FisheyeModel& model);
// A daylight room's measured sky by name (empty: the one its photos were taken under), its
// fisheye read with the lens the room describes in words, and checked. Throws relume::Error
// naming the room's file or the image and what is wrong.
SkyImage readRoomSky(const Scene& room, const std::string& name);
// An HDR fisheye file in the common convention (fisheyeLookingUp: equidistant, 180 degrees,
// looking up, image up = +Y, the circle filling the image), read and checked; through a calibrated
// `lens` (fx > 0) instead of the ideal equidistant projection when one is given (it must have been
// calibrated on images of the file's size).
SkyImage readFisheyeLookingUp(const std::string& path, const FisheyeLens& lens = {});
void checkSkyImage(const SkyImage& sky);

// The upper hemisphere cut into bands of equal elevation width, each band into cells whose
// count follows its solid angle, so that cells are about square and of about equal solid angle.
class SkyRegions {
 public:
  explicit SkyRegions(int n = 64);
  int size() const { return int(cells_.size()); }
  // The region holding `direction` (z >= 0), or -1 below the horizon.
  int regionOf(const glm::dvec3& direction) const;
  double solidAngle(int k) const;
  glm::dvec3 centre(int k) const;  // the direction at the cell's centre (elevation, azimuth)
  // Elevation and azimuth bounds (radians; azimuth from +X towards +Y).
  struct Cell {
    double elev0, elev1, azim0, azim1;
  };
  const Cell& cell(int k) const { return cells_[size_t(k)]; }

 private:
  std::vector<Cell> cells_;
  std::vector<int> bandStart_;  // first cell of each band, and size() at the end
  double bandWidth_ = 0;
};

struct Sun {
  bool found = false;
  glm::dvec3 direction{0.0, 0.0, 1.0};
  // Irradiance on a plane facing the sun (W/m^2 per channel): its radiance in excess of the sky
  // around it, integrated over the pixels of its circle.
  glm::dvec3 irradiance{0.0};
  double solidAngle = 0;  // sr of the pixels taken as the sun
  int pixels = 0;
  // Its pixels look clipped (at exactly half float's largest value, 65504, or two or more at
  // exactly one peak): its irradiance is then understated, and its colour shifted towards the channels that
  // clipped least. Front ends warn; an HDR sky must be saved as full float, bracketed far enough.
  // (A synthetic sun of one uniform radiance whose disc covers two whole pixels looks clipped too;
  // a real sun's limb darkening gives every pixel its own value.)
  bool clipped = false;
  // Clipped, and its colour taken from its pixels that clipped in no channel: each clipped pixel
  // was given that colour, at what its unclipped channels measure (or the least its clipped ones
  // allow). The irradiance is then right in colour, and still a lower bound where a pixel clipped
  // in every channel.
  bool colourFromUnclipped = false;
};

struct SkyRadiance {
  // Each region's mean radiance; within the sun's circle the sky behind it (sunBackground).
  std::vector<glm::dvec3> region;
  Sun sun;
  glm::dvec3 sunBackground{0.0};  // the sky's radiance around the sun (the ring beyond its circle)
};

struct SkyOptions {
  // There is a sun when the brightest pixel exceeds this many times the median luminance of the
  // sky's pixels (a clear sky's sun is 10^4 - 10^5 times brighter than the sky around it).
  double sunThreshold = 200;
  // The sun's pixels: all within this angle of the brightest one (the lens and the pixel filter
  // spread its disc), their excess over the sky around the circle taken as its irradiance.
  double sunRadiusDeg = 3;
};

// Each region's mean radiance (pixels weighted by their solid angle; a region no pixel centre
// falls into takes the radiance seen at its centre) and the sun.
SkyRadiance averageSky(const SkyImage& sky, const SkyRegions& regions, const SkyOptions& options = {});

// Irradiance (W/m^2 per channel) on a plane of normal `normal` from the regions' radiance over
// the upper hemisphere (plus the sun when it is above the plane): sum of L_k times the
// projected solid angle of region k on the plane's side, integrated numerically.
glm::dvec3 planeIrradiance(const SkyRegions& regions, const SkyRadiance& sky, const glm::dvec3& normal);

}  // namespace relume::daylight
