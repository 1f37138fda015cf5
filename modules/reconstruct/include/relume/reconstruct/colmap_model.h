#pragma once
#include <iosfwd>
// COLMAP sparse models (cameras, images, points3D) in COLMAP's text and binary formats, and the
// similarity transforms that put them into Relume's metric frame (metres, +Z up).
#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "relume/geometry/camera.h"

namespace relume::recon {

// One intrinsic model. Parameters in COLMAP's order:
//   SIMPLE_PINHOLE f cx cy · PINHOLE fx fy cx cy · SIMPLE_RADIAL f cx cy k
//   RADIAL f cx cy k1 k2 · OPENCV fx fy cx cy k1 k2 p1 p2
// Pixel coordinates put the centre of the top-left pixel at (0.5, 0.5), as COLMAP and Relume do.
struct ColmapCamera {
  int id = 0;
  std::string model = "PINHOLE";
  int width = 0, height = 0;
  std::vector<double> params;

  double fx() const;
  double fy() const;
  double cx() const;
  double cy() const;
  bool hasDistortion() const;
  // Normalised camera coordinates (x/z, y/z) -> distorted pixel.
  glm::dvec2 distort(glm::dvec2 normalised) const;
  // Pixel -> normalised camera coordinates with the distortion removed (iterative inverse).
  glm::dvec2 undistort(glm::dvec2 pixel) const;
  // The same camera with the distortion removed (fx fy cx cy of the model).
  glm::dmat3 K() const;
  // Parameters of a model name, or -1 when Relume does not support it; the supported names.
  static int parameterCount(const std::string& model);
  static std::string supportedModels();
};

struct ColmapObservation {
  glm::dvec2 xy{0.0};
  int64_t point3D = -1;  // -1: not triangulated
};

struct ColmapImage {
  int id = 0;
  glm::dvec4 q{1, 0, 0, 0};  // world-to-camera rotation as a unit quaternion (w, x, y, z)
  glm::dvec3 t{0.0};         // x_cam = R(q) X + t
  int camera = 0;
  std::string name;  // file name relative to the image folder
  std::vector<ColmapObservation> points;

  glm::dmat3 R() const;
  glm::dvec3 center() const;
  void setRotation(const glm::dmat3& R);
};

struct ColmapTrackElement {
  int image = 0;
  int point2D = 0;
};

struct ColmapPoint {
  int64_t id = 0;
  glm::dvec3 xyz{0.0};
  std::array<uint8_t, 3> rgb{0, 0, 0};
  double error = -1;  // mean reprojection error, pixels
  std::vector<ColmapTrackElement> track;
};

struct ColmapModel {
  std::map<int, ColmapCamera> cameras;
  std::map<int, ColmapImage> images;
  std::map<int64_t, ColmapPoint> points;

  // The image called `name`: its file name, or the file name without folder and extension.
  const ColmapImage* findImage(const std::string& name) const;
  // Relume's pinhole camera of an image (the model's distortion is left out; see ColmapCamera).
  Camera camera(const ColmapImage& image) const;
};

// Reads a model folder: text (cameras.txt, images.txt, points3D.txt) when present, else binary
// (.bin). points3D may be missing (a model of known cameras). Throws relume::Error naming the file
// and line or record at fault.
ColmapModel readColmapModel(const std::string& folder);
ColmapModel readColmapText(const std::string& folder);
ColmapModel readColmapBinary(const std::string& folder);
// The same from streams (bytes in, model or relume::Error out; the names are for the messages):
// what the readers above wrap, and what the fuzzing harnesses call. `points` may be null.
ColmapModel parseColmapText(std::istream& cameras, std::istream& images, std::istream* points, const std::string& camerasName,
                            const std::string& imagesName, const std::string& pointsName);
ColmapModel parseColmapBinary(std::istream& cameras, std::istream& images, std::istream* points,
                              const std::string& camerasName, const std::string& imagesName, const std::string& pointsName);
// Writes the three text files (each atomically), creating the folder.
void writeColmapText(const ColmapModel& model, const std::string& folder);
// Replaces the model folder as a whole: the new model is written beside it and swapped in, so
// that a failure at any point leaves the old folder (and whatever else it held) as it was.
void replaceColmapText(const ColmapModel& model, const std::string& folder);

// X' = s R X + t.
struct Similarity {
  double s = 1.0;
  glm::dmat3 R{1.0};
  glm::dvec3 t{0.0};
  glm::dvec3 apply(const glm::dvec3& X) const { return s * (R * X) + t; }
};
// Moves points and cameras by a similarity (projections are unchanged).
void transformModel(ColmapModel& model, const Similarity& S);
// The mean of the registered cameras' centres.
glm::dvec3 meanCameraCentre(const ColmapModel& model);
// The world's up in the model's frame, from the photos alone: people hold cameras without roll,
// so every camera's x axis is horizontal and up is the direction most nearly perpendicular to all
// of them (signed as the photos' up). The cameras' pitch, all downwards in a room, does not bias
// it, as it does their mean up direction. When the x axes barely differ (every photo looks the
// same way), the mean of the photos' up directions. Zero without images.
glm::dvec3 estimateUp(const ColmapModel& model);
// The mean reprojection error over every observation of every point (pixels; 0 with no points).
double meanReprojectionError(const ColmapModel& model);

}  // namespace relume::recon
