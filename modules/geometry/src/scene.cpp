#include "relume/geometry/scene.h"

#include <algorithm>
#include <glm/geometric.hpp>

#include "relume/geometry/polygon.h"

namespace relume {

int Scene::findPolygon(const std::string& name) const {
  for (size_t i = 0; i < polygons.size(); ++i)
    if (polygons[i].name == name) return int(i);
  return -1;
}

int Scene::findLamp(const std::string& name) const {
  for (size_t i = 0; i < lamps.size(); ++i)
    if (lamps[i].name == name) return int(i);
  return -1;
}

const SkyCapture* Scene::findSky(const std::string& name) const {
  for (const auto& c : skies)
    if (c.name == name) return &c;
  return nullptr;
}

const Photo* Scene::findPhoto(const std::string& name) const {
  for (const auto& p : photos)
    if (p.name == name) return &p;
  return nullptr;
}

int Scene::lampOfPolygon(int polygon) const {
  for (size_t i = 0; i < lamps.size(); ++i)
    if (lamps[i].polygon == polygon) return int(i);
  return -1;
}

std::vector<int> Scene::outsidePolygons() const {
  std::vector<int> out;
  for (size_t i = 0; i < polygons.size(); ++i) {
    const Polygon& p = polygons[i];
    if (p.kind == PolygonKind::Window) continue;
    for (const auto& w : polygons) {
      if (w.kind != PolygonKind::Window || w.vertices.size() < 3) continue;
      const glm::dvec3 n = polygonNormal(w.vertices);  // into the room
      double in = -1e300, beyond = -1e300;
      for (const auto& v : p.vertices) {
        const double d = glm::dot(v - w.vertices[0], n);
        in = std::max(in, d);
        beyond = std::max(beyond, -d);
      }
      if (in <= 0.01 && beyond > 0.01) {
        out.push_back(int(i));
        break;
      }
    }
  }
  return out;
}

}  // namespace relume
