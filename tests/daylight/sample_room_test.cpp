// Daylight on the project's own daylight sample room (resources/daylight_room: rendered by Blender
// Cycles with resources/scripts/make_daylight_room.py, lit only through its window by Blender's
// Nishita sky, each sky captured by an HDR fisheye on the roof). What is checked against what:
// - the sun found in each fisheye against the sun Blender was given;
// - the basis solution's sunlit patch, the box's sun shadow and a box's indirect light against
//   ray casting on the room's model (the test's own rays, not the solver's links);
// - the relit photos against Cycles' renders of the same changes (the bars).
// The albedos in scene.json are never given to the method: they are what a user does not have
// (one test reads the ceiling's and the back wall's, as the truth their estimates are checked
// against).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <numbers>
#include <string>

#include "relume/daylight/basis.h"
#include "relume/daylight/relight.h"
#include "relume/daylight/sky.h"
#include "relume/geometry/error.h"
#include "relume/geometry/polygon.h"
#include "relume/geometry/scene.h"
#include "relume/image/image.h"
#include "relume/project/room_io.h"
#include "relume/radiosity/hierarchy.h"
#include "relume/raytrace/ray_scene.h"
#include "relume/relight/compare.h"
#include "relume/relight/relighter.h"

using namespace relume;
using namespace relume::daylight;

namespace {
constexpr double kPi = std::numbers::pi;
const std::string kRoom = std::string(RELUME_SOURCE_DIR) + "/resources/daylight_room";

// The suns make_daylight_room.py gave Blender's sky: elevation, and rotation about +Z from +Y
// towards +X (degrees).
struct SunTruth {
  const char* sky;
  double elevation, rotation;
};
constexpr SunTruth kSuns[] = {{"sun0", 30, 100}, {"sun1", 48, 70}, {"sun2", 22, 112}};

glm::dvec3 blenderSun(const SunTruth& s) {
  const double e = s.elevation * kPi / 180, r = s.rotation * kPi / 180;
  return {std::cos(e) * std::sin(r), std::cos(e) * std::cos(r), std::sin(e)};
}

const Scene& room() {
  static const Scene s = loadRoom(kRoom);
  return s;
}
int polygonNamed(const std::string& name) {
  const int i = room().findPolygon(name);
  EXPECT_GE(i, 0) << "no polygon " << name;
  return i;
}
SkyRadiance roomSky(const std::string& name, int regions = 64) { return averageSky(readRoomSky(room(), name), SkyRegions(regions)); }

BasisOptions options() {
  BasisOptions o;
  o.regions = 16;  // the region count does not change where the sun lands
  return o;
}

// Does the ray from `p` towards `d` leave the room (through the window: the room is closed
// otherwise)? The model's own polygons, windows left out, in an Embree scene of the test's.
struct ModelRays {
  RayScene scene;
  static std::vector<std::vector<glm::dvec3>> solid() {
    std::vector<std::vector<glm::dvec3>> v;
    for (const auto& p : room().polygons)
      if (p.kind == PolygonKind::Real && p.group != "outside") v.push_back(p.vertices);
    return v;
  }
  ModelRays() : scene(solid()) {}
  bool open(const glm::dvec3& p, const glm::dvec3& d) const {
    return scene.intersect(Ray{glm::vec3(p), glm::vec3(d), 1e-4f, 1e30f}).polygon < 0;
  }
};

// Whether a point facing `n` is wholly in the sun along `d` (1: all five rays over a 4 mm cross
// leave the room), wholly shaded (0: none does), or on a shadow's edge (-1).
int sunlit(const ModelRays& rays, const glm::dvec3& p, const glm::dvec3& n, const glm::dvec3& d) {
  int open = 0;
  for (const glm::dvec3 off : {glm::dvec3(0.0), glm::dvec3(0.004, 0, 0), glm::dvec3(-0.004, 0, 0), glm::dvec3(0, 0.004, 0),
                               glm::dvec3(0, -0.004, 0)})
    open += rays.open(p + 1e-4 * n + off, d) ? 1 : 0;
  return open == 0 ? 0 : (open == 5 ? 1 : -1);
}

// The main photo's pixels showing `surface`, split by sunlit(): per class the sums of a and b.
struct SunSplit {
  glm::dvec3 a[2]{glm::dvec3(0.0), glm::dvec3(0.0)}, b[2]{glm::dvec3(0.0), glm::dvec3(0.0)};
  long n[2]{0, 0};
  glm::dvec3 ratio(int k) const { return a[k] / b[k]; }
};
}  // namespace

