#include "relume/reconstruct/click_build.h"

#include <QDir>
#include <QFile>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QSaveFile>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>

#include "relume/geometry/error.h"
#include "relume/image/image.h"
#include "relume/project/room_io.h"
#include "relume/project/save_hooks.h"
#include "relume/reconstruct/colmap_driver.h"
#include "relume/reconstruct/multiview.h"
#include "relume/reconstruct/photos.h"

namespace fs = std::filesystem;

namespace relume::recon {

namespace {
std::string fmt(const char* f, double a, double b = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, f, a, b);
  return buf;
}

void writeJson(const QString& path, const QJsonObject& o) {
  QSaveFile f(path);
  if (!f.open(QIODevice::WriteOnly) || f.write(QJsonDocument(o).toJson(QJsonDocument::Indented)) < 0 || !f.commit())
    throw Error(path.toStdString(), "", "cannot write: " + f.errorString().toStdString());
}

// Cameras solved from the clicked correspondences (TotalCalib) and known intrinsics.
ColmapModel solveFromClicks(Clicks& clicks, const ClickWorkspace& w, const ClickCameraOptions& o, ClickBuild& out) {
  std::vector<std::string> photoNames;
  std::map<std::string, int> index;
  for (const auto& [n, pt] : clicks.points)
    if (!pt.typed)
      for (const auto& [photo, px] : pt.clicks)
        if (!index.count(photo)) index[photo] = int(photoNames.size()), photoNames.push_back(photo);
  if (photoNames.empty()) throw Error(clicks.file, "points", "no point is clicked in photos");
  std::map<std::string, std::string> photoFile;  // stem -> the 8-bit photo
  for (const auto& f : listPhotos(w.photosDir))
    if (!isRadianceFile(f)) photoFile[fs::path(f).stem().string()] = f;
  for (const auto& name : photoNames)
    if (!photoFile.count(name)) throw Error(w.photosDir, "", "has no photo named " + name + " (clicked in the clicks file)");
  ColmapCamera cam;
  cam.id = 1;
  if (!o.intrinsicsFile.empty()) {
    const Intrinsics in = readIntrinsics(o.intrinsicsFile);
    cam.model = "OPENCV";
    cam.width = in.width;
    cam.height = in.height;
    cam.params = {in.fx, in.fy, in.cx, in.cy, in.k1, in.k2, in.p1, in.p2};
  } else if (o.focal != 0) {
    if (!(o.focal > 0)) throw Error("", "focal length", "must be a positive number of pixels");
    int wdt = 0, hgt = 0;
    imageSize(photoFile.at(photoNames.front()), wdt, hgt);
    cam.model = "PINHOLE";
    cam.width = wdt;
    cam.height = hgt;
    cam.params = {o.focal, o.focal, wdt / 2.0, hgt / 2.0};
  } else {
    // The focal length from the photos' EXIF (35 mm equivalent), principal point at the centre.
    const std::string& f = photoFile.at(photoNames.front());
    const PhotoInfo info = readPhotoInfo(f);
    if (!(info.focalPixels() > 0))
      throw Error(w.photosDir, "",
                  "holds no COLMAP model and the photos' EXIF gives no focal length: give the intrinsics (a "
                  "calibration) or the focal length to solve the cameras from the clicks");
    cam.model = "PINHOLE";
    cam.width = info.width;
    cam.height = info.height;
    cam.params = {info.focalPixels(), info.focalPixels(), info.width / 2.0, info.height / 2.0};
    out.notes.push_back(fmt("focal length from EXIF: %.1f px", info.focalPixels()) + " (" + f + ")");
  }
  std::vector<Track> tracks;
  for (const auto& [n, pt] : clicks.points) {
    if (pt.typed) continue;
    Track t;
    t.name = n;
    for (const auto& [photo, px] : pt.clicks) {
      const glm::dvec2 u = cam.undistort(px);
      t.clicks.emplace_back(index[photo], glm::dvec2(cam.fx() * u.x + cam.cx(), cam.fy() * u.y + cam.cy()));
    }
    tracks.push_back(t);
  }
  Camera K;
  K.K = cam.K();
  K.width = cam.width;
  K.height = cam.height;
  const CameraSolution sol = solveCameras(std::vector<Camera>(photoNames.size(), K), photoNames, tracks);
  ColmapModel model;
  model.cameras[1] = cam;
  for (size_t i = 0; i < photoNames.size(); ++i) {
    if (!sol.posed[i]) {
      out.warnings.push_back("photo " + photoNames[i] + " could not be posed from its clicks");
      continue;
    }
    ColmapImage im;
    im.id = int(i + 1);
    im.camera = 1;
    im.name = fs::path(photoFile.at(photoNames[i])).filename().string();
    im.setRotation(sol.cameras[i].R);
    im.t = sol.cameras[i].t;
    model.images[im.id] = im;
  }
  out.notes.push_back(fmt("cameras solved from %.0f clicked points: reprojection rms %.3f px", double(tracks.size()), sol.rmsError));
  // Clicks in photos that could not be posed are left out (a point then needs two other clicks).
  for (auto& [n, pt] : clicks.points) {
    std::vector<std::pair<std::string, glm::dvec2>> kept;
    for (const auto& c : pt.clicks)
      if (index.count(c.first) && sol.posed[size_t(index[c.first])]) kept.push_back(c);
    if (!pt.typed && kept.size() < 2)
      throw Error(clicks.file, "point " + n, "is clicked in fewer than two of the photos that could be posed");
    pt.clicks = kept;
  }
  return model;
}
}  // namespace

