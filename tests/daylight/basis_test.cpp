// Basis radiosity solutions through a window (Grosch, Eble, Mueller 2007, §5, §6.1): energy
// through an opening against closed forms, the regions' combination against a solve with the
// sky's exact radiance per direction, and the sun's beam against the flux it carries.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <glm/geometric.hpp>
#include <memory>
#include <numbers>

#include "relume/daylight/basis.h"
#include "relume/geometry/binary.h"
#include "relume/geometry/error.h"
#include "relume/geometry/progress.h"
#include "relume/geometry/scene.h"
#include "relume/radiosity/form_factor.h"
#include "relume/radiosity/hierarchy.h"
#include "relume/relight/relighter.h"
#include "window_room.h"

using namespace relume;
using namespace relume::daylight;
using namespace relume::testing;

namespace {
constexpr double kPi = std::numbers::pi;
BasisOptions coarse(int regions) {
  BasisOptions o;
  o.regions = regions;
  o.groundReflectance = 0;  // a black ground
  auto e = std::make_shared<radiosity::Options>();
  e->minArea = 0.01;
  o.engine = e;
  return o;
}

SkyRadiance uniformSky(int regions, double l) {
  SkyRadiance s;
  s.region.assign(size_t(regions), glm::dvec3(l));
  return s;
}

// A smooth sky: brighter towards the zenith (the CIE overcast sky's 1 + 2 sin(elevation)) and
// towards one azimuth.
double smoothSky(const glm::dvec3& d) {
  if (d.z < 0) return 0.0;
  const double az = std::atan2(d.y, d.x);
  return (1.0 + 2.0 * d.z) / 3.0 * (1.0 + 0.4 * std::cos(az - 0.5));
}

// Each region's mean of the smooth sky, integrated over the cell (solid-angle weighted).
SkyRadiance smoothSkyMeans(const SkyRegions& regions) {
  SkyRadiance s;
  for (int k = 0; k < regions.size(); ++k) {
    const auto& c = regions.cell(k);
    double sum = 0, w = 0;
    constexpr int n = 24;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const double e = c.elev0 + (i + 0.5) / n * (c.elev1 - c.elev0);
        const double a = c.azim0 + (j + 0.5) / n * (c.azim1 - c.azim0);
        const double dw = std::cos(e);
        sum += dw * smoothSky({std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)});
        w += dw;
      }
    s.region.push_back(glm::dvec3(sum / w));
  }
  return s;
}
}  // namespace

TEST(DistantLight, UniformSkyThroughAWindowGivesHalfPiLAtItsCentre) {
  // The kernel alone: a point at the window's centre facing out sees the upper half of the sky.
  const auto win = facingMinusX(W, Y0, Y1, Z0, Z1);
  radiosity::DistantLight sky;
  sky.radiance = [](const glm::dvec3& d) { return d.z >= 0 ? 1.0 : 0.0; };
  const glm::dvec3 centre(W - 1e-4, 0.5 * (Y0 + Y1), 0.5 * (Z0 + Z1));
  EXPECT_NEAR(radiosity::distantFormFactor(centre, {1, 0, 0}, win, sky) * kPi, kPi / 2, 0.02 * kPi / 2);
  // Facing into the room it sees nothing through the window behind it; outside it gets nothing.
  EXPECT_EQ(radiosity::distantFormFactor(centre, {-1, 0, 0}, win, sky), 0.0);
  EXPECT_EQ(radiosity::distantFormFactor(centre + glm::dvec3(1, 0, 0), {1, 0, 0}, win, sky), 0.0);
}

