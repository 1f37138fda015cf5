#pragma once
// A closed box room with a window cut into its +X wall, for the daylight tests.
#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "relume/geometry/scene.h"

namespace relume::testing {

constexpr double W = 4.3, D = 4.6, H = 2.8;             // the room
constexpr double Y0 = 1.85, Y1 = 3.25, Z0 = 0.9, Z1 = 2.1;  // the window in the +X wall

inline Polygon poly(const std::string& name, std::vector<glm::dvec3> v, double albedo, PolygonKind kind = PolygonKind::Real) {
  Polygon p;
  p.name = p.group = name;
  p.kind = kind;
  p.vertices = std::move(v);
  p.albedo = glm::dvec3(albedo);
  return p;
}
// A rectangle in the plane x = const, facing -X (into a room on its -X side).
inline std::vector<glm::dvec3> facingMinusX(double x, double y0, double y1, double z0, double z1) {
  return {{x, y1, z0}, {x, y0, z0}, {x, y0, z1}, {x, y1, z1}};
}
inline std::vector<glm::dvec3> facingPlusX(double x, double y0, double y1, double z0, double z1) {
  return {{x, y0, z0}, {x, y1, z0}, {x, y1, z1}, {x, y0, z1}};
}

// A closed box room with a window cut into its +X wall (the wall in four pieces around it).
inline Scene windowRoom(double floor, double walls, double ceiling) {
  Scene s;
  s.sourceFile = "window_room.json";
  s.polygons.push_back(poly("floor", {{0, 0, 0}, {W, 0, 0}, {W, D, 0}, {0, D, 0}}, floor));
  s.polygons.push_back(poly("ceiling", {{0, 0, H}, {0, D, H}, {W, D, H}, {W, 0, H}}, ceiling));
  s.polygons.push_back(poly("wall_back", {{0, D, 0}, {W, D, 0}, {W, D, H}, {0, D, H}}, walls));
  s.polygons.push_back(poly("wall_front", {{W, 0, 0}, {0, 0, 0}, {0, 0, H}, {W, 0, H}}, walls));
  s.polygons.push_back(poly("wall_left", facingPlusX(0, 0, D, 0, H), walls));
  s.polygons.push_back(poly("wall_right_below", facingMinusX(W, 0, D, 0, Z0), walls));
  s.polygons.push_back(poly("wall_right_above", facingMinusX(W, 0, D, Z1, H), walls));
  s.polygons.push_back(poly("wall_right_front", facingMinusX(W, 0, Y0, Z0, Z1), walls));
  s.polygons.push_back(poly("wall_right_back", facingMinusX(W, Y1, D, Z0, Z1), walls));
  s.polygons.push_back(poly("window", facingMinusX(W, Y0, Y1, Z0, Z1), 0.0, PolygonKind::Window));
  return s;
}

}  // namespace relume::testing
