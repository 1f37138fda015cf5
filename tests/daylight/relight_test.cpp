// Daylight differential rendering: the sun's patch per pixel against the window's outline cast
// by the test's own geometry, and a virtual box that darkens only where it newly blocks the sun
// and shows its albedo x irradiance / pi.
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <glm/geometric.hpp>
#include <memory>
#include <numbers>

#include "relume/daylight/basis.h"
#include "relume/daylight/relight.h"
#include "relume/geometry/camera.h"
#include "relume/geometry/error.h"
#include "relume/geometry/polygon.h"
#include "relume/radiosity/hierarchy.h"
#include "relume/raytrace/ray_scene.h"
#include "relume/relight/relighter.h"
#include "window_room.h"

using namespace relume;
using namespace relume::daylight;
using namespace relume::testing;

namespace {
constexpr double kPi = std::numbers::pi;
constexpr double kElev = 30 * kPi / 180;
const glm::dvec3 kSun(std::cos(kElev), 0.0, std::sin(kElev));  // towards +X, through the window
constexpr double kSunE = 2.0;                                     // irradiance facing the sun

// A dark sky but for the sun (every region black), so that the sun's light is all there is.
SkyRadiance sunOnly(int regions) {
  SkyRadiance s;
  s.region.assign(size_t(regions), glm::dvec3(0.0));
  s.sun.found = true;
  s.sun.direction = kSun;
  s.sun.irradiance = glm::dvec3(kSunE);
  return s;
}

// Is the floor point (x, y) in the window's patch: does the line towards the sun cross the window?
bool inPatch(double x, double y) {
  const double t = (W - x) / kSun.x;  // to the window's plane
  const glm::dvec3 p = glm::dvec3(x, y, 0) + t * kSun;
  return p.y > Y0 && p.y < Y1 && p.z > Z0 && p.z < Z1;
}
// Distance (m) from (x, y) to the patch's outline, along the floor: within `d` of an edge?
bool nearPatchEdge(double x, double y, double d) {
  for (double dx : {-d, 0.0, d})
    for (double dy : {-d, 0.0, d})
      if (inPatch(x + dx, y + dy) != inPatch(x, y)) return true;
  return false;
}

// Does the line from p towards the sun cross the box [lo, hi]? (The test's own ray-box test.)
bool inBoxShadow(const glm::dvec3& p, const glm::dvec3& lo, const glm::dvec3& hi) {
  double t0 = 0, t1 = 1e9;
  for (int a = 0; a < 3; ++a) {
    if (std::abs(kSun[a]) < 1e-12) {
      if (p[a] < lo[a] || p[a] > hi[a]) return false;
      continue;
    }
    double u = (lo[a] - p[a]) / kSun[a], v = (hi[a] - p[a]) / kSun[a];
    if (u > v) std::swap(u, v);
    t0 = std::max(t0, u), t1 = std::min(t1, v);
  }
  return t0 < t1;
}
// Is the floor point p well inside (1) or well outside (-1) the box's sun shadow, 3 cm either way?
int shadowSide(const glm::dvec3& p, const glm::dvec3& lo, const glm::dvec3& hi) {
  int in = 0;
  for (const glm::dvec3& d : {glm::dvec3(0.0), glm::dvec3(0.03, 0, 0), glm::dvec3(-0.03, 0, 0), glm::dvec3(0, 0.03, 0), glm::dvec3(0, -0.03, 0)})
    in += inBoxShadow(p + d, lo, hi);
  return in == 5 ? 1 : in == 0 ? -1 : 0;
}

BasisOptions options() {
  BasisOptions o;
  o.regions = 16;
  o.groundReflectance = 0;
  return o;
}

glm::vec3 pixel(const ImageRGB& im, size_t i) { return {im.pixels[3 * i], im.pixels[3 * i + 1], im.pixels[3 * i + 2]}; }
}  // namespace

TEST(DaylightRelight, TheSunsPatchPerPixelIsTheWindowsOutlineCastOnTheFloor) {
  const Scene room = windowRoom(0.5, 0.0, 0.0);  // only the floor reflects: no light but the sun's
  DaylightBasis basis(room, sunOnly(16), options());
  const Camera cam = Camera::lookAt({0.6, 2.55, 2.5}, {2.2, 2.55, 0.0}, 320, 240, 220);
  const SeenPixels seen = seePixels(basis, cam);
  const ImageRGB e = irradianceImage(basis, seen, sunOnly(16));
  size_t floorPixels = 0, wrong = 0, inside = 0;
  double worstInside = 0;
  for (size_t i = 0; i < seen.surface.size(); ++i) {
    if (seen.surface[i] != 0) continue;
    const glm::dvec3& p = seen.point[i];
    if (nearPatchEdge(p.x, p.y, 0.05)) continue;  // the pixels' footprint and the sun's penumbra
    ++floorPixels;
    const bool lit = pixel(e, i).x > 0.5 * kSunE * std::sin(kElev);
    if (lit != inPatch(p.x, p.y)) ++wrong;
    if (inPatch(p.x, p.y)) {
      ++inside;
      worstInside = std::max(worstInside, std::abs(pixel(e, i).x / (kSunE * std::sin(kElev)) - 1));
    }
  }
  std::printf("floor pixels %zu (%zu in the patch): %zu on the wrong side of the outline; inside, E within %.3f %% of "
              "E_sun sin(e)\n",
              floorPixels, inside, wrong, 100 * worstInside);
  ASSERT_GT(inside, 2000u);
  EXPECT_LT(double(wrong), 0.002 * double(floorPixels));
  // Inside, the floor sees the sun fully (its disc stays within the window) and nothing else
  // lights it but light from the floor itself, which a plane cannot see.
  EXPECT_LT(worstInside, 0.01);
}

