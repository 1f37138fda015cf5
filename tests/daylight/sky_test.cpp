// The measured sky: fisheye geometry, the hemisphere's regions, region means and the sun, judged
// against skies made here with known radiance (no external images).
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <cstdio>
#include <glm/geometric.hpp>
#include <numbers>

#include "relume/daylight/sky.h"
#include "relume/geometry/error.h"
#include "relume/geometry/scene.h"

using namespace relume;
using namespace relume::daylight;

namespace {
constexpr double kPi = std::numbers::pi;

glm::dvec3 fromElevAzim(double elevDeg, double azimDeg) {
  const double e = elevDeg * kPi / 180, a = azimDeg * kPi / 180;
  return {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
}

// A fisheye of the given sky function, each pixel the mean over 3 x 3 sub-pixels (41 x 41 within
// 2 degrees of `hot`, where a sun's disc is smaller than a pixel).
SkyImage render(const FisheyeModel& model, int width, int height, const std::function<glm::dvec3(const glm::dvec3&)>& sky,
                const glm::dvec3& hot = glm::dvec3(0.0)) {
  SkyImage s{ImageRGB(width, height), model, "synthetic.exr"};
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      glm::dvec3 sum(0.0);
      int n = 0;
      const auto c = pixelDirection(s.model, x + 0.5, y + 0.5);
      const int k = c && glm::dot(*c, hot) > std::cos(2 * kPi / 180) ? 41 : 3;
      for (int j = 0; j < k; ++j)
        for (int i = 0; i < k; ++i)
          if (const auto d = pixelDirection(s.model, x + (i + 0.5) / k, y + (j + 0.5) / k)) sum += sky(*d), ++n;
      if (n) s.image.set(x, y, glm::vec3(sum / double(n)));
    }
  return s;
}
// The sun found in `s` within `withinDeg` of `sunDir`, and the irradiance its disc of radiance
// `sunL` and radius `sunRadius` gives (L times its solid angle, wherever the pixels put it) within
// 5 %; the sky averaged over 64 regions.
SkyRadiance expectTheSun(const SkyImage& s, const SkyRegions& regions, const glm::dvec3& sunDir, double sunL, double sunRadius,
                         double withinDeg) {
  const SkyRadiance avg = averageSky(s, regions);
  EXPECT_TRUE(avg.sun.found);
  EXPECT_LT(std::acos(std::min(1.0, glm::dot(avg.sun.direction, sunDir))) * 180 / kPi, withinDeg);
  const double expected = sunL * 2 * kPi * (1 - std::cos(sunRadius));
  EXPECT_NEAR(avg.sun.irradiance.x, expected, 0.05 * expected);
  return avg;
}
SkyImage render(int size, FisheyeProjection proj, const std::function<glm::dvec3(const glm::dvec3&)>& sky,
                const glm::dvec3& hot = glm::dvec3(0.0)) {
  return render(fisheyeLookingUp(size, size, proj), size, size, sky, hot);
}
}  // namespace

TEST(Fisheye, PixelsAndDirectionsAreInverseAndFollowTheLensModel) {
  for (auto proj : {FisheyeProjection::Equidistant, FisheyeProjection::Equisolid}) {
    const FisheyeModel m = fisheyeLookingUp(256, 256, proj);
    // The centre looks up; the circle's edge is the horizon; image up is +Y, and (seen from
    // below) image right is -X.
    EXPECT_NEAR(glm::length(*pixelDirection(m, 128, 128) - glm::dvec3(0, 0, 1)), 0, 1e-12);
    EXPECT_NEAR(glm::length(*pixelDirection(m, 128, 0) - glm::dvec3(0, 1, 0)), 0, 1e-9);
    EXPECT_NEAR(glm::length(*pixelDirection(m, 256, 128) - glm::dvec3(-1, 0, 0)), 0, 1e-9);
    EXPECT_FALSE(pixelDirection(m, 5, 5).has_value());  // a corner, outside the circle
    for (double e : {5.0, 30.0, 60.0, 89.0})
      for (double a : {0.0, 77.0, 200.0, 300.0}) {
        const glm::dvec3 d = fromElevAzim(e, a);
        const auto p = directionPixel(m, d);
        ASSERT_TRUE(p);
        EXPECT_NEAR(glm::length(*pixelDirection(m, p->x, p->y) - d), 0, 1e-9) << e << " " << a;
      }
    // Equidistant: 45 degrees from the axis is half way out; equisolid: sin(22.5) / sin(45).
    const double r = glm::length(*directionPixel(m, fromElevAzim(45, 0)) - glm::dvec2(128, 128)) / 128;
    EXPECT_NEAR(r, proj == FisheyeProjection::Equidistant ? 0.5 : std::sin(kPi / 8) / std::sin(kPi / 4), 1e-9);
  }
}