TEST(DaylightSampleRoom, ItsFisheyesShowTheSunWhereBlenderPutIt) {
  for (const SunTruth& s : kSuns) {
    const SkyRadiance sky = roomSky(s.sky);
    ASSERT_TRUE(sky.sun.found) << s.sky;
    EXPECT_FALSE(sky.sun.clipped) << s.sky << ": saved as full float, nothing clips";
    const double off = std::acos(std::min(1.0, glm::dot(sky.sun.direction, blenderSun(s)))) * 180 / kPi;
    std::printf("%s: sun found %.2f deg from where Blender put it (%zu pixels, irradiance facing it %.2f)\n", s.sky, off,
                size_t(sky.sun.pixels), sky.sun.irradiance.y);
    EXPECT_LT(off, 1.0) << s.sky;
  }
}

TEST(DaylightSampleRoom, TheSunlitPatchOfTheSolutionSitsWhereRaysThroughTheWindowPutIt) {
  // One basis refined for the photos' sky; each fisheye's sun solved on its links. The floor's
  // sunlit patch in the solution (each leaf's direct sun, area-weighted) against floor points a
  // centimetre apart whose ray towards the sun leaves through the window (the furniture's
  // shadows included).
  DaylightBasis basis(room(), roomSky(room().photoSky, 16), options());
  const int floor = polygonNamed("floor");
  const ModelRays rays;
  for (const SunTruth& s : kSuns) {
    const glm::dvec3 d = roomSky(s.sky, 16).sun.direction;
    basis.sunSolution(d);
    const auto& eng = basis.engine();
    glm::dvec2 sum(0.0);
    double w = 0;
    std::vector<int> stack{eng.surfaceRoot(floor)};
    while (!stack.empty()) {
      const int n = stack.back();
      stack.pop_back();
      const auto& N = eng.nodes()[size_t(n)];
      if (!N.isLeaf()) {
        for (int i = 0; i < N.childCount; ++i) stack.push_back(eng.children()[size_t(N.childBegin + i)]);
        continue;
      }
      const double m = double(N.area) * basis.sunDirect()[size_t(n)].y;
      sum += m * glm::dvec2(N.center.x, N.center.y);
      w += m;
    }
    glm::dvec2 want(0.0);
    size_t lit = 0;
    glm::dvec3 lo(1e9), hi(-1e9);
    for (const auto& c : room().polygons[size_t(floor)].vertices) lo = glm::min(lo, c), hi = glm::max(hi, c);
    for (double x = lo.x + 0.005; x < hi.x; x += 0.01)
      for (double y = lo.y + 0.005; y < hi.y; y += 0.01)
        if (rays.open({x, y, 0.0}, d)) want += glm::dvec2(x, y), ++lit;
    ASSERT_GT(lit, 1000u) << s.sky;
    want /= double(lit);
    ASSERT_GT(w, 0.0) << s.sky;
    const glm::dvec2 got = sum / w;
    std::printf("%s: patch centroid (%.3f, %.3f), rays put it at (%.3f, %.3f): %.1f cm off (%.2f m^2 sunlit)\n", s.sky, got.x,
                got.y, want.x, want.y, 100 * glm::length(got - want), 1e-4 * double(lit));
    EXPECT_LT(glm::length(got - want), 0.05) << s.sky;
  }
}