TEST(DaylightRelight, AVirtualBoxDarkensOnlyWhereItNewlyBlocksTheSunAndShowsItsAlbedo) {
  const Scene room = windowRoom(0.5, 0.6, 0.7);
  const SkyRadiance sky = sunOnly(16);
  DaylightBasis basis(room, sky, options());
  // A 40 cm box standing in the patch's middle.
  const double xc = W - 0.5 * (Z0 + Z1) / std::tan(kElev), yc = 0.5 * (Y0 + Y1), h = 0.2;
  const glm::dvec3 lo(xc - h, yc - h, 0.0), hi(xc + h, yc + h, 2 * h);
  const glm::dvec3 albedo(0.8, 0.4, 0.1);
  const Camera cam = Camera::lookAt({0.4, 0.6, 2.3}, {xc, yc, 0.0}, 320, 240, 220);
  const SeenPixels seen = seePixels(basis, cam);
  const ImageRGB ePhoto = irradianceImage(basis, seen, sky);
  std::vector<Polygon> faces;
  for (const auto& f : boxObject("box", lo, hi, albedo).polygons) {
    Polygon p = poly("box", f, 0.0);
    p.albedo = albedo;
    faces.push_back(p);
  }
  const int firstVirtual = int(room.polygons.size());
  ASSERT_EQ(basis.addObjects(faces).front(), firstVirtual);
  const SeenPixels seenBox = seePixels(basis, cam);
  const ImageRGB eBox = irradianceImage(basis, seenBox, sky);
  // The "photo": a uniform grey surface everywhere (what it shows does not matter to the ratio).
  ImageRGB photo(cam.width, cam.height);
  for (auto& v : photo.pixels) v = 0.25f;
  const ImageRGB out = differentialRender(photo, ePhoto, eBox, seenBox, firstVirtual, {6, albedo});
  auto shadowed = [&](const glm::dvec3& p) { return inBoxShadow(p, lo, hi); };
  size_t inShadow = 0, darkened = 0, stillLit = 0, wronglyDark = 0, top = 0, topRight = 0;
  std::vector<float> farRatio;
  std::vector<uint8_t> isFar(seenBox.surface.size(), 0);
  for (size_t i = 0; i < seenBox.surface.size(); ++i) {
    const int s = seenBox.surface[i];
    if (s == 0) {
      const glm::dvec3& p = seenBox.point[i];
      const double dx = std::max({lo.x - p.x, p.x - hi.x, 0.0}), dy = std::max({lo.y - p.y, p.y - hi.y, 0.0});
      const glm::dvec3 shifted = p + glm::dvec3(0.03, 0, 0), back = p - glm::dvec3(0.03, 0, 0);
      const bool solid = shadowed(p) && shadowed(shifted) && shadowed(back) && shadowed(p + glm::dvec3(0, 0.03, 0)) &&
                         shadowed(p - glm::dvec3(0, 0.03, 0));
      const bool clear = !shadowed(p) && !shadowed(shifted) && !shadowed(back) && !shadowed(p + glm::dvec3(0, 0.03, 0)) &&
                         !shadowed(p - glm::dvec3(0, 0.03, 0));
      if (solid && inPatch(p.x, p.y) && !nearPatchEdge(p.x, p.y, 0.03)) {
        ++inShadow;
        // What stays is the light the sun does not bring directly: a small share of it.
        if (pixel(out, i).x < 0.35f * 0.25f) ++darkened;
      } else if (clear && inPatch(p.x, p.y) && !nearPatchEdge(p.x, p.y, 0.03)) {
        ++stillLit;  // in the sun, out of the box's shadow: it must stay lit
        if (pixel(out, i).x < 0.35f * 0.25f) ++wronglyDark;
      } else if (std::hypot(dx, dy) > 1.0 && !inPatch(p.x, p.y) && !nearPatchEdge(p.x, p.y, 0.03)) {
        // Far from the box and out of the sun: lit only by the room, which lost the patch the
        // box shades and gained what the box reflects (the nearer, the more) — a smooth
        // change, no new edges: next to each other, two pixels change alike.
        isFar[i] = 1;
        farRatio.push_back(pixel(out, i).y / 0.25f);
      }
    } else if (s >= firstVirtual) {
      // The top face: lit by the sun at sin(e) (and a little by the room).
      const glm::dvec3& p = seenBox.point[i];
      if (std::abs(p.z - hi.z) > 1e-6 || p.x < lo.x + 0.03 || p.x > hi.x - 0.03 || p.y < lo.y + 0.03 || p.y > hi.y - 0.03) continue;
      ++top;
      const glm::vec3 want = glm::vec3(albedo / kPi * (kSunE * std::sin(kElev)));
      const glm::vec3 got = pixel(out, i);
      if (got.x > want.x && got.x < 1.15f * want.x && std::abs(got.y / got.x - 0.5f) < 0.02f) ++topRight;
    }
  }
  ASSERT_GT(farRatio.size(), 2000u);
  size_t pairs = 0, jumps = 0;
  for (size_t i = 0; i + 1 < isFar.size(); ++i) {
    if (!isFar[i] || !isFar[i + 1] || (i + 1) % size_t(cam.width) == 0) continue;
    ++pairs;
    jumps += std::abs(pixel(out, i).y - pixel(out, i + 1).y) > 0.005f * 0.25f;
  }
  std::sort(farRatio.begin(), farRatio.end());
  std::printf("box shadow: %zu of %zu pixels darkened below 35 %%; far floor (green): ratios %.3f - %.3f, %zu of %zu "
              "neighbours differing by more than 0.5 %%; top face: %zu of %zu at albedo x E / pi\n",
              darkened, inShadow, farRatio.front(), farRatio.back(), jumps, pairs, topRight, top);
  ASSERT_GT(inShadow, 200u);
  ASSERT_GT(top, 100u);
  std::printf("in the sun and out of the box's shadow: %zu of %zu pixels darkened\n", wronglyDark, stillLit);
  ASSERT_GT(stillLit, 1000u);
  EXPECT_GT(double(darkened), 0.98 * double(inShadow));
  EXPECT_LT(double(wronglyDark), 0.01 * double(stillLit));
  EXPECT_LT(double(jumps), 0.01 * double(pairs));
  EXPECT_EQ(topRight, top);
}

