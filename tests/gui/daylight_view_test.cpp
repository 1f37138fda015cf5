// The daylight viewport's renderer (GlDaylightRenderer, Mesa under Xvfb) against the library's CPU
// path for the same method (DaylightRelighting::render with DaylightMethod::Volume): the same
// room, sky, box and camera must give the same picture — the box where it is, lit alike, and its
// shadows where the CPU path puts them, and nothing where it puts none.
#include <QGuiApplication>
#include <QOffscreenSurface>
#include <QOpenGLContext>
#include <QSurfaceFormat>
#include <QtTest>
#include <cmath>
#include <numbers>

#include "../daylight/window_room.h"
#include "relume/daylight/relight.h"
#include "relume/geometry/error.h"
#include "relume/ibr/fan.h"
#include "relume/ibr/mesh.h"
#include "relume/ibr/relit_objects.h"
#include "relume/radiosity/hierarchy.h"
#include "relume/raytrace/ray_scene.h"
#include "relume/relight/relighter.h"
#include "relume/viewport/gl_daylight.h"

using namespace relume;
using namespace relume::daylight;
using namespace relume::testing;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kElev = 30 * kPi / 180;

double luminance(const ImageRGB& im, size_t i) {
  return 0.2126 * im.pixels[3 * i] + 0.7152 * im.pixels[3 * i + 1] + 0.0722 * im.pixels[3 * i + 2];
}

// Where the sun's patch falls on the floor (its middle), the sun through the window and a sky of
// 16 regions, the camera looking at the patch, and a session on a coarse hierarchy (both renderers
// read the same session, and it is solved several times over).
const double kPatchX = W - 0.5 * (Z0 + Z1) / std::tan(kElev), kPatchY = 0.5 * (Y0 + Y1);

SkyRadiance testSky() {
  SkyRadiance sky;
  sky.region.resize(16);
  for (size_t k = 0; k < sky.region.size(); ++k) sky.region[k] = glm::dvec3(0.3 + 0.05 * double(k % 4), 0.35, 0.45);
  sky.sun.found = true;
  sky.sun.direction = glm::dvec3(std::cos(kElev), 0.0, std::sin(kElev));
  sky.sun.irradiance = glm::dvec3(2.0, 1.9, 1.7);
  return sky;
}

Camera testCamera() { return Camera::lookAt({0.4, 0.6, 2.3}, {kPatchX, kPatchY, 0.0}, 320, 240, 220); }

std::unique_ptr<DaylightRelighting> testSession(const Scene& room, const SkyRadiance& sky) {
  const Camera cam = testCamera();
  ImageRGB photo(cam.width, cam.height);
  for (auto& v : photo.pixels) v = 0.25f;
  BasisOptions options;
  options.regions = 16;
  options.groundReflectance = 0;
  auto engine = std::make_shared<radiosity::Options>();
  engine->epsilon = 0.03;
  engine->minArea = 0.02;
  options.engine = engine;
  auto relit = std::make_unique<DaylightRelighting>(room, photo, cam, sky, options);
  relit->setInteractive({{6, 512}, 64});
  return relit;
}

}  // namespace

class DaylightViewTest : public QObject {
  Q_OBJECT
  QOffscreenSurface surface_;
  QOpenGLContext context_;

 private slots:
  void initTestCase() {
    QSurfaceFormat f;
    f.setVersion(3, 3);
    f.setProfile(QSurfaceFormat::CoreProfile);
    context_.setFormat(f);
    QVERIFY(context_.create());
    surface_.setFormat(context_.format());
    surface_.create();
    QVERIFY(context_.makeCurrent(&surface_));
  }

  void theViewDrawsTheBoxAndItsShadowsAsTheLibrarysInteractivePathDoes() { compareWithTheCpuPath(false); }
  // A 4 cm post in the box's sun shadow casts its own: where the room already shadows the floor,
  // the box takes nothing more away (only new shadows), as on the CPU path.
  void whereTheRoomAlreadyShadowsTheFloorTheBoxTakesNothingMore() { compareWithTheCpuPath(true); }
  // An image-based object (Dinh, Metoyer, Turk) in the sun's patch: the view draws it and its
  // shadows as the CPU path does (ibr::drawImageObjectsInDaylight): its pixels lit alike by the
  // sun, the window samples and the irradiance volume, its shadows from the same silhouettes.
  void theViewDrawsAnImageBasedObjectAndItsShadowsAsTheCpuPathDoes() { compareImageObject(false); }
  // The same across the patch's edge: its points see the sun or not, each on its own (the CPU
  // path asks five rays towards the sun's disc, the view its four maps: they differ along the edge).
  void anImageBasedObjectAcrossTheSunsEdgeIsLitPointByPoint() { compareImageObject(true); }