TEST(DaylightSampleRoom, TheBoxsSunShadowCoversTheFloorRayCastingSaysItHides) {
  // The photos' sky; the virtual box of the variant "virtual_box_sun0" added to the hierarchy.
  // Per pixel of the main view showing the floor in the sun: the box hides it from the sun (the
  // test's own rays against the box), or not — 2 cm either side of the shadow's outline left out
  // (the pixel's footprint and the sun's penumbra). Hidden points must lose most of their light,
  // the others keep it.
  const SkyRadiance sky = roomSky(room().photoSky, 16);
  DaylightBasis basis(room(), sky, options());
  const Photo* main = room().findPhoto(room().mainPhoto);
  ASSERT_NE(main, nullptr);
  const SeenPixels before = seePixels(basis, main->camera);
  const ImageRGB e0 = irradianceImage(basis, before, sky);
  const Variant* v = nullptr;
  for (const auto& x : room().variants)
    if (x.name == "virtual_box_sun0") v = &x;
  ASSERT_NE(v, nullptr);
  const std::vector<Polygon> box = variantObjects(room(), *v, room().sourceFile);
  basis.addObjects(box);
  const SeenPixels after = seePixels(basis, main->camera);
  const ImageRGB e1 = irradianceImage(basis, after, sky);
  std::vector<std::vector<glm::dvec3>> faces;
  for (const auto& f : box) faces.push_back(f.vertices);
  const RayScene boxRays(faces);
  const ModelRays rays;
  const glm::dvec3 d = sky.sun.direction;
  const int floor = polygonNamed("floor");
  auto hidden = [&](const glm::dvec3& p) { return boxRays.intersect(Ray{glm::vec3(p), glm::vec3(d), 1e-4f, 1e30f}).polygon >= 0; };
  size_t hiddenN = 0, hiddenDark = 0, openN = 0, openDark = 0;
  for (size_t i = 0; i < after.surface.size(); ++i) {
    if (after.surface[i] != floor || before.surface[i] != floor) continue;
    const glm::dvec3 p = after.point[i];
    if (!rays.open(p, d)) continue;  // the room itself keeps the sun off
    int in = 0, sunny = 0;
    for (const glm::dvec3& o : {glm::dvec3(0.0), glm::dvec3(0.02, 0, 0), glm::dvec3(-0.02, 0, 0), glm::dvec3(0, 0.02, 0),
                                glm::dvec3(0, -0.02, 0)}) {
      in += hidden(p + o);
      sunny += rays.open(p + o, d);
    }
    if (sunny < 5 || (in > 0 && in < 5)) continue;
    // Dark: less than half the light it had; the sun brings most of it in the patch.
    const bool dark = e1.pixels[3 * i + 1] < 0.5f * e0.pixels[3 * i + 1];
    if (in == 5) ++hiddenN, hiddenDark += dark;
    else ++openN, openDark += dark;
  }
  std::printf("floor in the sun: %zu of %zu points the box hides darkened, %zu of %zu it does not hide\n", hiddenDark, hiddenN,
              openDark, openN);
  ASSERT_GT(hiddenN, 100u);
  ASSERT_GT(openN, 500u);
  EXPECT_GE(double(hiddenDark), 0.8 * double(hiddenN));
  EXPECT_LE(double(openDark), 0.1 * double(openN));
}

