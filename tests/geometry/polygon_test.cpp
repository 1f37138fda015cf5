#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include "relume/geometry/camera.h"
#include "relume/geometry/polygon.h"

using namespace relume;

TEST(Polygon, AreaNormalCentroidOfATiltedRectangle) {
  const std::vector<glm::dvec3> v = {{0, 0, 0}, {2, 0, 0}, {2, 1, 1}, {0, 1, 1}};
  EXPECT_NEAR(polygonArea(v), 2 * std::sqrt(2.0), 1e-12);
  const glm::dvec3 n = polygonNormal(v);
  EXPECT_NEAR(n.y, -std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(n.z, std::sqrt(0.5), 1e-12);
  const glm::dvec3 c = polygonCentroid(v);
  EXPECT_NEAR(c.x, 1.0, 1e-12);
  EXPECT_NEAR(c.y, 0.5, 1e-12);
}

TEST(Polygon, PlaneFrameRoundTrip) {
  const std::vector<glm::dvec3> v = {{1, 2, 3}, {3, 2, 4}, {2, 5, 6}};
  const PlaneFrame f = PlaneFrame::of(v);
  for (const auto& p : v) EXPECT_LT(glm::length(f.toWorld(f.toUV(p)) - p), 1e-12);
  EXPECT_NEAR(glm::dot(f.u, f.normal), 0.0, 1e-12);
  EXPECT_NEAR(glm::dot(f.v, f.normal), 0.0, 1e-12);
}

TEST(Polygon, ClipToRectKeepsTheOverlapArea) {
  // A unit-area diamond clipped to the right half-plane keeps half its area.
  const std::vector<glm::dvec2> diamond = {{0, -1}, {1, 0}, {0, 1}, {-1, 0}};
  EXPECT_NEAR(polygonArea2D(diamond), 2.0, 1e-12);
  const auto half = clipToRect(diamond, {0, -5}, {5, 5});
  EXPECT_NEAR(polygonArea2D(half), 1.0, 1e-12);
  EXPECT_TRUE(clipToRect(diamond, {2, 2}, {3, 3}).empty());
}

TEST(Camera, ProjectsWhatItsRaysPassThrough) {
  Camera c;
  c.width = 640;
  c.height = 480;
  c.K[0][0] = c.K[1][1] = 500;
  c.K[2][0] = 320;
  c.K[2][1] = 240;
  // Looking along +y from (0, -3, 1): x_cam = x, y_cam = -z, z_cam = y.
  c.R = glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0, 0, 1), glm::dvec3(0, -1, 0));
  const glm::dvec3 eye(0, -3, 1);
  c.t = -(c.R * eye);
  EXPECT_LT(glm::length(c.center() - eye), 1e-12);
  const glm::dvec3 d = c.rayDirection(100.5, 50.5);
  glm::dvec2 px;
  ASSERT_TRUE(c.project(eye + 4.0 * d, px));
  EXPECT_NEAR(px.x, 100.5, 1e-9);
  EXPECT_NEAR(px.y, 50.5, 1e-9);
  EXPECT_FALSE(c.project(eye - d, px));  // behind the camera
}
