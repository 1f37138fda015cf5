// Image-based objects lit by daylight, on the project's own daylight sample room
// (resources/daylight_room): the fan of a box placed where the room's virtual_box_sun0 variant
// puts its orange box, drawn into the interactive method's render under that variant's sky, checked
// against ray casting from the sun (its shadow) and against the same box given as polygons, which
// the daylight path lights itself (its appearance).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <glm/geometric.hpp>
#include <string>

#include "relume/daylight/basis.h"
#include "relume/daylight/relight.h"
#include "relume/daylight/sky.h"
#include "relume/geometry/error.h"
#include "relume/geometry/scene.h"
#include "relume/ibr/fan.h"
#include "relume/ibr/mesh.h"
#include "relume/ibr/relit_objects.h"
#include "relume/image/image.h"
#include "relume/project/room_io.h"
#include "relume/radiosity/hierarchy.h"
#include "relume/raytrace/ray_scene.h"

using namespace relume;

namespace {
const std::string kRoom = std::string(RELUME_SOURCE_DIR) + "/resources/daylight_room";

const Scene& room() {
  static const Scene s = loadRoom(kRoom);
  return s;
}

// A closed box of the given size standing on z = 0 at the origin, one albedo.
ibr::Mesh boxMesh(const glm::dvec3& size, const glm::vec3& albedo) {
  ibr::Mesh m;
  for (int i = 0; i < 8; ++i)
    m.positions.push_back(glm::vec3(i & 1 ? size.x : 0, i & 2 ? size.y : 0, i & 4 ? size.z : 0));
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.triangles.push_back(glm::uvec3(q[0], q[1], q[2]));
    m.triangles.push_back(glm::uvec3(q[0], q[2], q[3]));
  }
  m.triangleAlbedo.assign(m.triangles.size(), albedo);
  m.name = "box";
  return m;
}

struct Session {
  daylight::SkyRadiance sky;
  std::unique_ptr<daylight::DaylightRelighting> relit;
  const Variant* variant = nullptr;
  ibr::ImageObject object;
};

Session& session() {
  static Session s = [] {
    Session out;
    for (const auto& v : room().variants)
      if (v.name == "virtual_box_sun0") out.variant = &v;
    if (!out.variant) throw Error(kRoom, "virtual_box_sun0", "missing");
    const Photo* main = room().findPhoto(room().mainPhoto);
    const ImageRGB photo = readImageLinear(kRoom + "/" + main->hdr);
    daylight::BasisOptions options;
    options.regions = 16;
    const daylight::SkyRegions regions(options.regions);
    out.relit = std::make_unique<daylight::DaylightRelighting>(
        room(), photo, main->camera, daylight::averageSky(daylight::readRoomSky(room(), room().photoSky), regions), options);
    out.sky = daylight::averageSky(daylight::readRoomSky(room(), out.variant->sky), regions);
    // The variant's box as an image-based object: its fan, standing where the box stands.
    const VirtualBox& b = out.variant->virtualObjects.at(0);
    ibr::FanOptions fo;
    fo.viewsPerRing = 48;
    fo.size = 128;
    out.object.name = "box";
    out.object.fan = ibr::buildFan(boxMesh(b.boxMax - b.boxMin, glm::vec3(b.albedo)), fo);
    out.object.fanFile = "box.fan";
    out.object.place.position = glm::dvec3(0.5 * (b.boxMin.x + b.boxMax.x), 0.5 * (b.boxMin.y + b.boxMax.y), b.boxMin.z);
    return out;
  }();
  return s;
}

}  // namespace