TEST(DaylightSampleRoom, ABoxInACornerTheSunNeverReachesGathersWhatRaysOverItsHemisphereSee) {
  // The box's faces' irradiance in the solution for the photos' sky against a brute-force
  // gather: cosine-distributed rays from points on each face, each taking the radiance of the
  // leaf it hits (B / pi of the same solution) or, out through the window, the sky's region (or
  // the ground's).
  const SkyRadiance sky = roomSky(room().photoSky, 16);
  DaylightBasis basis(room(), sky, options());
  const glm::dvec3 lo(0.1, 0.1, 0.0), hi(0.5, 0.5, 0.4);  // the front-left corner, far from every patch
  const ModelRays rays;
  for (const SunTruth& s : kSuns) ASSERT_FALSE(rays.open(glm::dvec3(0.5, 0.5, 0.4), blenderSun(s))) << s.sky;
  std::vector<Polygon> faces;
  for (const auto& f : boxObject("box", lo, hi, glm::dvec3(0.5)).polygons) {
    Polygon p;
    p.name = p.group = "box";
    p.vertices = f;
    p.albedo = glm::dvec3(0.5);
    faces.push_back(p);
  }
  const std::vector<int> ids = basis.addObjects(faces);
  const std::vector<glm::vec3> b = basis.combine(sky);
  const auto& eng = basis.engine();
  const glm::dvec3 ground = basis.groundRadiance(sky);
  uint64_t state = 99;
  auto uni = [&] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return double(state >> 11) / 9007199254740992.0;
  };
  for (int id : ids) {
    const auto& v = eng.surfaces()[size_t(id)].vertices;
    const glm::dvec3 n = polygonNormal(v);
    if (n.z < -0.5) continue;  // the bottom face stands on the floor
    const glm::dvec3 t = glm::normalize(v[1] - v[0]), u = glm::cross(n, t);
    double brute = 0;
    constexpr int points = 16, count = 2048;
    for (int p = 0; p < points; ++p) {
      glm::dvec3 c(0.0);
      for (const auto& q : v) c += q / double(v.size());
      const glm::dvec3 x = c + (uni() - 0.5) * 0.4 * glm::length(v[1] - v[0]) * t + (uni() - 0.5) * 0.4 * glm::length(v[2] - v[1]) * u +
                           1e-4 * n;
      for (int r = 0; r < count; ++r) {
        const double r1 = uni(), r2 = uni(), s = std::sqrt(r1), phi = 2 * kPi * r2;
        const glm::dvec3 d = s * std::cos(phi) * t + s * std::sin(phi) * u + std::sqrt(1 - r1) * n;
        const RayHit hit = eng.rayScene().intersect(Ray{glm::vec3(x), glm::vec3(d), 1e-5f, 1e30f});
        double l = 0;
        if (hit.polygon >= 0) {
          l = b[size_t(eng.findLeaf(hit.polygon, eng.toUV(hit.polygon, x + double(hit.t) * d)))].y / kPi;
        } else {
          const int k = basis.regions().regionOf(d);
          l = k >= 0 ? sky.region[size_t(k)].y : ground.y;
        }
        brute += kPi * l / count;  // cosine-weighted: E = pi x the mean radiance
      }
    }
    brute /= points;
    const double solved = basis.surfaceMean(b, id).y / 0.5;
    std::printf("box face (normal %+.0f %+.0f %+.0f): solution %.4f, brute-force gather %.4f (%+.1f %%)\n", n.x, n.y, n.z, solved,
                brute, 100 * (solved / brute - 1));
    EXPECT_NEAR(solved, brute, 0.15 * brute);
  }
}

