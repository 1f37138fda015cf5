#include "relume/geometry/scene.h"

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

}  // namespace relume