TEST(ImageObjectsInDaylight, TheSunShadowOfABoxsFanCoversTheFloorRayCastingSaysTheBoxHides) {
  // The test for the box's sun shadow, for its image-based twin: of the sunlit floor
  // points the box hides from the sun (rays to the sun met with the box's own faces), at least
  // 80 % lose half their light or more, and at most 10 % of those it does not hide.
  Session& s = session();
  daylight::DaylightRelighting& relit = *s.relit;
  const ImageRGB before = relit.render(s.sky, {}, daylight::DaylightMethod::Volume);
  ImageRGB after = before;
  std::vector<uint8_t> mask;
  const auto stats = ibr::drawImageObjectsInDaylight(relit, s.sky, {s.object}, after, &mask);
  ASSERT_EQ(stats.size(), 1u);
  std::printf("fan view %d, %zu pixels, shadows on %zu pixels\n", stats[0].view, stats[0].objectPixels, stats[0].shadowPixels);
  const VirtualBox& b = s.variant->virtualObjects.at(0);
  const glm::dvec3 lo = b.boxMin, hi = b.boxMax;
  const std::vector<std::vector<glm::dvec3>> faces = {
      {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z}},
      {{lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}},
      {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, lo.y, hi.z}, {lo.x, lo.y, hi.z}},
      {{lo.x, hi.y, lo.z}, {hi.x, hi.y, lo.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}},
      {{lo.x, lo.y, lo.z}, {lo.x, hi.y, lo.z}, {lo.x, hi.y, hi.z}, {lo.x, lo.y, hi.z}},
      {{hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {hi.x, hi.y, hi.z}, {hi.x, lo.y, hi.z}}};
  const RayScene boxRays(faces);
  std::vector<std::vector<glm::dvec3>> solid;
  for (const auto& p : room().polygons)
    if (p.kind == PolygonKind::Real && p.group != "outside") solid.push_back(p.vertices);
  const RayScene roomRays(solid);
  const glm::dvec3 d = glm::normalize(s.sky.sun.direction);
  ASSERT_TRUE(s.sky.sun.found);
  auto open = [&](const glm::dvec3& p) { return roomRays.intersect(Ray{glm::vec3(p), glm::vec3(d), 1e-4f, 1e30f}).polygon < 0; };
  auto hidden = [&](const glm::dvec3& p) { return boxRays.intersect(Ray{glm::vec3(p), glm::vec3(d), 1e-4f, 1e30f}).polygon >= 0; };
  const daylight::SeenPixels px = daylight::seePixels(relit.basis(), relit.camera());
  const int floor = room().findPolygon("floor");
  ASSERT_GE(floor, 0);
  size_t hiddenN = 0, hiddenDark = 0, openN = 0, openDark = 0;
  for (size_t i = 0; i < px.surface.size(); ++i) {
    if (px.surface[i] != floor || mask[i]) continue;  // the floor where the object is not drawn over it
    const glm::dvec3 p = px.point[i];
    int in = 0, sunny = 0;
    for (const glm::dvec3& o : {glm::dvec3(0.0), glm::dvec3(0.02, 0, 0), glm::dvec3(-0.02, 0, 0), glm::dvec3(0, 0.02, 0),
                                glm::dvec3(0, -0.02, 0)}) {
      in += hidden(p + o);
      sunny += open(p + o);
    }
    if (sunny < 5 || (in > 0 && in < 5)) continue;
    const bool dark = after.pixels[3 * i + 1] < 0.5f * before.pixels[3 * i + 1];
    if (in == 5) ++hiddenN, hiddenDark += dark;
    else ++openN, openDark += dark;
  }
  std::printf("floor in the sun: %zu of %zu points the box hides darkened, %zu of %zu it does not hide\n", hiddenDark, hiddenN,
              openDark, openN);
  ASSERT_GT(hiddenN, 50u);
  ASSERT_GT(openN, 300u);
  EXPECT_GE(double(hiddenDark), 0.8 * double(hiddenN));
  EXPECT_LE(double(openDark), 0.1 * double(openN));
}