TEST(DaylightRelight, TheInteractivePathDrawsTheBoxAndItsSunShadowAsTheFullSolutionDoes) {
  // The paper's interactive method (the irradiance volume, samples through the window, nothing
  // solved again) against the full one (the box in the hierarchy, every basis solved again): the
  // box's sun shadow where ray casting puts it, the box's pixels alike.
  const Scene room = windowRoom(0.5, 0.6, 0.7);
  SkyRadiance sky = sunOnly(16);
  for (size_t k = 0; k < sky.region.size(); ++k) sky.region[k] = glm::dvec3(0.05 + 0.01 * double(k % 4));
  const double xc = W - 0.5 * (Z0 + Z1) / std::tan(kElev), yc = 0.5 * (Y0 + Y1), h = 0.2;
  const glm::dvec3 lo(xc - h, yc - h, 0.0), hi(xc + h, yc + h, 2 * h);
  const glm::dvec3 albedo(0.8, 0.4, 0.1);
  const Camera cam = Camera::lookAt({0.4, 0.6, 2.3}, {xc, yc, 0.0}, 320, 240, 220);
  ImageRGB photo(cam.width, cam.height);
  for (auto& v : photo.pixels) v = 0.25f;
  DaylightRelighting relit(room, photo, cam, sky, options());
  // A coarser volume than the default: the box's indirect light is a small part of its pixels here.
  relit.setInteractive({{6, 512}, 64});
  std::vector<Polygon> faces;
  for (const auto& f : boxObject("box", lo, hi, albedo).polygons) {
    Polygon p = poly("box", f, 0.0);
    p.albedo = albedo;
    faces.push_back(p);
  }
  const ImageRGB full = relit.render(sky, faces, DaylightMethod::NearField);
  const ImageRGB fast = relit.render(sky, faces, DaylightMethod::Volume);
  const SeenPixels room0 = seePixels(relit.basis(), cam);  // the room without the box
  size_t shadow = 0, darkened = 0, lit = 0, wronglyDark = 0, boxPixels = 0;
  double boxFast = 0, boxFull = 0;
  const RayScene box(std::vector<std::vector<glm::dvec3>>{faces[0].vertices, faces[1].vertices, faces[2].vertices,
                                                          faces[3].vertices, faces[4].vertices, faces[5].vertices});
  for (size_t i = 0; i < room0.surface.size(); ++i) {
    const glm::dvec3 eye = cam.center(), d = cam.rayDirection(double(i % 320) + 0.5, double(i / 320) + 0.5);
    const RayHit hb = box.intersect(Ray{glm::vec3(eye), glm::vec3(d), 0.f, 1e30f});
    if (hb.polygon >= 0) {
      // Well inside the box's outline (not its edge pixels, which the two paths cover alike only on average).
      bool inner = true;
      for (int dy = -2; dy <= 2 && inner; ++dy)
        for (int dx = -2; dx <= 2 && inner; ++dx)
          inner = box.intersect(Ray{glm::vec3(eye), glm::vec3(cam.rayDirection(double(i % 320) + 0.5 + dx, double(i / 320) + 0.5 + dy)), 0.f, 1e30f})
                      .polygon == hb.polygon;
      if (!inner) continue;
      ++boxPixels;
      boxFast += pixel(fast, i).x;
      boxFull += pixel(full, i).x;
      continue;
    }
    if (room0.surface[i] != 0) continue;
    const glm::dvec3& p = room0.point[i];
    if (!inPatch(p.x, p.y) || nearPatchEdge(p.x, p.y, 0.03)) continue;
    const int side = shadowSide(p, lo, hi);
    if (side > 0) {
      ++shadow;
      darkened += pixel(fast, i).x < 0.35f * pixel(photo, i).x;
    } else if (side < 0) {
      ++lit;
      wronglyDark += pixel(fast, i).x < 0.9f * pixel(full, i).x;
    }
  }
  std::printf("interactive path: %zu of %zu shadow pixels darkened below 35 %%, %zu of %zu sunlit ones darker than the full "
              "path's by 10 %%; the box's inner pixels %.4f vs the full path's %.4f (%zu pixels)\n",
              darkened, shadow, wronglyDark, lit, boxFast / double(boxPixels), boxFull / double(boxPixels), boxPixels);
  ASSERT_GT(shadow, 200u);
  ASSERT_GT(lit, 1000u);
  ASSERT_GT(boxPixels, 500u);
  EXPECT_GT(double(darkened), 0.8 * double(shadow));
  EXPECT_LT(double(wronglyDark), 0.1 * double(lit));
  EXPECT_NEAR(boxFast, boxFull, 0.1 * boxFull);

  // The room's light the interactive path keeps follows the solutions: after another sun's
  // solution (links refined for its patch, so the first sun's is solved again on them), the room
  // alone under the first sky is what the solutions say now, not what they said before.
  relit.render(sky, {}, DaylightMethod::Volume);
  const ImageRGB before = relit.lastIrradiance();
  relit.basis().sunSolution(glm::dvec3(0.75, 0.35, 0.55));  // through the window too
  relit.render(sky, {}, DaylightMethod::Volume);
  const ImageRGB now = irradianceImage(relit.basis(), seePixels(relit.basis(), cam), sky);
  float changed = 0;
  for (size_t i = 0; i < now.pixels.size(); ++i) changed = std::max(changed, std::abs(now.pixels[i] - before.pixels[i]));
  std::printf("the room alone after another sun's solution: largest change of irradiance %.3g\n", double(changed));
  EXPECT_GT(changed, 0.f);  // (else the check below would hold with a stale cache too)
  EXPECT_EQ(relit.lastIrradiance().pixels, now.pixels);
}