 private:
  void compareImageObject(bool acrossTheEdge);
  void compareWithTheCpuPath(bool post) {
    // The sun through the window and a sky of 16 regions; a box where the sun's patch falls.
    Scene room = windowRoom(0.5, 0.6, 0.7);
    const double xc = kPatchX, yc = kPatchY, h = 0.2;
    if (post) {
      const double x0 = xc - 0.55, y0 = yc - 0.02, s = 0.04, z = 0.7;
      room.polygons.push_back(poly("post_px", facingPlusX(x0 + s, y0, y0 + s, 0, z), 0.5));
      room.polygons.push_back(poly("post_mx", facingMinusX(x0, y0, y0 + s, 0, z), 0.5));
      room.polygons.push_back(poly("post_py", {{x0, y0 + s, 0}, {x0 + s, y0 + s, 0}, {x0 + s, y0 + s, z}, {x0, y0 + s, z}}, 0.5));
      room.polygons.push_back(poly("post_my", {{x0 + s, y0, 0}, {x0, y0, 0}, {x0, y0, z}, {x0 + s, y0, z}}, 0.5));
      room.polygons.push_back(poly("post_top", {{x0, y0, z}, {x0 + s, y0, z}, {x0 + s, y0 + s, z}, {x0, y0 + s, z}}, 0.5));
    }
    const SkyRadiance sky = testSky();
    const glm::dvec3 lo(xc - h, yc - h, 0.0), hi(xc + h, yc + h, 2 * h);
    const glm::dvec3 albedo(0.8, 0.4, 0.1);
    const Camera cam = testCamera();
    auto session = testSession(room, sky);
    DaylightRelighting& relit = *session;
    std::vector<Polygon> faces;
    for (const auto& f : boxObject("box", lo, hi, albedo).polygons) {
      Polygon p = poly("box", f, 0.0);
      p.albedo = albedo;
      faces.push_back(p);
    }
    const ImageRGB cpuRoom = relit.render(sky, {}, DaylightMethod::Volume);
    const ImageRGB cpu = relit.render(sky, faces, DaylightMethod::Volume);

    GlDaylightRenderer gl;
    gl.initialize();
    gl.setRoom(relit.roomPolygons(), relit.camera());
    const InteractiveSky light = relit.interactiveSky(sky);
    QCOMPARE(int(light.window.size()) >= 60, true);
    gl.setSky(light);
    const ImageRGB glRoom = gl.renderLinear();
    // Without objects the view is the library's room under the sky, pixel for pixel.
    if (qEnvironmentVariableIsSet("RELUME_DEBUG_DIR")) {
      const std::string dir = qEnvironmentVariable("RELUME_DEBUG_DIR").toStdString();
      const std::string tag = post ? "_post" : "";
      writeImage(dir + "/gl_room" + tag + ".exr", glRoom);
      writeImage(dir + "/cpu_room" + tag + ".exr", cpuRoom);
      writeImage(dir + "/cpu_box" + tag + ".exr", cpu);
    }
    double worstRoom = 0;
    size_t bad = 0;
    for (size_t i = 0; i < glRoom.pixels.size(); ++i)
      bad += std::abs(glRoom.pixels[i] - cpuRoom.pixels[i]) > 1e-4 * std::max(1e-3, double(cpuRoom.pixels[i]));
    qInfo("%zu of %zu values differ", bad, glRoom.pixels.size());
    for (size_t i = 0; i < glRoom.pixels.size(); ++i)
      worstRoom = std::max(worstRoom, double(std::abs(glRoom.pixels[i] - cpuRoom.pixels[i])) /
                                          std::max(1e-3, double(cpuRoom.pixels[i])));
    qInfo("room without objects: largest relative difference %.2e", worstRoom);
    QVERIFY(worstRoom < 1e-4);

    glm::dvec3 blo(1e300), bhi(-1e300);
    for (const auto& f : faces)
      for (const auto& v : f.vertices) blo = glm::min(blo, v), bhi = glm::max(bhi, v);
    gl.setObjects(faces, relit.objectIndirect(sky, faces),
                  relit.shadowReach(light, 0.5 * (blo + bhi), 0.5 * glm::length(bhi - blo)));
    QCOMPARE(gl.mapCount(), int(light.window.size()) + 4);
    const ImageRGB view = gl.renderLinear();
    if (qEnvironmentVariableIsSet("RELUME_DEBUG_DIR"))
      writeImage(qEnvironmentVariable("RELUME_DEBUG_DIR").toStdString() + "/gl_box" + (post ? "_post" : "") + ".exr", view);

    // Per pixel: the box (a ray meets it), a shadow (darker than the room by 5 % or more), or neither.
    size_t overDark = 0;
    size_t boxPixels = 0, cpuShadow = 0, glShadow = 0, both = 0, either = 0;
    double boxCpu = 0, boxGl = 0, shadowCpu = 0, shadowGl = 0;
    const RayScene box([&] {
      std::vector<std::vector<glm::dvec3>> p;
      for (const auto& f : faces) p.push_back(f.vertices);
      return p;
    }());
    for (size_t i = 0; i < size_t(cam.width) * size_t(cam.height); ++i) {
      const int x = int(i % size_t(cam.width)), y = int(i / size_t(cam.width));
      const glm::dvec3 eye = cam.center(), d = cam.rayDirection(x + 0.5, y + 0.5);
      if (box.intersect(Ray{glm::vec3(eye), glm::vec3(d), 0.f, 1e30f}).polygon >= 0) {
        ++boxPixels;
        boxCpu += luminance(cpu, i);
        boxGl += luminance(view, i);
        continue;
      }
      const double room0 = luminance(cpuRoom, i);
      const bool c = luminance(cpu, i) < 0.95 * room0, g = luminance(view, i) < 0.95 * room0;
      cpuShadow += c;
      glShadow += g;
      both += c && g;
      either += c || g;
      overDark += luminance(view, i) < luminance(cpu, i) - 0.25 * room0;  // light taken that the room had not
      shadowCpu += room0 - luminance(cpu, i);  // the light the box takes away
      shadowGl += room0 - luminance(view, i);
    }
    const double iou = either ? double(both) / double(either) : 0;
    qInfo("box: %zu pixels, mean luminance GL %.4f, CPU %.4f; shadows: GL %zu pixels, CPU %zu, intersection over union "
          "%.3f; light taken away (luminance summed over the pixels) %.2f (GL), %.2f (CPU)",
          boxPixels, boxGl / double(std::max<size_t>(boxPixels, 1)), boxCpu / double(std::max<size_t>(boxPixels, 1)),
          glShadow, cpuShadow, iou, shadowGl, shadowCpu);
    QVERIFY(boxPixels > 1000);
    QVERIFY(cpuShadow > 500);
    qInfo("%zu pixels darker than on the CPU path by a quarter of the room's light or more", overDark);
    QVERIFY(iou > 0.95);
    QVERIFY(overDark < cpuShadow / 50);
    QVERIFY(std::abs(boxGl / boxCpu - 1) < 0.05);
    QVERIFY(std::abs(shadowGl / shadowCpu - 1) < 0.05);

    // The box moved out of the sun: its sun shadow goes with it (the maps are made again).
    for (auto& f : faces)
      for (auto& v : f.vertices) v.y -= 1.2;
    blo.y -= 1.2, bhi.y -= 1.2;
    gl.setObjects(faces, relit.objectIndirect(sky, faces),
                  relit.shadowReach(light, 0.5 * (blo + bhi), 0.5 * glm::length(bhi - blo)));
    const ImageRGB moved = gl.renderLinear(), cpuMoved = relit.render(sky, faces, DaylightMethod::Volume);
    double worst = 0;
    size_t differ = 0;
    for (size_t i = 0; i < size_t(cam.width) * size_t(cam.height); ++i) {
      const double a = luminance(moved, i), b = luminance(cpuMoved, i);
      worst = std::max(worst, std::abs(a - b));
      differ += std::abs(a - b) > 0.05 * std::max(b, 1e-3);
    }
    qInfo("moved: %zu pixels differ from the CPU path by more than 5 %%", differ);
    QVERIFY(differ < size_t(cam.width) * size_t(cam.height) / 100);
  }
};