TEST(Fisheye, PixelSolidAnglesCoverTheHemisphere) {
  for (auto proj : {FisheyeProjection::Equidistant, FisheyeProjection::Equisolid}) {
    const FisheyeModel m = fisheyeLookingUp(256, 256, proj);
    double sum = 0;
    for (int y = 0; y < 256; ++y)
      for (int x = 0; x < 256; ++x) sum += pixelSolidAngle(m, x, y);
    EXPECT_NEAR(sum, 2 * kPi, 0.01 * 2 * kPi);
  }
}

TEST(SkyRegions, CoverTheHemisphereInAboutEqualCells) {
  for (int n : {16, 64, 256}) {
    const SkyRegions r(n);
    ASSERT_EQ(r.size(), n);
    double sum = 0;
    for (int k = 0; k < n; ++k) {
      sum += r.solidAngle(k);
      EXPECT_NEAR(r.solidAngle(k), 2 * kPi / n, 0.35 * 2 * kPi / n) << "n " << n << " cell " << k;
      EXPECT_EQ(r.regionOf(r.centre(k)), k);
    }
    EXPECT_NEAR(sum, 2 * kPi, 1e-9);
    EXPECT_EQ(r.regionOf({0, 0, -1}), -1);
  }
}

TEST(Sky, AUniformSkyAveragesToItsRadianceAndGivesPiLOnAHorizontalPlane) {
  const glm::dvec3 L(1.7, 1.5, 1.2);
  const SkyImage s = render(256, FisheyeProjection::Equidistant, [&](const glm::dvec3&) { return L; });
  const SkyRegions regions(64);
  const SkyRadiance avg = averageSky(s, regions);
  EXPECT_FALSE(avg.sun.found);
  for (int k = 0; k < regions.size(); ++k) EXPECT_NEAR(glm::length(avg.region[size_t(k)] - L), 0, 1e-4) << k;
  // Irradiance: pi L on a horizontal plane, pi L / 2 on a vertical one (upper hemisphere only).
  const glm::dvec3 up = planeIrradiance(regions, avg, {0, 0, 1}), side = planeIrradiance(regions, avg, {1, 0, 0});
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(up[c], kPi * L[c], 0.005 * kPi * L[c]);
    EXPECT_NEAR(side[c], kPi * L[c] / 2, 0.005 * kPi * L[c] / 2);
  }
}

TEST(Sky, TheSunIsFoundWhereItIsAndItsLightKeptApartFromItsRegion) {
  // A sky brightening towards the zenith, and a sun of 0.53 degrees at elevation 30, azimuth
  // 120, of radiance 2e5 times the sky's.
  const glm::dvec3 sunDir = fromElevAzim(30, 120);
  const double sunRadius = 0.265 * kPi / 180, sunL = 2e5;
  auto skyL = [](const glm::dvec3& d) { return glm::dvec3(0.5 + 0.5 * d.z, 0.6 + 0.5 * d.z, 0.9 + 0.5 * d.z); };
  const SkyImage s = render(512, FisheyeProjection::Equidistant, [&](const glm::dvec3& d) {
    return glm::dot(d, sunDir) >= std::cos(sunRadius) ? glm::dvec3(sunL) : skyL(d);
  }, sunDir);
  const SkyRegions regions(64);
  const SkyRadiance avg = expectTheSun(s, regions, sunDir, sunL, sunRadius, 0.5);
  // The sun's region keeps the sky's radiance around it.
  const int k = regions.regionOf(sunDir);
  EXPECT_NEAR(avg.region[size_t(k)].x, skyL(regions.centre(k)).x, 0.05);
}