ClickWorkspace openClickWorkspace(const std::string& path, const std::string& photosOption) {
  ClickWorkspace w;
  const QDir d(QString::fromStdString(path));
  if (!d.exists()) throw Error(path, "", "no such workspace or model folder");
  if (d.exists("sparse/cameras.txt") || d.exists("sparse/cameras.bin")) w.modelFolder = d.filePath("sparse").toStdString();
  else if (d.exists("cameras.txt") || d.exists("cameras.bin")) w.modelFolder = d.path().toStdString();
  if (!photosOption.empty()) w.photosDir = photosOption;
  else if (const auto info = readWorkspaceInfo(d.path().toStdString())) w.photosDir = info->photos;
  if (w.photosDir.empty()) {
    QDir up(d);
    if (up.cdUp() && up.exists("photos")) w.photosDir = up.filePath("photos").toStdString();
  }
  return w;
}

ClickBuild buildFromClicks(const Clicks& input, const ClickWorkspace& w, const ClickCameraOptions& o,
                           const std::string& undistortDir, Progress& progress) {
  if (w.photosDir.empty()) throw Error(w.modelFolder, "", "the photos folder is unknown; give it");
  ClickBuild out;
  out.clicks = input;
  Clicks& clicks = out.clicks;
  // Work in progress: a point clicked once and used by no polygon is left out; used, it is an error.
  {
    std::map<std::string, std::string> usedBy;
    for (const auto& poly : clicks.polygons)
      for (const auto& c : poly.corners) usedBy.emplace(c, poly.name);
    for (auto it = clicks.points.begin(); it != clicks.points.end();) {
      const auto& p = it->second;
      if (!p.typed && p.clicks.size() < 2) {
        const auto u = usedBy.find(it->first);
        if (u != usedBy.end())
          throw Error(clicks.file, "point " + it->first,
                      "is a corner of polygon " + u->second + " but is clicked in " + std::to_string(p.clicks.size()) +
                          " photo(s); it needs two or more, or a typed position");
        out.warnings.push_back("point " + it->first + " is clicked in one photo only and no polygon uses it: left out");
        it = clicks.points.erase(it);
      } else {
        ++it;
      }
    }
    if (clicks.polygons.empty()) throw Error(clicks.file, "polygons", "there are no polygons to build");
  }
  progress.report(0.05, "cameras");
  if (!w.modelFolder.empty()) out.model = readColmapModel(w.modelFolder);
  else out.model = solveFromClicks(clicks, w, o, out);
  // The metric frame: control points (clicked and measured) when there are 3 or more; else, for
  // cameras solved from clicks, a distance between two points and the floor.
  if (controlPoints(clicks).size() >= 3) {
    const ControlFit f = fitControlPoints(clicks, out.model);
    transformModel(out.model, f.S);
    double worst = 0;
    for (const auto& [n, r] : f.residuals) worst = std::max(worst, r);
    out.notes.push_back("metric frame from " + std::to_string(f.residuals.size()) + " control points: " +
                        fmt("scale %.6g, largest residual %.4f m", f.S.s, worst));
  } else if (w.modelFolder.empty()) {
    if (o.scaleA.empty() || o.scaleB.empty() || !(o.scaleMetres > 0))
      throw Error(clicks.file, "metric frame",
                  "without a model the metric frame is needed: 3 or more control points (clicked and typed), or two "
                  "points and their distance (and three floor points)");
    auto lookup = [&](const std::string& n, const std::string& what) {
      const auto it = clicks.points.find(n);
      if (it == clicks.points.end() || it->second.clicks.size() < 2)
        throw Error(clicks.file, what, "'" + n + "' is not a point clicked in two or more photos");
      return triangulateClickedPoint(clicks, it->first, out.model).X;
    };
    std::vector<glm::dvec3> floor;
    if (!o.floor.empty() && o.floor.size() < 3) throw Error(clicks.file, "floor points", "three or more are needed");
    for (const auto& f : o.floor) floor.push_back(lookup(f, "floor point"));
    const Similarity S = metricFrame(lookup(o.scaleA, "scale point"), lookup(o.scaleB, "scale point"), o.scaleMetres,
                                     floor, meanCameraCentre(out.model));
    transformModel(out.model, S);
    out.notes.push_back(fmt("metric frame from the distance between two points (%.4g m)", o.scaleMetres));
  }
  progress.report(0.3, "triangulating " + std::to_string(clicks.points.size()) + " points");
  out.scene = sceneFromClicks(clicks, out.model, w.photosDir, undistortDir, out.report);
  std::string weak;
  for (const auto& [n, tp] : out.report.points)
    if (!tp.reprojectionError.empty() && tp.rayAngleDeg < 10) weak += " " + n + fmt(" (%.1f deg)", tp.rayAngleDeg);
  if (!weak.empty())
    out.warnings.push_back("clicked in photos taken from nearly the same direction, so their depth is weak (click them "
                           "in a photo further to the side):" + weak);
  return out;
}

