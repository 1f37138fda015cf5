// relume sky: what a measured sky holds (its regions, its sun), as the daylight basis will use it.
#include <QCommandLineParser>
#include <QJsonArray>
#include <QJsonObject>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "commands.h"
#include "relume/daylight/sky.h"
#include "relume/geometry/error.h"
#include "relume/geometry/scene.h"
#include "relume/image/image.h"

namespace relume::cli {

namespace dl = relume::daylight;

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
  p.addOption({"circle", "The image circle as CX,CY,R in pixels (default: centred, filling the image).", "CX,CY,R"});
  p.addOption({"regions", "Number of sky regions (default 64).", "N"});
  p.addOption({"json", "Also write the regions, the sun and the irradiances as JSON.", "OUT.json"});
  p.addOption({"sky", "With a daylight ROOM: which of its skies (default: the one its photos were taken under).", "NAME"});
  parseOrThrow(p, args, 1, "relume sky FISHEYE.exr|PANORAMA.exr|ROOM [--sky NAME] [--panorama] [--projection equidistant|equisolid|equirectangular] [--fov 180] [--regions 64]");
  std::string file = p.positionalArguments()[0].toStdString();
  std::string description;  // the lens in words, when a room's daylight section gives it
  if (!isRadianceFile(file)) {
    const Scene room = openRoom(p.positionalArguments()[0]);
    if (room.skies.empty()) throw Error(room.sourceFile, "daylight", "the room lists no measured sky");
    const std::string want = p.isSet("sky") ? p.value("sky").toStdString() : room.photoSky.empty() ? room.skies.front().name : room.photoSky;
    const SkyCapture* cap = room.findSky(want);
    if (!cap) throw Error(room.sourceFile, "--sky", "the room has no sky named '" + want + "'");
    file = room.baseDir + "/" + cap->fisheye;
    description = cap->fisheyeModel;
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
  dl::FisheyeModel model =
      proj == "equirectangular" ? dl::equirectangular(w, h)
      : description.empty()
          ? dl::fisheyeLookingUp(w, h, proj == "equisolid" ? dl::FisheyeProjection::Equisolid : dl::FisheyeProjection::Equidistant, fov)
          : dl::fisheyeFromDescription(description, w, h, file);
  if (p.isSet("circle") && proj == "equirectangular") throw Error("", "--circle", "a panorama has no image circle");
  if (p.isSet("circle")) {
    const QStringList c = p.value("circle").split(',');
    bool a = false, b = false, r = false;
    if (c.size() != 3) throw Error("", "--circle", "must be CX,CY,R (pixels)");
    model.centre = {c[0].toDouble(&a), c[1].toDouble(&b)};
    model.radius = c[2].toDouble(&r);
    if (!a || !b || !r) throw Error("", "--circle", "must be CX,CY,R (pixels)");
  }
  progress.report(0, "reading " + file);
  const dl::SkyImage sky = dl::readSkyImage(file, model);
  progress.report(0.3, "averaging the sky over " + std::to_string(regions) + " regions");
  const dl::SkyRegions cells(regions);
  const dl::SkyRadiance avg = dl::averageSky(sky, cells);
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

}  // namespace relume::cli