TEST(DaylightBasis, UniformSkyAndBlackGroundGiveHalfPiLAtTheWindowsCentre) {
  // The whole path: a small grey receiver 5 mm inside the window's centre, facing out, in a
  // black room; a uniform sky of radiance L combined from the regions' bases.
  Scene room = windowRoom(0, 0, 0);
  const double yc = 0.5 * (Y0 + Y1), zc = 0.5 * (Z0 + Z1), h = 0.01, x = W - 0.005;
  room.polygons.push_back(poly("probe", facingPlusX(x, yc - h, yc + h, zc - h, zc + h), 0.5));
  const int probe = int(room.polygons.size()) - 1;
  constexpr double L = 3.0;
  DaylightBasis basis(room, uniformSky(64, L), coarse(64));
  const auto b = basis.combine(uniformSky(64, L));
  const double e = basis.surfaceMean(b, probe).x / 0.5;
  std::printf("uniform sky L = %g: irradiance at the window's centre %.4f, pi L / 2 = %.4f (%+.2f %%)\n", L, e,
              kPi * L / 2, 100 * (e / (kPi * L / 2) - 1));
  EXPECT_NEAR(e, kPi * L / 2, 0.02 * kPi * L / 2);
}

TEST(DaylightBasis, RegionsCombinedMatchTheExactSkyWithinThreePercent) {
  const Scene room = windowRoom(0.3, 0.7, 0.8);
  for (int n : {16, 64}) {
    const SkyRegions regions(n);
    const SkyRadiance means = smoothSkyMeans(regions);
    DaylightBasis basis(room, means, coarse(n));
    const auto combined = basis.combine(means);
    auto exact = std::make_shared<radiosity::DistantLight>();
    exact->radiance = smoothSky;
    const auto truth = basis.solveFor(exact);
    double worst = 0;
    std::string where;
    for (size_t s = 0; s < room.polygons.size(); ++s) {
      if (room.polygons[s].kind == PolygonKind::Window) continue;
      const double t = basis.surfaceMean(truth, int(s)).x, c = basis.surfaceMean(combined, int(s)).x;
      ASSERT_GT(t, 0) << room.polygons[s].name;
      if (std::abs(c / t - 1) > worst) worst = std::abs(c / t - 1), where = room.polygons[s].name;
    }
    std::printf("N = %d regions: worst per-polygon mean radiosity %.2f %% off the exact sky's (%s); %.3f s per basis\n", n,
                100 * worst, where.c_str(), basis.secondsPerBasis());
    if (n == 64) EXPECT_LT(worst, 0.03);
  }
}

TEST(DaylightBasis, TheSunsBeamLandsWhereTheWindowLetsItAndCarriesItsFlux) {
  const double rho = 0.5;
  const Scene room = windowRoom(rho, 0, 0);  // only the floor reflects
  // Links refined for another sun (45 degrees up, 20 degrees round): the beam asked for below
  // lands elsewhere on the same links.
  SkyRadiance refine = uniformSky(16, 0.05);
  refine.sun.found = true;
  refine.sun.direction = {std::cos(kPi / 4) * std::cos(0.35), std::cos(kPi / 4) * std::sin(0.35), std::sin(kPi / 4)};
  refine.sun.irradiance = glm::dvec3(1.0);
  BasisOptions options = coarse(16);
  options.engine = nullptr;  // the engine's own refinement (2e-3 m^2 elements)
  DaylightBasis basis(room, refine, options);
  const double elev = 30 * kPi / 180;
  const glm::dvec3 sun(std::cos(elev), 0, std::sin(elev));
  const auto b = basis.sunSolution(sun);
  // All of the beam through the window (irradiance 1 normal to it) lands on the floor.
  const double flux = (Y1 - Y0) * (Z1 - Z0) * sun.x;
  const double floorMean = basis.surfaceMean(b, 0).x;
  EXPECT_NEAR(floorMean, rho * flux / (W * D), 0.02 * rho * flux / (W * D));
  // Inside the patch the floor gets sin(elevation); far from it nothing.
  const auto& eng = basis.engine();
  const double xMid = W - 0.5 * (Z0 + Z1) / std::tan(elev);
  const int inPatch = eng.findLeaf(0, eng.toUV(0, {xMid, 0.5 * (Y0 + Y1), 0}));
  const int outside = eng.findLeaf(0, eng.toUV(0, {0.3, 0.3, 0}));
  EXPECT_NEAR(b[size_t(inPatch)].x, rho * std::sin(elev), 0.03 * rho * std::sin(elev));
  EXPECT_LT(b[size_t(outside)].x, 1e-6);
  std::printf("sun at 30 deg: floor mean %.5f (flux says %.5f); patch centre %.4f (rho sin e = %.4f)\n", floorMean,
              rho * flux / (W * D), b[size_t(inPatch)].x, rho * std::sin(elev));
}

