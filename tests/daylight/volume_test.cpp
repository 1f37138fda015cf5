// The irradiance volume (Grosch et al. 2007 §5-6): the indirect light it gives a box's faces
// against a brute-force gather over each face's hemisphere in the solved room, the transfer
// coefficients against a half-blocked sky worked out by hand, and grid points inside furniture
// kept out of the interpolation.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <numbers>

#include "relume/daylight/basis.h"
#include "relume/daylight/volume.h"
#include "relume/geometry/polygon.h"
#include "relume/radiosity/hierarchy.h"
#include "relume/radiosity/sh.h"
#include "relume/raytrace/ray_scene.h"
#include "relume/relight/relighter.h"
#include "window_room.h"

using namespace relume;
using namespace relume::daylight;
using namespace relume::testing;

namespace {
constexpr double kPi = std::numbers::pi;

SkyRadiance testSky(int regions) {
  SkyRadiance sky;
  for (int k = 0; k < regions; ++k) sky.region.push_back(glm::dvec3(0.6 + 0.05 * double(k % 5), 0.7, 0.8 - 0.04 * double(k % 3)));
  const double e = 30 * kPi / 180;
  sky.sun.found = true;
  sky.sun.direction = glm::dvec3(std::cos(e), 0.0, std::sin(e));  // in through the +X window
  sky.sun.irradiance = glm::dvec3(30.0);
  return sky;
}

BasisOptions options() {
  BasisOptions o;
  o.regions = 16;
  o.groundReflectance = 0.2;
  return o;
}

// The indirect irradiance at x on a face of normal n, gathered by brute force: cosine-distributed
// rays against the solved room, each taking the radiance of the leaf it hits (B / pi of the
// combined solution); rays out through the window carry nothing (the direct light is apart).
double gather(const DaylightBasis& basis, const std::vector<glm::vec3>& b, const glm::dvec3& x, const glm::dvec3& n, int rays,
              uint64_t& state) {
  auto uni = [&] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return double(state >> 11) / 9007199254740992.0;
  };
  const auto& eng = basis.engine();
  const glm::dvec3 t = glm::normalize(glm::cross(n, std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
  const glm::dvec3 u = glm::cross(n, t);
  double e = 0;
  for (int r = 0; r < rays; ++r) {
    const double r1 = uni(), r2 = uni(), s = std::sqrt(r1), phi = 2 * kPi * r2;
    const glm::dvec3 d = s * std::cos(phi) * t + s * std::sin(phi) * u + std::sqrt(1 - r1) * n;
    const RayHit hit = eng.rayScene().intersect(Ray{glm::vec3(x), glm::vec3(d), 1e-5f, 1e30f});
    if (hit.polygon < 0) continue;
    if (glm::dot(d, polygonNormal(eng.surfaces()[size_t(hit.polygon)].vertices)) >= 0) continue;
    const glm::dvec3 h = x + double(hit.t) * d;
    e += kPi * b[size_t(eng.findLeaf(hit.polygon, eng.toUV(hit.polygon, h)))].y / kPi / rays;
  }
  return e;
}
}  // namespace

TEST(IrradianceVolume, ABoxsFacesGetTheIndirectLightARayGatherOverTheirHemispheresSees) {
  const Scene room = windowRoom(0.4, 0.7, 0.8);
  const SkyRadiance sky = testSky(16);
  DaylightBasis basis(room, sky, options());
  IrradianceVolume volume(basis);
  volume.combine(basis, sky);
  const std::vector<glm::vec3> b = basis.combine(sky);
  uint64_t state = 7;
  // A box in the corner the sun never reaches (the case), and one on the floor beside the
  // sunlit patch, where the reflected light changes fastest.
  struct Case {
    const char* name;
    glm::dvec3 lo, hi;
    double bound;
  };
  for (const Case& c : {Case{"corner", {0.1, 0.1, 0.0}, {0.6, 0.6, 0.5}, 0.15}, Case{"beside the patch", {1.4, 0.6, 0.0}, {1.9, 1.1, 0.5}, 0.15}}) {
    double worst = 0;
    for (const auto& f : boxObject("box", c.lo, c.hi, glm::dvec3(0.5)).polygons) {
      const glm::dvec3 n = polygonNormal(f);
      if (n.z < -0.5) continue;  // the bottom face stands on the floor
      glm::dvec3 centre(0.0);
      for (const auto& q : f) centre += q / double(f.size());
      double fromVolume = 0, brute = 0;
      constexpr int points = 9;
      for (int p = 0; p < points; ++p) {
        // A 3 x 3 lattice over the face's middle.
        const glm::dvec3 t = glm::normalize(f[1] - f[0]), u = glm::cross(n, t);
        const glm::dvec3 x = centre + (p % 3 - 1) * 0.15 * t + (p / 3 - 1) * 0.15 * u + 1e-4 * n;
        fromVolume += radiosity::shIrradiance(volume.at(x), n).y / points;
        brute += gather(basis, b, x, n, 4096, state) / points;
      }
      const double err = fromVolume / brute - 1;
      worst = std::max(worst, std::abs(err));
      std::printf("%s box, face (%+.0f %+.0f %+.0f): volume %.4f, gather %.4f (%+.1f %%)\n", c.name, n.x, n.y, n.z, fromVolume, brute,
                  100 * err);
      EXPECT_NEAR(fromVolume, brute, c.bound * brute) << c.name;
    }
    std::printf("%s box: worst face %.1f %%\n", c.name, 100 * worst);
  }
}

TEST(IrradianceVolume, TheSkyHalfBlockedLeavesHalfTheTransfer) {
  // A point on the floor facing up under a roof over every direction with x > 0: by hand, C_00 =
  // Y_00 x pi / 2 (half the cosine lobe), C_11 (the x band) = -0.4886 x 2 / 3 (the integral of
  // cos x |x| over the open half), the others as the open half gives them.
  const RayScene roof({{{0.0, -1000, 1}, {1000, -1000, 1}, {1000, 1000, 1}, {0.0, 1000, 1}}});
  const glm::dvec3 up(0, 0, 1);
  const auto open = radiosity::shTransfer({0, 0, 0}, up, nullptr);
  const auto half = radiosity::shTransfer({0, 0, 0}, up, &roof, 4096);
  const double y00 = 0.5 / std::sqrt(kPi);
  EXPECT_NEAR(open[0], y00 * kPi, 1e-12);
  EXPECT_NEAR(half[0], y00 * kPi / 2, 0.01 * open[0]);
  EXPECT_NEAR(half[3], -0.488603 * 2.0 / 3.0, 0.01);
  EXPECT_NEAR(half[2], open[2] / 2, 0.01);  // the z band: the cosine lobe's half
  EXPECT_NEAR(half[1], 0.0, 0.01);          // y: symmetric about the open half
  // Band 2: (3z^2 - 1) is even in x, so half of the open lobe's 0.315392 x pi / 2; xz integrates
  // to 1.092548 x (-2) x (integral of sin^2 cos^2 over theta = pi / 16); xy, yz, x^2 - y^2 to 0.
  EXPECT_NEAR(open[6], 0.315392 * kPi / 2, 1e-5);
  EXPECT_NEAR(half[6], 0.315392 * kPi / 4, 0.01);
  EXPECT_NEAR(half[7], -1.092548 * kPi / 8, 0.01);
  EXPECT_NEAR(half[4], 0.0, 0.01);
  EXPECT_NEAR(half[5], 0.0, 0.01);
  EXPECT_NEAR(half[8], 0.0, 0.01);
  // A uniform radiance L from the open half: irradiance pi L / 2.
  radiosity::SH9 uniform;
  uniform.c[0] = glm::dvec3(1.0 / y00);  // L = 1 everywhere
  EXPECT_NEAR(radiosity::shApply(uniform, half).x, kPi / 2, 0.02);
}

TEST(IrradianceVolume, PointsInsideFurnitureTakeNoPartInTheLight) {
  // A closed cabinet around the grid's first point: that point sees only back faces.
  Scene room = windowRoom(0.4, 0.7, 0.8);
  for (const auto& f : boxObject("cabinet", {0.05, 0.05, 0.0}, {0.55, 0.6, 0.45}, glm::dvec3(0.5)).polygons)
    room.polygons.push_back(poly("cabinet", f, 0.5));
  const SkyRadiance sky = testSky(16);
  DaylightBasis basis(room, sky, options());
  IrradianceVolume volume(basis, VolumeOptions{8, 1024});
  volume.combine(basis, sky);
  size_t insideCount = 0;
  for (size_t p = 0; p < volume.pointCount(); ++p) insideCount += volume.inRoom(p);
  EXPECT_FALSE(volume.inRoom(0)) << "the point at " << volume.point(0).x << ", " << volume.point(0).y << ", " << volume.point(0).z;
  EXPECT_EQ(insideCount, volume.pointCount() - 1);
  // Above the cabinet's top, between that point and the ones beside it: the trilinear weights of
  // the seven corners in the room, renormalised; the one inside (it holds almost nothing: back
  // faces are dark) takes no part.
  const glm::dvec3 x(0.45, 0.45, 0.5);
  const int n = volume.resolution();
  int i0[3];
  double f[3];
  for (int a = 0; a < 3; ++a) {
    const double g = (x[a] - volume.lower()[a]) / (volume.upper()[a] - volume.lower()[a]) * n - 0.5;
    i0[a] = int(std::floor(g));
    f[a] = g - i0[a];
  }
  ASSERT_EQ(i0[0], 0);
  ASSERT_EQ(i0[1], 0);
  ASSERT_EQ(i0[2], 0);  // the cell whose corner 0 is the point inside the cabinet
  glm::dvec3 expected(0.0);
  double total = 0;
  for (int c = 1; c < 8; ++c) {
    const int di = c & 1, dj = (c >> 1) & 1, dk = (c >> 2) & 1;
    const double w = (di ? f[0] : 1 - f[0]) * (dj ? f[1] : 1 - f[1]) * (dk ? f[2] : 1 - f[2]);
    expected += w * volume.combinedAt(size_t((dk * n + dj) * n + di)).c[0];
    total += w;
  }
  expected /= total;
  const radiosity::SH9 got = volume.at(x);
  for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(got.c[0][ch], expected[ch], 1e-9 * std::abs(expected[ch]) + 1e-12);
  const double neighbour = radiosity::shIrradiance(volume.combinedAt(1), {0, 0, 1}).y;
  EXPECT_LT(radiosity::shIrradiance(volume.combinedAt(0), {0, 0, 1}).y, 0.2 * neighbour);

  // Combining only around a box gives at() inside it exactly what combining everywhere gives:
  // every point it reads, the substitute of the point in the cabinet included, is combined.
  const glm::dvec3 probes[] = {{0.3, 0.3, 0.2}, {0.45, 0.45, 0.5}, {0.7, 0.4, 0.3}};
  std::vector<radiosity::SH9> full;
  for (const auto& q : probes) full.push_back(volume.at(q));
  SkyRadiance brighter = sky;
  for (auto& r : brighter.region) r *= 2.0;
  brighter.sun.irradiance *= 2.0;
  volume.combine(basis, brighter);
  volume.combine(basis, sky, {0.0, 0.0, 0.0}, {0.8, 0.8, 0.6});
  for (size_t q = 0; q < full.size(); ++q)
    for (size_t c = 0; c < 9; ++c)
      for (int ch = 0; ch < 3; ++ch)
        EXPECT_NEAR(volume.at(probes[q]).c[c][ch], full[q].c[c][ch], 1e-6 * std::abs(full[q].c[c][ch]) + 1e-9) << q << " " << c;
}
