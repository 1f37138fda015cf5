#include "relume/raytrace/outside.h"

#include <algorithm>
#include <glm/geometric.hpp>
#include <memory>

#include "relume/geometry/polygon.h"
#include "relume/raytrace/ray_scene.h"

namespace relume {

namespace {
// The polygon's centroid and its vertices moved a tenth of the way towards it (inside the polygon
// and off its edges, where a line would graze the neighbouring polygons).
std::vector<glm::dvec3> pointsOf(const std::vector<glm::dvec3>& v) {
  const glm::dvec3 c = polygonCentroid(v);
  std::vector<glm::dvec3> out{c};
  for (const auto& q : v) out.push_back(q + 0.1 * (c - q));
  return out;
}
}  // namespace

std::vector<int> outsidePolygons(const Scene& scene) {
  std::vector<int> out;
  std::vector<int> windows;
  for (size_t i = 0; i < scene.polygons.size(); ++i)
    if (scene.polygons[i].kind == PolygonKind::Window && scene.polygons[i].vertices.size() >= 3) windows.push_back(int(i));
  if (windows.empty()) return out;
  // Everything but the windows blocks a line (a window is an opening). Built once some polygon
  // lies beyond a window's plane: a room without one (most) casts no ray (the virtual-object
  // check calls this at every move of a drag).
  std::unique_ptr<RayScene> rays;
  auto blockers = [&]() -> const RayScene& {
    if (!rays) {
      std::vector<std::vector<glm::dvec3>> solid;
      for (const auto& q : scene.polygons)
        if (q.kind != PolygonKind::Window && q.vertices.size() >= 3) solid.push_back(q.vertices);
      rays = std::make_unique<RayScene>(solid);
    }
    return *rays;
  };
  for (size_t i = 0; i < scene.polygons.size(); ++i) {
    const Polygon& p = scene.polygons[i];
    if (p.kind == PolygonKind::Window || p.vertices.size() < 3) continue;
    const glm::dvec3 np = polygonNormal(p.vertices);
    bool outside = false;
    for (int w : windows) {
      const auto& wv = scene.polygons[size_t(w)].vertices;
      const glm::dvec3 n = polygonNormal(wv);  // into the room
      double in = -1e300, beyond = -1e300;
      for (const auto& v : p.vertices) {
        const double d = glm::dot(v - wv[0], n);
        in = std::max(in, d);
        beyond = std::max(beyond, -d);
      }
      if (!(in <= 0.01 && beyond > 0.01)) continue;
      // Seen through the window: some line from the window to the polygon's front, unblocked.
      for (const auto& x : pointsOf(p.vertices)) {
        for (const auto& y : pointsOf(wv)) {
          const glm::dvec3 d = y - x;
          const double len = glm::length(d);
          if (!(len > 1e-6) || glm::dot(np, d) <= 0) continue;
          // (From just off the polygon, to the window's point: the line's own ends are no block.)
          if (!blockers().occluded(glm::vec3(x + 1e-4 * d / len), glm::vec3(y), 1e-4f)) {
            outside = true;
            break;
          }
        }
        if (outside) break;
      }
      if (outside) break;
    }
    if (outside) out.push_back(int(i));
  }
  return out;
}

}  // namespace relume