TEST(Sky, ASunClippedAtHalfFloatsLargestValueOrSaturatedIsFlagged) {
  // The same sun as above, saved three ways: full float (not clipped), as half float (every pixel
  // above 65504 becomes 65504) and as a camera's saturation (every pixel above a tenth of its
  // peak becomes that).
  const glm::dvec3 sunDir = fromElevAzim(30, 120);
  const double sunRadius = 0.265 * kPi / 180;
  const SkyImage full = render(256, FisheyeProjection::Equidistant, [&](const glm::dvec3& d) {
    return glm::dot(d, sunDir) >= std::cos(sunRadius) ? glm::dvec3(3e5, 2.5e5, 2e5) : glm::dvec3(0.6, 0.7, 0.9);
  }, sunDir);
  float peak = 0;
  for (float v : full.image.pixels) peak = std::max(peak, v);
  ASSERT_GT(peak, 65504.f);
  SkyImage half = full, saturated = full;
  for (float& v : half.image.pixels) v = std::min(v, 65504.f);
  for (float& v : saturated.image.pixels) v = std::min(v, 0.1f * peak);
  const SkyRegions regions(64);
  const SkyRadiance a = averageSky(full, regions), b = averageSky(half, regions), c = averageSky(saturated, regions);
  ASSERT_TRUE(a.sun.found && b.sun.found && c.sun.found);
  EXPECT_FALSE(a.sun.clipped);
  EXPECT_TRUE(b.sun.clipped);
  EXPECT_TRUE(c.sun.clipped);
  // What clipping does to the light: understated (a pixel clipped in every channel holds only a
  // lower bound), but not whitened: the disc's edge pixels, clipped nowhere, give the sun's colour,
  // and the clipped pixels take it (unrestored, clipping at 65504 made the sun's R/B 1.0 here).
  for (const SkyRadiance* x : {&b, &c}) {
    std::printf("sun irradiance against full float's: R %.3f G %.3f B %.3f, R/B %.3f (full float %.3f)\n",
                x->sun.irradiance.x / a.sun.irradiance.x, x->sun.irradiance.y / a.sun.irradiance.y,
                x->sun.irradiance.z / a.sun.irradiance.z, x->sun.irradiance.x / x->sun.irradiance.z,
                a.sun.irradiance.x / a.sun.irradiance.z);
    EXPECT_TRUE(x->sun.colourFromUnclipped);
    for (int ch = 0; ch < 3; ++ch) EXPECT_LE(x->sun.irradiance[ch], 1.001 * a.sun.irradiance[ch]);
    EXPECT_NEAR(x->sun.irradiance.x / x->sun.irradiance.z, a.sun.irradiance.x / a.sun.irradiance.z, 0.03);
    EXPECT_NEAR(x->sun.irradiance.x / x->sun.irradiance.y, a.sun.irradiance.x / a.sun.irradiance.y, 0.03);
  }
}

TEST(Sky, BadSkyImagesAreRefusedWithTheirProblem) {
  SkyImage s = render(64, FisheyeProjection::Equidistant, [](const glm::dvec3&) { return glm::dvec3(1.0); });
  auto message = [](const SkyImage& sky) {
    try {
      checkSkyImage(sky);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message(s), "no error");
  SkyImage nan = s;
  nan.image.set(10, 20, glm::vec3(std::nanf(""), 1, 1));
  EXPECT_NE(message(nan).find("synthetic.exr: pixel (10, 20): the radiance is NaN or infinite"), std::string::npos) << message(nan);
  SkyImage outside = s;
  outside.model.radius = 40;
  EXPECT_NE(message(outside).find("does not lie inside the 64x64 image"), std::string::npos) << message(outside);
  SkyImage below = s;
  below.model.axes = glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, -1));  // looking down
  below.model.fovDeg = 150;
  EXPECT_NE(message(below).find("only what lies below the horizon"), std::string::npos) << message(below);
}

