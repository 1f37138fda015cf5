// `relume evaluate --geometry`: a clicked model's lamps and polygons take their truth from the
// bundle's by name, else by where they are.
#include <gtest/gtest.h>

#include "relume/geometry/scene.h"
#include "relume/relight/compare.h"

using namespace relume;

namespace {
Polygon quad(const std::string& name, glm::dvec3 o, glm::dvec3 u, glm::dvec3 v, PolygonKind kind = PolygonKind::Real) {
  Polygon p;
  p.name = name;
  p.kind = kind;
  p.vertices = {o, o + u, o + u + v, o + v};
  return p;
}
void addLamp(Scene& s, const std::string& name, glm::dvec3 centre) {
  const double a = 0.1;
  s.polygons.push_back(quad(name + "_panel", centre + glm::dvec3(-a, a, 0), {2 * a, 0, 0}, {0, -2 * a, 0}, PolygonKind::Light));
  Lamp l;
  l.name = name;
  l.polygon = int(s.polygons.size()) - 1;
  s.lamps.push_back(l);
}
}  // namespace

TEST(BundleMatch, LampsByNameOrPlacePolygonsByTheirPlane) {
  Scene bundle;
  bundle.polygons.push_back(quad("floor", {0, 0, 0}, {4, 0, 0}, {0, 3, 0}));
  bundle.polygons.push_back(quad("wall_back", {0, 3, 0}, {4, 0, 0}, {0, 0, 2.5}));  // normal -y
  bundle.polygons.push_back(quad("table_top", {1, 1, 0.75}, {1, 0, 0}, {0, 0.6, 0}));
  addLamp(bundle, "A", {1, 1.5, 2.48});
  addLamp(bundle, "B", {3, 1.5, 2.48});

  // Clicked: corners a centimetre off, other names, one lamp named as the bundle's, one not, and
  // things the bundle does not have.
  Scene model;
  model.polygons.push_back(quad("p0", {0.01, 0.0, 0.005}, {3.98, 0, 0}, {0, 2.99, 0}));    // the floor
  model.polygons.push_back(quad("p1", {0.0, 2.995, 0.01}, {4, 0, 0}, {0, 0, 2.48}));       // the back wall
  model.polygons.push_back(quad("p2", {1.02, 1.01, 0.76}, {0.97, 0, 0}, {0, 0.58, 0}));    // the table
  model.polygons.push_back(quad("p3", {1.02, 1.01, 0.40}, {0.97, 0, 0}, {0, 0.58, 0}));    // a shelf in no plane of the bundle
  model.polygons.push_back(quad("p4", {0, 0, 0}, {0, 3, 0}, {0, 0, 2.5}));                 // a wall the bundle lacks
  addLamp(model, "B", {3.02, 1.49, 2.47});
  addLamp(model, "lamp2", {1.03, 1.52, 2.47});  // where the bundle's A is
  addLamp(model, "C", {2.0, 0.2, 2.47});        // 0.5 m and more from both

  const BundleMatch m = matchToBundle(model, bundle);
  ASSERT_EQ(m.lamp.size(), 3u);
  EXPECT_EQ(m.lamp[0], bundle.findLamp("B"));
  EXPECT_EQ(m.lamp[1], bundle.findLamp("A"));
  EXPECT_EQ(m.lamp[2], -1);
  ASSERT_EQ(m.polygon.size(), model.polygons.size());
  EXPECT_EQ(m.polygon[0], 0);
  EXPECT_EQ(m.polygon[1], 1);
  EXPECT_EQ(m.polygon[2], 2);
  EXPECT_EQ(m.polygon[3], -1);
  EXPECT_EQ(m.polygon[4], -1);
  EXPECT_EQ(m.polygon[5], bundle.lamps[1].polygon);  // lamp B's panel
  EXPECT_EQ(m.polygon[6], bundle.lamps[0].polygon);  // lamp A's
}

TEST(BundleMatch, ThePolygonOfTheSameNameWinsInTheSamePlane) {
  // Two bundle polygons in one plane, side by side: the model's "right" is matched by name even
  // though its centre lies in the other; a same-named polygon in another plane is not.
  Scene bundle;
  bundle.polygons.push_back(quad("left", {0, 0, 0}, {0.6, 0, 0}, {0, 1, 0}));
  bundle.polygons.push_back(quad("right", {0.6, 0, 0}, {0.6, 0, 0}, {0, 1, 0}));
  bundle.polygons.push_back(quad("up", {0, 0, 1}, {1.2, 0, 0}, {0, 1, 0}));
  Scene model;
  model.polygons.push_back(quad("right", {0.4, 0, 0}, {0.36, 0, 0}, {0, 1, 0}));  // its centre in "left"
  model.polygons.push_back(quad("up", {0, 0, 0.3}, {1.2, 0, 0}, {0, 1, 0}));
  const BundleMatch m = matchToBundle(model, bundle);
  EXPECT_EQ(m.polygon[0], 1);
  EXPECT_EQ(m.polygon[1], -1);
}

TEST(BundleMatch, APanelOrAPosterInAWallsPlaneIsNotTheWall) {
  // A ceiling with a lamp's panel flush in it, a back wall with a poster on it, an L-shaped wall:
  // the model's ceiling (its centre under the panel) is the ceiling, its wall (its centre on the
  // poster) the wall, its poster the poster, and the L's short arm the L.
  Scene bundle;
  bundle.polygons.push_back(quad("ceiling", {0, 0, 2.5}, {0, 3, 0}, {4, 0, 0}));  // normal -z
  bundle.polygons.push_back(quad("wall_back", {0, 3, 0}, {4, 0, 0}, {0, 0, 2.5}));
  bundle.polygons.push_back(quad("poster", {1.5, 2.99, 1.0}, {1, 0, 0}, {0, 0, 0.7}));
  Polygon l;
  l.name = "wall_l";
  l.vertices = {{0, 0, 0}, {0, 3, 0}, {0, 3, 0.6}, {0, 1, 0.6}, {0, 1, 2.5}, {0, 0, 2.5}};  // normal +x, an L
  bundle.polygons.push_back(l);
  bundle.polygons.push_back(quad("panel", {1.8, 1.3, 2.5}, {0, 0.4, 0}, {0.4, 0, 0}, PolygonKind::Light));
  Scene model;
  model.polygons.push_back(quad("a", {0, 0, 2.49}, {0, 3, 0}, {4, 0, 0}));           // centre (2, 1.5): under the panel
  model.polygons.push_back(quad("b", {0, 2.995, 0}, {4, 0, 0}, {0, 0, 2.7}));         // centre (2, 1.35): on the poster
  model.polygons.push_back(quad("c", {1.5, 2.985, 1.0}, {1, 0, 0}, {0, 0, 0.7}));     // the poster
  model.polygons.push_back(quad("d", {0.005, 1.5, 0}, {0, 1.5, 0}, {0, 0, 0.6}));     // the L's low arm
  const BundleMatch m = matchToBundle(model, bundle);
  EXPECT_EQ(m.polygon[0], 0);
  EXPECT_EQ(m.polygon[1], 1);
  EXPECT_EQ(m.polygon[2], 2);
  EXPECT_EQ(m.polygon[3], 3);
}
