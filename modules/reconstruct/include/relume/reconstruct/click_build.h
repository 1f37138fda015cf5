#pragma once
// From clicks to a project (Loscos 2000 §3, TotalCalib-style): the one path that `relume
// triangulate` and the workbench's "Build model" both take. The cameras come from a COLMAP model
// when the workspace holds one, else they are solved from the clicked correspondences with known
// intrinsics; the metric frame comes from control points (clicked and measured) or from a typed
// distance and floor points; then every point is triangulated and every polygon fitted.
#include <string>
#include <vector>

#include "relume/geometry/progress.h"
#include "relume/geometry/scene.h"
#include "relume/reconstruct/clicks.h"
#include "relume/reconstruct/colmap_model.h"
#include "relume/reconstruct/multiview.h"

namespace relume::recon {

// WORKSPACE: a `relume reconstruct` workspace (sparse/ + workspace.json), a COLMAP model folder,
// or a folder without a model; the photos folder comes from `photosOption`, the workspace's
// workspace.json, or a photos/ folder beside it (empty when none of them gives one).
struct ClickWorkspace {
  std::string modelFolder, photosDir;
};
ClickWorkspace openClickWorkspace(const std::string& path, const std::string& photosOption = "");

// How to get cameras and a metric frame when the workspace holds no model.
struct ClickCameraOptions {
  std::string intrinsicsFile;  // JSON of `relume calibrate`; else `focal`; else the photos' EXIF
  double focal = 0;            // pixels, principal point at the centre
  // The metric frame when fewer than 3 control points exist: two points and their distance,
  // optionally three or more floor points (z = 0).
  std::string scaleA, scaleB;
  double scaleMetres = 0;
  std::vector<std::string> floor;
};

struct ClickBuild {
  Clicks clicks;  // as triangulated (clicks in photos that could not be posed left out)
  ColmapModel model;  // the cameras used, in the metric frame
  Scene scene;
  TriangulationReport report;
  std::vector<std::string> notes;     // what was decided (cameras solved, metric frame), for the user
  std::vector<std::string> warnings;  // weak depth, photos not posed, points not used
};

// Cameras, metric frame, triangulation and polygon fit. Points clicked in fewer than two photos
// and not typed (work in progress) are left out with a warning when no polygon uses them.
// Photos with distortion are undistorted into `undistortDir`. Throws relume::Error naming the
// clicks file and the point, polygon or option at fault.
ClickBuild buildFromClicks(const Clicks& clicks, const ClickWorkspace& workspace, const ClickCameraOptions& options,
                           const std::string& undistortDir, Progress& progress);

// The similarity that takes the model's camera centres onto those of the photos with the same
// names in `reference` (a COLMAP model folder or workspace, or a room bundle or project): a
// reconstruction put in the frame of known cameras. Throws relume::Error with fewer than 3 shared.
struct KnownCameraAlignment {
  CenterAlignment fit;              // S, per-camera errors (metres), median and largest
  std::vector<std::string> photos;  // the shared photos, in the order of fit.errors
};
KnownCameraAlignment alignToKnownCameras(const ColmapModel& model, const std::string& reference);

// Writes the built model as a Relume project (atomically, as saveProject), with the clicks it
// came from (clicks.json, as `clicks` holds them) and the triangulation report (triangulation.json:
// per point its position, reprojection errors and ray angle; per polygon its plane rms).
void saveClickProject(const ClickBuild& build, const Clicks& clicks, const std::string& folder, Progress& progress);

}  // namespace relume::recon