TEST(DaylightSampleRoom, RelitPhotosMatchCyclesWhereTheLightChanges) {
  // The whole path as `relume evaluate` runs it: reflectances from the main photo under the
  // photos' sky, then the photo under another sun and with a virtual box, against Cycles' renders
  // of the same (gain-corrected PSNR as the comparison protocol; the "change" mask: where the
  // truth differs from the photo). The bars: near-field at least the unchanged photo
  // + 8 dB where the light changes, the distant baseline + 2 dB and 35 dB over the whole image for
  // the box.
  const Photo* main = room().findPhoto(room().mainPhoto);
  ASSERT_NE(main, nullptr);
  const ImageRGB photo = readImageLinear(kRoom + "/" + main->hdr);
  DaylightRelighting relit(room(), photo, main->camera, roomSky(room().photoSky));
  // The ceiling no photo shows: measured from the shown polygons' sunlit and shaded pixels, within
  // 10 % of Blender's albedo in luminance (scene.json's albedos read only as the truth here; the
  // shown polygons' mean, which it took before, is 26 % below).
  const int ceiling = polygonNamed("ceiling");
  ASSERT_FALSE(relit.estimated()[size_t(ceiling)]);
  ASSERT_TRUE(relit.unseenFit().ok);
  const double got = luminance(relit.reflectances()[size_t(ceiling)]), want = luminance(room().polygons[size_t(ceiling)].albedo);
  std::printf("ceiling: %.3f, truth %.3f\n", got, want);
  EXPECT_NEAR(got, want, 0.1 * want);
  // The back wall, which the photo shows and which is lit mostly by the other walls: each channel
  // within 10 % (the plain update pi L / E swung it to 0.70/0.89/0.92 against 0.72/0.70/0.64).
  const int back = polygonNamed("wall_back");
  ASSERT_TRUE(relit.estimated()[size_t(back)]);
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(relit.reflectances()[size_t(back)][c], room().polygons[size_t(back)].albedo[c],
                0.1 * room().polygons[size_t(back)].albedo[c])
        << "channel " << c;
  const CompareMasks masks = benchmarkMasks(photo, readImageLinear(kRoom + "/truth/unoccluded.exr"));
  for (const char* name : {"virtual_box_sun0", "sun1"}) {
    const Variant* v = nullptr;
    for (const auto& x : room().variants)
      if (x.name == name) v = &x;
    ASSERT_NE(v, nullptr);
    const ImageRGB truth = readImageLinear(kRoom + "/" + v->hdr);
    const SkyRadiance sky = roomSky(v->sky);
    const std::vector<Polygon> objects = variantObjects(room(), *v, room().sourceFile);
    const ImageRGB near = relit.render(sky, objects, DaylightMethod::NearField);
    const ImageRGB distant = relit.render(sky, objects, DaylightMethod::Distant);
    const std::vector<uint8_t> change = benchmarkMasks(photo, truth).shadow;
    auto psnr = [&](const ImageRGB& img, const std::vector<uint8_t>& mask) { return compareImages(img, truth, mask).psnr; };
    const double nearAll = psnr(near, masks.all), nearChange = psnr(near, change), distantChange = psnr(distant, change),
                 photoAll = psnr(photo, masks.all), photoChange = psnr(photo, change);
    std::printf("%s: near-field %.2f / %.2f dB (all / change), distant %.2f / %.2f, the photo unchanged %.2f / %.2f\n", name,
                nearAll, nearChange, psnr(distant, masks.all), distantChange, photoAll, photoChange);
    if (objects.empty()) {
      // No ghost of the photos' sun patch: the floor it lit, now shaded, against the floor that
      // was shaded both times, each as relit over Cycles' (measured under sun1: 0.976 and 1.023).
      // The patch is the photo x E_new / E_photo: a photos' sun too strong against the rest of the
      // light in the solution (E_photo too high there) leaves it darker than the floor around it.
      const ModelRays rays;
      const SeenPixels px = seePixels(relit.basis(), main->camera);
      const int floor = polygonNamed("floor");
      const glm::dvec3 before = roomSky(room().photoSky).sun.direction;
      SunSplit split;  // [0]: shaded both times, [1]: lit in the photo, shaded now
      for (int y = 0; y < px.height; ++y)
        for (int x = 0; x < px.width; ++x) {
          const size_t i = size_t(y) * size_t(px.width) + size_t(x);
          if (px.surface[i] != floor || sunlit(rays, px.point[i], px.normal[i], sky.sun.direction) != 0) continue;
          const int k = sunlit(rays, px.point[i], px.normal[i], before);
          if (k < 0) continue;
          split.a[k] += near.at(x, y);
          split.b[k] += truth.at(x, y);
          ++split.n[k];
        }
      ASSERT_GT(split.n[1], 2000) << name;
      const double patch = luminance(split.ratio(1)), rest = luminance(split.ratio(0));
      std::printf("%s: the floor where the photos' sun was, relit over Cycles' %.3f; shaded both times %.3f\n", name, patch, rest);
      EXPECT_NEAR(patch, 1.0, 0.05) << name;
      EXPECT_NEAR(patch / rest, 1.0, 0.08) << name;
    }
    EXPECT_GE(nearChange, photoChange + 8) << name;
    if (!objects.empty()) EXPECT_GE(nearChange, distantChange + 2) << name;
    if (!objects.empty()) EXPECT_GE(nearAll, 35) << name;
    if (objects.empty()) EXPECT_GE(nearAll, photoAll + 8) << name;
  }
}

