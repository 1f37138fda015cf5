// relume ibr-fan: the image fan of a mesh (Dinh, Metoyer, Turk), for image-based virtual objects.
// The image-based object figures of relume bench.
#include <QCommandLineParser>
#include <QJsonArray>
#include <QJsonObject>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <numbers>
#include <vector>

#include "commands.h"
#include "relume/geometry/error.h"
#include "relume/geometry/polygon.h"
#include "relume/ibr/fan.h"
#include "relume/ibr/ibr_object.h"
#include "relume/ibr/normal_code.h"
#include "relume/ibr/relit_objects.h"
#include "relume/raytrace/ray_scene.h"
#include "relume/relight/relighter.h"

namespace relume::cli {

namespace {
int intOption(const QCommandLineParser& p, const char* name, int fallback) {
  if (!p.isSet(name)) return fallback;
  bool ok = false;
  const int v = p.value(name).toInt(&ok);
  if (!ok) throw Error("", std::string("--") + name, "expected a whole number, got '" + p.value(name).toStdString() + "'");
  return v;
}
}  // namespace

int ibrFanCommand(const QStringList& args, Progress& progress) {
  QCommandLineParser p;
  p.setApplicationDescription(
      "Render a mesh's image fan: rings of orthographic views around it, per pixel coverage, normal code (225 "
      "codes, dithered), depth and albedo, for an image-based virtual object (relume relight --virtual-object).");
  p.addPositionalArgument("MESH", "The mesh (.obj with its .mtl colours, .ply, or glTF 2 .gltf/.glb), metres, +Z up unless "
                                 "--up y (glTF is turned from its +Y up by itself).");
  p.addOption({{"o", "output"}, "The fan file to write (.fan).", "FAN"});
  p.addOption({"views", "Views per ring (default 96).", "N"});
  p.addOption({"size", "Pixels across a view (default 256).", "PX"});
  p.addOption({"rings", "Ring elevations in degrees (default 15,45,75).", "E1,E2,..."});
  p.addOption({"no-dither", "Code each normal to its nearest code (shows the banding dithering removes)."});
  p.addOption({"up", "The mesh's up axis: z (default) or y.", "AXIS"});
  parseOrThrow(p, args, 1, "relume ibr-fan MESH -o FAN [--views 96] [--size 256] [--rings 15,45,75] [--no-dither] [--up y]");
  if (!p.isSet("output")) throw Error("", "command line", "-o FAN is required");
  ibr::FanOptions o;
  o.viewsPerRing = intOption(p, "views", o.viewsPerRing);
  o.size = intOption(p, "size", o.size);
  if (p.isSet("rings")) {
    o.ringElevations.clear();
    for (const QString& s : p.value("rings").split(',')) {
      bool ok = false;
      const double e = s.toDouble(&ok);
      if (!ok) throw Error("", "--rings", "expected degrees separated by commas, got '" + p.value("rings").toStdString() + "'");
      o.ringElevations.push_back(e);
    }
  }
  o.dither = !p.isSet("no-dither");
  if (p.isSet("up")) {
    if (p.value("up") == "y") o.yUp = true;
    else if (p.value("up") != "z") throw Error("", "--up", "must be z or y");
  }
  const std::string mesh = p.positionalArguments()[0].toStdString(), out = p.value("output").toStdString();
  const auto t0 = std::chrono::steady_clock::now();
  progress.report(0, "reading " + mesh);
  const ibr::Mesh m = ibr::readMesh(mesh);
  const auto fan = ibr::buildFan(m, o, progress);
  ibr::writeFan(*fan, out);
  std::fprintf(stderr, "%zu triangles: %d views of %d x %d in %.1f s (radius %.3f m); wrote %s\n", m.triangles.size(),
               fan->viewCount(), fan->size, fan->size, seconds(t0), fan->radius, out.c_str());
  return 0;
}

}  // namespace relume::cli

// ---- relume bench: the image-based object figures ----