TEST(DaylightBasis, ARoomWithoutAWindowOrWithAWindowFacingOutOrInNoWallIsRefused) {
  Scene room = windowRoom(0.5, 0.5, 0.5);
  Scene closed = room;
  closed.polygons.pop_back();
  try {
    DaylightBasis b(closed, uniformSky(16, 1), coarse(16));
    FAIL() << "a room without a window was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("window_room.json"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no window"), std::string::npos) << e.what();
  }
  Scene reversed = room;
  auto& v = reversed.polygons.back().vertices;
  std::reverse(v.begin(), v.end());
  try {
    DaylightBasis b(reversed, uniformSky(16, 1), coarse(16));
    FAIL() << "a window facing out of the room was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("faces away"), std::string::npos) << e.what();
  }
  Scene floating = room;  // half a metre into the room, in no wall
  for (auto& p : floating.polygons.back().vertices) p.x -= 0.5;
  try {
    DaylightBasis b(floating, uniformSky(16, 1), coarse(16));
    FAIL() << "a window in no wall was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not in a wall"), std::string::npos) << e.what();
  }
}

TEST(DaylightBasis, ConeTestNeverRulesOutADirectionInsideTheCell) {
  const SkyRegions regions(64);
  uint64_t s = 12345;
  auto uni = [&] {
    s = s * 6364136223846793005ull + 1442695040888963407ull;
    return double(s >> 11) / 9007199254740992.0;
  };
  for (int i = 0; i < 200000; ++i) {
    const double z = uni() * 2 - 1, a = uni() * 2 * kPi, r = std::sqrt(1 - z * z);
    const glm::dvec3 axis(r * std::cos(a), r * std::sin(a), z);
    const double half = uni() * 0.3;
    // A direction within the cone: rotate the axis by up to `half`.
    const double zz = uni() * 2 - 1, aa = uni() * 2 * kPi, rr = std::sqrt(1 - zz * zz);
    const glm::dvec3 t = glm::normalize(glm::cross(axis, glm::dvec3(rr * std::cos(aa), rr * std::sin(aa), zz)));
    const double ang = uni() * half;
    const glm::dvec3 d = std::cos(ang) * axis + std::sin(ang) * t;
    const int k = regions.regionOf(d);
    if (k < 0) continue;
    ASSERT_TRUE(coneMeetsCell(axis, half, regions.cell(k))) << "axis " << axis.x << " " << axis.y << " " << axis.z;
  }
}