TEST(Fisheye, ADescriptionInWordsGivesTheLensAndItsOrientation) {
  const FisheyeModel m = fisheyeFromDescription("equidistant, 180 deg, looking up (+Z), image up = +Y", 256, 256, "s.json");
  const FisheyeModel ref = fisheyeLookingUp(256, 256);
  for (double x : {10.5, 128.0, 200.25})
    for (double y : {30.0, 128.0, 250.5}) {
      const auto a = pixelDirection(m, x, y), b = pixelDirection(ref, x, y);
      ASSERT_EQ(a.has_value(), b.has_value());
      if (a) EXPECT_NEAR(glm::length(*a - *b), 0, 1e-12);
    }
  const FisheyeModel rotated = fisheyeFromDescription("Equisolid 150 deg, looking up, image up = -X", 100, 80, "s.json");
  EXPECT_EQ(rotated.projection, FisheyeProjection::Equisolid);
  EXPECT_DOUBLE_EQ(rotated.fovDeg, 150);
  EXPECT_DOUBLE_EQ(rotated.radius, 40);
  // The top of the circle: towards image up (-X), 75 degrees from the zenith.
  EXPECT_NEAR(glm::length(*pixelDirection(rotated, 50, 0) - fromElevAzim(15, 180)), 0, 1e-9);
  auto error = [](const std::string& text) {
    try {
      fisheyeFromDescription(text, 64, 64, "s.json");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error("fisheye, 180 deg, looking up, image up = +Y").find("equidistant or equisolid"), std::string::npos);
  EXPECT_NE(error("equidistant, looking up, image up = +Y").find("field of view"), std::string::npos);
  EXPECT_NE(error("equidistant, 180 deg, looking down, image up = +Y").find("looking up"), std::string::npos);
  EXPECT_NE(error("equidistant, 180 deg, looking up").find("image's up"), std::string::npos);
}

TEST(Panorama, PixelsAndDirectionsAreInverseAndTheCellsCoverTheSphere) {
  const FisheyeModel m = equirectangular(512, 256);
  // The centre column looks along +X, a quarter of the way in along +Y (to the left of +X seen
  // from inside, +Z up), the top row at the zenith.
  EXPECT_LT(glm::length(*pixelDirection(m, 256, 128) - glm::dvec3(1, 0, 0)), 1e-12);
  EXPECT_LT(glm::length(*pixelDirection(m, 128, 128) - glm::dvec3(0, 1, 0)), 1e-12);
  EXPECT_GT(pixelDirection(m, 10.5, 0.5)->z, 0.9999);
  for (int k = 0; k < 200; ++k) {
    const glm::dvec3 d = fromElevAzim(-85 + 170.0 * ((k * 37) % 200) / 199.0, 360.0 * ((k * 53) % 200) / 200.0);
    const auto p = directionPixel(m, d);
    ASSERT_TRUE(p);
    EXPECT_LT(glm::length(*pixelDirection(m, p->x, p->y) - d), 1e-9) << k;
  }
  double sphere = 0;
  for (int y = 0; y < m.height; ++y)
    for (int x = 0; x < m.width; ++x) sphere += pixelSolidAngle(m, x, y);
  EXPECT_NEAR(sphere, 4 * kPi, 1e-9);
}

TEST(Panorama, ASkyReadFromAPanoramaGivesWhatItsFisheyeGives) {
  // The same sky (brightening towards the zenith, a 0.53-degree sun at elevation 30, azimuth 120)
  // seen by a 512 x 256 panorama and by a 512-pixel fisheye: regions, sun and irradiance agree.
  const glm::dvec3 sunDir = fromElevAzim(30, 120);
  const double sunRadius = 0.265 * kPi / 180, sunL = 2e5;
  auto skyL = [](const glm::dvec3& d) { return glm::dvec3(0.5 + 0.5 * d.z, 0.6 + 0.5 * d.z, 0.9 + 0.5 * d.z); };
  auto sky = [&](const glm::dvec3& d) {
    if (d.z < 0) return glm::dvec3(0.2);  // the ground, which the panorama sees too
    return glm::dot(d, sunDir) >= std::cos(sunRadius) ? glm::dvec3(sunL) : skyL(d);
  };
  const SkyImage pano = render(equirectangular(512, 256), 512, 256, sky, sunDir);
  const SkyImage fish = render(512, FisheyeProjection::Equidistant, sky, sunDir);
  checkSkyImage(pano);
  const SkyRegions regions(64);
  const SkyRadiance a = averageSky(pano, regions), b = averageSky(fish, regions);
  ASSERT_TRUE(a.sun.found);
  EXPECT_LT(std::acos(std::min(1.0, glm::dot(a.sun.direction, sunDir))) * 180 / kPi, 0.5);
  const double expected = sunL * 2 * kPi * (1 - std::cos(sunRadius));
  EXPECT_NEAR(a.sun.irradiance.x, expected, 0.05 * expected);
  double worst = 0;
  for (int k = 0; k < regions.size(); ++k)
    worst = std::max(worst, glm::length(a.region[size_t(k)] - b.region[size_t(k)]) / glm::length(b.region[size_t(k)]));
  std::printf("panorama vs fisheye: regions within %.3f %%, sun %.3f vs %.3f\n", 100 * worst, a.sun.irradiance.x,
              b.sun.irradiance.x);
  EXPECT_LT(worst, 0.01);
  const glm::dvec3 up = planeIrradiance(regions, a, {0, 0, 1}), upFish = planeIrradiance(regions, b, {0, 0, 1});
  EXPECT_NEAR(up.x, upFish.x, 0.01 * upFish.x);
  // A panorama whose size is not the model's is refused by name.
  SkyImage wrong = pano;
  wrong.model = equirectangular(256, 128);
  try {
    checkSkyImage(wrong);
    ADD_FAILURE() << "a panorama of another size was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("synthetic.exr"), std::string::npos);
  }
}

TEST(Fisheye, ACalibratedLensMapsPixelsAndDirectionsBothWaysAndCoversTheHemisphere) {
  // OpenCV's fisheye model (as `relume calibrate --fisheye` writes it): theta_d = theta (1 + k1
  // theta^2 + ...), pixel = principal + focal * theta_d along the direction's azimuth.
  const double k[4] = {0.03, -0.012, 0.004, -0.0006};
  const glm::dvec2 focal(130, 131), principal(321.3, 238.8);
  auto lensOf = [&](const double (&kk)[4], double circle) {
    FisheyeLens l;
    l.width = 640, l.height = 480, l.fx = focal.x, l.fy = focal.y, l.cx = principal.x, l.cy = principal.y;
    for (int i = 0; i < 4; ++i) l.k[i] = kk[i];
    l.circleX = principal.x, l.circleY = principal.y, l.circleRadius = circle;
    return l;
  };
  const FisheyeModel m = fisheyeCalibrated(lensOf(k, 0), 180, "lens.json");
  auto thetaD = [&](double t) { return t + k[0] * std::pow(t, 3) + k[1] * std::pow(t, 5) + k[2] * std::pow(t, 7) + k[3] * std::pow(t, 9); };
  // Looking up with image up = +Y: 60 degrees from the zenith towards -X lies to the image's right.
  const auto p = directionPixel(m, fromElevAzim(30, 180));
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->x, principal.x + focal.x * thetaD(kPi / 3), 1e-9);
  EXPECT_NEAR(p->y, principal.y, 1e-9);
  const auto q = directionPixel(m, fromElevAzim(20, 90));  // towards +Y: image up
  ASSERT_TRUE(q);
  EXPECT_NEAR(q->y, principal.y - focal.y * thetaD(70 * kPi / 180), 1e-9);
  double worstAngle = 0, worstPixel = 0;
  for (int e = 1; e <= 89; e += 4)
    for (int a = 0; a < 360; a += 17) {
      const glm::dvec3 d = fromElevAzim(e, a);
      const auto px = directionPixel(m, d);
      ASSERT_TRUE(px) << e << " " << a;
      const auto back = pixelDirection(m, px->x, px->y);
      ASSERT_TRUE(back);
      worstAngle = std::max(worstAngle, std::acos(std::min(1.0, glm::dot(*back, d))));
      const auto again = directionPixel(m, *back);
      worstPixel = std::max(worstPixel, glm::length(*again - *px));
    }
  EXPECT_LT(worstAngle, 1e-7);
  EXPECT_LT(worstPixel, 1e-6);
  EXPECT_FALSE(directionPixel(m, fromElevAzim(-5, 0))) << "below the 180-degree view";
  double sum = 0;
  for (int y = 0; y < 480; ++y)
    for (int x = 0; x < 640; ++x) sum += pixelSolidAngle(m, x, y);
  std::printf("calibrated lens: solid angle over the image %.5f (2 pi = %.5f)\n", sum, 2 * kPi);
  EXPECT_NEAR(sum, 2 * kPi, 0.005 * 2 * kPi);
  // Its image circle bounds the view when given.
  const FisheyeModel circled = fisheyeCalibrated(lensOf(k, 150), 180, "lens.json");
  EXPECT_TRUE(pixelDirection(circled, principal.x + 149, principal.y));
  EXPECT_FALSE(pixelDirection(circled, principal.x + 151, principal.y));
  // A distortion that folds the image back on itself before the view's edge is no lens.
  const double fold[4] = {-0.5, 0, 0, 0};
  const std::string e = [&] {
    try {
      fisheyeCalibrated(lensOf(fold, 0), 180, "lens.json");
    } catch (const Error& err) {
      return std::string(err.what());
    }
    return std::string();
  }();
  EXPECT_NE(e.find("lens.json"), std::string::npos) << e;
  EXPECT_NE(e.find("folds"), std::string::npos) << e;
}

