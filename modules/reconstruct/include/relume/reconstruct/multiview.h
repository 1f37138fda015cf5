#pragma once
// Multi-view geometry of the TotalCalib-style workflow (Loscos 2000 §3): triangulating clicked
// points, relative poses from correspondences, and the similarity fits of the metric frame.
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "relume/geometry/camera.h"
#include "relume/reconstruct/colmap_model.h"

namespace relume::recon {

// One pixel observation of a point: undistorted pixel coordinates in `camera`'s photo.
struct Observation {
  const Camera* camera = nullptr;
  std::string photo;  // for messages
  glm::dvec2 pixel{0.0};
};

struct TriangulatedPoint {
  glm::dvec3 X{0.0};
  std::vector<double> reprojectionError;  // pixels, per observation
  double rmsError = 0;
  double rayAngleDeg = 0;  // widest angle between two of its viewing rays: below ~10 deg depth is weak
  double maxError() const;
};

// Linear (DLT) triangulation from two or more views, then Levenberg-Marquardt on the
// reprojection error. Throws relume::Error (element `what`) with fewer than 2 observations, rays
// that (nearly) coincide, or a point that ends up behind one of the cameras (naming the photo).
TriangulatedPoint triangulatePoint(const std::vector<Observation>& obs, const std::string& what);

// Least-squares similarity taking `from` to `to` (Umeyama 1991); needs 3 non-collinear points.
Similarity fitSimilarity(const std::vector<glm::dvec3>& from, const std::vector<glm::dvec3>& to);

// The metric frame of a model known up to a similarity: the distance between `a` and `b` becomes
// `metres`; the plane through `floor` (3 or more points) becomes z = 0 with +Z on the side of
// `above` (the cameras' mean centre), the origin at the first floor point's foot.
Similarity metricFrame(const glm::dvec3& a, const glm::dvec3& b, double metres, const std::vector<glm::dvec3>& floor,
                       const glm::dvec3& above);

// Camera-centre residuals after the best similarity from `estimated` to `truth` (same order).
struct CenterAlignment {
  Similarity S;
  std::vector<double> errors;  // metres, per camera
  double median = 0, max = 0;
};
CenterAlignment alignCenters(const std::vector<glm::dvec3>& estimated, const std::vector<glm::dvec3>& truth);

// ---- Bundle adjustment (Ceres Solver: automatic derivatives, a robust loss, sparse Schur) ----

struct BundleObservation {
  int camera = -1, point = -1;
  glm::dvec2 pixel{0.0};  // undistorted
};

struct BundleOptions {
  // Huber loss scale in pixels: residuals beyond it count linearly, so a mis-click pulls the
  // solution far less than under squares. 0: plain least squares.
  double robustPixels = 2.0;
  int maxIterations = 100;
};

struct BundleReport {
  double initialRms = 0, rms = 0;  // pixels, over every observation, before and after
  int iterations = 0;
  bool converged = false;
  size_t beyondRobust = 0;  // observations whose final error exceeds 3 x robustPixels (likely mis-clicks)
};

// Refines the poses of `cameras` (R and t; K is kept) and `points` to minimise the reprojection
// error of `observations`. Cameras in `fixedCameras` do not move (the gauge: at least one). When
// `scaleCamera` >= 0, the largest component of its translation is held too (the scale of a model
// known up to a similarity). Observations of points behind a camera are reported, not solved
// (relume::Error naming the point when every observation is).
BundleReport bundleAdjust(std::vector<Camera>& cameras, std::vector<glm::dvec3>& points,
                          const std::vector<BundleObservation>& observations, const std::vector<int>& fixedCameras,
                          int scaleCamera = -1, const BundleOptions& options = {});

// ---- Cameras from point correspondences alone (when automatic matching fails) ----

// A correspondence track: the same scene point clicked in several photos (pixel per photo index,
// photos without a click are left out).
struct Track {
  std::string name;
  std::vector<std::pair<int, glm::dvec2>> clicks;  // (photo index, undistorted pixel)
};

struct RelativePose {
  glm::dmat3 R{1.0};  // second camera relative to the first: x2 = R x1 + t, |t| = 1
  glm::dvec3 t{0.0};
  std::vector<bool> inliers;
  double fundamentalRms = 0;  // Sampson distance of the inliers, pixels, after refinement
};

// Fundamental and essential matrices by RANSAC, then non-linear refinement of (R, t) on the
// Sampson error of the inliers; the pose with the points in front of both cameras.
RelativePose relativePose(const std::vector<glm::dvec2>& p1, const std::vector<glm::dvec2>& p2, const glm::dmat3& K1,
                          const glm::dmat3& K2);

struct CameraSolution {
  std::vector<Camera> cameras;          // posed, in an arbitrary similarity frame (first = origin)
  std::vector<bool> posed;              // photos that could be posed
  std::vector<TriangulatedPoint> points;  // per track (X = 0 for tracks left out)
  std::vector<bool> triangulated;
  double rmsError = 0;  // pixels, over all observations used
  BundleReport bundle;  // the final bundle adjustment (beyondRobust: clicks that look wrong)
};
// Poses every photo from tracks and intrinsics: relative pose of the pair sharing most tracks,
// resection (PnP) of the others, multi-view triangulation, and a final bundle adjustment
// (Levenberg-Marquardt over poses and points). `cameras` give K and size; R, t are ignored.
CameraSolution solveCameras(const std::vector<Camera>& intrinsics, const std::vector<std::string>& photoNames,
                            const std::vector<Track>& tracks);

}  // namespace relume::recon