TEST(DaylightBasis, ACellHoldsEveryDirectionOfAConeItIsSaidToHold) {
  // Cones around random axes, their directions on the rim and inside: where coneInsideCell says
  // the cone lies in the axis's region, regionOf puts every one of them there. 64 regions and 7
  // (whose top cell is a whole cap around the zenith).
  for (const int n : {64, 7}) {
    const SkyRegions regions(n);
    uint64_t s = 777 + uint64_t(n);
    auto uni = [&] {
      s = s * 6364136223846793005ull + 1442695040888963407ull;
      return double(s >> 11) / 9007199254740992.0;
    };
    int inside = 0;
    for (int i = 0; i < 20000; ++i) {
      const double z = uni(), a = uni() * 2 * kPi, r = std::sqrt(1 - z * z);
      const glm::dvec3 axis(r * std::cos(a), r * std::sin(a), z);
      const double half = uni() * 0.4;
      const int k = regions.regionOf(axis);
      if (k < 0 || !coneInsideCell(axis, half, regions.cell(k))) continue;
      ++inside;
      const glm::dvec3 t0 = glm::normalize(glm::cross(axis, std::abs(axis.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0)));
      const glm::dvec3 t1 = glm::cross(axis, t0);
      for (int j = 0; j < 64; ++j) {
        const double phi = 2 * kPi * j / 64, ang = j % 2 ? half : uni() * half;
        const glm::dvec3 d = std::cos(ang) * axis + std::sin(ang) * (std::cos(phi) * t0 + std::sin(phi) * t1);
        ASSERT_EQ(regions.regionOf(d), k) << n << " regions, axis " << axis.x << " " << axis.y << " " << axis.z
                                          << ", half-angle " << half;
      }
    }
    // Not vacuous: a good share of the narrow cones fit in their cells.
    EXPECT_GT(inside, 2000) << n << " regions";
  }
  // The cones that cannot fit: wider than a hemisphere's edge, or reaching below the horizon.
  const SkyRegions one(1);
  EXPECT_TRUE(coneInsideCell({0, 0, 1}, 1.5, one.cell(0)));
  EXPECT_FALSE(coneInsideCell({0, 0, 1}, kPi / 2, one.cell(0)));
  EXPECT_FALSE(coneInsideCell({1, 0, 0.05}, 0.1, one.cell(0)));
}

TEST(DaylightBasis, AWindowPieceLitAlikeIsSummedWholeAndGivesTheFactorItsPartsGive) {
  // A sky region's light with and without `uniform`: cut to 1.5-degree pieces everywhere, or whole
  // where the region lights the piece throughout. The cosine-weighted factor is additive over
  // pieces, so the two agree to rounding, at points near and far from the window, facing any way.
  const SkyRegions regions(64);
  const std::vector<glm::dvec3> window = {{0, 0.5, 0.8}, {0, 2.0, 0.8}, {0, 2.0, 2.0}, {0, 0.5, 2.0}};
  // The window is in the plane x = 0, its normal (+x) into the room; light arrives from -x.
  uint64_t s = 4242;
  auto uni = [&] {
    s = s * 6364136223846793005ull + 1442695040888963407ull;
    return double(s >> 11) / 9007199254740992.0;
  };
  double worst = 0, total = 0;
  for (int k = 0; k < regions.size(); ++k) {
    radiosity::DistantLight cut, whole;
    const SkyRegions::Cell cell = regions.cell(k);
    cut.radiance = [&regions, k](const glm::dvec3& d) { return regions.regionOf(d) == k ? 1.0 : 0.0; };
    cut.mayShine = [cell](const glm::dvec3& axis, double half) { return coneMeetsCell(axis, half, cell); };
    whole = cut;
    whole.uniform = [cell](const glm::dvec3& axis, double half) { return coneInsideCell(axis, half, cell); };
    for (int i = 0; i < 6; ++i) {
      const glm::dvec3 p(0.2 + 3.0 * uni(), 0.2 + 2.5 * uni(), 0.1 + 2.0 * uni());
      glm::dvec3 n(uni() * 2 - 1, uni() * 2 - 1, uni() * 2 - 1);
      n = glm::normalize(n);
      const double a = radiosity::distantFormFactor(p, n, window, cut, false);
      const double b = radiosity::distantFormFactor(p, n, window, whole, false);
      total += a;
      worst = std::max(worst, std::abs(a - b));
    }
  }
  EXPECT_GT(total, 0.1);  // the regions facing the window do light the points
  EXPECT_LT(worst, 1e-12);
}