void DaylightViewTest::compareImageObject(bool acrossTheEdge) {
  const Scene room = windowRoom(0.5, 0.6, 0.7);
  const double xc = kPatchX, yc = kPatchY;
  const SkyRadiance sky = testSky();
  const Camera cam = testCamera();
  auto session = testSession(room, sky);
  DaylightRelighting& relit = *session;

  // A slightly bumpy ball, 40 cm across standing in the sun's patch, or 60 cm across its edge.
  ibr::Mesh ball = ibr::bumpyBall(96, 48, acrossTheEdge ? 0.3 : 0.2, 0.04);
  ball.triangleAlbedo.assign(ball.triangles.size(), glm::vec3(0.8f, 0.45f, 0.15f));
  ibr::FanOptions fo;
  fo.viewsPerRing = 48;
  fo.size = 128;
  ibr::ImageObject ob;
  ob.name = "ball";
  ob.fan = ibr::buildFan(ball, fo);
  ob.fanFile = "ball.fan";
  ob.place.position = glm::dvec3(xc, acrossTheEdge ? Y0 + 0.05 : yc, 0.0);
  ob.place.yaw = 0.3;

  const ImageRGB cpuRoom = relit.render(sky, {}, DaylightMethod::Volume);
  ImageRGB cpu = cpuRoom;
  std::vector<uint8_t> mask(size_t(cam.width) * size_t(cam.height), 0);
  ibr::drawImageObjectsInDaylight(relit, sky, {ob}, cpu, &mask);

  GlDaylightRenderer gl;
  gl.initialize();
  gl.setRoom(relit.roomPolygons(), relit.camera());
  const InteractiveSky light = relit.interactiveSky(sky);
  gl.setSky(light);
  const ibr::ImageFan& fan = *ob.fan;
  const glm::dvec3 c = ob.place.toWorld(fan, fan.centre);
  const double r = fan.radius * ob.place.scale;
  ibr::DisplayDaylight d = ibr::daylightForDisplay(relit, sky, ob, cam.center(), size_t(GlDaylightRenderer::imageLamps()));
  gl.setImageObjects({ob}, {d.light}, {d.tables});
  gl.setObjects({}, relit.objectIndirect(sky, {}), relit.shadowReach(light, c, r));
  const ImageRGB view = gl.renderLinear();
  if (qEnvironmentVariableIsSet("RELUME_DEBUG_DIR")) {
    const std::string dir = qEnvironmentVariable("RELUME_DEBUG_DIR").toStdString();
    const std::string tag = acrossTheEdge ? "_edge" : "";
    writeImage(dir + "/gl_fan" + tag + ".exr", view);
    writeImage(dir + "/cpu_fan" + tag + ".exr", cpu);
  }
  // The object's pixels (covered on the CPU path), and the shadows (room pixels darker than the
  // room without the object by 5 % or more).
  size_t objectPixels = 0, glCovered = 0, cpuShadow = 0, glShadow = 0, both = 0, either = 0, overDark = 0;
  double objCpu = 0, objGl = 0, err2 = 0, peak = 0, takenCpu = 0, takenGl = 0;
  std::vector<char> shadowed(mask.size());
  for (size_t i = 0; i < mask.size(); ++i) shadowed[i] = luminance(cpu, i) < 0.95 * luminance(cpuRoom, i);
  // (A pixel on the CPU shadow's outline, a neighbour in and one out: the two may put a sharp sun
  // edge half a pixel apart.)
  auto outline = [&](size_t i) {
    const int x = int(i % size_t(cam.width)), y = int(i / size_t(cam.width));
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int xx = std::clamp(x + dx, 0, cam.width - 1), yy = std::clamp(y + dy, 0, cam.height - 1);
        if (shadowed[size_t(yy) * size_t(cam.width) + size_t(xx)] != shadowed[i]) return true;
      }
    return false;
  };
  for (size_t i = 0; i < size_t(cam.width) * size_t(cam.height); ++i) {
    const double a = luminance(view, i), b = luminance(cpu, i), room0 = luminance(cpuRoom, i);
    if (mask[i] == 255) {
      ++objectPixels;
      objCpu += b;
      objGl += a;
      err2 += (a - b) * (a - b);
      peak = std::max(peak, b);
      glCovered += std::abs(a - room0) > 0.02 * room0;
      continue;
    }
    if (mask[i] > 0) continue;  // (the outline, blended: neither)
    const bool cs = b < 0.95 * room0, gs = a < 0.95 * room0;
    cpuShadow += cs;
    glShadow += gs;
    both += cs && gs;
    either += cs || gs;
    overDark += a < b - 0.25 * room0 && !outline(i);
    takenCpu += room0 - b;
    takenGl += room0 - a;
  }
  const double psnr = 10 * std::log10(peak * peak / std::max(err2 / double(std::max<size_t>(objectPixels, 1)), 1e-30));
  const double iou = either ? double(both) / double(either) : 0;
  qInfo("object: %zu pixels (GL draws %zu of them), mean luminance GL %.4f, CPU %.4f, %.2f dB; shadows: GL %zu pixels, "
        "CPU %zu, intersection over union %.3f; light taken away %.2f (GL), %.2f (CPU); %zu pixels off the shadow's outline "
        "darker than the CPU's by a quarter of the room's light",
        objectPixels, glCovered, objGl / double(std::max<size_t>(objectPixels, 1)), objCpu / double(std::max<size_t>(objectPixels, 1)),
        psnr, glShadow, cpuShadow, iou, takenGl, takenCpu, overDark);
  QVERIFY(objectPixels > 500);
  QVERIFY(cpuShadow > 500);
  QVERIFY(glCovered > objectPixels * 99 / 100);
  QVERIFY(std::abs(objGl / objCpu - 1) < 0.03);
  QVERIFY(psnr > (acrossTheEdge ? 28 : 45));
  QVERIFY(iou > 0.9);
  QVERIFY(std::abs(takenGl / takenCpu - 1) < 0.1);
  QVERIFY(overDark < cpuShadow / 50);
}

QTEST_MAIN(DaylightViewTest)
#include "daylight_view_test.moc"
