// Which polygons of a room lie outside it (daylight takes them as the ground; a virtual object
// must not stand among them): those a window sees beyond its plane — not the far wing of an
// L-shaped room, which lies beyond the plane of a window in the near wing's inner corner.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "relume/geometry/scene.h"
#include "relume/raytrace/outside.h"

using namespace relume;

namespace {
Polygon quad(const std::string& name, PolygonKind kind, std::vector<glm::dvec3> v) {
  Polygon p;
  p.name = name;
  p.kind = kind;
  p.vertices = std::move(v);
  return p;
}
}  // namespace

TEST(Outside, TheGroundAndTheStreetSeenThroughAWindowButNotTheFarWingOfAnLShapedRoom) {
  // Near wing x 0..4, y 0..3; far wing x 0..2, y 3..6; 2.5 m high. The window (1 x 1 m) in the
  // near wing's wall y = 3, x 2..4, facing the outside corner (x > 2, y > 3); normals into the room.
  Scene s;
  const auto R = PolygonKind::Real;
  s.polygons = {
      quad("window", PolygonKind::Window, {{2.5, 3, 1}, {3.5, 3, 1}, {3.5, 3, 2}, {2.5, 3, 2}}),
      quad("corner_wall_below", R, {{2, 3, 0}, {4, 3, 0}, {4, 3, 1}, {2, 3, 1}}),
      quad("corner_wall_above", R, {{2, 3, 2}, {4, 3, 2}, {4, 3, 2.5}, {2, 3, 2.5}}),
      quad("corner_wall_left", R, {{2, 3, 1}, {2.5, 3, 1}, {2.5, 3, 2}, {2, 3, 2}}),
      quad("corner_wall_right", R, {{3.5, 3, 1}, {4, 3, 1}, {4, 3, 2}, {3.5, 3, 2}}),
      quad("near_floor", R, {{0, 0, 0}, {4, 0, 0}, {4, 3, 0}, {0, 3, 0}}),
      quad("far_wall_inner", R, {{2, 3, 0}, {2, 3, 2.5}, {2, 6, 2.5}, {2, 6, 0}}),  // faces -x, into the far wing
      quad("far_wall_outer", R, {{0, 3, 0}, {0, 6, 0}, {0, 6, 2.5}, {0, 3, 2.5}}),  // faces +x
      quad("far_floor", R, {{0, 3, 0}, {2, 3, 0}, {2, 6, 0}, {0, 6, 0}}),
      quad("ground", R, {{2.1, 3.1, -0.001}, {30, 3.1, -0.001}, {30, 30, -0.001}, {2.1, 30, -0.001}}),
      quad("street_facade", R, {{0, 12, 0}, {8, 12, 0}, {8, 12, 6}, {0, 12, 6}}),  // faces -y, towards the window
  };
  std::vector<std::string> outside;
  for (int i : outsidePolygons(s)) outside.push_back(s.polygons[size_t(i)].name);
  std::sort(outside.begin(), outside.end());
  EXPECT_EQ(outside, (std::vector<std::string>{"ground", "street_facade"}));
  // Without a window nothing is outside.
  Scene closed = s;
  closed.polygons.erase(closed.polygons.begin());
  EXPECT_TRUE(outsidePolygons(closed).empty());
}