TEST(DaylightBasis, ALampsTermIsTheEngineSolvingThatLampAloneAndAddsToTheSky) {
  // A lamp in the daylight room (Loscos's per-lamp term beside the sky's): its solution, made on
  // the hierarchy refined for the sky and then for the lamp, against the engine solving the same
  // room lit by that lamp alone from scratch (the window an opening, nothing through it) — per
  // surface and right under the lamp; and the sky's combination with the lamp on is the sky's
  // plus the lamp's.
  Scene room = windowRoom(0.3, 0.6, 0.8);
  const double a = 0.15, cx = 1.4, cy = 2.3, z = H - 0.05;
  room.polygons.push_back(poly("lamp", {{cx - a, cy - a, z}, {cx - a, cy + a, z}, {cx + a, cy + a, z}, {cx + a, cy - a, z}}, 0.0,
                               PolygonKind::Light));
  Lamp lamp;
  lamp.name = "A";
  lamp.polygon = int(room.polygons.size()) - 1;
  lamp.radiance = glm::dvec3(40.0, 36.0, 30.0);
  room.lamps.push_back(lamp);
  const glm::dvec3 m = kPi * lamp.radiance;
  const SkyRadiance sky = uniformSky(16, 2.0);
  DaylightBasis basis(room, sky, coarse(16));
  ASSERT_EQ(basis.lampCount(), 1);
  const std::vector<glm::vec3> skyOnly = basis.combine(sky);
  const double scale = basis.engine().refinementScale();
  basis.setLampExitance(0, m);
  const std::vector<glm::vec3> both = basis.combine(sky);
  // Objects added later are refined against the sky's threshold, not the lamp's.
  EXPECT_EQ(basis.engine().refinementScale(), scale);
  const std::vector<glm::vec3>& unit = basis.lampSolution(0);
  ASSERT_EQ(both.size(), unit.size());
  double worstSum = 0;
  for (size_t n = 0; n < skyOnly.size(); ++n)  // the nodes made for the lamp hold their parents' sky values
    for (int c = 0; c < 3; ++c)
      worstSum = std::max(worstSum, std::abs(double(both[n][c]) - double(skyOnly[n][c]) - m[c] * double(unit[n][c])) /
                                        std::max(1e-3, double(both[n][c])));
  EXPECT_LT(worstSum, 1e-4);

  std::vector<radiosity::Surface> surfaces = radiosity::surfacesFromScene(room);
  for (size_t i = 0; i < room.polygons.size(); ++i)
    if (room.polygons[i].kind == PolygonKind::Window) surfaces[i].opening = true;
  radiosity::HierarchicalRadiosity alone(surfaces, *coarse(16).engine);
  alone.solve();
  for (int s : {0, 1, 2, 4, 5}) {  // floor, ceiling, back wall, left wall, the wall below the window
    const double mine = basis.surfaceMean(unit, s).y * m.y, theirs = alone.surfaceRadiosity(s).y;
    std::printf("%-18s lamp's term %.4f, the lamp alone %.4f (%+.2f %%)\n", room.polygons[size_t(s)].name.c_str(), mine, theirs,
                100 * (mine / theirs - 1));
    EXPECT_NEAR(mine, theirs, 0.03 * theirs) << room.polygons[size_t(s)].name;
  }
  const glm::dvec2 under = basis.engine().toUV(0, {cx, cy, 0.0});
  const double mine = unit[size_t(basis.engine().findLeaf(0, under))].y * m.y;
  const double theirs = alone.radiosity(alone.findLeaf(0, alone.toUV(0, {cx, cy, 0.0}))).y;
  std::printf("floor under the lamp: lamp's term %.4f, the lamp alone %.4f (%+.2f %%)\n", mine, theirs, 100 * (mine / theirs - 1));
  EXPECT_NEAR(mine, theirs, 0.05 * theirs);

  EXPECT_THROW(basis.setLampExitance(1, m), Error);
  EXPECT_THROW(basis.setLampExitance(0, glm::dvec3(-1.0)), Error);
}