TEST(DaylightRelight, TheInteractivePartsAGpuRendererIsGivenAreTheCpuPaths) {
  // What a GPU renderer of the interactive method is given (DaylightRelighting::interactiveSky,
  // shadowReach, objectIndirect) must be what the CPU path renders with: samples that stand for
  // the windows' whole area, the sky's radiance per direction, the room relit under the sky, and
  // tiles that hold every pixel a box's shadows darken.
  const Scene room = windowRoom(0.5, 0.6, 0.7);
  SkyRadiance sky = sunOnly(16);
  for (size_t k = 0; k < sky.region.size(); ++k) sky.region[k] = glm::dvec3(0.2 + 0.02 * double(k), 0.3, 0.4);
  const Camera cam = Camera::lookAt({0.4, 0.6, 2.3}, {2.0, 2.5, 0.0}, 160, 120, 110);
  ImageRGB photo(cam.width, cam.height);
  for (auto& v : photo.pixels) v = 0.25f;
  BasisOptions o = options();
  auto engine = std::make_shared<radiosity::Options>();
  engine->epsilon = 0.03;  // coarse: this is about the parts, not the solution's accuracy
  engine->minArea = 0.02;
  o.engine = engine;
  DaylightRelighting relit(room, photo, cam, sky, o);
  relit.setInteractive({{4, 256}, 64});
  const InteractiveSky light = relit.interactiveSky(sky);
  double area = 0;
  for (const auto& s : light.window) {
    area += s.area;
    EXPECT_NEAR(s.point.x, W, 1e-9);  // on the window
    EXPECT_TRUE(s.point.y > Y0 - 1e-9 && s.point.y < Y1 + 1e-9 && s.point.z > Z0 - 1e-9 && s.point.z < Z1 + 1e-9);
    EXPECT_NEAR(glm::dot(s.normal, glm::dvec3(-1, 0, 0)), 1.0, 1e-12);  // into the room
  }
  EXPECT_NEAR(area, (Y1 - Y0) * (Z1 - Z0), 1e-9);
  EXPECT_GE(light.window.size(), 60u);
  ASSERT_TRUE(light.sun);
  ASSERT_EQ(light.sunDirections.size(), 4u);
  for (const auto& d : light.sunDirections) EXPECT_GT(glm::dot(d, kSun), std::cos(0.3 * kPi / 180));
  // The sky's radiance per direction: each region's own at its centre, the ground's (none here) below.
  const SkyRegions& regions = relit.basis().regions();
  for (int k = 0; k < int(sky.region.size()); ++k) {
    const glm::dvec3 c = regions.centre(k);
    const double phi = std::atan2(c.y, c.x), theta = std::acos(c.z);
    const int u = std::clamp(int((phi + kPi) / (2 * kPi) * light.radiance.width), 0, light.radiance.width - 1);
    const int v = std::clamp(int(theta / kPi * light.radiance.height), 0, light.radiance.height - 1);
    EXPECT_NEAR(light.radiance.at(u, v).x, sky.region[size_t(k)].x, 1e-6) << "region " << k;
  }
  EXPECT_EQ(light.radiance.at(0, light.radiance.height - 1), glm::vec3(0.f));
  // The room under the sky is the render without objects; radiance per unit irradiance times the
  // irradiance gives it back.
  const ImageRGB alone = relit.render(sky, {}, DaylightMethod::Volume);
  EXPECT_EQ(light.room.pixels, alone.pixels);
  const ImageRGB& e = relit.lastIrradiance();
  for (size_t i = 0; i < alone.pixels.size(); ++i)
    if (light.gain.pixels[i] > 0) EXPECT_NEAR(light.gain.pixels[i] * e.pixels[i], alone.pixels[i], 1e-4f * alone.pixels[i]);
  // A box in the sun's patch: every pixel its shadows darken lies in a tile shadowReach flags.
  const double xc = W - 0.5 * (Z0 + Z1) / std::tan(kElev), yc = 0.5 * (Y0 + Y1), h = 0.2;
  std::vector<Polygon> faces;
  for (const auto& f : boxObject("box", {xc - h, yc - h, 0.0}, {xc + h, yc + h, 2 * h}, glm::dvec3(0.5)).polygons) {
    Polygon p = poly("box", f, 0.0);
    p.albedo = glm::dvec3(0.5);
    faces.push_back(p);
  }
  const ImageRGB withBox = relit.render(sky, faces, DaylightMethod::Volume);
  const ShadowReach reach = relit.shadowReach(light, {xc, yc, h}, std::sqrt(3.0) * h);
  ASSERT_EQ(reach.tilesX, (cam.width + 7) / 8);
  ASSERT_EQ(reach.tilesY, (cam.height + 7) / 8);
  size_t darker = 0, outside = 0, flagged = 0;
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      if (withBox.at(x, y).x < alone.at(x, y).x * 0.999f) {
        ++darker;
        outside += !reach.any(size_t(y / 8) * size_t(reach.tilesX) + size_t(x / 8));
      }
    }
  for (size_t t = 0; t < size_t(reach.tilesX) * size_t(reach.tilesY); ++t) flagged += reach.any(t);
  std::printf("the box darkens %zu pixels, %zu of them outside the %zu of %d tiles flagged\n", darker, outside, flagged,
              reach.tilesX * reach.tilesY);
  EXPECT_GT(darker, 100u);
  EXPECT_EQ(outside, 0u);
  EXPECT_LT(flagged, size_t(reach.tilesX * reach.tilesY));  // (a culling that flags everything would pass the above)
  // The box's indirect light per vertex, on both sides of every face: the faces' front sides
  // lit by the room (the sky's light reflected by its walls), none negative.
  const ObjectIndirect ind = relit.objectIndirect(sky, faces);
  ASSERT_EQ(ind.front.size(), faces.size());
  for (size_t f = 0; f < faces.size(); ++f) {
    ASSERT_EQ(ind.front[f].size(), faces[f].vertices.size());
    ASSERT_EQ(ind.back[f].size(), faces[f].vertices.size());
    for (const auto& v : ind.front[f]) EXPECT_GT(v.x, 0.0);
    for (const auto& v : ind.back[f]) EXPECT_GE(v.x, 0.0);
  }
}

