// relume reconstruct | align | triangulate | hdr-merge | calibrate: from photographs to a project.
#include <QCommandLineParser>
#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QSaveFile>
#include <QTemporaryDir>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <numbers>
#include <optional>
#include <random>

#include "commands.h"
#include "relume/daylight/sky.h"
#include "relume/geometry/error.h"
#include "relume/image/image.h"
#include "relume/project/fisheye_lens.h"
#include "relume/project/room_io.h"
#include "relume/reconstruct/click_build.h"
#include "relume/reconstruct/clicks.h"
#include "relume/reconstruct/colmap_driver.h"
#include "relume/reconstruct/colmap_model.h"
#include "relume/reconstruct/matching.h"
#include "relume/reconstruct/multiview.h"
#include "relume/reconstruct/photos.h"
#include "relume/reconstruct/polygon_fit.h"

namespace fs = std::filesystem;

namespace relume::cli {

using namespace relume::recon;

namespace {
std::string str(const QString& s) { return s.toStdString(); }

std::vector<double> numbers(const QString& text, const std::string& option) {
  std::vector<double> v;
  for (const QString& part : text.split(',', Qt::SkipEmptyParts)) {
    bool ok = false;
    double x;
    const QString p = part.trimmed();
    if (p.contains('/')) {  // 1/30
      const auto nd = p.split('/');
      const double a = nd.value(0).toDouble(&ok), b = ok ? nd.value(1).toDouble(&ok) : 0;
      x = ok && b != 0 ? a / b : 0;
      ok = ok && b != 0;
    } else {
      x = p.toDouble(&ok);
    }
    if (!ok) throw Error("", option, "'" + str(part) + "' is not a number");
    v.push_back(x);
  }
  return v;
}

const ColmapPoint& pointById(const ColmapModel& m, const QString& id, const std::string& option) {
  bool ok = false;
  const qint64 v = id.trimmed().toLongLong(&ok);
  const auto it = m.points.find(v);
  if (!ok || it == m.points.end())
    throw Error("", option, "'" + str(id) + "' is not a 3-D point id of the model (see points3D.txt)");
  return it->second;
}

// --scale P1,P2,METRES and --floor P1,P2,P3[,...] with points given by `lookup`.
Similarity metricFromOptions(const QCommandLineParser& p, const std::function<glm::dvec3(const QString&, const std::string&)>& lookup,
                             const glm::dvec3& cameras) {
  const QStringList sc = p.value("scale").split(',');
  if (sc.size() != 3) throw Error("", "--scale", "expected P1,P2,METRES");
  bool ok = false;
  const double metres = sc[2].toDouble(&ok);
  if (!ok) throw Error("", "--scale", "'" + str(sc[2]) + "' is not a distance in metres");
  std::vector<glm::dvec3> floor;
  if (p.isSet("floor")) {
    const QStringList fl = p.value("floor").split(',');
    if (fl.size() < 3) throw Error("", "--floor", "expected three or more points P1,P2,P3");
    for (const auto& f : fl) floor.push_back(lookup(f, "--floor"));
  }
  return metricFrame(lookup(sc[0], "--scale"), lookup(sc[1], "--scale"), metres, floor, cameras);
}
}  // namespace

int reconstructCommand(const QStringList& args, Progress& progress) {
  QCommandLineParser p;
  p.setApplicationDescription("Photos to a COLMAP sparse model (cameras and points) with COLMAP's command line.");
  p.addPositionalArgument("PHOTOS_DIR", "Folder of photos (JPEG, PNG, TIFF).");
  p.addOption({"out", "Workspace folder (model as text in WORKSPACE/sparse).", "WORKSPACE"});
  p.addOption({"matcher", "exhaustive (default) or sequential.", "M"});
  p.addOption({"intrinsics", "Known intrinsics (JSON from `relume calibrate`), held fixed.", "FILE"});
  p.addOption({"camera", "Known intrinsics as MODEL:p1,p2,... (COLMAP's order), held fixed.", "SPEC"});
  p.addOption({"scale", "Metric scale: two 3-D point ids and their distance.", "P1,P2,METRES"});
  p.addOption({"floor", "Floor plane: three or more 3-D point ids (z = 0, +Z up).", "P1,P2,P3"});
  p.addOption({"colmap", "The COLMAP executable (default: $RELUME_COLMAP or colmap on PATH).", "PATH"});
  p.addOption({"known-cameras",
               "Cameras already known (COLMAP model folder, workspace or room): only points are triangulated "
               "(COLMAP point_triangulator); the poses stay.",
               "MODEL"});
  parseOrThrow(p, args, 1, "relume reconstruct PHOTOS_DIR --out WORKSPACE [--scale P1,P2,M --floor P1,P2,P3]");
  if (!p.isSet("out")) throw Error("", "command line", "--out WORKSPACE is required");
  if (p.isSet("floor") && !p.isSet("scale")) throw Error("", "--floor", "needs --scale too (the metric frame takes both)");
  ColmapOptions opt;
  opt.executable = str(p.value("colmap"));
  if (p.isSet("matcher")) opt.matcher = str(p.value("matcher"));
  if (p.isSet("intrinsics")) {
    const Intrinsics in = readIntrinsics(str(p.value("intrinsics")));
    opt.cameraModel = "OPENCV";
    opt.cameraParams = {in.fx, in.fy, in.cx, in.cy, in.k1, in.k2, in.p1, in.p2};
  } else if (p.isSet("camera")) {
    const QStringList mp = p.value("camera").split(':');
    if (mp.size() != 2) throw Error("", "--camera", "expected MODEL:p1,p2,... e.g. PINHOLE:800,800,640,480");
    opt.cameraModel = str(mp[0]);
    opt.cameraParams = numbers(mp[1], "--camera");
  }
  if (p.isSet("known-cameras")) {
    const ClickWorkspace k = openClickWorkspace(str(p.value("known-cameras")));
    QDir kd(p.value("known-cameras"));
    if (!k.modelFolder.empty()) opt.knownCameras = k.modelFolder;
    else if (kd.exists("colmap/cameras.txt")) opt.knownCameras = str(kd.filePath("colmap"));
    else throw Error(str(p.value("known-cameras")), "", "holds no COLMAP model of the cameras");
  }
  const std::string photos = str(QFileInfo(p.positionalArguments()[0]).absoluteFilePath());
  const std::string ws = str(p.value("out"));
  ColmapRun run = runColmap(photos, ws, opt, progress);
  if (!run.leftOut.empty()) {
    std::string l;
    for (const auto& s : run.leftOut) l += " " + s;
    std::fprintf(stderr, "warning: COLMAP could not register%s\n", l.c_str());
  }
  writeWorkspaceInfo(ws, photos, run, false);  // first: a bad --scale below leaves a usable workspace
  if (p.isSet("scale")) {
    const Similarity S = metricFromOptions(
        p, [&](const QString& id, const std::string& o) { return pointById(run.model, id, o).xyz; }, meanCameraCentre(run.model));
    transformModel(run.model, S);
    writeColmapText(run.model, run.modelFolder);
    writeWorkspaceInfo(ws, photos, run, true);
  }
  std::fprintf(stderr, "reconstructed: %zu of %zu photos registered, %zu points -> %s\n", run.registered.size(),
               run.registered.size() + run.leftOut.size(), run.model.points.size(), run.modelFolder.c_str());
  return 0;
}

int alignCommand(const QStringList& args, Progress& progress) {
  QCommandLineParser p;
  p.setApplicationDescription(
      "Put a model into the metric frame: either the similarity that takes its camera centres to known ones "
      "(--to, matched by photo name; prints the per-camera error), or a known distance and the floor "
      "(--scale, --floor: 3-D point ids of the model). Writes the moved model with -o.");
  p.addPositionalArgument("MODEL", "Workspace or COLMAP model folder.");
  p.addOption({"to", "Reference: a COLMAP model folder, workspace, or room bundle/project.", "REF"});
  p.addOption({"scale", "Two 3-D point ids and their distance.", "P1,P2,METRES"});
  p.addOption({"floor", "Three or more 3-D point ids on the floor (z = 0, +Z up).", "P1,P2,P3"});
  p.addOption({QStringList{"o", "output"}, "Write the aligned model (text) here.", "DIR"});
  p.addOption({"json", "Write the errors as JSON.", "OUT.json"});
  parseOrThrow(p, args, 1, "relume align MODEL (--to REFERENCE | --scale P1,P2,M [--floor P1,P2,P3]) [-o DIR] [--json F]");
  if (p.isSet("to") == p.isSet("scale")) throw Error("", "command line", "give either --to REFERENCE or --scale P1,P2,METRES");
  if (p.isSet("floor") && !p.isSet("scale")) throw Error("", "--floor", "needs --scale too (the metric frame takes both)");
  const ClickWorkspace w = openClickWorkspace(str(p.positionalArguments()[0]));
  if (w.modelFolder.empty()) throw Error(str(p.positionalArguments()[0]), "", "holds no COLMAP model");
  ColmapModel model = readColmapModel(w.modelFolder);
  if (p.isSet("scale")) {
    const Similarity S = metricFromOptions(
        p, [&](const QString& id, const std::string& o) { return pointById(model, id, o).xyz; }, meanCameraCentre(model));
    transformModel(model, S);
    std::printf("metric frame: scale %.6g\n", S.s);
    if (p.isSet("output")) writeColmapText(model, str(p.value("output")));
    return 0;
  }
  const QString to = p.value("to");
  progress.report(0, "aligning the cameras");
  const KnownCameraAlignment k = alignToKnownCameras(model, str(to));
  const CenterAlignment& a = k.fit;
  const std::vector<std::string>& names = k.photos;
  QJsonObject per;
  for (size_t i = 0; i < names.size(); ++i) {
    per[QString::fromStdString(names[i])] = a.errors[i];
    std::printf("%-16s camera-centre error %.4f m\n", names[i].c_str(), a.errors[i]);
  }
  std::printf("median %.4f m, max %.4f m over %zu cameras (scale %.6g)\n", a.median, a.max, names.size(), a.S.s);
  if (p.isSet("json"))
    writeJsonAtomically(p.value("json"), QJsonObject{{"cameras", int(names.size())},
                                                     {"median_m", a.median},
                                                     {"max_m", a.max},
                                                     {"scale", a.S.s},
                                                     {"errors_m", per}});
  if (p.isSet("output")) {
    transformModel(model, a.S);
    writeColmapText(model, str(p.value("output")));
  }
  return 0;
}

int triangulateCommand(const QStringList& args, Progress& progress) {
  QCommandLineParser p;
  p.setApplicationDescription(
      "Corners clicked in two or more photos -> 3-D points and polygons -> a Relume project "
      "(TotalCalib-style). Without a model in WORKSPACE, the cameras are solved from the clicks.");
  p.addPositionalArgument("WORKSPACE", "Workspace of `relume reconstruct`, a COLMAP model folder, or a new folder.");
  p.addOption({"clicks", "The clicks (JSON; see README).", "CLICKS.json"});
  p.addOption({QStringList{"o", "output"}, "The Relume project to write.", "PROJECT"});
  p.addOption({"photos", "The photos folder (default: from the workspace, or photos/ beside it).", "DIR"});
  p.addOption({"intrinsics", "Without a model: the camera's intrinsics (JSON of `relume calibrate`).", "FILE"});
  p.addOption({"focal", "Without a model: focal length in pixels (principal point at the centre).", "F"});
  p.addOption({"scale", "Without a model: two point names and their distance.", "P1,P2,METRES"});
  p.addOption({"floor", "Without a model: three or more floor point names (z = 0).", "P1,P2,P3"});
  parseOrThrow(p, args, 1, "relume triangulate WORKSPACE --clicks CLICKS.json -o PROJECT");
  if (!p.isSet("clicks") || !p.isSet("output")) throw Error("", "command line", "--clicks CLICKS.json and -o PROJECT are required");
  const ClickWorkspace w = openClickWorkspace(str(p.positionalArguments()[0]), str(p.value("photos")));
  if (w.photosDir.empty()) throw Error(str(p.positionalArguments()[0]), "", "the photos folder is unknown; pass --photos DIR");
  // The file as the workbench saves it too: work in progress is accepted, and left out.
  const Clicks clicks = readClicks(str(p.value("clicks")), true);
  ClickCameraOptions o;
  o.intrinsicsFile = str(p.value("intrinsics"));
  if (p.isSet("focal")) {
    bool ok = false;
    o.focal = p.value("focal").toDouble(&ok);
    if (!ok || !(o.focal > 0)) throw Error("", "--focal", "must be a positive number of pixels");
  }
  if (p.isSet("scale")) {
    const QStringList sc = p.value("scale").split(',');
    if (sc.size() != 3) throw Error("", "--scale", "expected P1,P2,METRES");
    bool ok = false;
    o.scaleMetres = sc[2].toDouble(&ok);
    if (!ok || !(o.scaleMetres > 0)) throw Error("", "--scale", "'" + str(sc[2]) + "' is not a distance in metres");
    o.scaleA = str(sc[0].trimmed());
    o.scaleB = str(sc[1].trimmed());
  }
  if (p.isSet("floor")) {
    const QStringList fl = p.value("floor").split(',');
    if (fl.size() < 3) throw Error("", "--floor", "expected three or more points P1,P2,P3");
    for (const auto& f : fl) o.floor.push_back(str(f.trimmed()));
  }
  QTemporaryDir tmp;
  const ClickBuild b = buildFromClicks(clicks, w, o, str(tmp.path()) + "/undistorted", progress);
  for (const auto& n : b.notes) std::fprintf(stderr, "%s\n", n.c_str());
  for (const auto& n : b.warnings) std::fprintf(stderr, "warning: %s\n", n.c_str());
  double worst = 0;
  std::string worstName;
  for (const auto& [n, tp] : b.report.points)
    if (tp.maxError() > worst) worst = tp.maxError(), worstName = n;
  std::fprintf(stderr, "triangulated %zu points (largest reprojection error %.2f px, point %s), %zu polygons, %zu lamps\n",
               b.report.points.size(), worst, worstName.c_str(), b.scene.polygons.size(), b.scene.lamps.size());
  // The clicks the polygons came from are kept in the project: it can be re-triangulated or edited.
  saveClickProject(b, clicks, str(p.value("output")), progress);
  std::fprintf(stderr, "wrote %s\n", qPrintable(p.value("output")));
  return 0;
}

int hdrMergeCommand(const QStringList& args, Progress& progress) {
  QCommandLineParser p;
  p.setApplicationDescription(
      "Merge a bracket of 8-bit exposures into a radiance image (Debevec-Malik). Given one folder, its photos are "
      "grouped into brackets by their EXIF exposure and each is merged: -o is then a folder of one photo per "
      "viewpoint (NAME.exr beside its middle exposure), ready for `relume reconstruct` and `relume triangulate`.");
  p.addPositionalArgument("IMAGES", "Two or more exposures of one viewpoint, or a folder of brackets.", "IMAGES...|DIR");
  p.addOption({QStringList{"o", "output"}, "The radiance image (.exr), or a folder for a folder of brackets.", "OUT"});
  p.addOption({"times", "Exposure times in seconds (e.g. 1/60,1/15,1/4); default: EXIF.", "T1,T2,..."});
  p.addOption({"ev", "Exposure steps in EV (t = 2^EV, Loscos 2000 Appendix B); default: EXIF.", "EV1,EV2,..."});
  p.addOption({"response", "Also write the recovered response curve (CSV).", "FILE.csv"});
  p.addHelpOption();
  if (!p.parse(args)) throw Error("", "command line", str(p.errorText()));
  if (p.isSet("help")) {
    std::fprintf(stdout, "%s", qPrintable(p.helpText()));
    return 0;
  }
  if (!p.isSet("output")) throw Error("", "command line", "-o OUT is required");
  if (p.positionalArguments().size() == 1 && QFileInfo(p.positionalArguments()[0]).isDir()) {
    const auto groups = mergeBracketFolder(str(p.positionalArguments()[0]), str(p.value("output")), progress);
    for (const auto& g : groups) {
      std::string names;
      for (const auto& ph : g) names.append(" ").append(fs::path(ph.path).filename().string());
      std::fprintf(stderr, "%s:%s\n", g.size() > 1 ? "merged" : "single", names.c_str());
    }
    std::fprintf(stderr, "%zu viewpoints -> %s\n", groups.size(), qPrintable(p.value("output")));
    return 0;
  }
  if (QFileInfo(p.value("output")).suffix().toLower() != "exr") throw Error(str(p.value("output")), "", "the output must be an .exr");
  std::vector<std::string> files;
  for (const auto& f : p.positionalArguments()) files.push_back(str(f));
  std::vector<double> times;
  if (p.isSet("times")) times = numbers(p.value("times"), "--times");
  else if (p.isSet("ev"))
    for (double ev : numbers(p.value("ev"), "--ev")) times.push_back(exposureFromEv(ev));
  const HdrResult r = mergeBracket(files, times, progress);
  writeImage(str(p.value("output")), r.radiance);
  if (p.isSet("response")) {
    QSaveFile f(p.value("response"));
    if (!f.open(QIODevice::WriteOnly)) throw Error(str(p.value("response")), "", "cannot write the file");
    f.write("value,r,g,b\n");
    for (int z = 0; z < 256; ++z)
      f.write(QString("%1,%2,%3,%4\n").arg(z).arg(r.response[0][z]).arg(r.response[1][z]).arg(r.response[2][z]).toUtf8());
    if (!f.commit()) throw Error(str(p.value("response")), "", "cannot write the file");
  }
  std::fprintf(stderr, "merged %zu exposures -> %s\n", files.size(), qPrintable(p.value("output")));
  return 0;
}

int calibrateCommand(const QStringList& args, Progress& progress) {
  QCommandLineParser p;
  p.setApplicationDescription(
      "Intrinsics and distortion from checkerboard photos (OpenCV calibrateCamera), or with --fisheye a fisheye lens "
      "(OpenCV's fisheye model) for the sky camera, with its image circle found in a photo through it.");
  p.addPositionalArgument("CHECKERBOARD_DIR", "Folder of checkerboard photos, one camera setting.");
  p.addOption({"pattern", "Inner corners, columns x rows (e.g. 9x6).", "CxR"});
  p.addOption({"square", "Square size in metres (e.g. 0.025).", "METRES"});
  p.addOption({"fisheye", "A fisheye lens (k1..k4 of OpenCV's fisheye model; COLMAP's OPENCV_FISHEYE), for `relume sky --lens`."});
  p.addOption({"circle-from", "With --fisheye: a photo through the lens (e.g. a sky image) whose image circle is found from "
                              "the dark border around it and kept with the lens.", "IMAGE"});
  p.addOption({QStringList{"o", "output"}, "Intrinsics JSON (default: CHECKERBOARD_DIR/intrinsics.json, with --fisheye "
                                           "CHECKERBOARD_DIR/fisheye.json).", "FILE"});
  parseOrThrow(p, args, 1, "relume calibrate CHECKERBOARD_DIR --pattern 9x6 --square 0.025 [--fisheye [--circle-from IMAGE]] [-o intrinsics.json]");
  if (p.isSet("circle-from") && !p.isSet("fisheye")) throw Error("", "--circle-from", "is for a fisheye lens: add --fisheye");
  if (!p.isSet("pattern") || !p.isSet("square")) throw Error("", "command line", "--pattern CxR and --square METRES are required");
  const QStringList pat = p.value("pattern").toLower().split('x');
  bool ok1 = false, ok2 = false, ok3 = false;
  const int cols = pat.value(0).toInt(&ok1), rows = pat.value(1).toInt(&ok2);
  const double square = p.value("square").toDouble(&ok3);
  if (pat.size() != 2 || !ok1 || !ok2) throw Error("", "--pattern", "expected inner corners as CxR, e.g. 9x6");
  if (!ok3) throw Error("", "--square", "'" + str(p.value("square")) + "' is not a length in metres");
  const std::string dir = str(p.positionalArguments()[0]);
  std::vector<std::string> files;
  for (const auto& f : listPhotos(dir))
    if (!isRadianceFile(f)) files.push_back(f);
  if (p.isSet("fisheye")) {
    // The image circle first (a photo of another size, or one whose circle cannot be found, is
    // refused before the calibration runs).
    std::optional<daylight::ImageCircle> circle;
    if (p.isSet("circle-from")) {
      const std::string image = str(p.value("circle-from"));
      const ImageRGB im = readImageLinear(image);
      if (!files.empty()) {
        int w = 0, h = 0;
        imageSize(files.front(), w, h);
        if (im.width != w || im.height != h)
          throw Error(image, "--circle-from",
                      "is " + std::to_string(im.width) + "x" + std::to_string(im.height) + ", the checkerboard photos " +
                          std::to_string(w) + "x" + std::to_string(h) + ": not the same camera setting");
      }
      circle = daylight::findImageCircle(im, image);
    }
    FisheyeCalibration cal = calibrateFisheyeCheckerboard(files, cols, rows, square, progress);
    FisheyeLens& in = cal.lens;
    for (const auto& r : cal.rejected) std::fprintf(stderr, "warning: no checkerboard found in %s\n", r.c_str());
    std::printf("fx %.2f fy %.2f cx %.2f cy %.2f k1 %.5f k2 %.5f k3 %.5f k4 %.5f, rms %.3f px, %zu photos\n", in.fx, in.fy, in.cx,
                in.cy, in.k[0], in.k[1], in.k[2], in.k[3], in.rms, cal.used.size());
    if (circle) {
      const daylight::ImageCircle& c = *circle;
      in.circleX = c.centre.x, in.circleY = c.centre.y, in.circleRadius = c.radius;
      // How far from its axis the calibrated lens sees at the circle's edge (the least over the
      // edge): the view the lens really has, as far as the calibration's distortion reaches.
      try {
        FisheyeLens bare = in;
        bare.circleRadius = 0;
        const daylight::FisheyeModel m = daylight::fisheyeCalibrated(bare, 200, str(p.value("circle-from")));
        double least = std::numeric_limits<double>::infinity();  // stays so when every point lies beyond the model's view
        for (int a = 0; a < 360; ++a) {
          const double ang = a * std::numbers::pi / 180;
          if (const auto d = daylight::pixelDirection(m, c.centre.x + c.radius * std::cos(ang), c.centre.y + c.radius * std::sin(ang)))
            least = std::min(least, std::acos(std::clamp(glm::dot(*d, m.axes[2]), -1.0, 1.0)));
        }
        if (std::isfinite(least))
          std::printf("image circle: centre %.2f, %.2f, radius %.2f px; the lens sees %.1f degrees from its axis there (a %.1f-degree view)\n",
                      c.centre.x, c.centre.y, c.radius, least * 180 / std::numbers::pi, 2 * least * 180 / std::numbers::pi);
        else
          std::printf("image circle: centre %.2f, %.2f, radius %.2f px; beyond 100 degrees from the lens's axis\n", c.centre.x,
                      c.centre.y, c.radius);
      } catch (const Error&) {
        std::printf("image circle: centre %.2f, %.2f, radius %.2f px\n", c.centre.x, c.centre.y, c.radius);
        std::fprintf(stderr, "warning: the calibrated distortion folds back before 100 degrees from the axis: the photos did not "
                             "reach the image's edge; take some with the board nearer it\n");
      }
    }
    const std::string out = p.isSet("output") ? str(p.value("output")) : (fs::path(dir) / "fisheye.json").string();
    writeFisheyeLens(in, out);
    std::printf("-> %s\nCOLMAP camera: OPENCV_FISHEYE %d %d %.6f %.6f %.6f %.6f %.8f %.8f %.8f %.8f\n", out.c_str(), in.width,
                in.height, in.fx, in.fy, in.cx, in.cy, in.k[0], in.k[1], in.k[2], in.k[3]);
    return 0;
  }
  const Intrinsics in = calibrateCheckerboard(files, cols, rows, square, progress);
  const std::string out = p.isSet("output") ? str(p.value("output")) : (fs::path(dir) / "intrinsics.json").string();
  writeIntrinsics(in, out);
  for (const auto& r : in.rejected) std::fprintf(stderr, "warning: no checkerboard found in %s\n", r.c_str());
  std::printf("fx %.2f fy %.2f cx %.2f cy %.2f k1 %.5f k2 %.5f p1 %.5f p2 %.5f, rms %.3f px, %zu photos -> %s\n", in.fx, in.fy,
              in.cx, in.cy, in.k1, in.k2, in.p1, in.p2, in.rms, in.used.size(), out.c_str());
  std::printf("COLMAP camera: OPENCV %d %d %.6f %.6f %.6f %.6f %.8f %.8f %.8f %.8f\n", in.width, in.height, in.fx, in.fy,
              in.cx, in.cy, in.k1, in.k2, in.p1, in.p2);
  return 0;
}

QJsonObject reconstructBench(const Scene& scene, int runs, Progress& progress) {
  QJsonObject out;
  // Triangulation and polygon fitting of 100 points: 25 quadrilaterals, each corner seen by 3
  // cameras of a room-sized rig, 0.5 px click noise.
  {
    std::mt19937 rng(11);
    std::normal_distribution<double> noise(0, 0.5);
    std::vector<Camera> cams;
    for (int i = 0; i < 3; ++i) cams.push_back(Camera::lookAt({-0.8 + 0.8 * i, -3.0, 1.5}, {0, 0, 1.2}, 1600, 1200, 1400));
    std::vector<std::vector<std::vector<Observation>>> quads(25);
    for (int q = 0; q < 25; ++q) {
      const glm::dvec3 o(-1.0 + 0.4 * (q % 5), 0.1 * (q / 5), 0.4 + 0.35 * (q / 5));
      for (int k = 0; k < 4; ++k) {
        const glm::dvec3 X = o + glm::dvec3(0.3 * (k == 1 || k == 2), 0.05 * k, 0.25 * (k >= 2));
        std::vector<Observation> obs;
        for (auto& c : cams) {
          glm::dvec2 px;
          c.project(X, px);
          obs.push_back({&c, "bench", px + glm::dvec2(noise(rng), noise(rng))});
        }
        quads[q].push_back(obs);
      }
    }
    std::vector<double> ms;
    size_t vertices = 0;
    for (int r = 0; r < std::max(runs, 5); ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      PickedPolygons picked;
      for (int q = 0; q < 25; ++q) {
        std::vector<glm::dvec3> pts;
        for (const auto& obs : quads[q]) pts.push_back(triangulatePoint(obs, "bench point").X);
        picked.add(std::to_string(q).append("-bench"), "bench", false, pts, cams[1].center());
      }
      ms.push_back(1000 * seconds(t0));
      vertices = 0;
      for (int id : picked.ids()) vertices += picked.get(id).vertices.size();
    }
    out["triangulate_and_fit_100_points_median_ms"] = median(ms);
    out["polygon_vertices"] = qint64(vertices);
  }
  // A full bundle adjustment (Ceres) of 100 points in 8 photos from a perturbed start, 0.5 px noise.
  {
    std::mt19937 rng(5);
    std::normal_distribution<double> N(0, 1);
    std::vector<Camera> truth;
    for (int i = 0; i < 8; ++i)
      truth.push_back(Camera::lookAt({0.5 + 0.5 * i, 0.4 + 0.2 * (i % 3), 1.3 + 0.1 * (i % 2)}, {2.2, 4.0, 1.0}, 1600, 1200, 1400));
    std::vector<glm::dvec3> X;
    for (int k = 0; k < 100; ++k) X.push_back({0.5 + 3.0 * (k % 10) / 9.0, 3.5 + 1.5 * ((k / 10) % 2), 0.1 + 2.2 * (k / 10) / 9.0});
    std::vector<BundleObservation> obs;
    for (int i = 0; i < 8; ++i)
      for (int k = 0; k < 100; ++k) {
        glm::dvec2 px;
        if (truth[i].project(X[k], px)) obs.push_back({i, k, px + 0.5 * glm::dvec2(N(rng), N(rng))});
      }
    std::vector<double> ms;
    BundleReport rep;
    for (int r = 0; r < std::max(runs, 5); ++r) {
      std::vector<Camera> cams = truth;
      std::vector<glm::dvec3> pts = X;
      for (int i = 2; i < 8; ++i) cams[i].t += 0.03 * glm::dvec3(N(rng), N(rng), N(rng));
      for (auto& p : pts) p += 0.02 * glm::dvec3(N(rng), N(rng), N(rng));
      const auto t0 = std::chrono::steady_clock::now();
      rep = bundleAdjust(cams, pts, obs, {0}, 1);
      ms.push_back(1000 * seconds(t0));
    }
    out["bundle_adjustment_100_points_8_photos"] = QJsonObject{{"median_ms", median(ms)},
                                                               {"observations", qint64(obs.size())},
                                                               {"iterations", rep.iterations},
                                                               {"final_rms_px", rep.rms}};
  }
  // Match proposals in 12-megapixel photos: the room's photos resampled to 4000 x 3000 (their
  // cameras with them), prepared once; a click in the main photo gets its proposals in all the
  // others at once, as the Model panel asks for them.
  if (const Photo* main = scene.findPhoto(scene.mainPhoto); main && !main->file.empty()) {
    const int W = 4000, H = 3000;
    std::vector<MatchImage> images;
    std::vector<Camera> cams;
    std::vector<double> prepMs;
    size_t mainIndex = 0;
    for (const auto& ph : scene.photos) {
      if (ph.file.empty()) continue;
      const Image8 small = readImage8((fs::path(scene.baseDir) / ph.file).string());
      const Image8 big = resizeImage8(small, W, H);
      const auto t0 = std::chrono::steady_clock::now();
      images.push_back(prepareForMatching(big));
      prepMs.push_back(1000 * seconds(t0));
      Camera c = ph.camera;
      const double sx = double(W) / small.width, sy = double(H) / small.height;
      c.K[0][0] *= sx, c.K[2][0] *= sx, c.K[1][1] *= sy, c.K[2][1] *= sy;
      c.width = W, c.height = H;
      if (ph.name == main->name) mainIndex = cams.size();
      cams.push_back(c);
    }
    // Clicks: polygon corners the main photo shows, away from its border.
    std::vector<glm::dvec2> clicks;
    for (const auto& poly : scene.polygons)
      for (const auto& v : poly.vertices) {
        glm::dvec2 px;
        if (clicks.size() < 12 && cams[mainIndex].project(v, px) && px.x > 100 && px.y > 100 && px.x < W - 100 && px.y < H - 100)
          clicks.push_back(px);
      }
    std::vector<const MatchImage*> others;
    std::vector<const Camera*> otherCams;
    for (size_t i = 0; i < images.size(); ++i)
      if (i != mainIndex) others.push_back(&images[i]), otherCams.push_back(&cams[i]);
    std::vector<double> ms;
    for (int r = 0; r < std::max(1, runs / 3); ++r)
      for (const auto& pa : clicks) {
        const auto t0 = std::chrono::steady_clock::now();
        (void)proposeMatchesInPhotos(images[mainIndex], pa, cams[mainIndex], others, otherCams, 3, 7, glm::dvec3(0, 0, 1));
        ms.push_back(1000 * seconds(t0));
      }
    out["match_proposals_12mp"] = QJsonObject{{"photos", qint64(images.size())},
                                              {"size", QString("%1x%2").arg(W).arg(H)},
                                              {"clicks", qint64(ms.size())},
                                              {"proposals_in_all_other_photos_median_ms", median(ms)},
                                              {"prepare_per_photo_median_ms", median(prepMs)}};
  }
  // A dragged point: its triangulation again from three clicks and the refit of its polygon.
  {
    std::vector<Camera> cams;
    for (int i = 0; i < 3; ++i) cams.push_back(Camera::lookAt({-0.8 + 0.8 * i, -3.0, 1.5}, {0, 0, 1.2}, 4000, 3000, 3500));
    std::vector<std::vector<Observation>> corners;
    for (int k = 0; k < 4; ++k) {
      const glm::dvec3 X(0.3 * (k == 1 || k == 2), 0.05 * k, 0.8 + 0.25 * (k >= 2));
      std::vector<Observation> obs;
      for (auto& c : cams) {
        glm::dvec2 px;
        c.project(X, px);
        obs.push_back({&c, "bench", px});
      }
      corners.push_back(obs);
    }
    std::vector<glm::dvec3> pts;
    for (const auto& obs : corners) pts.push_back(triangulatePoint(obs, "bench point").X);
    std::vector<double> ms;
    for (int r = 0; r < std::max(runs, 5) * 20; ++r) {
      corners[0][0].pixel.x += (r % 2 ? -0.7 : 0.7);  // the drag's step
      const auto t0 = std::chrono::steady_clock::now();
      pts[0] = triangulatePoint(corners[0], "dragged point").X;
      PickedPolygons picked;
      picked.add("dragged", "bench", false, pts, cams[1].center());
      ms.push_back(1000 * seconds(t0));
    }
    out["dragged_point_triangulate_and_refit_median_ms"] = median(ms);
  }
  // COLMAP on the room's photos (skipped, and said so, when COLMAP is missing).
  const Photo* main = scene.findPhoto(scene.mainPhoto);
  if (main) {
    const std::string photosDir = (fs::path(scene.baseDir) / main->file).parent_path().string();
    try {
      findColmap();
      std::vector<double> feat, match, map, total;
      size_t registered = 0, photos = 0;
      for (int r = 0; r < std::min(runs, 3); ++r) {
        ProgressScope sub(progress, double(r) / std::min(runs, 3), double(r + 1) / std::min(runs, 3));
        QTemporaryDir tmp;
        const auto t0 = std::chrono::steady_clock::now();
        const ColmapRun run = runColmap(photosDir, str(tmp.path()), ColmapOptions{}, sub);
        total.push_back(seconds(t0));
        feat.push_back(run.secondsFeatures);
        match.push_back(run.secondsMatching);
        map.push_back(run.secondsMapping);
        registered = run.registered.size();
        photos = run.registered.size() + run.leftOut.size();
      }
      out["colmap"] = QJsonObject{{"photos", qint64(photos)},
                                  {"registered", qint64(registered)},
                                  {"median_seconds", median(total)},
                                  {"features_median_seconds", median(feat)},
                                  {"matching_median_seconds", median(match)},
                                  {"mapping_median_seconds", median(map)}};
    } catch (const Error& e) {
      out["colmap"] = QJsonObject{{"skipped", QString::fromStdString(e.what())}};
    }
  }
  return out;
}

}  // namespace relume::cli