TEST(ImageObjectsInDaylight, ABoxsFanLooksAsTheSameBoxGivenAsPolygons) {
  // The daylight path lights a polygon box itself (window samples with shadow maps, the sun per
  // pixel, the irradiance volume per vertex); the fan of the same box, lit through the 225 codes'
  // tables by the same window samples, sun and volume, must show the same light: over the pixels
  // both draw, the mean radiance per channel within 8 %, and the per-pixel luminance (after a
  // 3 x 3 box filter, the dithered codes' noise averaged as the fidelity bar takes it)
  // within 15 % on 85 % of them. Under sun0 the box stands in the sunlit patch; under sun1 the
  // patch's edge runs through it (the sun is seen past the room per point of the object, not
  // once from its centre).
  Session& s = session();
  daylight::DaylightRelighting& relit = *s.relit;
  const std::vector<Polygon> polygons = daylight::variantObjects(room(), *s.variant, room().sourceFile);
  daylight::DaylightBasis& basis = relit.basis();
  const size_t roomSurfaces = basis.engine().surfaces().size();
  const auto ids = basis.addObjects(polygons);
  const daylight::SeenPixels seen = daylight::seePixels(basis, relit.camera());
  basis.removeObjects(ids);
  const int W = relit.camera().width, H = relit.camera().height;
  for (const char* skyName : {"sun0", "sun1"}) {
    const daylight::SkyRadiance sky =
        daylight::averageSky(daylight::readRoomSky(room(), skyName), daylight::SkyRegions(int(s.sky.region.size())));
    const ImageRGB poly = relit.render(sky, polygons, daylight::DaylightMethod::Volume);
    ImageRGB fan = relit.render(sky, {}, daylight::DaylightMethod::Volume);
    std::vector<uint8_t> mask;
    ibr::drawImageObjectsInDaylight(relit, sky, {s.object}, fan, &mask);
    auto boxAt = [&](int x, int y) {
      const size_t i = size_t(y) * W + x;
      return seen.surface[i] >= int(roomSurfaces) && mask[i] == 255;
    };
    auto box3 = [&](const ImageRGB& im, int x, int y) {
      glm::dvec3 sum(0.0);
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) sum += glm::dvec3(im.at(x + dx, y + dy));
      return sum / 9.0;
    };
    auto lum = [](const glm::dvec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; };
    glm::dvec3 sumPoly(0.0), sumFan(0.0);
    std::map<int, std::pair<double, double>> faces;
    size_t n = 0, close = 0;
    for (int y = 1; y + 1 < H; ++y)
      for (int x = 1; x + 1 < W; ++x) {
        bool all = true;
        for (int dy = -1; dy <= 1 && all; ++dy)
          for (int dx = -1; dx <= 1 && all; ++dx) all = boxAt(x + dx, y + dy);
        if (!all) continue;  // the box's edges: the fan's are as sharp as its pixels
        const glm::dvec3 a = box3(poly, x, y), b = box3(fan, x, y);
        sumPoly += a;
        sumFan += b;
        auto& f = faces[seen.surface[size_t(y) * W + x] - int(roomSurfaces)];
        f.first += lum(a);
        f.second += lum(b);
        ++n;
        close += std::abs(lum(b) / lum(a) - 1.0) <= 0.15;
      }
    ASSERT_GT(n, 200u) << skyName;
    const glm::dvec3 ratio = sumFan / sumPoly;
    std::printf("%s: box pixels %zu, fan / polygons mean %.3f %.3f %.3f, within 15 %% on %.1f %%; per face", skyName, n,
                ratio.x, ratio.y, ratio.z, 100.0 * double(close) / double(n));
    for (const auto& [f, l] : faces) std::printf(" %d: %.3f", f, l.second / l.first);
    std::printf("\n");
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(ratio[c], 1.0, 0.08) << skyName << " channel " << c;
    EXPECT_GE(double(close), 0.85 * double(n)) << skyName;
  }
}

TEST(ImageObjectsInDaylight, FansOfOneNameInAFileAreToldApart) {
  // Each is dragged, saved and named in messages by its name: a repeated one gets its place.
  Session& s = session();
  const std::string dir = std::string(RELUME_BINARY_DIR) + "/ibr_daylight_names";
  std::filesystem::create_directories(dir);
  ibr::writeFan(*s.object.fan, dir + "/box.fan");
  Variant v;
  for (int i = 0; i < 3; ++i) {
    VirtualBox b;
    b.name = i < 2 ? "box" : "";
    b.fan = "box.fan";
    b.position = glm::dvec3(1.0 + i, 2.0, 0.0);
    v.virtualObjects.push_back(b);
  }
  std::vector<ibr::ImageObject> out;
  ibr::appendImageObjects(v, dir + "/objects.json", out);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0].name, "box");
  EXPECT_EQ(out[1].name, "box (2)");
  EXPECT_EQ(out[2].name, "image_object_2");
  EXPECT_EQ(out[1].fanFile, dir + "/box.fan");
  EXPECT_DOUBLE_EQ(out[2].place.position.x, 3.0);
  // A room's own variant names its fans from the room's folder (an OBJ + JSON room's JSON folder),
  // not from the folder of the file the room was read from (its OBJ, elsewhere).
  std::vector<ibr::ImageObject> own;
  ibr::appendImageObjects(v, dir + "/mesh/room.obj", own, dir);
  ASSERT_EQ(own.size(), 3u);
  EXPECT_EQ(own[0].fanFile, dir + "/box.fan");
  EXPECT_THROW(ibr::appendImageObjects(v, dir + "/mesh/room.obj", own), Error);  // no dir/mesh/box.fan
}

namespace {
// A square panel of side `side` centred on c, facing along the unit n (one polygon, two-sided for
// rays).
Polygon panel(const glm::dvec3& c, const glm::dvec3& n, double side) {
  const glm::dvec3 a = glm::normalize(glm::cross(n, std::abs(n.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0)));
  const glm::dvec3 b = glm::cross(n, a);
  const double h = 0.5 * side;
  Polygon p;
  p.name = "panel";
  p.group = "panel";
  p.kind = PolygonKind::Real;
  p.albedo = glm::dvec3(0.5);
  p.vertices = {c - h * a - h * b, c + h * a - h * b, c + h * a + h * b, c - h * a + h * b};
  return p;
}
}  // namespace