namespace {
// Pixels of shown polygons, each with a reflectance of its own, lit in the model
//   E(rho) = sky + rho x room (the unseen polygons' reflected light, affine in their reflectance)
// plus, on the sunlit half, the sun; the photo made from a known unseen reflectance. What
// fitUnseenReflectance is given is only what a renderer gives it: the irradiance at two trial
// reflectances and the sun.
struct UnseenScene {
  SeenPixels px;
  ImageRGB photo, restA, restB, sun;
  std::vector<bool> usable{true, true};
  UnseenScene(double truth, double a, double b, double roomShare) {
    const int w = 40, h = 20;
    px.width = w;
    px.height = h;
    const size_t n = size_t(w) * size_t(h);
    px.surface.assign(n, -1);
    px.normal.assign(n, glm::dvec3(0, 0, 1));
    photo = restA = restB = sun = ImageRGB(w, h);
    const glm::dvec3 sunE(3.0, 2.8, 2.5), sky(0.30, 0.35, 0.45), room = roomShare * glm::dvec3(0.5, 0.45, 0.4);
    const glm::dvec3 rho[2] = {{0.4, 0.3, 0.2}, {0.7, 0.7, 0.6}};
    for (size_t i = 0; i < n; ++i) {
      const int x = int(i % size_t(w)), y = int(i / size_t(w));
      const int s = x < w / 2 ? 0 : 1;
      px.surface[i] = s;
      // Shaded pixels see the sky and the room a little less (further from the window).
      const double k = 1.0 + 0.01 * y;
      const glm::dvec3 es = y < h / 2 ? sunE * 0.5 : glm::dvec3(0.0);  // the sun at 60 degrees from the normal
      for (int c = 0; c < 3; ++c) {
        const double ea = k * (sky[c] + a * room[c]), eb = k * (sky[c] + b * room[c]), et = k * (sky[c] + truth * room[c]);
        restA.pixels[3 * i + c] = float(ea);
        restB.pixels[3 * i + c] = float(eb);
        sun.pixels[3 * i + c] = float(es[c]);
        photo.pixels[3 * i + c] = float(rho[s][c] * (et + es[c]) / kPi);
      }
    }
  }
};
const glm::dvec3 kSunUp(0.0, std::sqrt(0.75), 0.5);  // 60 degrees from the pixels' normal
}  // namespace