TEST(Sky, ASkySeenThroughACalibratedLensGivesWhatTheSkyHolds) {
  // The same sky and sun as above, photographed through a distorted fisheye of unequal focal
  // lengths inside its image circle: the sun where it is, its irradiance and the sky's on a
  // horizontal plane as the sky itself gives them.
  const glm::dvec3 sunDir = fromElevAzim(30, 120);
  const double sunRadius = 0.265 * kPi / 180, sunL = 2e5;
  auto skyL = [](const glm::dvec3& d) { return glm::dvec3(0.5 + 0.5 * d.z, 0.6 + 0.5 * d.z, 0.9 + 0.5 * d.z); };
  const double k[4] = {0.03, -0.012, 0.004, -0.0006};
  FisheyeLens l;
  l.width = 640, l.height = 520, l.fx = 150, l.fy = 153, l.cx = 321.3, l.cy = 262.8;
  for (int i = 0; i < 4; ++i) l.k[i] = k[i];
  l.circleX = 321.0, l.circleY = 263.0, l.circleRadius = 252;  // the horizon 250 px out along y
  const FisheyeModel lens = fisheyeCalibrated(l, 180, "lens.json");
  const SkyImage s = render(lens, 640, 520, [&](const glm::dvec3& d) {
    return glm::dot(d, sunDir) >= std::cos(sunRadius) ? glm::dvec3(sunL) : skyL(d);
  }, sunDir);
  checkSkyImage(s);
  // An image circle that cuts the horizon off (236 px) leaves part of the sky unseen: refused.
  SkyImage cut = s;
  cut.model.radius = 236;
  try {
    checkSkyImage(cut);
    ADD_FAILURE() << "a circle short of the horizon";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("outside its image circle"), std::string::npos) << e.what();
  }
  const SkyRegions regions(64);
  const SkyRadiance avg = expectTheSun(s, regions, sunDir, sunL, sunRadius, 0.3);
  // The sky alone on a horizontal plane: pi (0.5 + 0.5 * 2/3) in red for this sky, exactly.
  SkyRadiance skyOnly = avg;
  skyOnly.sun.found = false;
  const glm::dvec3 e = planeIrradiance(regions, skyOnly, {0, 0, 1});
  const double want = kPi * (0.5 + 0.5 * 2.0 / 3.0);
  std::printf("through the calibrated lens: sun %.4g (expected %.4g), sky on a horizontal plane %.4f (exact %.4f)\n",
              avg.sun.irradiance.x, sunL * 2 * kPi * (1 - std::cos(sunRadius)), e.x, want);
  EXPECT_NEAR(e.x, want, 0.01 * want);
}

