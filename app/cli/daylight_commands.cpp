// relume sky: what a measured sky holds (its regions, its sun), as the daylight basis uses it.
// relume daylight-basis: the room's basis radiosity solutions (one per sky region, the ground,
// the sun) and what each of its measured skies gives, combined from them.
#include <QCommandLineParser>
#include <QJsonArray>
#include <QJsonObject>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <map>

#include "commands.h"
#include <QDir>
#include <QFileInfo>
#include <QFile>
#include <QJsonDocument>
#include <QSet>

#include "relume/daylight/basis.h"
#include "relume/daylight/relight.h"
#include "relume/project/room_io.h"
#include "relume/geometry/polygon.h"
#include "relume/relight/compare.h"
#include "relume/relight/relighter.h"
#include "relume/daylight/sky.h"
#include "relume/daylight/volume.h"
#include "relume/project/fisheye_lens.h"
#include "relume/ibr/fan.h"
#include "relume/ibr/relit_objects.h"
#include "relume/radiosity/sh.h"
#include "relume/radiosity/form_factor.h"
#include "relume/radiosity/hierarchy.h"
#include "relume/relight/solution_render.h"
#include "relume/geometry/error.h"
#include "relume/geometry/scene.h"
#include "relume/image/image.h"

namespace relume::cli {

namespace dl = relume::daylight;

namespace {
// An empty folder, or one an earlier `relight --sky FOLDER` wrote: frames.json and only the images
// it lists (the only kind of folder a new run may replace).
bool isFramesFolder(const QString& dir) {
  const QStringList entries = QDir(dir).entryList(QDir::AllEntries | QDir::NoDotAndDotDot | QDir::Hidden);
  if (entries.isEmpty()) return true;
  QFile f(QDir(dir).filePath("frames.json"));
  if (!f.open(QIODevice::ReadOnly)) return false;
  const QJsonObject root = QJsonDocument::fromJson(f.readAll()).object();
  QSet<QString> listed{"frames.json"};
  for (const QJsonValue& v : root["frames"].toArray()) {
    listed.insert(v.toObject()["image"].toString());
    listed.insert(v.toObject()["linear"].toString());
  }
  for (const QString& e : entries)
    if (!listed.contains(e)) return false;
  return true;
}

// The sky averaged into regions; a clipped sun is said on stderr (its light would be understated).
dl::SkyRadiance averaged(const dl::SkyImage& image, const dl::SkyRegions& cells) {
  dl::SkyRadiance s = dl::averageSky(image, cells);
  if (s.sun.found && s.sun.clipped)
    std::fprintf(stderr,
                 "warning: %s: the sun's pixels are clipped (at 65504, half float's largest value, or saturated): its light is "
                 "understated%s; save the sky as full-float HDR, bracketed far enough\n",
                 image.file.c_str(),
                 s.sun.colourFromUnclipped ? " (its colour is taken from its pixels that did not clip)" : " and its colour shifted");
  return s;
}

double luminance(const glm::dvec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }
QJsonArray rgbJson(const glm::dvec3& v) { return QJsonArray{v.x, v.y, v.z}; }
}  // namespace

// relume daylight-basis ROOM -o PROJECT: the daylight session estimated and solved once, kept in
// the project beside the room (the project is written atomically, the session file with it).
int keepDaylightSession(const Scene& room, int regions, const std::string& out, Progress& progress) {
  if (room.skies.empty() || room.photoSky.empty())
    throw Error(room.sourceFile, "daylight", "the room lists no measured sky of its photos (\"photos_sun\"): nothing to estimate under");
  const Photo* main = room.findPhoto(room.mainPhoto);
  if (!main || main->hdr.empty())
    throw Error(room.sourceFile, "main_photo", "the daylight session needs the main photo's linear (EXR) image");
  const ImageRGB photo = readImageLinear(main->hdr.front() == '/' ? main->hdr : room.baseDir + "/" + main->hdr);
  const dl::SkyRegions cells(regions);
  dl::BasisOptions options;
  options.regions = regions;
  Progress work(progress, 0.0, 0.9);
  const auto t0 = std::chrono::steady_clock::now();
  dl::DaylightRelighting session(room, photo, main->camera, averaged(dl::readRoomSky(room, room.photoSky), cells), options, work);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto& eng = session.basis().engine();
  std::printf("daylight session: reflectances estimated under sky %s and %d basis solutions on %zu elements and %zu links, "
              "in %.1f s\n",
              room.photoSky.c_str(), session.basis().basisCount(), eng.nodes().size(), eng.links().size(), secs);
  const dl::UnseenFit& fit = session.unseenFit();
  if (fit.ok) std::printf("  polygons no photo shows: reflectance %.3f, measured from %d sunlit and shaded polygons\n", fit.rho.x, fit.polygons);
  else std::printf("  polygons no photo shows: the shown polygons' mean (%s)\n", fit.why.c_str());
  Progress saving(progress, 0.9, 1.0);
  saveProject(room, out, saving, [&](const std::string& staging) {
    if (!QDir().mkpath(QString::fromStdString(staging + "/daylight")))
      throw Error(staging + "/daylight", "", "cannot create the folder");
    try {
      session.save(staging + "/daylight/solution.bin");
    } catch (const Error& e) {  // named as the user knows it, not by the staging folder
      throw Error(out + "/daylight/solution.bin", e.element(), e.problem());
    }
  });
  std::fprintf(stderr, "wrote project %s (its daylight session in daylight/solution.bin)\n", out.c_str());
  return 0;
}

int daylightBasisCommand(const QStringList& args, Progress& progress) {
  QCommandLineParser p;
  p.setApplicationDescription(
      "Solve a daylight room's basis radiosity solutions (Grosch, Eble, Mueller 2007): the windows as openings, one "
      "solution per sky region at unit radiance, one for the ground, one for the sun of each sky; then combine them "
      "for each of the room's measured skies and print each polygon's mean radiance.");
  p.addPositionalArgument("ROOM", "A daylight room (bundle folder, project or .obj with its .json) with windows and skies.");
  p.addOption({"regions", "Number of sky regions (default 64).", "N"});
  p.addOption({"sky", "The sky to refine the links for (default: the one the photos were taken under).", "NAME"});
  p.addOption({"exact", "Also solve the refining sky with its exact radiance per direction (the fisheye's pixels, "
                        "the sun apart) and report how far the regions' combination is from it."});
  p.addOption({"json", "Write the report as JSON.", "OUT.json"});
  p.addOption({"render", "Write each sky's solution seen through the main photo's camera as DIR/SKY.exr (radiance "
                         "B / pi of the model's own albedos: the simulation, not the relit photo).", "DIR"});
  p.addOption({"grid", "Also build the irradiance volume for virtual objects: N x N x N points over the room (N from "
                       "2 to 32, e.g. 8), each basis's indirect light as spherical harmonics, and print each sky's at the room's "
                       "centre.", "N"});
  p.addOption({{"o", "output"}, "Write the room as a Relume project that keeps its daylight session: the reflectances "
                                "estimated from the main photo under the photos' sky and every basis solution, in "
                                "PROJECT/daylight/solution.bin, so that relume relight --sky and the workbench open it "
                                "without estimating or solving again. Takes no other option.", "PROJECT"});
  parseOrThrow(p, args, 1,
               "relume daylight-basis ROOM [--regions 64] [--grid 8] [--sky NAME] [--exact] [--json OUT.json] [--render DIR]\n"
               "       relume daylight-basis ROOM -o PROJECT");
  bool ok = true;
  const int regions = p.isSet("regions") ? p.value("regions").toInt(&ok) : 64;
  if (!ok || regions < 1 || regions > 4096) throw Error("", "--regions", "must be a whole number from 1 to 4096");
  if (p.isSet("output")) {
    for (const char* o : {"regions", "grid", "sky", "exact", "json", "render"})
      if (p.isSet(o))
        throw Error("", std::string("--") + o,
                    "is for the report of the model's own simulation; -o PROJECT keeps the session relume relight --sky and "
                    "the workbench use (64 regions, refined for the photos' sky) and takes no other option");
    return keepDaylightSession(openRoom(p.positionalArguments()[0]), 64, p.value("output").toStdString(), progress);
  }
  const int grid = p.isSet("grid") ? p.value("grid").toInt(&ok) : 0;
  if (!ok || (p.isSet("grid") && (grid < 2 || grid > 32))) throw Error("", "--grid", "must be a whole number from 2 to 32");
  const Scene room = openRoom(p.positionalArguments()[0]);
  const dl::SkyImage refineImage = dl::readRoomSky(room, p.value("sky").toStdString());
  const dl::SkyRegions cells(regions);
  const dl::SkyRadiance refineSky = averaged(refineImage, cells);
  dl::BasisOptions options;
  options.regions = regions;
  dl::DaylightBasis basis(room, refineSky, options, progress);
  const auto& eng = basis.engine();
  std::printf("%d basis solutions (%d regions and the ground) on %zu elements and %zu links: refined in %.1f s, "
              "%.2f s per basis; ground albedo %.3f\n",
              basis.basisCount(), regions, eng.nodes().size(), eng.links().size(), basis.refineSeconds(),
              basis.secondsPerBasis(), basis.groundReflectance());
  std::unique_ptr<dl::IrradianceVolume> volume;
  if (grid > 0) {
    volume = std::make_unique<dl::IrradianceVolume>(basis, dl::VolumeOptions{grid, 2048}, progress);
    size_t inside = 0;
    for (size_t q = 0; q < volume->pointCount(); ++q) inside += volume->inRoom(q);
    std::printf("irradiance volume: %d^3 points (%zu inside the room, the rest inside furniture or walls), %d bases, built "
                "in %.1f s\n",
                grid, inside, volume->basisCount(), volume->buildSeconds());
  }
  QJsonArray skies;
  for (const auto& cap : room.skies) {
    const dl::SkyImage image = dl::readRoomSky(room, cap.name);
    const dl::SkyRadiance sky = averaged(image, cells);
    Progress stage(progress, 0, 1);
    const auto b = basis.combine(sky, stage);
    std::printf("sky %s%s:\n", cap.name.c_str(), sky.sun.found ? "" : " (no sun found)");
    QJsonObject polys;
    for (size_t s = 0; s < room.polygons.size(); ++s) {
      if (room.polygons[s].kind == PolygonKind::Window || eng.isRemoved(int(s))) continue;
      const glm::dvec3 l = basis.surfaceMean(b, int(s)) / std::numbers::pi;
      std::printf("  %-20s %10.5f %10.5f %10.5f\n", room.polygons[s].name.c_str(), l.x, l.y, l.z);
      polys[QString::fromStdString(room.polygons[s].name)] = rgbJson(l);
    }
    QJsonObject skyReport{{"name", QString::fromStdString(cap.name)}, {"mean_radiance", polys}};
    if (volume) {
      // The indirect irradiance at the room's centre from six directions (the volume's light).
      volume->combine(basis, sky, stage);
      const glm::dvec3 centre = 0.5 * (volume->lower() + volume->upper());
      const radiosity::SH9 sh = volume->at(centre);
      QJsonObject e;
      std::printf("  indirect irradiance at the room's centre:");
      for (const auto& [name, n] : {std::pair{"+x", glm::dvec3(1, 0, 0)}, {"-x", glm::dvec3(-1, 0, 0)}, {"+y", glm::dvec3(0, 1, 0)},
                                    {"-y", glm::dvec3(0, -1, 0)}, {"+z", glm::dvec3(0, 0, 1)}, {"-z", glm::dvec3(0, 0, -1)}}) {
        const glm::dvec3 v = radiosity::shIrradiance(sh, n);
        std::printf(" %s %.4f", name, luminance(v));
        e[name] = rgbJson(v);
      }
      std::printf("\n");
      skyReport["volume_centre_irradiance"] = e;
    }
    skies.append(skyReport);
    if (p.isSet("render")) {
      const Photo* main = room.findPhoto(room.mainPhoto);
      if (!main) throw Error(room.sourceFile, "--render", "the room has no main photo to look through");
      if (!QDir().mkpath(p.value("render"))) throw Error(p.value("render").toStdString(), "--render", "cannot create the folder");
      const std::string out = p.value("render").toStdString() + "/" + cap.name + ".exr";
      writeImage(out, renderRadiosity(eng, b, main->camera, stage));
      std::printf("  wrote %s\n", out.c_str());
    }
  }
  QJsonObject report{{"room", QString::fromStdString(room.sourceFile)},
                     {"regions", regions},
                     {"elements", double(eng.nodes().size())},
                     {"links", double(eng.links().size())},
                     {"refine_seconds", basis.refineSeconds()},
                     {"seconds_per_basis", basis.secondsPerBasis()},
                     {"ground_albedo", basis.groundReflectance()},
                     {"skies", skies}};
  if (volume) report["volume"] = QJsonObject{{"grid", grid}, {"build_seconds", volume->buildSeconds()}};
  if (p.isSet("exact")) {
    // The refining sky's luminance per direction, the sun's pixels given their region's mean.
    const dl::SkyRadiance& avg = refineSky;
    auto exact = std::make_shared<radiosity::DistantLight>();
    exact->pieceDeg = options.pieceDeg;
    const dl::SkyImage* im = &refineImage;
    const dl::SkyRegions* cellsPtr = &cells;
    const double sunCos = std::cos(dl::SkyOptions{}.sunRadiusDeg * std::numbers::pi / 180);
    // Both without the sun: the ground lit by the sky alone, in the exact solve as in the combination.
    dl::SkyRadiance grey = avg;
    for (auto& r : grey.region) r = glm::dvec3(luminance(r));
    grey.sun.found = false;
    const glm::dvec3 ground = basis.groundRadiance(grey);
    exact->radiance = [im, cellsPtr, &avg, sunCos, ground](const glm::dvec3& d) {
      const int k = cellsPtr->regionOf(d);
      if (k < 0) return luminance(ground);
      if (avg.sun.found && glm::dot(d, avg.sun.direction) > sunCos) return luminance(avg.region[size_t(k)]);
      const auto px = dl::directionPixel(im->model, d);
      if (!px) return luminance(avg.region[size_t(k)]);
      const int x = std::clamp(int(px->x), 0, im->image.width - 1), y = std::clamp(int(px->y), 0, im->image.height - 1);
      return luminance(glm::dvec3(im->image.at(x, y)));
    };
    progress.report(0, "solving the sky's exact radiance per direction");
    const auto truth = basis.solveFor(exact, progress);
    const auto combined = basis.combine(grey, progress);
    double worst = 0, sum = 0;
    int n = 0;
    std::string where;
    for (size_t s = 0; s < room.polygons.size(); ++s) {
      if (room.polygons[s].kind == PolygonKind::Window || eng.isRemoved(int(s))) continue;
      const double t = basis.surfaceMean(truth, int(s)).x, c = basis.surfaceMean(combined, int(s)).x;
      if (!(t > 0)) continue;
      const double e = std::abs(c / t - 1);
      sum += e;
      ++n;
      if (e > worst) worst = e, where = room.polygons[s].name;
    }
    std::printf("regions vs the exact sky (no sun): per-polygon mean radiosity off by %.2f %% at worst (%s), %.2f %% "
                "on average over %d polygons\n",
                100 * worst, where.c_str(), n ? 100 * sum / n : 0.0, n);
    report["exact_worst_percent"] = 100 * worst;
    report["exact_mean_percent"] = n ? 100 * sum / n : 0.0;
    report["exact_worst_polygon"] = QString::fromStdString(where);
  }
  if (p.isSet("json")) writeJsonAtomically(p.value("json"), report);
  return 0;
}

int skyCommand(const QStringList& args, Progress& progress) {
  QCommandLineParser p;
  p.setApplicationDescription(
      "Read an HDR fisheye of the sky (looking up, image up = +Y, the circle filling the image unless given), find the "
      "sun, average the rest over the sky's regions and print the irradiance it gives.");
  p.addPositionalArgument("FISHEYE", "Linear HDR fisheye image (EXR).");
  p.addOption({"projection", "equidistant (default), equisolid, or equirectangular (a 360 x 180 degree panorama, its "
                             "centre column along +X, +Z up).", "NAME"});
  p.addOption({"panorama", "With a daylight ROOM: read its sky's equirectangular panorama instead of its fisheye."});
  p.addOption({"fov", "Field of view across the image circle in degrees (default 180).", "DEG"});
  p.addOption({"circle", "The image circle as CX,CY,R in pixels, or auto: found from the dark border around it "
                         "(default: centred, filling the image; with --lens, the lens file's).", "CX,CY,R|auto"});
  p.addOption({"lens", "A calibrated fisheye (`relume calibrate --fisheye`, OpenCV's fisheye model) instead of an "
                       "ideal projection; --fov limits its view (default 180).", "LENS.json"});
  p.addOption({"regions", "Number of sky regions (default 64).", "N"});
  p.addOption({"json", "Also write the regions, the sun and the irradiances as JSON.", "OUT.json"});
  p.addOption({"sky", "With a daylight ROOM: which of its skies (default: the one its photos were taken under).", "NAME"});
  parseOrThrow(p, args, 1, "relume sky FISHEYE.exr|PANORAMA.exr|ROOM [--sky NAME] [--panorama] [--projection equidistant|equisolid|equirectangular] [--lens LENS.json] [--circle CX,CY,R|auto] [--fov 180] [--regions 64]");
  if (p.isSet("lens") && (p.isSet("projection") || p.isSet("panorama")))
    throw Error("", "--lens", "a calibrated lens is its own projection: give --lens or --projection / --panorama, not both");
  std::string file = p.positionalArguments()[0].toStdString();
  std::string description;  // the lens in words, when a room's daylight section gives it
  FisheyeLens roomLens;     // and its calibrated lens, when it names one
  if (!isRadianceFile(file)) {
    if (p.isSet("lens"))
      throw Error(p.value("lens").toStdString(), "--lens",
                  "is for a fisheye image; a room's sky takes the lens its daylight section names (fisheye_lens), or "
                  "the one its words describe");
    const Scene room = openRoom(p.positionalArguments()[0]);
    if (room.skies.empty()) throw Error(room.sourceFile, "daylight", "the room lists no measured sky");
    const std::string want = p.isSet("sky") ? p.value("sky").toStdString() : room.photoSky.empty() ? room.skies.front().name : room.photoSky;
    const SkyCapture* cap = room.findSky(want);
    if (!cap) throw Error(room.sourceFile, "--sky", "the room has no sky named '" + want + "'");
    file = room.baseDir + "/" + cap->fisheye;
    description = cap->fisheyeModel;
    roomLens = cap->lens;
    if (p.isSet("panorama")) {
      if (cap->panorama.empty()) throw Error(room.sourceFile, "--panorama", "the sky '" + want + "' has no panorama");
      file = room.baseDir + "/" + cap->panorama;
      description.clear();
    }
  } else if (p.isSet("panorama")) {
    throw Error("", "--panorama", "needs a daylight room; for an image give --projection equirectangular");
  }
  QString proj = p.value("projection").isEmpty() ? "equidistant" : p.value("projection");
  if (p.isSet("panorama")) proj = "equirectangular";
  if (proj != "equidistant" && proj != "equisolid" && proj != "equirectangular")
    throw Error("", "--projection", "must be equidistant, equisolid or equirectangular, not '" + proj.toStdString() + "'");
  bool ok = true;
  const double fov = p.isSet("fov") ? p.value("fov").toDouble(&ok) : 180.0;
  if (!ok || !(fov > 0 && fov <= 360)) throw Error("", "--fov", "must be a number of degrees in (0, 360]");
  const int regions = p.isSet("regions") ? p.value("regions").toInt(&ok) : 64;
  if (!ok || regions < 1 || regions > 100000) throw Error("", "--regions", "must be a whole number from 1 to 100000");
  int w = 0, h = 0;
  imageSize(file, w, h);
  dl::FisheyeModel model;
  if (p.isSet("lens")) {
    const std::string lensFile = p.value("lens").toStdString();
    const FisheyeLens lens = readFisheyeLens(lensFile);
    if (lens.width != w || lens.height != h)
      throw Error(lensFile, "width, height",
                  "the lens was calibrated on " + std::to_string(lens.width) + "x" + std::to_string(lens.height) +
                      " images, " + file + " is " + std::to_string(w) + "x" + std::to_string(h));
    model = dl::fisheyeCalibrated(lens, fov, lensFile);
  } else {
    model = proj == "equirectangular" ? dl::equirectangular(w, h)
            : description.empty()
                ? dl::fisheyeLookingUp(w, h, proj == "equisolid" ? dl::FisheyeProjection::Equisolid : dl::FisheyeProjection::Equidistant, fov)
                : dl::fisheyeFromDescription(description, w, h, file, roomLens);
  }
  if (p.isSet("circle") && proj == "equirectangular") throw Error("", "--circle", "a panorama has no image circle");
  if (p.isSet("circle")) {
    glm::dvec2 centre(0.0);
    double radius = 0;
    if (p.value("circle") == "auto") {
      progress.report(0, "finding the image circle of " + file);
      const dl::ImageCircle c = dl::findImageCircle(readImageLinear(file), file);
      std::printf("image circle: centre %.2f, %.2f, radius %.2f px (its edge %.2f px off the circle, %d points)\n", c.centre.x,
                  c.centre.y, c.radius, c.rms, c.points);
      centre = c.centre, radius = c.radius;
    } else {
      const QStringList c = p.value("circle").split(',');
      bool a = false, b = false, r = false;
      if (c.size() != 3) throw Error("", "--circle", "must be CX,CY,R (pixels) or auto");
      centre = {c[0].toDouble(&a), c[1].toDouble(&b)};
      radius = c[2].toDouble(&r);
      if (!a || !b || !r || !(radius > 0)) throw Error("", "--circle", "must be CX,CY,R (pixels, R positive) or auto");
    }
    if (model.projection == dl::FisheyeProjection::OpenCvFisheye) model.circleCentre = centre;
    else model.centre = centre;
    model.radius = radius;
  }
  progress.report(0, "reading " + file);
  const dl::SkyImage sky = dl::readSkyImage(file, model);
  progress.report(0.3, "averaging the sky over " + std::to_string(regions) + " regions");
  const dl::SkyRegions cells(regions);
  const dl::SkyRadiance avg = averaged(sky, cells);
  const double deg = 180 / std::numbers::pi;
  const glm::dvec3 horizontal = dl::planeIrradiance(cells, avg, {0, 0, 1});
  dl::SkyRadiance skyOnly = avg;
  skyOnly.sun.found = false;
  const glm::dvec3 diffuse = dl::planeIrradiance(cells, skyOnly, {0, 0, 1});
  if (avg.sun.found) {
    const glm::dvec3& d = avg.sun.direction;
    double az = std::atan2(d.y, d.x) * deg;
    if (az < 0) az += 360;
    std::printf("sun: elevation %.2f deg, azimuth %.2f deg (from +X towards +Y), %d pixels, %.3g sr; irradiance facing it %.4g %.4g %.4g\n",
                std::asin(d.z) * deg, az, avg.sun.pixels, avg.sun.solidAngle, avg.sun.irradiance.x, avg.sun.irradiance.y,
                avg.sun.irradiance.z);
  } else {
    std::printf("sun: none found (no pixel far brighter than the sky)\n");
  }
  std::printf("horizontal irradiance: sky %.4g %.4g %.4g, with the sun %.4g %.4g %.4g (%d regions)\n", diffuse.x, diffuse.y,
              diffuse.z, horizontal.x, horizontal.y, horizontal.z, cells.size());
  if (p.isSet("json")) {
    auto rgb = [](const glm::dvec3& v) { return QJsonArray{v.x, v.y, v.z}; };
    QJsonArray reg;
    for (int k = 0; k < cells.size(); ++k) {
      const auto& c = cells.cell(k);
      reg.append(QJsonObject{{"elevation_deg", QJsonArray{c.elev0 * deg, c.elev1 * deg}},
                             {"azimuth_deg", QJsonArray{c.azim0 * deg, c.azim1 * deg}},
                             {"solid_angle_sr", cells.solidAngle(k)},
                             {"radiance", rgb(avg.region[size_t(k)])}});
    }
    QJsonObject sun{{"found", avg.sun.found}};
    if (avg.sun.found)
      sun = QJsonObject{{"found", true},
                        {"direction", rgb(avg.sun.direction)},
                        {"irradiance", rgb(avg.sun.irradiance)},
                        {"solid_angle_sr", avg.sun.solidAngle},
                        {"pixels", avg.sun.pixels}};
    writeJsonAtomically(p.value("json"), QJsonObject{{"file", QString::fromStdString(file)},
                                                     {"regions", reg},
                                                     {"sun", sun},
                                                     {"horizontal_irradiance_sky", rgb(diffuse)},
                                                     {"horizontal_irradiance", rgb(horizontal)}});
  }
  return 0;
}


int evaluateDaylight(const Scene& bundle, const QString& outDir, Progress& progress) {
  const Photo* main = bundle.findPhoto(bundle.mainPhoto);
  if (!main || main->hdr.empty())
    throw Error(bundle.sourceFile, "main_photo", "a daylight evaluation needs the main photo's linear (EXR) image");
  auto path = [&](const std::string& rel) { return rel.front() == '/' ? rel : bundle.baseDir + "/" + rel; };
  const auto dir = [&](const std::string& f) { return QDir(outDir).filePath(QString::fromStdString(f)).toStdString(); };
  const ImageRGB photo = readImageLinear(path(main->hdr));
  const dl::SkyRegions cells(64);
  const dl::SkyRadiance photoSky = averaged(dl::readRoomSky(bundle, bundle.photoSky), cells);
  // What a user does not have, the albedos, is never read: DaylightRelighting estimates them.
  Progress pre(progress, 0.0, 0.4);
  dl::DaylightRelighting relit(bundle, photo, main->camera, photoSky, {}, pre);
  writeImage(dir("photo.irradiance.exr"), relit.photoIrradiance());
  const dl::UnseenFit& fit = relit.unseenFit();
  QJsonArray reflectances;
  for (size_t s = 0; s < bundle.polygons.size(); ++s) {
    if (bundle.polygons[s].kind != PolygonKind::Real || relit.reflectances()[s].x < 0) continue;
    const bool seen = relit.estimated()[s];
    const glm::dvec3 r = relit.reflectances()[s], t = bundle.polygons[s].albedo;
    reflectances.append(QJsonObject{{"polygon", QString::fromStdString(bundle.polygons[s].name)},
                                    {"recovered", rgbJson(r)},
                                    {"estimated_from_photo", seen},
                                    {"truth", rgbJson(t)}});
    if (polygonArea(bundle.polygons[s].vertices) >= 1.0)
      std::fprintf(stderr, "  reflectance %-16s %.3f %.3f %.3f (truth %.3f %.3f %.3f)%s\n", bundle.polygons[s].name.c_str(), r.x, r.y,
                   r.z, t.x, t.y, t.z, seen                       ? ""
                   : fit.ok && r == fit.rho ? " not in the photo: measured (below)"
                                            : " not in the photo: its material's, or the seen polygons' mean");
  }
  if (fit.ok)
    std::fprintf(stderr,
                 "  unseen polygons: reflectance %.3f %.3f %.3f measured from %d shown polygons' sunlit and shaded pixels "
                 "(%ld / %ld; their light changes %.1f %% from one trial reflectance to the other)\n",
                 fit.rho.x, fit.rho.y, fit.rho.z, fit.polygons, fit.sunlitPixels, fit.shadedPixels, 100 * fit.sensitivity);
  else
    std::fprintf(stderr, "  unseen polygons: reflectance not measured (%s)\n", fit.why.c_str());
  const CompareMasks masks = benchmarkMasks(photo, readImageLinear(path("truth/unoccluded.exr")));
  QJsonArray variants;
  int done = 0;
  for (const auto& v : bundle.variants) {
    Progress stage(progress, 0.4 + 0.6 * done / double(bundle.variants.size()), 0.4 + 0.6 * (done + 1) / double(bundle.variants.size()));
    ++done;
    if (v.hdr.empty() || !QFileInfo::exists(QString::fromStdString(path(v.hdr)))) {
      std::fprintf(stderr, "%-18s no truth image: skipped\n", v.name.c_str());
      continue;
    }
    const ImageRGB truth = readImageLinear(path(v.hdr));
    if (truth.width != photo.width || truth.height != photo.height)
      throw Error(path(v.hdr), "variant " + v.name, "the truth image is " + std::to_string(truth.width) + "x" +
                                                     std::to_string(truth.height) + ", the main photo " + std::to_string(photo.width) +
                                                     "x" + std::to_string(photo.height));
    const dl::SkyRadiance sky = averaged(dl::readRoomSky(bundle, v.sky.empty() ? bundle.photoSky : v.sky), cells);
    const std::vector<Polygon> objects = dl::variantObjects(bundle, v, bundle.sourceFile);
    Progress a(stage, 0.0, 0.5), b(stage, 0.5, 0.9);
    const ImageRGB near = relit.render(sky, objects, dl::DaylightMethod::NearField, a);
    writeImage(dir(v.name + ".irradiance.exr"), relit.lastIrradiance());
    const ImageRGB distant = relit.render(sky, objects, dl::DaylightMethod::Distant, b);
    // The paper's interactive path (the irradiance volume and window samples; nothing solved again).
    Progress c(stage, 0.9, 1.0);
    const ImageRGB volume = relit.render(sky, objects, dl::DaylightMethod::Volume, c);
    writeImage(dir(v.name + ".near-field.exr"), near);
    writeImage(dir(v.name + ".distant.exr"), distant);
    writeImage(dir(v.name + ".volume.exr"), volume);
    writeImage(dir(v.name + ".png"), sideBySide({&photo, &distant, &volume, &near, &truth}));
    const CompareMasks change = benchmarkMasks(photo, truth);
    auto scores = [&](const ImageRGB& img) {
      const Comparison c1 = compareImages(img, truth, masks.all), c2 = compareImages(img, truth, change.shadow);
      return QJsonObject{{"psnr_all", c1.psnr}, {"psnr_change", c2.psnr}, {"gain_all", rgbJson(c1.gain)}, {"gain_change", rgbJson(c2.gain)}};
    };
    const QJsonObject n = scores(near), d = scores(distant), u = scores(photo), vol = scores(volume);
    const double changeFraction = double(std::count(change.shadow.begin(), change.shadow.end(), 1)) / double(change.shadow.size());
    variants.append(QJsonObject{{"name", QString::fromStdString(v.name)},
                                {"near_field", n},
                                {"distant", d},
                                {"volume", vol},
                                {"photo_unchanged", u},
                                {"change_mask_fraction", changeFraction}});
    std::fprintf(stderr,
                 "%-18s near-field %5.2f/%5.2f  volume %5.2f/%5.2f  distant %5.2f/%5.2f  photo %5.2f/%5.2f dB (all/change; change mask "
                 "%.1f %%)\n",
                 v.name.c_str(), n["psnr_all"].toDouble(), n["psnr_change"].toDouble(), vol["psnr_all"].toDouble(),
                 vol["psnr_change"].toDouble(), d["psnr_all"].toDouble(),
                 d["psnr_change"].toDouble(), u["psnr_all"].toDouble(), u["psnr_change"].toDouble(), 100 * changeFraction);
  }
  writeJsonAtomically(QString::fromStdString(dir("report.json")),
                      QJsonObject{{"bundle", QString::fromStdString(bundle.baseDir)},
                                  {"reflectances", reflectances},
                                  {"unseen_reflectance",
                                   fit.ok ? QJsonValue(QJsonObject{{"measured", rgbJson(fit.rho)},
                                                                   {"polygons_sunlit_and_shaded", fit.polygons},
                                                                   {"sunlit_pixels", qint64(fit.sunlitPixels)},
                                                                   {"shaded_pixels", qint64(fit.shadedPixels)},
                                                                   {"sensitivity", fit.sensitivity}})
                                          : QJsonValue(QString::fromStdString("not measured: " + fit.why))},
                                  {"variants", variants}});
  std::fprintf(stderr, "wrote %s\n", dir("report.json").c_str());
  return 0;
}

int daylightRelight(const Scene& room, const std::string& skyName, const std::vector<std::string>& objectFiles,
                    const std::vector<std::string>& lampFiles, const std::map<std::string, glm::dvec3>& lampScale, const std::string& method, const std::string& camera,
                    const std::string& out, Progress& progress, const std::string& lensFile) {
  if (method != "near-field" && method != "distant" && method != "volume")
    throw Error("", "--daylight", "must be near-field, volume or distant, not '" + method + "'");
  // Lamps switched on beside the daylight: S x the radiance the room gives the lamp (the photos
  // show them off, so they cannot tell it), every other lamp off.
  std::vector<glm::dvec3> lampExitance(room.lamps.size(), glm::dvec3(0.0));
  for (const auto& [name, scale] : lampScale) {
    const int l = lampNamed(room, name, scale, room.sourceFile);
    const glm::dvec3 radiance = room.lamps[size_t(l)].radiance;
    if (scale != glm::dvec3(0.0) && !(std::max({radiance.x, radiance.y, radiance.z}) > 0))
      throw Error(room.sourceFile, "lamp '" + name + "'",
                  "the room gives no radiance for it, and a daylight photo (lamps off) cannot tell it: give its radiance_rgb");
    lampExitance[size_t(l)] = std::numbers::pi * radiance * scale;
  }
  bool anyLamp = false;
  for (const auto& e : lampExitance) anyLamp = anyLamp || e != glm::dvec3(0.0);
  // Virtual lamps and objects, as the lamp path takes them: a file given with --virtual-lamp
  // or --virtual-object adds all it lists (a lamp's exitance is pi x its radiance, per face).
  // What the options ask of a file must be there and lit under daylight (given with both, it must
  // list both); what else it lists is taken item by item when it can be, and each item left out is
  // said. A file is read once, with everything asked of it.
  struct AskedFile {
    std::string path;
    bool lamps = false, objects = false;
  };
  std::vector<AskedFile> files;
  std::map<QString, size_t> fileIndex;
  auto ask = [&](const std::string& f, bool lamps) {
    const auto [it, fresh] = fileIndex.emplace(QFileInfo(QString::fromStdString(f)).absoluteFilePath(), files.size());
    if (fresh) files.push_back({f});
    (lamps ? files[it->second].lamps : files[it->second].objects) = true;
  };
  for (const auto& f : lampFiles) ask(f, true);
  for (const auto& f : objectFiles) ask(f, false);
  std::vector<dl::BasisLamp> virtualLamps, besideLamps;  // asked for; listed beside objects
  std::vector<std::string> besideLampFiles;
  std::vector<Polygon> objects;
  std::vector<ibr::ImageObject> imageObjects, besideImages;  // asked for; listed beside lamps
  std::vector<std::string> besideImageFiles;
  auto leftOut = [](const std::exception& e) { std::fprintf(stderr, "warning: left out: %s\n", e.what()); };
  for (const auto& file : files) {
    const std::string& f = file.path;
    const Variant v = readVariantFile(f);
    if (file.lamps && v.virtualLamps.empty()) throw Error(f, "virtual_lights", "lists no virtual lamp");
    if (file.objects && v.virtualObjects.empty()) throw Error(f, "virtual_objects", "lists no virtual object");
    if (file.lamps) {
      for (auto& l : dl::variantLamps(v, f)) virtualLamps.push_back(std::move(l));
    } else {
      for (size_t i = 0; i < v.virtualLamps.size(); ++i) {
        Variant one;
        one.virtualLamps = {v.virtualLamps[i]};
        if (one.virtualLamps[0].name.empty()) one.virtualLamps[0].name = "virtual_lamp_" + std::to_string(i);
        one.virtualLampPolygons = {v.virtualLampPolygons.at(i)};
        try {
          for (auto& l : dl::variantLamps(one, f)) {
            besideLamps.push_back(std::move(l));
            besideLampFiles.push_back(f);
          }
        } catch (const std::exception& e) {
          leftOut(e);
        }
      }
    }
    // Image-based objects (an entry with a fan) are drawn after the render, lit by the same sky.
    Variant polygonal = v;
    std::erase_if(polygonal.virtualObjects, [](const VirtualBox& b) { return !b.fan.empty(); });
    if (file.objects) {
      for (auto& o : dl::variantObjects(room, polygonal, f)) objects.push_back(std::move(o));
      ibr::appendImageObjects(v, f, imageObjects);
    } else {
      for (const auto& b : v.virtualObjects) {
        Variant one;
        one.virtualObjects = {b};
        try {
          if (b.fan.empty()) {
            for (auto& o : dl::variantObjects(room, one, f)) objects.push_back(std::move(o));
          } else {
            const size_t before = besideImages.size();
            ibr::appendImageObjects(one, f, besideImages);
            try {
              for (size_t i = before; i < besideImages.size(); ++i) ibr::checkImageObject(room, besideImages[i]);
            } catch (...) {
              besideImages.resize(before);
              throw;
            }
            besideImageFiles.resize(besideImages.size(), f);
          }
        } catch (const std::exception& e) {
          leftOut(e);
        }
      }
    }
  }
  // Lamps a file lists beside the objects asked for: lit by the near-field method only, and not
  // beside image-based objects (lit by daylight only).
  for (size_t i = 0; i < besideLamps.size(); ++i)
    if (!imageObjects.empty())
      leftOut(Error(besideLampFiles[i], "virtual lamp " + besideLamps[i].name,
                    "left out beside image-based objects, which are lit by daylight only"));
    else if (method == "near-field") virtualLamps.push_back(std::move(besideLamps[i]));
    else
      leftOut(Error(besideLampFiles[i], "virtual lamp " + besideLamps[i].name,
                    "virtual lamps under daylight take the near-field method (--daylight near-field)"));
  // Image-based objects a lamp file lists beside its lamps: drawn where they can be.
  for (size_t i = 0; i < besideImages.size(); ++i) {
    const std::string why = method == "distant" ? "the distant method lights boxes and meshes only: use --daylight volume or near-field"
                            : anyLamp || !virtualLamps.empty()
                                ? "under daylight image-based objects are lit by daylight only: switch the lamps off"
                                : "";
    if (why.empty()) imageObjects.push_back(std::move(besideImages[i]));
    else leftOut(Error(besideImageFiles[i], "image-based object '" + besideImages[i].name + "'", why));
  }
  if (anyLamp && method == "distant")
    throw Error("", "--lamp", "the distant method is the sky at infinity alone: no lamp with --daylight distant");
  if (anyLamp && method == "volume" && !objects.empty())
    throw Error("", "--lamp", "the volume method lights virtual objects by daylight only: with a lamp on, use near-field");
  if (!virtualLamps.empty() && method != "near-field")
    throw Error("", "--virtual-lamp", "virtual lamps under daylight take the near-field method (--daylight near-field)");
  for (const auto& o : imageObjects) ibr::checkImageObject(room, o);
  if (!imageObjects.empty()) {
    if (method == "distant")
      throw Error(imageObjects.front().fanFile, "image-based object '" + imageObjects.front().name + "'",
                  "the distant method lights boxes and meshes only: use --daylight volume or near-field");
    if (anyLamp || !virtualLamps.empty())
      throw Error(imageObjects.front().fanFile, "image-based object '" + imageObjects.front().name + "'",
                  "under daylight image-based objects are lit by daylight only: switch the lamps off");
  }
  const Photo* main = room.findPhoto(camera.empty() ? room.mainPhoto : camera);
  if (!main) throw Error(room.sourceFile, "--camera", "the room has no photo named '" + camera + "'");
  if (main->hdr.empty()) throw Error(room.sourceFile, "photo " + main->name, "daylight relighting needs its linear (EXR) image");
  const std::string hdr = main->hdr.front() == '/' ? main->hdr : room.baseDir + "/" + main->hdr;
  // The sky: one of the room's measured skies by name, an HDR fisheye file (looking up, image up
  // +Y), or a folder of them — a time-varying sky, played back one frame per image. Every sky is
  // read and checked before anything is solved or written.
  const dl::SkyRegions cells(64);
  const QFileInfo skyInfo(QString::fromStdString(skyName));
  struct Frame {
    std::string file, stem;
    dl::SkyRadiance sky;
  };
  std::vector<Frame> frames;
  if (!lensFile.empty() && !skyInfo.isDir() && !isRadianceFile(skyName))
    throw Error(lensFile, "--lens", "is the lens of a fisheye file or folder given as --sky; the room's own skies (here '" +
                                        skyName + "') name theirs in its daylight section");
  const FisheyeLens lens = lensFile.empty() ? FisheyeLens{} : readFisheyeLens(lensFile);
  auto fisheye = [&](const std::string& file) { return averaged(dl::readFisheyeLookingUp(file, lens), cells); };
  if (skyInfo.isDir()) {
    const QStringList names = QDir(skyInfo.filePath()).entryList({"*.exr", "*.EXR", "*.hdr", "*.HDR"}, QDir::Files, QDir::Name);
    if (names.isEmpty()) throw Error(skyName, "--sky", "the folder holds no HDR sky image (.exr or .hdr)");
    for (const QString& n : names) {
      const std::string file = QDir(skyInfo.filePath()).filePath(n).toStdString();
      frames.push_back({file, QFileInfo(n).completeBaseName().toStdString(), fisheye(file)});
    }
    // Two images with one name (a.exr, a.hdr) would write one frame over the other.
    for (size_t i = 0; i < frames.size(); ++i)
      for (size_t j = 0; j < i; ++j)
        if (frames[i].stem == frames[j].stem)
          throw Error(frames[i].file, "--sky", "has the same name as " + frames[j].file + ": the frames would overwrite each other");
    const QFileInfo outInfo(QString::fromStdString(out));
    if (outInfo.exists() && !outInfo.isDir())
      throw Error(out, "-o", "with a folder of skies the output is a folder (one image per sky), and this is a file");
    // An earlier run's frames are replaced; a folder holding anything else is never touched.
    if (outInfo.isDir() && !isFramesFolder(outInfo.absoluteFilePath()))
      throw Error(out, "-o", "the folder exists and holds other files: give a new or empty folder (or an earlier run's frames)");
  } else {
    frames.push_back({skyName, "", isRadianceFile(skyName) ? fisheye(skyName) : averaged(dl::readRoomSky(room, skyName), cells)});
  }
  const dl::DaylightMethod how = method == "distant" ? dl::DaylightMethod::Distant
                                 : method == "volume" ? dl::DaylightMethod::Volume
                                                      : dl::DaylightMethod::NearField;
  const ImageRGB photo = readImageLinear(hdr);
  Progress pre(progress, 0.0, 0.7);
  std::string opened;
  const auto session = dl::openDaylightRelighting(room, photo, main->camera, averaged(dl::readRoomSky(room, room.photoSky), cells),
                                                  {}, pre, &opened);
  if (!opened.empty()) std::fprintf(stderr, "%s\n", opened.c_str());
  dl::DaylightRelighting& relit = *session;
  for (size_t l = 0; l < lampExitance.size(); ++l) relit.setLampExitance(int(l), lampExitance[l]);
  // The room and its boxes and meshes, then the image-based objects under the same sky.
  auto renderSky = [&](const dl::SkyRadiance& sky, Progress& draw) {
    ImageRGB img = relit.render(sky, objects, how, draw, virtualLamps);
    const auto stats = ibr::drawImageObjectsInDaylight(relit, sky, imageObjects, img, nullptr, silentProgress(), objects);
    for (size_t i = 0; i < stats.size(); ++i)
      std::fprintf(stderr, "image-based object '%s': fan view %d, %zu pixels, shadows on %zu pixels\n",
                   imageObjects[i].name.c_str(), stats[i].view, stats[i].objectPixels, stats[i].shadowPixels);
    return img;
  };
  if (!skyInfo.isDir()) {
    Progress draw(progress, 0.7, 1.0);
    writeImage(out, renderSky(frames.front().sky, draw));
    std::fprintf(stderr, "wrote %s\n", out.c_str());
    return 0;
  }
  // Playback: the frames into a folder made beside the output and renamed into place at the end,
  // so that an interrupted run leaves no half sequence (and an earlier one stays whole).
  const QString outDir = QDir::cleanPath(QFileInfo(QString::fromStdString(out)).absoluteFilePath());
  const QString partial = outDir + ".partial", old = outDir + ".old";
  QDir(partial).removeRecursively();
  if (!QDir().mkpath(partial)) throw Error(partial.toStdString(), "-o", "cannot create the folder");
  QJsonArray list;
  std::vector<double> times;
  for (size_t i = 0; i < frames.size(); ++i) {
    Progress draw(progress, 0.7 + 0.3 * double(i) / double(frames.size()), 0.7 + 0.3 * double(i + 1) / double(frames.size()));
    const auto t0 = std::chrono::steady_clock::now();
    const ImageRGB img = renderSky(frames[i].sky, draw);
    const double ms = 1000.0 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    times.push_back(ms);
    for (const char* ext : {".exr", ".png"}) writeImage(QDir(partial).filePath(QString::fromStdString(frames[i].stem + ext)).toStdString(), img);
    const dl::Sun& sun = frames[i].sky.sun;
    const double elev = sun.found ? std::asin(std::clamp(sun.direction.z, -1.0, 1.0)) * 180 / std::numbers::pi : 0;
    std::fprintf(stderr, "frame %zu/%zu %s: %s, rendered in %.0f ms\n", i + 1, frames.size(), frames[i].stem.c_str(),
                 sun.found ? ("sun " + std::to_string(int(std::lround(elev))) + " deg up").c_str() : "no sun", ms);
    QJsonObject f{{"sky", QString::fromStdString(frames[i].file)},
                  {"image", QString::fromStdString(frames[i].stem + ".png")},
                  {"linear", QString::fromStdString(frames[i].stem + ".exr")},
                  {"render_ms", ms}};
    if (sun.found) f["sun_direction"] = rgbJson(sun.direction);
    list.append(f);
  }
  std::vector<double> sorted = times;
  std::sort(sorted.begin(), sorted.end());
  writeJsonAtomically(QDir(partial).filePath("frames.json"),
                      QJsonObject{{"method", QString::fromStdString(method)},
                                  {"frames", list},
                                  {"render_ms_median", sorted[sorted.size() / 2]}});
  // The earlier run's frames step aside, the new ones move in, then the old go.
  QDir(old).removeRecursively();
  const bool hadEarlier = QFileInfo(outDir).isDir();
  if (hadEarlier && !QDir().rename(outDir, old))
    throw Error(out, "-o", "cannot move the earlier frames aside; the new ones are in " + partial.toStdString());
  if (!QDir().rename(partial, outDir)) {
    if (hadEarlier) QDir().rename(old, outDir);
    throw Error(out, "-o", "cannot move the finished frames into place; they are in " + partial.toStdString());
  }
  QDir(old).removeRecursively();
  std::fprintf(stderr, "wrote %zu frames to %s (median %.0f ms a frame)\n", frames.size(), out.c_str(), sorted[sorted.size() / 2]);
  return 0;
}

QJsonObject daylightBench(const Scene& scene, int runs, Progress& progress) {
  auto ms = [](std::chrono::steady_clock::time_point t0) {
    return 1000.0 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
  };
  const dl::SkyRegions cells(64);
  const dl::SkyImage photoImage = dl::readRoomSky(scene, scene.photoSky);
  std::vector<double> averaging;
  dl::SkyRadiance photoSky;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    photoSky = averaged(photoImage, cells);
    averaging.push_back(ms(t0));
  }
  // The basis (64 regions and the ground), once: it takes seconds.
  progress.report(0.0, "bench: 64 daylight basis solutions");
  auto t0 = std::chrono::steady_clock::now();
  dl::DaylightBasis basis(scene, photoSky, {}, progress);
  const double basisSeconds = ms(t0) / 1000;
  // Another sky: its sun solved once, then the combination (Eq. 3) alone, repeated.
  const SkyCapture* other = nullptr;
  for (const auto& c : scene.skies)
    if (!other && c.name != scene.photoSky) other = &c;
  const dl::SkyRadiance sky = other ? averaged(dl::readRoomSky(scene, other->name), cells) : photoSky;
  t0 = std::chrono::steady_clock::now();
  if (sky.sun.found) basis.sunSolution(sky.sun.direction);
  const double newSunSeconds = ms(t0) / 1000;
  std::vector<double> combine;
  for (int r = 0; r < std::max(runs, 5); ++r) {
    t0 = std::chrono::steady_clock::now();
    const auto b = basis.combine(sky);
    combine.push_back(ms(t0));
  }
  // The relit main photo under that sky (irradiance per pixel, direct sun by rays; differential).
  QJsonObject relit;
  if (const Photo* main = scene.findPhoto(scene.mainPhoto); main && !main->hdr.empty()) {
    const ImageRGB photo = readImageLinear(main->hdr.front() == '/' ? main->hdr : scene.baseDir + "/" + main->hdr);
    const dl::SeenPixels seen = dl::seePixels(basis, main->camera);
    const ImageRGB ePhoto = dl::irradianceImage(basis, seen, photoSky);
    std::vector<double> frame;
    for (int r = 0; r < runs; ++r) {
      t0 = std::chrono::steady_clock::now();
      const ImageRGB e = dl::irradianceImage(basis, seen, sky);
      const ImageRGB img = dl::differentialRender(photo, ePhoto, e, seen, int(basis.engine().surfaces().size()), {});
      frame.push_back(ms(t0));
    }
    // A 40 cm box added to the live hierarchy, every basis solved again, and taken out.
    std::vector<Polygon> faces;
    glm::dvec3 lo(1e300), hi(-1e300);
    for (const auto& p : scene.polygons)
      if (p.kind == PolygonKind::Real && polygonNormal(p.vertices).z > 0.9 && !basis.engine().isRemoved(int(&p - scene.polygons.data())))
        for (const auto& v : p.vertices) lo = glm::min(lo, v), hi = glm::max(hi, v);
    const glm::dvec3 c = 0.5 * (lo + hi);
    Variant v;
    VirtualBox box;
    box.name = "box";
    box.boxMin = {c.x - 0.2, c.y - 0.2, lo.z};
    box.boxMax = {c.x + 0.2, c.y + 0.2, lo.z + 0.4};
    box.albedo = glm::dvec3(0.5);
    v.virtualObjects.push_back(box);
    faces = dl::variantObjects(scene, v, scene.sourceFile);
    t0 = std::chrono::steady_clock::now();
    const auto ids = basis.addObjects(faces);
    const double add = ms(t0) / 1000;
    // Taken out by putting the saved hierarchy and solutions back; against (same run) taking the
    // surfaces out of the hierarchy and solving every basis again, which removing them in another
    // order than added does.
    t0 = std::chrono::steady_clock::now();
    basis.removeObjects(ids);
    const double removed = ms(t0) / 1000;
    const auto again = basis.addObjects(faces);
    t0 = std::chrono::steady_clock::now();
    basis.removeObjects(std::vector<int>(again.rbegin(), again.rend()));
    const double removedSolving = ms(t0) / 1000;
    std::fprintf(stderr, "bench: a box added to the near-field bases in %.2f s, taken out in %.3f s (by removing and solving "
                 "again: %.2f s)\n", add, removed, removedSolving);
    relit = QJsonObject{{"width", photo.width},
                        {"height", photo.height},
                        {"median_ms", median(frame)},
                        {"object_added_seconds", add},
                        {"object_removed_seconds", removed},
                        {"object_removed_by_solving_again_seconds", removedSolving}};
    // The interactive path (Grosch et al. §6.3, §7): the same box moved under the sky, lit by the
    // irradiance volume and the window samples, nothing solved again; the session's own
    // reflectance estimate first (three rounds of bases), its volume built on the first frame.
    progress.report(0.8, "bench: a box moved under daylight (irradiance volume)");
    dl::DaylightRelighting session(scene, photo, main->camera, photoSky);
    t0 = std::chrono::steady_clock::now();
    session.volume();
    const double volumeSeconds = ms(t0) / 1000;
    std::vector<double> volumeCombine, moved;
    for (int r = 0; r < std::max(runs, 5); ++r) {
      t0 = std::chrono::steady_clock::now();
      session.volume().combine(session.basis(), sky);
      volumeCombine.push_back(ms(t0));
    }
    auto t1 = std::chrono::steady_clock::now();
    session.render(sky, faces, dl::DaylightMethod::Volume);  // the room under this sky, once; the per-pixel caches cold
    const double firstMs = ms(t1);
    for (int r = 0; r < std::max(runs, 5); ++r) {
      std::vector<Polygon> shifted = faces;
      for (auto& f : shifted)
        for (auto& q : f.vertices) q.x += 0.05 * (r % 2 ? 1 : -1);
      t0 = std::chrono::steady_clock::now();
      session.render(sky, shifted, dl::DaylightMethod::Volume);
      moved.push_back(ms(t0));
    }
    relit["volume"] = QJsonObject{{"grid", session.volume().resolution()},
                                  {"build_seconds", volumeSeconds},
                                  {"combination_median_ms", median(volumeCombine)},
                                  {"object_first_ms", firstMs},
                                  {"object_moved_median_ms", median(moved)},
                                  {"pixels_touched", double(session.lastTouchedPixels())},
                                  {"direct_samples", session.interactive().directSamples}};
  }
  // A lamp beside the daylight (last: its refinement adds elements): its solution, solved once,
  // and the combination with it on.
  QJsonObject lamp;
  if (basis.lampCount() > 0) {
    progress.report(0.95, "bench: a lamp beside the daylight");
    t0 = std::chrono::steady_clock::now();
    basis.lampSolution(0);
    const double lampSeconds = ms(t0) / 1000;
    basis.setLampExitance(0, glm::dvec3(100.0));
    std::vector<double> withLamp;
    for (int r = 0; r < std::max(runs, 5); ++r) {
      t0 = std::chrono::steady_clock::now();
      const auto b = basis.combine(sky);
      withLamp.push_back(ms(t0));
    }
    basis.setLampExitance(0, glm::dvec3(0.0));
    lamp = QJsonObject{{"lamp", QString::fromStdString(scene.lamps.front().name)},
                       {"solution_seconds", lampSeconds},
                       {"combination_with_lamp_median_ms", median(withLamp)}};
  }
  const auto& eng = basis.engine();
  return QJsonObject{{"regions", cells.size()},
                     {"lamp_beside_daylight", lamp},
                     {"elements", double(eng.nodes().size())},
                     {"links", double(eng.links().size())},
                     {"basis_seconds", basisSeconds},
                     {"refine_seconds", basis.refineSeconds()},
                     {"seconds_per_basis", basis.secondsPerBasis()},
                     {"sky_averaging_median_ms", median(averaging)},
                     {"new_sun_seconds", newSunSeconds},
                     {"combination_median_ms", median(combine)},
                     {"relit_image", relit}};
}

}  // namespace relume::cli