TEST(DaylightRelight, TheUnseenPolygonsReflectanceIsWhereTheSunlitAndShadedPixelsAgree) {
  for (const double truth : {0.25, 0.55, 0.85}) {
    UnseenScene scene(truth, 0.5, 0.8, 1.0);
    const UnseenFit fit = fitUnseenReflectance(scene.px, scene.photo, scene.restA, scene.restB, scene.sun, 0.5, 0.8, kSunUp,
                                               glm::dvec3(3.0, 2.8, 2.5), scene.usable);
    ASSERT_TRUE(fit.ok) << truth;
    EXPECT_EQ(fit.polygons, 2);
    EXPECT_NEAR(fit.rho.x, truth, 0.01) << "trial reflectances 0.5 and 0.8, truth outside them or between";
  }
  // A shown polygon not usable (a lamp's, say) tells nothing; with none left there is no fit.
  UnseenScene scene(0.55, 0.5, 0.8, 1.0);
  scene.usable = {false, false};
  EXPECT_FALSE(fitUnseenReflectance(scene.px, scene.photo, scene.restA, scene.restB, scene.sun, 0.5, 0.8, kSunUp,
                                    glm::dvec3(3.0, 2.8, 2.5), scene.usable)
                   .ok);
  // Unseen polygons that light the shaded pixels hardly at all: their reflectance is not asked.
  UnseenScene faint(0.55, 0.5, 0.8, 0.01);
  EXPECT_FALSE(fitUnseenReflectance(faint.px, faint.photo, faint.restA, faint.restB, faint.sun, 0.5, 0.8, kSunUp,
                                    glm::dvec3(3.0, 2.8, 2.5), faint.usable)
                   .ok);
  // Sunlit pixels three times as bright as any unseen reflectance can explain (a sun three times
  // too weak in the sky image): no value makes the two agree, and a bound is no measurement.
  UnseenScene off(0.55, 0.5, 0.8, 1.0);
  for (size_t i = 0; i < off.sun.pixels.size(); ++i)
    if (off.sun.pixels[i] > 0) off.photo.pixels[i] *= 3;
  const UnseenFit none = fitUnseenReflectance(off.px, off.photo, off.restA, off.restB, off.sun, 0.5, 0.8, kSunUp,
                                              glm::dvec3(3.0, 2.8, 2.5), off.usable);
  EXPECT_FALSE(none.ok);
  EXPECT_FALSE(none.why.empty());
  // No sun on any pixel: nothing to compare the shaded pixels with.
  UnseenScene dark(0.55, 0.5, 0.8, 1.0);
  dark.sun = ImageRGB(dark.px.width, dark.px.height);
  EXPECT_FALSE(fitUnseenReflectance(dark.px, dark.photo, dark.restA, dark.restB, dark.sun, 0.5, 0.8, kSunUp,
                                    glm::dvec3(3.0, 2.8, 2.5), dark.usable)
                   .ok);
}