namespace relume::cli {

namespace {

double medianMs(std::vector<double> v) { return median(std::move(v)) * 1000.0; }

}  // namespace

QJsonObject ibrBench(const Scene& sceneIn, int runs, Progress& progress) {
  QJsonObject out;
  // A fan of a mesh of a million triangles, at the defaults (three rings of 96 views, 256 x 256).
  {
    progress.report(0.0, "bench: a 1M-triangle mesh's image fan");
    const ibr::Mesh big = ibr::bumpyBall(1000, 500, 0.25, 0.08);
    const auto t0 = std::chrono::steady_clock::now();
    const auto fan = ibr::buildFan(big, ibr::FanOptions{}, progress);
    const size_t bytes = ibr::fanBytes(*fan).size();
    out["fan"] = QJsonObject{{"triangles", qint64(big.triangles.size())}, {"views", fan->viewCount()},
                             {"size", fan->size}, {"seconds", seconds(t0)}, {"file_bytes", qint64(bytes)}};
  }
  // Banding on a smooth sphere (the normal image of a sphere filling the view, coded plain and
  // dithered), at growing sizes: a band of plain coding is a cell of the 17 x 17 grid wide; a
  // dithered run is longest at the rim, where the normals lie beyond the outermost codes.
  {
    QJsonArray banding;
    for (int w : {256, 512, 1024, 2048}) {
      std::vector<glm::vec2> xy(size_t(w) * size_t(w), glm::vec2(0.f));
      std::vector<uint8_t> mask(xy.size(), 0), plain(xy.size()), dithered(xy.size());
      for (int y = 0; y < w; ++y)
        for (int x = 0; x < w; ++x) {
          const float a = (x + 0.5f) / float(w) * 2 - 1, b = 1 - (y + 0.5f) / float(w) * 2;
          if (a * a + b * b >= 0.98f) continue;
          xy[size_t(y) * size_t(w) + size_t(x)] = glm::vec2(a, b);
          mask[size_t(y) * size_t(w) + size_t(x)] = 1;
        }
      ibr::encodeNormalImage(xy, mask, w, w, false, plain);
      ibr::encodeNormalImage(xy, mask, w, w, true, dithered);
      const int p = ibr::longestCodeRun(plain, w, w), d = ibr::longestCodeRun(dithered, w, w);
      const int pm = ibr::longestCodeRun(plain, w, w, w / 2), dm = ibr::longestCodeRun(dithered, w, w, w / 2);
      banding.append(QJsonObject{{"sphere_pixels", w},
                                 {"longest_run_plain", p},
                                 {"longest_run_dithered", d},
                                 {"ratio", double(p) / double(std::max(d, 1))},
                                 {"middle_row_plain", pm},
                                 {"middle_row_dithered", dm}});
      std::fprintf(stderr, "banding, sphere %d px across: longest run plain %d, dithered %d (middle row %d, %d)\n", w, p, d, pm, dm);
    }
    out["banding"] = banding;
  }
  // One object in the relit room, seen through the main photo's camera at 640 x 480.
  Scene scene = sceneIn;
  progress.report(0.5, "bench: preprocessing the room for the image-based object");
  const RelightData data = preprocessRoom(scene, RelightOptions{});
  RelightSession session(scene, data);
  session.update();
  session.syncEngine();
  const Photo* photo = scene.findPhoto(data.photo);
  const Camera cam = resized(photo->camera, 640, 480);
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const auto& p : scene.polygons)
    for (const auto& v : p.vertices) {
      lo = glm::min(lo, v);
      hi = glm::max(hi, v);
    }
  ibr::ImageObject object;
  object.name = "bench ball";
  object.fanFile = "(bench)";
  object.fan = ibr::buildFan(ibr::bumpyBall(200, 100, 0.25, 0.08), ibr::FanOptions{}, progress);
  const auto& h = session.engine();
  // Where a designer would put it: on the floor in the open (not cutting the room, seen by the
  // camera), lit by as many lamps as any floor point on a 10 cm grid (the lines from its top to
  // the lamps' centres unblocked), the one nearest the room's middle among those — so that its
  // shadows fall where the photo shows them rather than under a table.
  {
    const glm::dvec3 middle(0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), lo.z);
    const double top = object.place.scale * (object.fan->boundsMax.z - object.fan->boundsMin.z);
    int bestLit = -1;
    std::string lastReason = "no floor point seen by the camera";
    double bestDist = 1e300;
    for (double y = lo.y + 0.05; y < hi.y; y += 0.1)
      for (double x = lo.x + 0.05; x < hi.x; x += 0.1) {
        ibr::ImageObject o = object;
        o.place.position = glm::dvec3(x, y, lo.z);
        glm::dvec2 pix;
        const glm::dvec3 c = o.place.toWorld(*o.fan, o.fan->centre);
        if (!cam.project(c, pix) || pix.x < 0 || pix.y < 0 || pix.x >= cam.width || pix.y >= cam.height ||
            h.rayScene().occluded(glm::vec3(cam.center()), glm::vec3(c)))
          continue;
        try {
          ibr::checkImageObject(scene, o);
        } catch (const Error& e) {
          lastReason = e.what();
          continue;
        }
        int lit = 0;
        for (const auto& lamp : scene.lamps) {
          const glm::dvec3 centre = polygonCentroid(scene.polygons[size_t(lamp.polygon)].vertices);
          lit += h.rayScene().occluded(glm::vec3(x, y, lo.z + 1.01 * top), glm::vec3(centre)) ? 0 : 1;
        }
        const double d = glm::length(o.place.position - middle);
        if (lit > bestLit || (lit == bestLit && d < bestDist)) {
          bestLit = lit;
          bestDist = d;
          object.place.position = o.place.position;
        }
      }
    if (bestLit < 0) {
      out["object"] = QString::fromStdString("not placed: no floor point in the open seen by the camera (" + lastReason + ")");
      return out;
    }
  }
  const glm::dvec3 centre = object.place.toWorld(*object.fan, object.fan->centre);
  std::vector<double> lighting, tables, roomViews, composite, shadows, drawing;
  const ImageRGB relit = session.render(cam, RelightMethod::Full);
  const ibr::IrradianceAt irradiance = [&](int surface, const glm::dvec3& p) {
    return glm::dvec3(h.irradiance(h.findLeaf(surface, h.toUV(surface, p))));
  };
  size_t pixels = 0, shadowPixels = 0;
  for (int r = 0; r < std::max(runs, 5); ++r) {
    progress.report(0.8 + 0.2 * r / std::max(runs, 5), "bench: image-based object, run " + std::to_string(r + 1));
    auto t0 = std::chrono::steady_clock::now();
    const ibr::ObjectLighting light = ibr::lightingAt(h, centre);
    lighting.push_back(seconds(t0));
    // A new lamp setting: every lamp's tables and the indirect table for the drawn view.
    const int view = object.fan->nearestView(glm::normalize(cam.center() - centre));
    t0 = std::chrono::steady_clock::now();
    for (const auto& lamp : light.lamps) (void)ibr::lampTables(*object.fan, view, object.place, lamp);
    (void)ibr::indirectTable(*object.fan, view, object.place, light.indirect);
    tables.push_back(seconds(t0));
    t0 = std::chrono::steady_clock::now();
    const ibr::RoomView room = ibr::roomView(h, cam);
    roomViews.push_back(seconds(t0));
    ImageRGB img = relit;
    t0 = std::chrono::steady_clock::now();
    shadowPixels = ibr::drawShadows(*object.fan, object.place, light, h, cam, room, irradiance, img).shadowPixels;
    shadows.push_back(seconds(t0));
    const auto t1 = std::chrono::steady_clock::now();
    pixels = ibr::drawObject(*object.fan, object.place, light, cam, room, img).objectPixels;
    drawing.push_back(seconds(t1));
    composite.push_back(seconds(t0));
  }
  out["object"] = QJsonObject{{"lamps", qint64(scene.lamps.size())},
                              {"position", QJsonArray{object.place.position.x, object.place.position.y, object.place.position.z}},
                              {"object_pixels", qint64(pixels)},
                              {"shadow_pixels", qint64(shadowPixels)},
                              {"image", "640x480"},
                              {"lighting_median_ms", medianMs(lighting)},
                              {"tables_update_median_ms", medianMs(tables)},
                              {"room_view_median_ms", medianMs(roomViews)},
                              {"composite_median_ms", medianMs(composite)},
                              {"shadows_median_ms", medianMs(shadows)},
                              {"object_median_ms", medianMs(drawing)}};
  return out;
}

}  // namespace relume::cli