KnownCameraAlignment alignToKnownCameras(const ColmapModel& model, const std::string& reference) {
  std::map<std::string, glm::dvec3> ref;  // camera centres by photo name
  const QDir d(QString::fromStdString(reference));
  const bool room = d.exists() && (d.exists("scene.json") || d.exists("project.json"));
  if (d.exists() && !room) {
    const ClickWorkspace rw = openClickWorkspace(reference);
    if (rw.modelFolder.empty()) throw Error(reference, "", "holds neither a COLMAP model nor a room");
    const ColmapModel r = readColmapModel(rw.modelFolder);
    for (const auto& [id, im] : r.images) ref[fs::path(im.name).stem().string()] = im.center();
  } else {
    const Scene s = loadRoom(reference);
    for (const auto& ph : s.photos) ref[ph.name] = ph.camera.center();
  }
  std::vector<glm::dvec3> est, tru;
  KnownCameraAlignment out;
  for (const auto& [id, im] : model.images) {
    const auto it = ref.find(fs::path(im.name).stem().string());
    if (it == ref.end()) continue;
    est.push_back(im.center());
    tru.push_back(it->second);
    out.photos.push_back(it->first);
  }
  if (est.size() < 3)
    throw Error(reference, "", "shares " + std::to_string(est.size()) + " photo name(s) with the model; alignment needs 3 or more");
  out.fit = alignCenters(est, tru);
  return out;
}

void saveClickProject(const ClickBuild& b, const Clicks& clicks, const std::string& folder, Progress& progress) {
  QJsonObject pts;
  for (const auto& [n, tp] : b.report.points) {
    QJsonObject o{{"xyz", QJsonArray{tp.X.x, tp.X.y, tp.X.z}}};
    if (!tp.reprojectionError.empty()) {
      QJsonArray errs;
      for (double e : tp.reprojectionError) errs.append(e);
      o["reprojection_px"] = errs;
      o["ray_angle_deg"] = tp.rayAngleDeg;
    } else {
      o["typed"] = true;
    }
    pts[QString::fromStdString(n)] = o;
  }
  QJsonObject planes;
  for (const auto& [n, r] : b.report.planeRms) planes[QString::fromStdString(n)] = r;
  const QJsonObject rep{{"points", pts}, {"plane_rms_m", planes}, {"seconds", b.report.seconds}};
  saveProject(b.scene, folder, progress, [&](const std::string& staging) {
    const QDir dir(QString::fromStdString(staging));
    writeJson(dir.filePath("triangulation.json"), rep);
    relume::detail::saveStep("triangulation.json written");
    writeClicks(clicks, dir.filePath("clicks.json").toStdString());
    relume::detail::saveStep("clicks.json written");
  });
}

}  // namespace relume::recon
