#pragma once
// Runs COLMAP's command line (feature_extractor, exhaustive/sequential matcher, mapper) as child
// processes: CPU SIFT, progress read from their output, Cancel kills them. The workspace holds
// COLMAP's database and models (colmap/) and the chosen model as text (sparse/).
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "relume/geometry/progress.h"
#include "relume/reconstruct/colmap_model.h"

namespace relume::recon {

struct ColmapOptions {
  std::string executable;           // empty: $RELUME_COLMAP, else `colmap` on PATH
  std::string matcher = "exhaustive";  // or "sequential" (photos taken in order)
  // Known intrinsics (e.g. from `relume calibrate` or EXIF): COLMAP model and its parameters,
  // held fixed in bundle adjustment. Empty: COLMAP's own guess (SIMPLE_RADIAL, refined).
  std::string cameraModel;
  std::vector<double> cameraParams;
  bool singleCamera = true;  // every photo from one camera
  // Rooms are low-texture: more, weaker SIFT features than COLMAP's default peak threshold
  // (0.0067); the mapper keeps models of 2+ photos (its default minimum of 10 discards a room's
  // whole model) and accepts initial pairs with 30+ inliers and new photos with 15+ (defaults 100,
  // 30, which left 6 of 8 benchmark photos unregistered). Measured alternatives, kept switchable:
  // DSP-SIFT with the default inlier counts (steadier on one benchmark room, worse on two others)
  // and guided matching (more matches, but wrong models more often).
  double siftPeakThreshold = 0.001;
  bool dspSift = false;
  int initMinInliers = 30;
  int absPoseMinInliers = 15;
  bool guidedMatching = false;
  // Epipolar distance (pixels) within which a match is an inlier of its pair (COLMAP's default).
  double matchMaxError = 4.0;
  // Matching + mapping attempts (own seeds): two that agree settle it, else a third decides.
  int attempts = 3;
  int threads = -1;
  // Cameras already known (a COLMAP model folder, e.g. from TotalCalib-style clicks or a rig):
  // features are matched and COLMAP's point_triangulator adds the points, the poses stay.
  std::string knownCameras;
};

struct ColmapRun {
  std::string modelFolder;              // WORKSPACE/sparse (text)
  ColmapModel model;
  std::vector<std::string> registered;  // image names
  std::vector<std::string> leftOut;     // photos COLMAP could not register
  double secondsFeatures = 0, secondsMatching = 0, secondsMapping = 0;  // summed over attempts
};

// The COLMAP executable, or throws relume::Error explaining how to install it.
std::string findColmap(const std::string& preferred = "");

// Photos of `photosDir` (8-bit JPEG/PNG/TIFF; EXR files are left to the HDR path) to a sparse
// model in `workspace` (mapper, or point_triangulator with options.knownCameras). Throws relume::Error when COLMAP is missing, when a step fails (quoting
// its last lines), or when fewer than 2 photos register (naming the photos left out); Cancelled
// when progress is cancelled (the child process is killed, the previous sparse/ stays).
ColmapRun runColmap(const std::string& photosDir, const std::string& workspace, const ColmapOptions& options,
                    Progress& progress);

// The workspace's description, workspace.json beside sparse/: the photos folder, the photos that
// registered and those left out, the number of points, whether the model is in the metric frame,
// COLMAP's times. Written atomically; `relume triangulate` and the workbench read it.
void writeWorkspaceInfo(const std::string& workspace, const std::string& photosDir, const ColmapRun& run, bool metric);
struct WorkspaceInfo {
  std::string photos;  // the photos folder the user reconstructed from (this machine's path)
  std::vector<std::string> registered, leftOut;
  long long points = 0;
  bool metric = false;
};
// workspace.json's bytes (`name` for the messages); throws relume::Error on invalid JSON or a
// field of the wrong type.
WorkspaceInfo parseWorkspaceInfo(const std::string& bytes, const std::string& name);
// The workspace's workspace.json, or nothing when it has none.
std::optional<WorkspaceInfo> readWorkspaceInfo(const std::string& workspace);

// Runs one COLMAP subcommand; progress lines are matched by `onLine`. Throws as runColmap does.
void runColmapStep(const std::string& colmap, const std::vector<std::string>& args, const std::string& what,
                   Progress& progress, const std::function<void(const std::string&)>& onLine);

}  // namespace relume::recon