TEST(DaylightRelight, AOneSidedVirtualLampSeenFromBehindIsADarkPanelAndFromTheFrontItsOwnRadiance) {
  // A 40 cm virtual panel 80 cm above the floor, seen from above: facing up, the camera sees its
  // emitting face (exitance / pi); facing down, its back — a panel that reflects nothing (one face
  // emits, the other is the lamp's dark housing), never the floor behind it showing through.
  const Scene room = windowRoom(0.5, 0.6, 0.7);
  SkyRadiance sky = sunOnly(16);
  for (auto& r : sky.region) r = glm::dvec3(0.05);
  sky.sun.found = false;  // an overcast sky: the lamp's light on the floor stands out
  const double xc = 1.6, yc = 2.3, a = 0.2, z = 0.8;
  const Camera cam = Camera::lookAt({0.4, 0.6, 2.3}, {xc, yc, 0.0}, 320, 240, 220);
  ImageRGB photo(cam.width, cam.height);
  for (auto& v : photo.pixels) v = 0.25f;
  BasisOptions coarse = options();  // the panel's pixels and its light on the floor need no fine mesh
  auto engine = std::make_shared<radiosity::Options>();
  engine->minArea = 0.05;
  coarse.engine = engine;
  DaylightRelighting relit(room, photo, cam, sky, coarse);
  const std::vector<glm::dvec3> up{{xc - a, yc - a, z}, {xc + a, yc - a, z}, {xc + a, yc + a, z}, {xc - a, yc + a, z}};
  const std::vector<glm::dvec3> down(up.rbegin(), up.rend());
  const glm::dvec3 m(3.0, 2.0, 1.0);
  const RayScene panel(std::vector<std::vector<glm::dvec3>>{up});
  std::vector<size_t> inner;  // pixels well inside the panel's outline
  for (int y = 2; y < cam.height - 2; ++y)
    for (int x = 2; x < cam.width - 2; ++x) {
      bool all = true;
      for (int d = -2; d <= 2 && all; d += 4)
        for (int e = -2; e <= 2 && all; e += 4)
          all = panel.intersect(Ray{glm::vec3(cam.center()), glm::vec3(cam.rayDirection(x + 0.5 + d, y + 0.5 + e)), 0.f, 1e30f})
                    .polygon >= 0;
      if (all) inner.push_back(size_t(y) * size_t(cam.width) + size_t(x));
    }
  ASSERT_GT(inner.size(), 300u);
  const ImageRGB front = relit.render(sky, {}, DaylightMethod::NearField, silentProgress(), {BasisLamp{"up", up, m, false}});
  const ImageRGB back = relit.render(sky, {}, DaylightMethod::NearField, silentProgress(), {BasisLamp{"down", down, m, false}});
  size_t ownRadiance = 0, dark = 0;
  for (size_t i : inner) {
    const glm::vec3 f = pixel(front, i), b = pixel(back, i);
    ownRadiance += glm::length(f - glm::vec3(m / kPi)) < 1e-4f;
    dark += std::max({b.x, b.y, b.z}) < 1e-6f;
  }
  std::printf("%zu pixels inside the panel: facing the camera %zu show exitance / pi, facing away %zu are dark\n", inner.size(),
              ownRadiance, dark);
  EXPECT_EQ(ownRadiance, inner.size());
  EXPECT_EQ(dark, inner.size());
  // Facing down it lights the floor below it, which the camera sees beside it.
  const SeenPixels seen = seePixels(relit.basis(), cam);
  double gain = 0;
  size_t floor = 0;
  for (size_t i = 0; i < seen.surface.size(); ++i)
    if (seen.surface[i] == 0 && std::hypot(seen.point[i].x - xc, seen.point[i].y - yc) < 0.6) {
      gain += pixel(back, i).x / 0.25 - pixel(front, i).x / 0.25;
      ++floor;
    }
  ASSERT_GT(floor, 100u);
  std::printf("the floor within 60 cm of the panel: %.2f x the photo more light with the panel facing down than up\n",
              gain / double(floor));
  EXPECT_GT(gain / double(floor), 0.5);
}

