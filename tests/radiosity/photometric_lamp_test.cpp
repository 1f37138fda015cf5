// Lamps with a photometric distribution (IES / EULUMDAT shape) in the engine: a cosine-shaped
// distribution is a Lambertian face, a narrow beam puts its flux where the file says, one that
// emits up and down is a two-sided face, and the room absorbs exactly the lamp's flux.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>
#include <numbers>

#include "relume/geometry/binary.h"
#include "relume/geometry/error.h"
#include "relume/geometry/photometry.h"
#include "relume/geometry/polygon.h"
#include "relume/radiosity/form_factor.h"
#include "relume/radiosity/hierarchy.h"
#include "support/test_rooms.h"

using namespace relume;
using namespace relume::radiosity;
using relume::test::quad;

namespace {
constexpr double kPi = std::numbers::pi;

// A rotationally symmetric distribution sampled every 2.5 degrees of gamma over 0..180.
std::shared_ptr<const PhotometricDistribution> rotational(const std::function<double(double gammaRad)>& f) {
  auto d = std::make_shared<PhotometricDistribution>();
  d->symmetry = PhotometricDistribution::Symmetry::Rotational;
  d->c = {0.0};
  for (double g = 0; g <= 180.0 + 1e-9; g += 2.5) {
    d->gamma.push_back(g);
    d->candela.push_back(f(g * kPi / 180.0));
  }
  return d;
}

struct Solved {
  std::unique_ptr<HierarchicalRadiosity> h;
  std::vector<Surface> surfaces;
  double absorbed = 0;
};

// The furnished test room with its own lamp off and one 30 cm lamp 0.4 m below the ceiling.
Solved solveRoomWith(const glm::dvec3& exitance, bool twoSided, std::shared_ptr<const PhotometricDistribution> photometry) {
  Solved s;
  s.surfaces = test::furnishedRoom(3.0, 3.5, 2.5, glm::dvec3(0.0));
  Surface lamp{"lamp2", quad({0.5, 2.5, 2.1}, {0, 0.3, 0}, {0.3, 0, 0}), glm::dvec3(0.0), exitance, twoSided};  // facing down
  lamp.photometry = std::move(photometry);
  s.surfaces.push_back(lamp);
  s.h = std::make_unique<HierarchicalRadiosity>(s.surfaces, Options{});
  s.h->solve();
  for (size_t i = 0; i < s.surfaces.size(); ++i)
    s.absorbed += polygonArea(s.surfaces[i].vertices) * (1.0 - s.surfaces[i].reflectance.x) * s.h->surfaceIrradiance(int(i)).x;
  return s;
}
}  // namespace

TEST(PhotometricLamp, ACosineDistributionLightsTheRoomAsALambertianFace) {
  // The file's scale does not matter: the lamp's exitance sets it.
  const auto cosine = rotational([](double g) { return 250.0 * std::max(0.0, std::cos(g)); });
  const Solved lambert = solveRoomWith(glm::dvec3(50.0), false, nullptr);
  const Solved shaped = solveRoomWith(glm::dvec3(50.0), false, cosine);
  for (size_t i = 0; i < lambert.surfaces.size(); ++i) {
    const double a = lambert.h->surfaceIrradiance(int(i)).x, b = shaped.h->surfaceIrradiance(int(i)).x;
    EXPECT_NEAR(b, a, 0.02 * a + 1e-6) << lambert.surfaces[i].name;
  }
  EXPECT_NEAR(shaped.absorbed, 50.0 * 0.09, 0.02 * 50.0 * 0.09);  // the room absorbs the lamp's flux
}

TEST(PhotometricLamp, ADistributionUpAndDownIsATwoSidedFace) {
  // I = I0 |cos gamma| over the whole sphere: half the flux each way, as a two-sided Lambertian
  // lamp whose faces each emit half the exitance.
  const auto both = rotational([](double g) { return 100.0 * std::abs(std::cos(g)); });
  const Solved twoSided = solveRoomWith(glm::dvec3(25.0), true, nullptr);
  const Solved shaped = solveRoomWith(glm::dvec3(50.0), false, both);
  for (size_t i = 0; i < twoSided.surfaces.size(); ++i) {
    const double a = twoSided.h->surfaceIrradiance(int(i)).x, b = shaped.h->surfaceIrradiance(int(i)).x;
    EXPECT_NEAR(b, a, 0.03 * a + 1e-6) << twoSided.surfaces[i].name;
  }
  EXPECT_NEAR(shaped.absorbed, 50.0 * 0.09, 0.05 * 50.0 * 0.09);
}