TEST(Sky, ARoomsSkyTakenThroughItsCalibratedLensIsReadThroughIt) {
  // A room whose measured sky names a calibrated lens (the words give only its orientation: image
  // up = -X): the fisheye is read through the lens, turned as the words say, and the sun is where
  // it was photographed.
  const glm::dvec3 sunDir = fromElevAzim(40, 200);
  FisheyeLens l;
  l.width = 320, l.height = 250, l.fx = 75, l.fy = 76, l.cx = 160.7, l.cy = 124.6;
  l.k[0] = 0.025, l.k[1] = -0.01;
  Scene room;
  room.baseDir = ::testing::TempDir();
  room.sourceFile = room.baseDir + "/scene.json";
  SkyCapture cap;
  cap.name = "noon";
  cap.fisheye = "lens_sky.exr";
  cap.fisheyeModel = "calibrated, looking up (+Z), image up = -X";
  cap.lens = l;
  room.skies.push_back(cap);
  room.photoSky = "noon";
  FisheyeModel m = fisheyeFromDescription(cap.fisheyeModel, 320, 250, "x", l);
  EXPECT_EQ(m.projection, FisheyeProjection::OpenCvFisheye);
  EXPECT_NEAR(glm::dot(*pixelDirection(m, l.cx, l.cy - 50), glm::dvec3(-1, 0, 0)), std::sin(50 / 75.0), 0.03) << "image up is -X";
  const SkyImage shot = render(m, 320, 250, [&](const glm::dvec3& d) {
    return glm::dot(d, sunDir) >= std::cos(0.265 * kPi / 180) ? glm::dvec3(2e4) : glm::dvec3(0.5 + 0.5 * d.z);  // within half float
  }, sunDir);
  writeImage(room.baseDir + "/lens_sky.exr", shot.image);
  const SkyImage read = readRoomSky(room, "noon");
  EXPECT_EQ(read.model.projection, FisheyeProjection::OpenCvFisheye);
  const SkyRadiance avg = averageSky(read, SkyRegions(64));
  ASSERT_TRUE(avg.sun.found);
  EXPECT_LT(std::acos(std::min(1.0, glm::dot(avg.sun.direction, sunDir))) * 180 / kPi, 0.5);
  // A lens calibrated on other images is refused, naming the fisheye.
  room.skies[0].lens.width = 640;
  try {
    readRoomSky(room, "noon");
    ADD_FAILURE() << "a lens of another image size";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("lens_sky.exr"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("calibrated on 640x250"), std::string::npos) << e.what();
  }
}