TEST(DaylightRelight, AKeptSessionOpensAsItWasSavedAndAnotherPhotoRoomOrADamagedFileIsRefusedByName) {
  // What a project keeps (daylight/solution.bin): opened again, the estimates and the images are
  // the solved session's; kept for another photo or room, or damaged, it is refused naming the
  // file, and openDaylightRelighting then solves as for a bundle and says why.
  Scene room = windowRoom(0.5, 0.6, 0.7);
  {  // a block in the sun's patch, so that what the windows' light reaches depends on visibility
    const double xc = W - 0.5 * (Z0 + Z1) / std::tan(kElev), yc = 0.5 * (Y0 + Y1);
    for (const auto& f : boxObject("block", {xc + 0.1, yc - 0.15, 0.0}, {xc + 0.4, yc + 0.15, 0.3}, glm::dvec3(0.5)).polygons)
      room.polygons.push_back(poly("block", f, 0.5));
  }
  SkyRadiance sky = sunOnly(4);
  for (auto& r : sky.region) r = glm::dvec3(0.05);
  const Camera cam = Camera::lookAt({0.4, 0.6, 2.3}, {1.6, 2.3, 0.0}, 160, 120, 110);
  ImageRGB photo(cam.width, cam.height);
  for (size_t i = 0; i < photo.pixels.size(); ++i) photo.pixels[i] = 0.2f + 0.1f * float(i % 7) / 7.f;
  BasisOptions coarse = options();  // a coarse hierarchy and four regions: what is kept matters, not its detail
  coarse.regions = 4;
  coarse.pieceDeg = 6;
  auto engine = std::make_shared<radiosity::Options>();
  engine->minArea = 0.1;
  engine->epsilon = 0.02;
  engine->visibilityRays = 4;
  coarse.engine = engine;
  DaylightRelighting solved(room, photo, cam, sky, coarse);
  // Kept after the session showed another sun (as the workbench saves): the basis then holds that
  // sun's solution, and opening must still solve nothing.
  SkyRadiance other = sky;
  other.sun.direction = glm::normalize(glm::dvec3(std::cos(0.8), 0.3, std::sin(0.8)));
  solved.render(other, {}, DaylightMethod::NearField);
  const std::string dir = ::testing::TempDir() + "/relume_kept_session";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir + "/daylight");
  const std::string file = dir + "/daylight/solution.bin";
  solved.save(file);
  DaylightRelighting kept(room, photo, cam, sky, coarse, file);
  EXPECT_EQ(kept.basis().revision(), 1u);  // read, nothing solved since (every solve counts)
  EXPECT_TRUE(kept.photoIrradiance().pixels == solved.photoIrradiance().pixels);
  EXPECT_EQ(kept.reflectances(), solved.reflectances());
  EXPECT_EQ(kept.estimated(), solved.estimated());
  EXPECT_EQ(kept.unseenFit().ok, solved.unseenFit().ok);
  EXPECT_EQ(kept.unseenFit().why, solved.unseenFit().why);
  EXPECT_EQ(kept.basis().engine().nodes().size(), solved.basis().engine().nodes().size());
  EXPECT_EQ(kept.basis().engine().links().size(), solved.basis().engine().links().size());
  auto farthest = [](const ImageRGB& a, const ImageRGB& b) {
    double worst = 0, mean = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i) {
      worst = std::max(worst, double(std::abs(a.pixels[i] - b.pixels[i])));
      mean += std::abs(double(b.pixels[i])) / double(a.pixels.size());
    }
    return worst / std::max(mean, 1e-12);  // relative to the image's mean
  };
  // A virtual lamp and a box added first thing, solved on the kept hierarchy as on the solved one.
  {
    const double xc = 1.6, yc = 2.3, h = 0.2;
    const std::vector<glm::dvec3> panel{{xc - h, yc - h, 1.5}, {xc - h, yc + h, 1.5}, {xc + h, yc + h, 1.5}, {xc + h, yc - h, 1.5}};
    std::vector<Polygon> faces;
    for (const auto& f : boxObject("box", {xc - h, yc + 0.5, 0.0}, {xc + h, yc + 0.9, 2 * h}, glm::dvec3(0.6)).polygons) {
      Polygon p = poly("box", f, 0.0);
      p.albedo = glm::dvec3(0.6);
      faces.push_back(p);
    }
    const std::vector<BasisLamp> lamps{BasisLamp{"v", panel, glm::dvec3(3.0), false}};
    const double d = farthest(kept.render(sky, faces, DaylightMethod::NearField, silentProgress(), lamps),
                              solved.render(sky, faces, DaylightMethod::NearField, silentProgress(), lamps));
    std::printf("kept vs solved with a virtual lamp and a box: largest difference %.2g of the mean\n", d);
    EXPECT_LT(d, 1e-6);  // the openings' links as they were: their visibility along the sun's beam is kept too
  }
  // The same images: the photo's irradiance, and the room under another sun (its patch refined
  // again on the kept hierarchy, as on the solved one).
  EXPECT_LT(farthest(kept.photoIrradiance(), solved.photoIrradiance()), 1e-6);
  const ImageRGB a = solved.render(other, {}, DaylightMethod::NearField);
  const ImageRGB b = kept.render(other, {}, DaylightMethod::NearField);
  const double diff = farthest(b, a);
  std::printf("kept vs solved under another sun: largest difference %.2g of the mean\n", diff);
  EXPECT_LT(diff, 1e-6);
  const ImageRGB c = solved.render(sky, {}, DaylightMethod::NearField);  // each session does the same from here on
  EXPECT_LT(farthest(kept.render(sky, {}, DaylightMethod::NearField), c), 1e-6);
  EXPECT_GT(farthest(a, c), 0.05);  // another sun: another image

  auto refusal = [&](const Scene& r, const ImageRGB& p) {
    try {
      DaylightRelighting again(r, p, cam, sky, coarse, file);
    } catch (const Error& e) {
      EXPECT_EQ(e.file(), file);
      return e.problem();
    }
    return std::string("opened");
  };
  ImageRGB otherPhoto = photo;
  otherPhoto.pixels[100] += 0.01f;
  EXPECT_NE(refusal(room, otherPhoto).find("another photo"), std::string::npos);
  Scene moved = room;
  for (auto& poly : moved.polygons)
    for (auto& v : poly.vertices) v.x += 0.01;
  EXPECT_NE(refusal(moved, photo).find("other polygons"), std::string::npos);
  // One byte changed in the middle, and the file cut short: damaged.
  std::vector<char> bytes;
  {
    std::ifstream in(file, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  ASSERT_GT(bytes.size(), 1000u);
  auto write = [&](const std::vector<char>& b) {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(b.data(), std::streamsize(b.size()));
  };
  std::vector<char> flipped = bytes;
  flipped[flipped.size() / 2] ^= 0x10;
  write(flipped);
  EXPECT_NE(refusal(room, photo).find("damaged"), std::string::npos);
  write(std::vector<char>(bytes.begin(), bytes.begin() + std::ptrdiff_t(bytes.size() / 3)));
  EXPECT_NE(refusal(room, photo).find("damaged"), std::string::npos);
  // A project whose kept session is damaged opens all the same, solved again, and says why.
  room.sourceFile = dir + "/project.json";
  EXPECT_EQ(keptSolutionFile(room), file);
  std::string how;
  const auto opened = openDaylightRelighting(room, photo, cam, sky, coarse, silentProgress(), &how);
  EXPECT_NE(how.find("not used"), std::string::npos) << how;
  EXPECT_NE(how.find(file), std::string::npos) << how;
  EXPECT_EQ(opened->reflectances(), solved.reflectances());
  write(bytes);  // whole again: opened from the file
  how.clear();
  const auto reopened = openDaylightRelighting(room, photo, cam, sky, coarse, silentProgress(), &how);
  EXPECT_NE(how.find("opened the project's kept"), std::string::npos) << how;
  std::filesystem::remove_all(dir);
}