TEST(DaylightBasis, AVirtualLampShinesAsTheSameLampSolvedAloneAndGoesWithoutATrace) {
  // A virtual lamp added to the live basis (Loscos §4.4 beside the sky) against the engine
  // solving the room lit by that lamp alone, the lamp in it from the start: per surface and right
  // under the lamp, one-sided and two-sided; taken out again, the sky's combination is what it was.
  const Scene room = windowRoom(0.3, 0.6, 0.8);
  const double a = 0.15, cx = 1.4, cy = 2.3, z = H - 0.4;
  const std::vector<glm::dvec3> quad{{cx - a, cy - a, z}, {cx - a, cy + a, z}, {cx + a, cy + a, z}, {cx + a, cy - a, z}};
  const glm::dvec3 m(120.0, 110.0, 95.0);
  const SkyRadiance sky = uniformSky(16, 2.0);
  DaylightBasis basis(room, sky, coarse(16));
  ASSERT_EQ(basis.lampCount(), 0);
  // The same sky with a sun shining through the window: its solution solved first (its links
  // refined, which adds elements), and kept.
  SkyRadiance sunny = sky;
  sunny.sun.found = true;
  sunny.sun.direction = glm::normalize(glm::dvec3(std::cos(kPi / 6), 0.2, std::sin(kPi / 6)));
  sunny.sun.irradiance = glm::dvec3(40.0);
  const std::vector<glm::vec3> beforeSunny = basis.combine(sunny);
  const std::vector<glm::vec3> before = basis.combine(sky);
  std::vector<glm::dvec3> beforeMeans;
  for (size_t s = 0; s < room.polygons.size(); ++s) beforeMeans.push_back(basis.surfaceMean(before, int(s)));
  const size_t surfaces = basis.engine().surfaces().size(), nodes = basis.engine().nodes().size();
  // Refused before anything is added: no area, a negative or non-finite exitance.
  EXPECT_THROW(basis.addObjects({}, {BasisLamp{"flat", {{1, 1, 1}, {2, 1, 1}, {3, 1, 1}}, m, false}}), Error);
  EXPECT_THROW(basis.addObjects({}, {BasisLamp{"negative", quad, glm::dvec3(-1.0), false}}), Error);
  EXPECT_THROW(basis.addObjects({}, {BasisLamp{"nan", quad, glm::dvec3(std::nan("")), false}}), Error);
  EXPECT_EQ(basis.engine().surfaces().size(), surfaces);
  EXPECT_EQ(basis.lampCount(), 0);

  double oneFacedCeiling = 0;
  for (bool twoSided : {false, true}) {
    const std::vector<int> ids = basis.addObjects({}, {BasisLamp{"pendant", quad, m, twoSided}});
    ASSERT_EQ(ids.size(), 1u);
    ASSERT_EQ(basis.lampCount(), 1);
    EXPECT_EQ(basis.sceneLampCount(), 0);
    EXPECT_EQ(basis.lampOfSurface(ids[0]), 0);
    EXPECT_TRUE(basis.isLamp(ids[0]));
    EXPECT_EQ(basis.lampExitance(0), m);
    const std::vector<glm::vec3> both = basis.combine(sky);

    // The same room with the lamp in it from the start, solved by the engine for the lamp alone.
    std::vector<radiosity::Surface> s = radiosity::surfacesFromScene(room);
    for (size_t i = 0; i < room.polygons.size(); ++i)
      if (room.polygons[i].kind == PolygonKind::Window) s[i].opening = true;
    radiosity::Surface lamp;
    lamp.name = "pendant";
    lamp.vertices = quad;
    lamp.exitance = m;
    lamp.twoSided = twoSided;
    s.push_back(lamp);
    radiosity::HierarchicalRadiosity alone(s, *coarse(16).engine);
    alone.solve();
    for (int f : {0, 1, 2, 4, 5}) {  // floor, ceiling, back wall, left wall, the wall below the window
      const double mine = basis.surfaceMean(both, f).y - beforeMeans[size_t(f)].y, theirs = alone.surfaceRadiosity(f).y;
      std::printf("%s, %-18s virtual lamp's share %.4f, the lamp alone %.4f (%+.2f %%)\n", twoSided ? "two faces" : "one face",
                  room.polygons[size_t(f)].name.c_str(), mine, theirs, 100 * (mine / theirs - 1));
      EXPECT_NEAR(mine, theirs, 0.04 * theirs) << room.polygons[size_t(f)].name << (twoSided ? ", two-sided" : "");
    }
    // The ceiling 40 cm above the lamp: lit directly by its upper face only when it has one.
    const double ceilingShare = basis.surfaceMean(both, 1).y - beforeMeans[1].y;
    if (twoSided) EXPECT_GT(ceilingShare, 3.0 * oneFacedCeiling);
    oneFacedCeiling = ceilingShare;
    basis.removeObjects(ids);
    EXPECT_EQ(basis.lampCount(), 0);
    EXPECT_FALSE(basis.isLamp(ids[0]));
    const std::vector<glm::vec3> after = basis.combine(sky);
    // Exactly as before: the hierarchy put back, nothing left behind, nothing solved again.
    EXPECT_EQ(basis.engine().nodes().size(), nodes);
    EXPECT_TRUE(after == before);
    EXPECT_TRUE(basis.combine(sunny) == beforeSunny);  // the sun's solution from before, not one solved with the lamp
    for (size_t f = 0; f < room.polygons.size(); ++f)
      if (room.polygons[f].kind != PolygonKind::Window)
        EXPECT_NEAR(basis.surfaceMean(after, int(f)).y, beforeMeans[f].y, 2e-3 * beforeMeans[f].y) << room.polygons[f].name;
  }

  // A Cancel at any point of the add (the lamp's links refined, the bases solved again) leaves the
  // basis as it was: no lamp, no surface that blocks light, the same light everywhere.
  int cancels = 0;
  for (int at = 1;; at *= 5) {
    int reports = 0;
    Progress* self = nullptr;
    Progress p([&](double, const std::string&) {
      if (++reports == at) self->cancel();
    });
    self = &p;
    try {
      basis.removeObjects(basis.addObjects({}, {BasisLamp{"pendant", quad, m, false}}, p));
      break;  // never reached the report at which it cancels
    } catch (const Cancelled&) {
      ++cancels;
    }
    EXPECT_EQ(basis.lampCount(), 0) << "cancelled at report " << at;
    size_t live = 0;
    for (const auto& sf : basis.engine().surfaces()) live += sf.vertices.empty() ? 0 : 1;
    EXPECT_EQ(live, surfaces) << "cancelled at report " << at;
    EXPECT_EQ(basis.engine().nodes().size(), nodes) << "cancelled at report " << at;
    const std::vector<glm::vec3> after = basis.combine(sky);
    EXPECT_TRUE(after == before) << "cancelled at report " << at;
    for (size_t f = 0; f < room.polygons.size(); ++f)
      if (room.polygons[f].kind != PolygonKind::Window)
        EXPECT_NEAR(basis.surfaceMean(after, int(f)).y, beforeMeans[f].y, 2e-3 * beforeMeans[f].y)
            << room.polygons[f].name << ", cancelled at report " << at;
  }
  std::printf("cancelled %d times at different points of the add, each time the basis was as before\n", cancels);
  EXPECT_GE(cancels, 2);
}