TEST(PhotometricLamp, ANarrowBeamPutsItsFluxWhereItsFileSays) {
  // A 10 cm downlight 2 m above a nearly black 8 x 8 m floor with I ~ cos^8 gamma: the floor right below
  // receives E = Phi (n + 1) / (2 pi h^2), 4.5 times what a Lambertian face of the same flux gives
  // there, and the floor receives all of its flux (cos^9 of 63 degrees is 0.0007).
  const double n = 8, h = 2.0, M = 50.0, A = 0.01;
  const auto beam = rotational([&](double g) { return g < kPi / 2 ? std::pow(std::cos(g), n) : 0.0; });
  std::vector<Surface> s;
  s.push_back({"floor", quad({-4, -4, 0}, {8, 0, 0}, {0, 8, 0}), glm::dvec3(0.01), glm::dvec3(0.0)});
  Surface lamp{"lamp", quad({-0.05, -0.05, h}, {0, 0.1, 0}, {0.1, 0, 0}), glm::dvec3(0.0), glm::dvec3(M)};
  lamp.photometry = beam;
  s.push_back(lamp);
  HierarchicalRadiosity engine(s, Options{});
  engine.solve();
  const double below = engine.irradiance(engine.findLeaf(0, engine.toUV(0, {0.0, 0.0, 0.0})))[0];
  const double expected = M * A * (n + 1) / (2 * kPi * h * h);
  EXPECT_NEAR(below, expected, 0.05 * expected);
  EXPECT_GT(below, 3.0 * M * A / (kPi * h * h));  // the Lambertian face's value, by far
  const double received = engine.surfaceIrradiance(0).x * 64.0;
  EXPECT_GT(received, 0.98 * M * A);
  EXPECT_LT(received, 1.01 * M * A);
}

TEST(PhotometricLamp, TheWeightFollowsTheDistributionsFrame) {
  // A distribution brighter towards C90 than C270 (I = cos gamma (1 + 0.8 sin C)), on a lamp
  // facing down whose first edge runs along +X: C0 = +X, C90 = C0 x nadir = +Y.
  auto d = std::make_shared<PhotometricDistribution>();
  d->symmetry = PhotometricDistribution::Symmetry::Full;
  for (double c = 0; c < 360.0; c += 10.0) d->c.push_back(c);
  for (double g = 0; g <= 90.0 + 1e-9; g += 5.0) d->gamma.push_back(g);
  for (double c : d->c)
    for (double g : d->gamma) d->candela.push_back(std::cos(g * kPi / 180) * (1.0 + 0.8 * std::sin(c * kPi / 180)));
  const std::vector<glm::dvec3> facingDown = {{0, 1, 1}, {1, 1, 1}, {1, 0, 1}, {0, 0, 1}};
  ASSERT_LT(areaVector(facingDown).z, 0.0);
  const EmitterShape shape(facingDown, false, d);
  const glm::dvec3 c = shape.centre;
  // 45 degrees off the nadir towards +Y (C90) and towards -Y (C270): 1.8 / 0.2 of the mean.
  const double towardsY = shape.weight(c + glm::dvec3(0, 1, -1)), awayY = shape.weight(c + glm::dvec3(0, -1, -1));
  EXPECT_NEAR(towardsY / awayY, 1.8 / 0.2, 0.2);
  // Straight down, relative to a Lambertian face of the same flux: pi I(0) / Phi, Phi = pi.
  EXPECT_NEAR(shape.weight(c + glm::dvec3(0, 0, -1)), 1.0, 0.02);
  EXPECT_EQ(shape.weight(c + glm::dvec3(0, 0, 1)), 0.0);  // nothing upwards
}

TEST(PhotometricLamp, AKeptSolutionIsNotReadIntoAnEngineWhoseLampHasAnotherDistribution) {
  // A kept state (a project's solution) was refined and linked for the lamp's distribution: read
  // into an engine whose lamp has another file's shape (same polygons, same exitance), it is
  // refused; into one made the same way, it is taken.
  auto engineWith = [](std::shared_ptr<const PhotometricDistribution> d) {
    std::vector<Surface> s = test::furnishedRoom(3.0, 3.5, 2.5, glm::dvec3(0.0));
    Surface lamp{"lamp2", quad({0.5, 2.5, 2.1}, {0, 0.3, 0}, {0.3, 0, 0}), glm::dvec3(0.0), glm::dvec3(50.0)};
    lamp.photometry = std::move(d);
    s.push_back(lamp);
    return std::make_unique<HierarchicalRadiosity>(s, Options{});
  };
  const auto wide = rotational([](double g) { return 250.0 * std::max(0.0, std::cos(g)); });
  const auto narrow = rotational([](double g) { return g < kPi / 2 ? 250.0 * std::pow(std::cos(g), 8) : 0.0; });
  auto solved = engineWith(wide);
  solved->solve();
  ByteWriter out;
  solved->writeState(out);
  {
    ByteReader in(out.bytes, "kept.bin");
    auto same = engineWith(rotational([](double g) { return 250.0 * std::max(0.0, std::cos(g)); }));
    EXPECT_NO_THROW(same->readState(in));
  }
  ByteReader in(out.bytes, "kept.bin");
  auto other = engineWith(narrow);
  try {
    other->readState(in);
    FAIL() << "a state kept for another distribution was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("kept.bin"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("lamp distributions"), std::string::npos) << e.what();
  }
}
