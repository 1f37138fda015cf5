#pragma once
// Photo import: EXIF, bracketed exposures merged into radiance images (Debevec & Malik 1997, as in
// Loscos 2000 Appendix B), and intrinsics from a checkerboard photo set.
#include <string>
#include <vector>

#include "relume/geometry/progress.h"
#include "relume/geometry/scene.h"
#include "relume/image/image.h"

namespace relume::recon {

struct PhotoInfo {
  std::string path;
  int width = 0, height = 0, channels = 0;
  bool floatData = false;       // EXR/HDR: already radiance
  double focalMm = 0;           // Exif FocalLength
  double focal35mm = 0;         // Exif FocalLengthIn35mmFilm
  double exposureTime = 0;      // seconds
  double fNumber = 0;
  double iso = 0;
  double exposureBias = 0;      // EV
  bool hasExposureBias = false;
  std::string make, model;
  // Focal length in pixels from the 35 mm equivalent (36 mm film width along the longer side), 0
  // when the photo does not say.
  double focalPixels() const;
};

// Reads the header and metadata; throws relume::Error naming the file when it is missing,
// unreadable or not an image.
PhotoInfo readPhotoInfo(const std::string& path);

// The image files of a folder (JPEG, PNG, TIFF, EXR), sorted by name.
std::vector<std::string> listPhotos(const std::string& folder);

// Exposure time of a bracket member given only its EV step: t_ref * 2^EV (Appendix B's table).
double exposureFromEv(double ev, double referenceTime = 1.0);

// Groups files into brackets of one viewpoint: consecutive files (by name) of the same size and
// camera whose exposures differ; a repeated exposure or another size starts a new group. Files
// without exposure data form groups of one.
std::vector<std::vector<PhotoInfo>> groupBrackets(const std::vector<PhotoInfo>& photos);

struct HdrResult {
  ImageRGB radiance;                  // relative radiance, linear RGB
  std::vector<float> response[3];     // recovered response: 256 exposure values per channel (R, G, B)
  std::vector<double> times;          // the exposure times used, seconds
};

// Merges 8-bit exposures of one viewpoint. `times` may be empty: then EXIF exposure times are used,
// else EXIF exposure biases through exposureFromEv. Throws relume::Error naming the file at fault
// (unreadable, other size, not 8-bit) or when no exposure times can be found.
HdrResult mergeBracket(const std::vector<std::string>& files, std::vector<double> times, Progress& progress);
// The same on decoded exposures (times required, one per image; `names` for messages).
HdrResult mergeBracket(const std::vector<Image8>& images, const std::vector<double>& times,
                       const std::vector<std::string>& names, Progress& progress);

struct Intrinsics {
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0;  // COLMAP's OPENCV model
  double rms = 0;                          // reprojection error of the calibration, pixels
  std::vector<std::string> used, rejected;  // photos where the pattern was / was not found
};

// Intrinsics and distortion from photos of a checkerboard with `cols` x `rows` inner corners and
// squares of `square` metres (OpenCV calibrateCamera). Throws relume::Error when fewer than 3
// photos show the whole pattern (naming the photos where it was not found).
Intrinsics calibrateCheckerboard(const std::vector<std::string>& files, int cols, int rows, double square,
                                 Progress& progress);
void writeIntrinsics(const Intrinsics& in, const std::string& jsonPath);
Intrinsics readIntrinsics(const std::string& jsonPath);
// The same from the JSON's bytes (`name` for the messages).
Intrinsics parseIntrinsics(const std::string& bytes, const std::string& name);

// A fisheye lens (relume::FisheyeLens, OpenCV's fisheye model) from photos of a checkerboard
// taken through it (cv::fisheye::calibrate): the board's corners found as for
// calibrateCheckerboard, so the board must be whole in each photo used. Throws relume::Error as
// calibrateCheckerboard does, and when OpenCV's fit fails (the views do not determine the lens:
// more views, the board nearer the image's edges). Kept with relume::writeFisheyeLens.
struct FisheyeCalibration {
  FisheyeLens lens;
  std::vector<std::string> used, rejected;  // photos where the pattern was / was not found
};
FisheyeCalibration calibrateFisheyeCheckerboard(const std::vector<std::string>& files, int cols, int rows, double square,
                                                Progress& progress);

// The exposure, focal and camera fields of `exif` that are set, as metadata to write with a photo.
ImageMetadata exifMetadata(const PhotoInfo& exif);

// A folder of bracketed photos to a folder of one photo per viewpoint: each bracket (see
// groupBrackets) is merged into NAME.exr beside a copy of its middle exposure NAME.ext (what
// COLMAP and the textures' 8-bit fallback use); single photos are copied. Returns the groups.
// What merging one bracket gave: the photo kept for the viewpoint, its radiance image (empty for
// a single photo), and the recovered response and exposure times.
struct MergedBracket {
  std::string photo, hdr;
  std::vector<float> response[3];
  std::vector<double> times;
};
std::vector<std::vector<PhotoInfo>> mergeBracketFolder(const std::string& folder, const std::string& outFolder,
                                                       Progress& progress, std::vector<MergedBracket>* merged = nullptr);
// The same for photos already read and grouped (groupBrackets), wherever they are.
void mergeBracketGroups(const std::vector<std::vector<PhotoInfo>>& groups, const std::string& outFolder, Progress& progress,
                        std::vector<MergedBracket>* merged = nullptr);

}  // namespace relume::recon
