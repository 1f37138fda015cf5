#pragma once
// Planar convex polygons and their local (u,v) frame.
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <span>
#include <string>
#include <vector>

namespace relume {

enum class PolygonKind { Real, Light, Window, Virtual };

struct Polygon {
  std::string name;
  std::string group;
  std::string material;
  PolygonKind kind = PolygonKind::Real;
  std::vector<glm::dvec3> vertices;  // counter-clockwise seen from the side the normal points to
  glm::dvec3 albedo{0.5};            // mean diffuse reflectance, linear RGB (unused for lamps)
};

// Newell normal times the area: |areaVector| = area, direction = normal.
glm::dvec3 areaVector(std::span<const glm::dvec3> verts);
double polygonArea(const std::vector<glm::dvec3>& verts);
glm::dvec3 polygonNormal(const std::vector<glm::dvec3>& verts);
glm::dvec3 polygonCentroid(std::span<const glm::dvec3> verts);

// An orthonormal frame in the polygon's plane: origin at vertex 0, u along the first edge,
// v = normal x u. Points map to (u,v) and back.
struct PlaneFrame {
  glm::dvec3 origin{0.0}, u{1, 0, 0}, v{0, 1, 0}, normal{0, 0, 1};

  static PlaneFrame of(const std::vector<glm::dvec3>& verts);
  glm::dvec2 toUV(const glm::dvec3& p) const;
  glm::dvec3 toWorld(const glm::dvec2& uv) const { return origin + u * uv.x + v * uv.y; }
};

// 2-D convex polygon helpers (counter-clockwise).
double polygonArea2D(const std::vector<glm::dvec2>& pts);
glm::dvec2 polygonCentroid2D(const std::vector<glm::dvec2>& pts);
// Clips a convex polygon to the axis-aligned rectangle [lo, hi] (Sutherland-Hodgman).
std::vector<glm::dvec2> clipToRect(const std::vector<glm::dvec2>& poly, glm::dvec2 lo, glm::dvec2 hi);
// Clips a 3-D polygon to the half-space dot(n, x - p) >= 0; the second form writes into `out`
// (cleared first, its capacity kept: a buffer used again allocates nothing).
std::vector<glm::dvec3> clipToHalfSpace(std::span<const glm::dvec3> poly, const glm::dvec3& p, const glm::dvec3& n);
void clipToHalfSpace(std::span<const glm::dvec3> poly, const glm::dvec3& p, const glm::dvec3& n,
                     std::vector<glm::dvec3>& out);
bool insideConvex2D(const std::vector<glm::dvec2>& poly, glm::dvec2 p, double eps = 0.0);
// Whether x, a point in the plane of the simple (convex or concave) polygon `verts`, lies inside
// it: the crossings of a ray in the polygon's own plane frame (a point on the outline may go
// either way).
bool insidePolygon(const std::vector<glm::dvec3>& verts, const glm::dvec3& x);

}  // namespace relume