TEST(DaylightBasis, AKeptBasisReadBackTakesTheNextLightThroughTheWindowsAsTheSolvedOneDoes) {
  // What a project keeps of a basis: read back into a basis made from the same room, it holds the
  // same solutions, and the next light through the windows is taken exactly as by the basis that
  // was solved — after a sun, whose links' visibility was taken along its beam, that visibility
  // is taken again towards the whole window (a block on the floor makes the two differ).
  Scene room = windowRoom(0.5, 0.6, 0.7);
  for (const auto& f : boxObject("block", {1.6, 1.2, 0.0}, {2.2, 1.8, 0.6}, glm::dvec3(0.5)).polygons)
    room.polygons.push_back(poly("block", f, 0.5));
  BasisOptions o = coarse(4);
  auto e = std::make_shared<radiosity::Options>(*o.engine);
  e->minArea = 0.05;
  o.engine = e;
  o.pieceDeg = 6;  // coarse: what is kept matters here, not its detail
  const SkyRadiance sky = uniformSky(4, 1.0);
  DaylightBasis solved(room, sky, o);
  const glm::dvec3 sun = glm::normalize(glm::dvec3(1.0, 0.2, 0.6));  // in through the +X window, low
  solved.sunSolution(sun);
  ByteWriter w;
  solved.write(w);
  w.seal();
  ByteReader r(w.bytes, "kept.bin");
  DaylightBasis kept(room, sky, o, r);
  r.expectEnd();
  const unsigned revision = kept.revision();
  ASSERT_EQ(kept.basisCount(), solved.basisCount());
  ASSERT_EQ(kept.engine().nodes().size(), solved.engine().nodes().size());
  ASSERT_EQ(kept.engine().links().size(), solved.engine().links().size());
  for (int k = 0; k < solved.basisCount(); ++k) EXPECT_TRUE(kept.basis(k) == solved.basis(k)) << "basis " << k;
  EXPECT_TRUE(kept.sunSolution(sun) == solved.sunSolution(sun));
  EXPECT_EQ(kept.revision(), revision);  // the sun's solution was kept, not solved again
  auto even = std::make_shared<radiosity::DistantLight>();
  even->radiance = [](const glm::dvec3& d) { return d.z > 0 ? 1.0 : 0.0; };
  const auto a = solved.solveFor(even), b = kept.solveFor(even);
  EXPECT_TRUE(a == b) << "the solutions for the next light differ";
  size_t differ = 0;
  for (size_t i = 0; i < solved.engine().links().size(); ++i)
    differ += solved.engine().links()[i].visibility != kept.engine().links()[i].visibility;
  EXPECT_EQ(differ, 0u);
  // A file whose checksum holds but whose element tree does not (a crafted file): refused before
  // anything is used. The engine's state starts 44 bytes in (the basis's header), its elements
  // 28 bytes later (version, sizes, fingerprint, scale) after their count; element 1's parent is
  // made -1 (a second root), then a child made to point back at the root.
  for (int damage = 0; damage < 2; ++damage) {
    std::vector<uint8_t> bytes(w.bytes.begin(), w.bytes.end() - 4);
    const size_t nodes = 44 + 28 + 8, node1 = nodes + 81;
    const int32_t bad = damage == 0 ? -1 : 0;
    std::memcpy(bytes.data() + (damage == 0 ? node1 : node1 + 81 * 4), &bad, 4);  // parent of element 1, or of 5
    ByteWriter crafted;
    crafted.bytes = bytes;
    crafted.seal();
    ByteReader cr(crafted.bytes, "crafted.bin");
    try {
      DaylightBasis broken(room, sky, o, cr);
      ADD_FAILURE() << "a crafted basis was read (damage " << damage << ")";
    } catch (const Error& err) {
      EXPECT_EQ(err.file(), "crafted.bin");
      EXPECT_NE(err.problem().find("damaged"), std::string::npos) << err.problem();
    }
  }
  // Another room, or other options: refused, naming the file.
  ByteReader again(w.bytes, "kept.bin");
  Scene moved = room;
  moved.polygons.back().vertices[0].z += 0.01;
  try {
    DaylightBasis other(moved, sky, o, again);
    ADD_FAILURE() << "a basis kept for another room was read";
  } catch (const Error& err) {
    EXPECT_EQ(err.file(), "kept.bin");
    EXPECT_NE(err.problem().find("other polygons"), std::string::npos) << err.problem();
  }
  ByteReader third(w.bytes, "kept.bin");
  try {
    DaylightBasis other(room, uniformSky(16, 1.0), coarse(16), third);
    ADD_FAILURE() << "a basis kept for 4 regions was read as one of 16";
  } catch (const Error& err) {
    EXPECT_NE(err.problem().find("regions"), std::string::npos) << err.problem();
  }
}