namespace {
// A fisheye photo's image: a sky inside the circle (1 at the centre, 0.25 at its edge), a dark
// tree line along part of its edge, a black border with faint noise; 8 x 8 sub-pixels at the edge.
ImageRGB circleImage(int w, int h, glm::dvec2 c, double r) {
  ImageRGB im(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      double sum = 0;
      for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 8; ++i) {
          const glm::dvec2 p(x + (i + 0.5) / 8, y + (j + 0.5) / 8);
          const double d = glm::length(p - c) / r, az = std::atan2(p.y - c.y, p.x - c.x) * 180 / kPi;
          if (d > 1) continue;
          const bool tree = d > 1 - 12 / r && az > 20 && az < 70;
          sum += tree ? 0.02 : 1 - 0.75 * d * d;
        }
      const double noise = 1e-4 * ((x * 7919 + y * 104729) % 13) / 13.0;
      im.set(x, y, glm::vec3(float(sum / 64 + noise)));
    }
  return im;
}
}  // namespace

TEST(Fisheye, TheImageCircleIsFoundFromTheDarkBorderAroundIt) {
  {
    const glm::dvec2 c(163.4, 127.2);
    const ImageCircle f = findImageCircle(circleImage(320, 260, c, 117.6), "sky.exr");
    std::printf("circle: centre %.3f %.3f radius %.3f (true 163.4 127.2 117.6), rms %.3f px over %d points\n", f.centre.x,
                f.centre.y, f.radius, f.rms, f.points);
    EXPECT_LT(glm::length(f.centre - c), 0.3);
    EXPECT_NEAR(f.radius, 117.6, 0.3);
  }
  {  // filling the image: only the corners are dark
    const ImageCircle f = findImageCircle(circleImage(256, 256, glm::dvec2(128, 128), 128), "sky.exr");
    EXPECT_LT(glm::length(f.centre - glm::dvec2(128, 128)), 0.3);
    EXPECT_NEAR(f.radius, 128, 0.3);
  }
  {  // Blender's own fisheye render of the daylight sample room's sky (equidistant, the circle filling it)
    const std::string file = std::string(RELUME_SOURCE_DIR) + "/resources/daylight_room/sky/fisheye_sun1.exr";
    const ImageRGB im = readImageLinear(file);
    const ImageCircle f = findImageCircle(im, file);
    std::printf("Blender's fisheye: centre %.3f %.3f radius %.3f (%dx%d), rms %.3f px\n", f.centre.x, f.centre.y, f.radius,
                im.width, im.height, f.rms);
    EXPECT_LT(glm::length(f.centre - glm::dvec2(im.width / 2.0, im.height / 2.0)), 0.5);
    EXPECT_NEAR(f.radius, im.width / 2.0, 0.5);
  }
  // Lit to its corners: no circle to find, and the message says what to do.
  ImageRGB lit(200, 150);
  for (int y = 0; y < 150; ++y)
    for (int x = 0; x < 200; ++x) lit.set(x, y, glm::vec3(0.5f));
  try {
    findImageCircle(lit, "full_frame.exr");
    ADD_FAILURE() << "a lit image has no circle";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("full_frame.exr"), std::string::npos) << m;
    EXPECT_NE(m.find("--circle"), std::string::npos) << m;
  }
}