TEST(DaylightSampleRoom, GivenTheTrueReflectancesTheSunAndTheRestOfTheLightAreAsCyclesRenderedThem) {
  // The transport alone: scene.json's albedos given to the engine as an oracle (here only), the
  // 64-region basis under the photos' sky, and the irradiance it puts on the floor's pixels
  // against Cycles' own (pi L / albedo from the photo), apart where the sun falls (wholly, by the
  // test's rays) and where it does not. The shaded floor takes all its light from the sky through
  // the window and from the room; the sunlit floor mostly from the sun. A sun too strong against
  // the rest would show as a patch brighter than the photo's once the sun moves (measured here:
  // sunlit 0.98, shaded 0.94-0.98 of Cycles' per channel).
  const Photo* main = room().findPhoto(room().mainPhoto);
  ASSERT_NE(main, nullptr);
  const ImageRGB photo = readImageLinear(kRoom + "/" + main->hdr);
  const SkyRadiance sky = roomSky(room().photoSky);
  DaylightBasis basis(room(), sky);
  const SeenPixels px = seePixels(basis, main->camera);
  const ImageRGB e = irradianceImage(basis, px, sky);
  const int floor = polygonNamed("floor");
  const glm::dvec3 albedo = room().polygons[size_t(floor)].albedo;
  const ModelRays rays;
  SunSplit split;
  for (int y = 0; y < px.height; ++y)
    for (int x = 0; x < px.width; ++x) {
      const size_t i = size_t(y) * size_t(px.width) + size_t(x);
      if (px.surface[i] != floor) continue;
      const int k = sunlit(rays, px.point[i], px.normal[i], sky.sun.direction);
      if (k < 0) continue;
      split.a[k] += e.at(x, y);
      split.b[k] += kPi * glm::dvec3(photo.at(x, y)) / albedo;
      ++split.n[k];
    }
  ASSERT_GT(split.n[0], 5000);
  ASSERT_GT(split.n[1], 5000);
  const glm::dvec3 shaded = split.ratio(0), lit = split.ratio(1);
  std::printf("floor irradiance, the solution over Cycles': shaded %.3f %.3f %.3f (%ld pixels), sunlit %.3f %.3f %.3f (%ld)\n",
              shaded.x, shaded.y, shaded.z, split.n[0], lit.x, lit.y, lit.z, split.n[1]);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(shaded[c], 1.0, 0.08) << "channel " << c;
    EXPECT_NEAR(lit[c], 1.0, 0.05) << "channel " << c;
    // The balance itself: the sunlit floor against the shaded floor as Cycles has it, within 5 %.
    EXPECT_NEAR(lit[c] / shaded[c], 1.0, 0.05) << "channel " << c;
  }
}

// Virtual objects given for a daylight room are checked as lamp-lit ones are, and the room's
// outside ground (reaching 36 m past the window and 35 m past the back wall) does not make the
// garden or the neighbour's house count as inside the room: each refused with the objects' file
// and the object named.
TEST(DaylightSampleRoom, AVirtualObjectOutsideTheRoomOrThroughAWallIsRefusedNamingItsFile) {
  const Scene& scene = room();
  auto objectsAt = [&](const glm::dvec3& lo, const glm::dvec3& hi) {
    Variant v;
    VirtualBox box;
    box.name = "crate2";
    box.boxMin = lo;
    box.boxMax = hi;
    box.albedo = glm::dvec3(0.5);
    v.virtualObjects.push_back(box);
    return variantObjects(scene, v, "/tmp/objects.json");
  };
  auto refusal = [&](const glm::dvec3& lo, const glm::dvec3& hi) {
    try {
      objectsAt(lo, hi);
    } catch (const Error& e) {
      EXPECT_EQ(e.file(), "/tmp/objects.json");
      EXPECT_NE(e.element().find("crate2"), std::string::npos) << e.what();
      return e.problem();
    }
    return std::string("accepted");
  };
  EXPECT_EQ(objectsAt({1.0, 1.0, 0.0}, {1.4, 1.4, 0.4}).size(), 6u);               // on the floor
  EXPECT_NE(refusal({1.0, 5.0, 0.0}, {1.4, 5.4, 0.4}).find("outside the room"), std::string::npos);  // behind the back wall
  EXPECT_NE(refusal({6.0, 2.0, 0.0}, {6.4, 2.4, 0.4}).find("outside the room"), std::string::npos);  // out on the ground
  EXPECT_NE(refusal({1.0, 4.2, 0.0}, {1.4, 4.6, 0.4}).find("intersects polygon 'wall_back'"), std::string::npos);
  EXPECT_NE(refusal({3.6, 2.0, 1.0}, {4.0, 2.4, 1.4}).find("intersects polygon 'window'"), std::string::npos);
}
