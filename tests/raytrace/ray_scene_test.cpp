#include <gtest/gtest.h>

#include "relume/raytrace/ray_scene.h"

using namespace relume;

namespace {
std::vector<std::vector<glm::dvec3>> wallScene() {
  // A 1 x 1 wall in the plane x = 0 spanning y, z in [0, 1].
  return {{{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}}};
}
}  // namespace

TEST(RayScene, SegmentsThroughTheWallAreBlockedOthersAreNot) {
  RayScene rs(wallScene());
  EXPECT_TRUE(rs.occluded({-1, 0.5f, 0.5f}, {1, 0.5f, 0.5f}));
  EXPECT_FALSE(rs.occluded({-1, 1.5f, 0.5f}, {1, 1.5f, 0.5f}));
  EXPECT_FALSE(rs.occluded({-1, 0.5f, 0.5f}, {-0.1f, 0.5f, 0.5f}));  // stops short of the wall
  std::vector<Segment> segs(2000);
  for (size_t i = 0; i < segs.size(); ++i) {
    const float y = -0.5f + 2.0f * float(i) / float(segs.size());
    segs[i] = {{-1, y, 0.5f}, {1, y, 0.5f}};
  }
  std::vector<uint8_t> blocked(segs.size());
  rs.occluded(segs, blocked);
  for (size_t i = 0; i < segs.size(); ++i) {
    const float y = segs[i].from.y;
    if (y > 0.01f && y < 0.99f) EXPECT_EQ(blocked[i], 1) << y;
    if (y < -0.01f || y > 1.01f) EXPECT_EQ(blocked[i], 0) << y;
  }
}

TEST(RayScene, IntersectionReportsPolygonDistanceAndNormal) {
  RayScene rs({{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 0, 2}, {0, 1, 2}, {1, 1, 2}, {1, 0, 2}}});
  const RayHit up = rs.intersect(Ray{{0.5f, 0.5f, 1}, {0, 0, 1}});
  EXPECT_EQ(up.polygon, 1);
  EXPECT_NEAR(up.t, 1.0f, 1e-5f);
  const RayHit down = rs.intersect(Ray{{0.5f, 0.5f, 1}, {0, 0, -1}});
  EXPECT_EQ(down.polygon, 0);
  EXPECT_NEAR(down.point.z, 0.0f, 1e-5f);
  EXPECT_EQ(rs.intersect(Ray{{5, 5, 1}, {0, 0, 1}}).polygon, -1);
}

TEST(RayScene, VisibilityFactorIsTheUnblockedFractionOfRayPairs) {
  // Points behind the wall's lower half see through only where they pass above z = 1.
  RayScene rs(wallScene());
  std::vector<glm::vec3> a, b;
  for (int i = 0; i < 100; ++i) {
    const float z = (i + 0.5f) / 50.f;  // 0 .. 2
    a.push_back({-1, 0.5f, z});
    b.push_back({1, 0.5f, z});
  }
  EXPECT_NEAR(rs.visibility(a, b), 0.5f, 0.011f);
  EXPECT_EQ(rs.raysCast(), 100u);
}
