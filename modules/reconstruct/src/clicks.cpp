#include "relume/reconstruct/clicks.h"

#include <QFile>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QSaveFile>
#include <glm/geometric.hpp>
#include <opencv2/imgproc.hpp>

#include <chrono>
#include <filesystem>

#include "relume/geometry/error.h"
#include "relume/geometry/validate.h"
#include "relume/image/image.h"
#include "relume/reconstruct/photos.h"
#include "relume/reconstruct/polygon_fit.h"

namespace fs = std::filesystem;

namespace relume::recon {

namespace {
std::string str(const QString& s) { return s.toStdString(); }

glm::dvec3 vec3(const QJsonValue& v, const std::string& file, const std::string& what) {
  const QJsonArray a = v.toArray();
  if (a.size() != 3 || !a[0].isDouble() || !a[1].isDouble() || !a[2].isDouble())
    throw Error(file, what, "expected [x, y, z] numbers");
  return {a[0].toDouble(), a[1].toDouble(), a[2].toDouble()};
}

ClickPoint pointFrom(const QJsonObject& o, const std::string& name, const std::string& file, bool draft) {
  ClickPoint p;
  p.name = name;
  for (auto it = o.begin(); it != o.end(); ++it) {
    if (it.key() == "xyz") {
      p.typed = vec3(it.value(), file, "point " + name + " xyz");
      continue;
    }
    const QJsonArray a = it.value().toArray();
    if (a.size() != 2 || !a[0].isDouble() || !a[1].isDouble())
      throw Error(file, "point " + name + " in photo " + str(it.key()), "expected [x, y] pixel coordinates");
    p.clicks.emplace_back(str(it.key()), glm::dvec2(a[0].toDouble(), a[1].toDouble()));
  }
  if (!p.typed && p.clicks.size() < 2 && !draft)
    throw Error(file, "point " + name,
                "is clicked in " + std::to_string(p.clicks.size()) + " photo(s); it needs two or more, or a typed \"xyz\"");
  return p;
}
}  // namespace

Clicks readClicks(const std::string& path, bool draft) {
  QFile f(QString::fromStdString(path));
  if (!f.open(QIODevice::ReadOnly)) throw Error(path, "", "cannot open the clicks file");
  const QByteArray bytes = f.readAll();
  return parseClicks(bytes.toStdString(), path, draft);
}

Clicks parseClicks(const std::string& bytes, const std::string& path, bool draft) {
  QJsonParseError err;
  const QJsonDocument doc = QJsonDocument::fromJson(QByteArray::fromStdString(bytes), &err);
  if (doc.isNull() || !doc.isObject())
    throw Error(path, "", "is not valid JSON: " + str(err.errorString()) + " at offset " + std::to_string(err.offset));
  const QJsonObject root = doc.object();
  Clicks c;
  c.file = path;
  c.main = str(root["main"].toString());
  const QJsonObject pts = root["points"].toObject();
  for (auto it = pts.begin(); it != pts.end(); ++it) {
    if (!it.value().isObject()) throw Error(path, "point " + str(it.key()), "expected an object of photo: [x, y]");
    c.points[str(it.key())] = pointFrom(it.value().toObject(), str(it.key()), path, draft);
  }
  const QJsonArray polys = root["polygons"].toArray();
  if (polys.isEmpty() && !draft) throw Error(path, "polygons", "the file lists no polygons");
  for (int i = 0; i < polys.size(); ++i) {
    const QJsonObject o = polys[i].toObject();
    ClickPolygon p;
    p.name = str(o["name"].toString());
    if (p.name.empty()) throw Error(path, "polygon " + std::to_string(i), "has no name");
    for (const auto& q : c.polygons)
      if (q.name == p.name) throw Error(path, "polygon " + p.name, "the name is used twice");
    p.group = o.contains("group") ? str(o["group"].toString()) : p.name;
    if (o["lamp"].isString()) p.lamp = str(o["lamp"].toString());
    else if (o["lamp"].toBool()) p.lamp = p.name;
    if (o.contains("radiance_rgb")) p.radiance = vec3(o["radiance_rgb"], path, "polygon " + p.name + " radiance_rgb");
    if (o.contains("albedo")) p.albedo = vec3(o["albedo"], path, "polygon " + p.name + " albedo");
    p.rectangle = o["rectangle"].toBool();
    p.plane = str(o["plane"].toString());
    const QJsonArray corners = o["corners"].toArray();
    for (int k = 0; k < corners.size(); ++k) {
      if (corners[k].isString()) {
        const std::string n = str(corners[k].toString());
        if (!c.points.count(n)) throw Error(path, "polygon " + p.name + " corner " + std::to_string(k), "names an unknown point '" + n + "'");
        p.corners.push_back(n);
      } else if (corners[k].isObject()) {
        const std::string n = p.name + "#" + std::to_string(k);
        if (c.points.count(n)) throw Error(path, "polygon " + p.name + " corner " + std::to_string(k), "a point is already called '" + n + "'");
        c.points[n] = pointFrom(corners[k].toObject(), n, path, draft);
        p.corners.push_back(n);
      } else {
        throw Error(path, "polygon " + p.name + " corner " + std::to_string(k), "expected a point name or {photo: [x, y], ...}");
      }
    }
    if (p.corners.size() < 3) throw Error(path, "polygon " + p.name, "needs three or more corners");
    c.polygons.push_back(std::move(p));
  }
  return c;
}

std::string clicksJson(const Clicks& c) {
  QJsonObject root;
  if (!c.main.empty()) root["main"] = QString::fromStdString(c.main);
  QJsonObject pts;
  for (const auto& [name, p] : c.points) {
    QJsonObject o;
    for (const auto& [photo, px] : p.clicks) o[QString::fromStdString(photo)] = QJsonArray{px.x, px.y};
    if (p.typed) o["xyz"] = QJsonArray{p.typed->x, p.typed->y, p.typed->z};
    pts[QString::fromStdString(name)] = o;
  }
  root["points"] = pts;
  QJsonArray polys;
  for (const auto& p : c.polygons) {
    QJsonObject o{{"name", QString::fromStdString(p.name)}, {"group", QString::fromStdString(p.group)}};
    if (!p.lamp.empty()) o["lamp"] = QString::fromStdString(p.lamp);
    if (p.radiance) o["radiance_rgb"] = QJsonArray{p.radiance->x, p.radiance->y, p.radiance->z};
    if (p.albedo) o["albedo"] = QJsonArray{p.albedo->x, p.albedo->y, p.albedo->z};
    if (p.rectangle) o["rectangle"] = true;
    if (!p.plane.empty()) o["plane"] = QString::fromStdString(p.plane);
    QJsonArray corners;
    for (const auto& k : p.corners) corners.append(QString::fromStdString(k));
    o["corners"] = corners;
    polys.append(o);
  }
  root["polygons"] = polys;
  return QJsonDocument(root).toJson(QJsonDocument::Indented).toStdString();
}

void writeClicks(const Clicks& clicks, const std::string& path) {
  QSaveFile f(QString::fromStdString(path));
  const std::string bytes = clicksJson(clicks);
  if (!f.open(QIODevice::WriteOnly) || f.write(bytes.data(), qint64(bytes.size())) < 0 || !f.commit())
    throw Error(path, "", "cannot write the clicks: " + str(f.errorString()));
}

namespace {
// Writes an undistorted copy (pinhole K of the same camera) of `src` to `dst`.
void undistortPhoto(const std::string& src, const std::string& dst, const ColmapCamera& cam) {
  const ImageRGB in = readImageLinear(src);
  if (in.width != cam.width || in.height != cam.height)
    throw Error(src, "", "is " + std::to_string(in.width) + "x" + std::to_string(in.height) + " but its camera is " +
                             std::to_string(cam.width) + "x" + std::to_string(cam.height) + " (a resized copy?)");
  cv::Mat mapx(in.height, in.width, CV_32F), mapy(in.height, in.width, CV_32F);
  for (int y = 0; y < in.height; ++y)
    for (int x = 0; x < in.width; ++x) {
      const glm::dvec2 n((x + 0.5 - cam.cx()) / cam.fx(), (y + 0.5 - cam.cy()) / cam.fy());
      const glm::dvec2 d = cam.distort(n);
      mapx.at<float>(y, x) = float(d.x - 0.5);
      mapy.at<float>(y, x) = float(d.y - 0.5);
    }
  cv::Mat srcM(in.height, in.width, CV_32FC3, const_cast<float*>(in.pixels.data())), out;
  cv::remap(srcM, out, mapx, mapy, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  ImageRGB o(in.width, in.height);
  std::memcpy(o.pixels.data(), out.ptr<float>(), o.pixels.size() * sizeof(float));
  writeImage(dst, o);
}
}  // namespace

namespace {
const ColmapImage* clickedImage(const Clicks& clicks, const ColmapModel& model, const std::string& photo) {
  const ColmapImage* im = model.findImage(photo);
  if (!im) throw Error(clicks.file, "photo " + photo, "is clicked, but the model has no camera for it");
  return im;
}

// Triangulates a clicked point with the model's cameras (`cams` by image id), the clicks'
// distortion removed first.
TriangulatedPoint triangulateClicked(const Clicks& clicks, const ClickPoint& p, const ColmapModel& model,
                                     const std::map<int, Camera>& cams) {
  std::vector<Observation> obs;
  for (const auto& [photo, px] : p.clicks) {
    const ColmapImage* im = clickedImage(clicks, model, photo);
    const ColmapCamera& cc = model.cameras.at(im->camera);
    if (px.x < 0 || px.y < 0 || px.x > cc.width || px.y > cc.height)
      throw Error(clicks.file, "point " + p.name + " in photo " + photo, "lies outside the photo");
    const glm::dvec2 n = cc.undistort(px);
    obs.push_back({&cams.at(im->id), photo, {cc.fx() * n.x + cc.cx(), cc.fy() * n.y + cc.cy()}});
  }
  try {
    return triangulatePoint(obs, "point " + p.name);
  } catch (const Error& e) {
    throw Error(clicks.file, e.element(), e.problem());
  }
}

std::map<int, Camera> camerasById(const ColmapModel& model) {
  std::map<int, Camera> cams;
  for (const auto& [id, im] : model.images) cams[id] = model.camera(im);
  return cams;
}
}  // namespace

TriangulatedPoint triangulateClickedPoint(const Clicks& clicks, const std::string& name, const ColmapModel& model) {
  return triangulateClicked(clicks, clicks.points.at(name), model, camerasById(model));
}

std::vector<Plane> polygonPlanes(const Clicks& clicks, const std::map<std::string, glm::dvec3>& positions,
                                 const std::string& leaveOut) {
  std::vector<Plane> out;
  for (const auto& poly : clicks.polygons) {
    std::vector<glm::dvec3> pts;
    for (const auto& c : poly.corners) {
      const auto it = positions.find(c);
      if (c != leaveOut && it != positions.end()) pts.push_back(it->second);
    }
    if (pts.size() < 3) continue;
    try {
      out.push_back(fitPlane(pts, poly.name));
    } catch (const Error&) {
      // Collinear corners: no plane to offer.
    }
  }
  return out;
}

std::vector<std::string> controlPoints(const Clicks& clicks) {
  std::vector<std::string> r;
  for (const auto& [name, p] : clicks.points)
    if (p.typed && p.clicks.size() >= 2) r.push_back(name);
  return r;
}

ControlFit fitControlPoints(const Clicks& clicks, const ColmapModel& model) {
  const auto names = controlPoints(clicks);
  if (names.size() < 3)
    throw Error(clicks.file, "control points",
                "the metric frame needs 3 or more points both clicked and measured (\"xyz\"); there are " +
                    std::to_string(names.size()));
  const auto cams = camerasById(model);
  std::vector<glm::dvec3> from, to;
  for (const auto& n : names) {
    from.push_back(triangulateClicked(clicks, clicks.points.at(n), model, cams).X);
    to.push_back(*clicks.points.at(n).typed);
  }
  ControlFit f;
  try {
    f.S = fitSimilarity(from, to);
  } catch (const Error& e) {
    throw Error(clicks.file, "control points", e.problem());
  }
  for (size_t i = 0; i < names.size(); ++i) f.residuals[names[i]] = glm::length(f.S.apply(from[i]) - to[i]);
  return f;
}

Scene sceneFromClicks(const Clicks& clicks, const ColmapModel& model, const std::string& photosDir,
                      const std::string& undistortDir, TriangulationReport& report) {
  const auto t0 = std::chrono::steady_clock::now();
  Scene scene;
  scene.sourceFile = clicks.file;
  scene.baseDir = fs::absolute(photosDir).string();
  // Cameras of the model's images, by image id; photos are named by their file stem, which must
  // then be unique.
  const std::map<int, Camera> cams = camerasById(model);
  std::map<std::string, const ColmapImage*> images;
  for (const auto& [id, im] : model.images) {
    const std::string stem = fs::path(im.name).stem().string();
    if (images.count(stem))
      throw Error(photosDir, "photo " + stem, "two model images share this name (" + images[stem]->name + ", " + im.name +
                                                  "); rename one");
    images[stem] = &im;
  }
  auto imageOf = [&](const std::string& photo) { return clickedImage(clicks, model, photo); };
  for (const auto& [name, p] : clicks.points) {
    if (p.typed && p.clicks.size() < 2) {
      TriangulatedPoint tp;
      tp.X = *p.typed;
      report.points[name] = tp;
      continue;
    }
    report.points[name] = triangulateClicked(clicks, p, model, cams);
  }
  // 1. A plane per polygon (or per shared "plane" key) through its corners.
  std::map<std::string, std::vector<glm::dvec3>> planePoints;
  for (const auto& poly : clicks.polygons)
    if (!poly.plane.empty())
      for (const auto& c : poly.corners) planePoints[poly.plane].push_back(report.points.at(c).X);
  glm::dvec3 allCentres(0.0);
  for (const auto& [n, c] : cams) allCentres += c.center() / double(cams.size());
  std::vector<Plane> planes;
  std::map<std::string, std::vector<size_t>> polygonsOfPoint;
  for (size_t k = 0; k < clicks.polygons.size(); ++k) {
    const auto& poly = clicks.polygons[k];
    std::vector<glm::dvec3> pts;
    for (const auto& c : poly.corners) {
      pts.push_back(report.points.at(c).X);
      polygonsOfPoint[c].push_back(k);
    }
    try {
      planes.push_back(fitPlane(poly.plane.empty() ? pts : planePoints[poly.plane], "polygon " + poly.name));
    } catch (const Error& e) {
      throw Error(clicks.file, e.element(), e.problem());
    }
    double rms = 0;
    for (const auto& p : pts) rms += std::pow(glm::dot(p - planes.back().point, planes.back().normal), 2);
    report.planeRms[poly.name] = std::sqrt(rms / pts.size());
  }
  // 2. Corners shared by several polygons go where their planes meet, so that the polygons join
  // without gaps: least squares over the planes, held weakly at the triangulated point (a corner
  // of one polygon is projected onto its plane, of two onto their common line, of three or more
  // onto their intersection).
  std::map<std::string, glm::dvec3> corner;
  for (const auto& [name, polys] : polygonsOfPoint) {
    const glm::dvec3 X0 = report.points.at(name).X;
    const double lambda = 1e-6;
    glm::dmat3 A(lambda);
    glm::dvec3 b = lambda * X0;
    for (size_t k : polys) {
      const Plane& pl = planes[k];
      A += glm::outerProduct(pl.normal, pl.normal);
      b += pl.normal * glm::dot(pl.normal, pl.point);
    }
    corner[name] = glm::inverse(A) * b;
  }
  // 3. The polygons through their corners.
  PickedPolygons picked;
  for (size_t k = 0; k < clicks.polygons.size(); ++k) {
    const auto& poly = clicks.polygons[k];
    std::vector<glm::dvec3> pts;
    glm::dvec3 viewer(0.0);
    int nv = 0;
    bool shared = false;
    for (const auto& c : poly.corners) {
      pts.push_back(corner.at(c));
      shared = shared || polygonsOfPoint.at(c).size() > 1;
      for (const auto& [photo, px] : clicks.points.at(c).clicks) {
        viewer += cams.at(imageOf(photo)->id).center();
        ++nv;
      }
    }
    viewer = nv ? viewer / double(nv) : allCentres;
    try {
      const Plane& pl = planes[k];
      std::vector<glm::dvec3> onPlane;
      for (const auto& p : pts) onPlane.push_back(pl.project(p));
      PolygonConstraints con;
      // Squaring moves corners; where a corner is shared, meeting the other polygons comes first.
      con.rectangle = poly.rectangle && !shared;
      con.keepOrder = true;
      Polygon P;
      P.name = poly.name;
      P.group = poly.group;
      P.material = poly.group;
      P.kind = poly.lamp.empty() ? PolygonKind::Real : PolygonKind::Light;
      P.vertices = convexPolygon(onPlane, pl, viewer, "polygon " + poly.name, con);
      if (poly.albedo) P.albedo = *poly.albedo;
      picked.addExact(P);
    } catch (const Error& e) {
      throw Error(clicks.file, e.element(), e.problem());
    }
  }
  for (const auto& [id, e] : picked.entries()) {
    scene.polygons.push_back(e.polygon);
    const auto& cp = clicks.polygons[scene.polygons.size() - 1];
    if (!cp.lamp.empty()) {
      Lamp l;
      l.name = cp.lamp;
      l.polygon = int(scene.polygons.size() - 1);
      l.radiance = cp.radiance.value_or(glm::dvec3(1.0));
      scene.lamps.push_back(l);
    }
  }
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // Photos: every model image present in photosDir.
  for (const auto& [stem, im] : images) {
    const fs::path file = fs::path(photosDir) / im->name;
    if (!fs::exists(file)) continue;
    Photo ph;
    ph.name = stem;
    ph.camera = cams.at(im->id);
    const ColmapCamera& cc = model.cameras.at(im->camera);
    fs::path hdr = fs::path(photosDir) / (stem + ".exr");
    if (cc.hasDistortion()) {
      fs::create_directories(undistortDir);
      const fs::path ud = fs::path(undistortDir) / (stem + ".png");
      undistortPhoto(file.string(), ud.string(), cc);
      ph.file = fs::absolute(ud).string();
      if (fs::exists(hdr)) {
        const fs::path udh = fs::path(undistortDir) / (stem + ".exr");
        undistortPhoto(hdr.string(), udh.string(), cc);
        ph.hdr = fs::absolute(udh).string();
      }
    } else {
      ph.file = im->name;
      if (fs::exists(hdr)) ph.hdr = stem + ".exr";
    }
    scene.photos.push_back(ph);
  }
  if (scene.photos.empty()) throw Error(photosDir, "", "holds none of the model's photos");
  scene.mainPhoto = clicks.main;
  if (scene.mainPhoto.empty()) scene.mainPhoto = scene.findPhoto("main") ? "main" : scene.photos.front().name;
  if (!scene.findPhoto(scene.mainPhoto))
    throw Error(clicks.file, "main", "names photo '" + scene.mainPhoto + "', which is not in " + photosDir);
  validateScene(scene);
  return scene;
}

}  // namespace relume::recon