TEST(ImageObjectsInDaylight, ABoxOrMeshOfTheRenderHidesTheFanBehindItAndShadesItFromTheSun) {
  // A render's boxes and meshes are not in the session's room: drawn with the image-based object,
  // they hide it where they stand nearer the camera, and hide the sun from it as the room does.
  Session& s = session();
  daylight::DaylightRelighting& relit = *s.relit;
  const ImageRGB base = relit.render(s.sky, {}, daylight::DaylightMethod::Volume);
  ImageRGB alone = base;
  std::vector<uint8_t> maskAlone;
  ibr::drawImageObjectsInDaylight(relit, s.sky, {s.object}, alone, &maskAlone);
  const glm::dvec3 centre = s.object.place.toWorld(*s.object.fan, s.object.fan->centre);
  const Camera& cam = relit.camera();
  size_t covered = 0;
  for (uint8_t m : maskAlone) covered += m > 0;
  ASSERT_GT(covered, 500u);

  // (a) A panel 60 % of the way from the camera to the object, 12 cm across: where a pixel's ray
  // meets it, the object is not drawn; elsewhere exactly as alone.
  const glm::dvec3 eye = cam.center(), towards = glm::normalize(centre - eye);
  const Polygon front = panel(eye + 0.6 * glm::length(centre - eye) * towards, -towards, 0.12);
  ImageRGB hid = base;
  std::vector<uint8_t> maskHid;
  ibr::drawImageObjectsInDaylight(relit, s.sky, {s.object}, hid, &maskHid, silentProgress(), {front});
  const RayScene frontRays({front.vertices});
  size_t behind = 0, behindDrawn = 0, beside = 0, besideChanged = 0;
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      const size_t i = size_t(y) * size_t(cam.width) + size_t(x);
      if (!maskAlone[i]) continue;
      const bool blocked = frontRays.intersect(Ray{glm::vec3(eye), glm::vec3(cam.rayDirection(x + 0.5, y + 0.5)), 0.f, 1e30f}).polygon >= 0;
      if (blocked) {
        ++behind;
        behindDrawn += maskHid[i] > 0;
      } else {
        ++beside;
        besideChanged += maskHid[i] != maskAlone[i];
      }
    }
  std::printf("object pixels behind the panel %zu (drawn on %zu), beside it %zu (changed %zu)\n", behind, behindDrawn, beside,
              besideChanged);
  ASSERT_GT(behind, 50u);
  ASSERT_GT(beside, 50u);
  EXPECT_EQ(behindDrawn, 0u);
  EXPECT_LE(besideChanged, beside / 50);

  // (b) A panel 0.6 m towards the sun, 1 m across, square to it: the sun no longer reaches the
  // object, which keeps only the window's sky and the room's light — much darker where the sun
  // fell on it, and nowhere brighter.
  ASSERT_TRUE(s.sky.sun.found);
  const glm::dvec3 sunDir = glm::normalize(s.sky.sun.direction);
  const Polygon shade = panel(centre + 0.6 * sunDir, -sunDir, 1.0);
  ImageRGB shaded = base;
  std::vector<uint8_t> maskShaded;
  ibr::drawImageObjectsInDaylight(relit, s.sky, {s.object}, shaded, &maskShaded, silentProgress(), {shade});
  double lumAlone = 0, lumShaded = 0;
  size_t n = 0, brighter = 0;
  for (size_t i = 0; i < maskAlone.size(); ++i) {
    if (maskAlone[i] < 255 || maskShaded[i] < 255) continue;  // wholly the object in both
    const double a = daylight::luminance(glm::dvec3(alone.at(int(i % size_t(cam.width)), int(i / size_t(cam.width))))),
                 b = daylight::luminance(glm::dvec3(shaded.at(int(i % size_t(cam.width)), int(i / size_t(cam.width)))));
    lumAlone += a;
    lumShaded += b;
    brighter += b > 1.01 * a + 1e-6;
    ++n;
  }
  std::printf("object's mean luminance with the sun %.4f, its sun hidden by a panel %.4f (%zu pixels, %zu brighter)\n",
              lumAlone / double(n), lumShaded / double(n), n, brighter);
  ASSERT_GT(n, 500u);
  EXPECT_LT(lumShaded, 0.6 * lumAlone);
  EXPECT_EQ(brighter, 0u);
}
