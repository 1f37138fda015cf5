#pragma once
// TotalCalib-style modelling from clicks (Loscos 2000 §3): corners clicked in two or more photos
// are triangulated with the photos' cameras, and each polygon is fitted through its corners.
//
// CLICKS.json:
//   { "main": "main",                                  (optional: the photo textures come from)
//     "points": { "P": {"main": [x, y], "view1": [x, y]},   (named points, shared by polygons)
//                 "Q": {"xyz": [x, y, z]},                   (a typed measurement, metres)
//                 "R": {"main": [x, y], "view1": [x, y], "xyz": [..]} },  (a control point: clicked
//                                                             and measured; 3+ fix the metric frame)
//     "polygons": [ { "name": "floor", "group": "floor",
//                     "lamp": false | "A",                    (a lamp: its name)
//                     "radiance_rgb": [r, g, b],              (optional, lamps)
//                     "rectangle": true,                      (optional constraint)
//                     "plane": "KEY",                         (optional: share one plane with others)
//                     "albedo": [r, g, b],                    (optional, default 0.5)
//                     "corners": [ "P", {"main": [x, y], "view2": [x, y]}, {"xyz": [..]} ] } ] }
// Pixel coordinates put the centre of the top-left pixel at (0.5, 0.5) (COLMAP's convention).
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "relume/geometry/scene.h"
#include "relume/reconstruct/colmap_model.h"
#include "relume/reconstruct/multiview.h"
#include "relume/reconstruct/polygon_fit.h"

namespace relume::recon {

struct ClickPoint {
  std::string name;
  std::vector<std::pair<std::string, glm::dvec2>> clicks;  // photo name, pixel (distorted, as clicked)
  std::optional<glm::dvec3> typed;                           // a measured position instead
};

struct ClickPolygon {
  std::string name, group;
  std::string lamp;  // empty: not a lamp
  std::optional<glm::dvec3> radiance;
  std::optional<glm::dvec3> albedo;
  bool rectangle = false;
  std::string plane;
  std::vector<std::string> corners;  // point names (inline corners get generated names)
};

struct Clicks {
  std::string file;
  std::string main;
  std::map<std::string, ClickPoint> points;
  std::vector<ClickPolygon> polygons;
};

// Reads a clicks file. `draft`: work in progress is accepted (points clicked in one photo only, no
// polygons yet), as the workbench saves it; the triangulation then leaves such points out.
Clicks readClicks(const std::string& path, bool draft = false);
// The same from the file's bytes (`file` names it in errors).
Clicks parseClicks(const std::string& bytes, const std::string& file, bool draft = false);
// The clicks as JSON (every point named, corners by name), and written atomically.
std::string clicksJson(const Clicks& clicks);
void writeClicks(const Clicks& clicks, const std::string& path);

// One clicked point triangulated with the model's cameras (distortion removed from the clicks).
TriangulatedPoint triangulateClickedPoint(const Clicks& clicks, const std::string& name, const ColmapModel& model);

// The planes of the polygons built so far, for match proposals on them: per polygon with three
// or more corners at known `positions` (other than `leaveOut`, the point being matched, whose old
// place must not vote), the least-squares plane through them; collinear corners give none.
std::vector<Plane> polygonPlanes(const Clicks& clicks, const std::map<std::string, glm::dvec3>& positions,
                                 const std::string& leaveOut = "");

// Points clicked in two or more photos and also measured ("xyz"): their names.
std::vector<std::string> controlPoints(const Clicks& clicks);
struct ControlFit {
  Similarity S;                              // model frame -> measured frame
  std::map<std::string, double> residuals;   // metres, per control point, after the fit
};
// The similarity that takes the control points, triangulated with the model's cameras, to their
// measured positions. Throws relume::Error with fewer than 3 (or collinear) control points.
ControlFit fitControlPoints(const Clicks& clicks, const ColmapModel& model);

struct TriangulationReport {
  std::map<std::string, TriangulatedPoint> points;  // per clicked point
  std::map<std::string, double> planeRms;           // per polygon, metres
  double seconds = 0;
};

// Triangulates every clicked point with the model's cameras (distortion removed from the clicks),
// fits the polygons and returns the scene: polygons, lamps (radiance from the file, else 1 until
// `relume preprocess` estimates it), and one photo per model image found in `photosDir` (its
// .exr beside it, if any, as the HDR). Photos whose camera has distortion are undistorted into
// `undistortDir`. Throws relume::Error naming the clicks file and the point or polygon at fault.
Scene sceneFromClicks(const Clicks& clicks, const ColmapModel& model, const std::string& photosDir,
                      const std::string& undistortDir, TriangulationReport& report);

}  // namespace relume::recon
