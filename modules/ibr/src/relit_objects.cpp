#include "relume/ibr/relit_objects.h"

#include <algorithm>
#include <glm/geometric.hpp>

#include "relume/geometry/error.h"
#include "relume/radiosity/hierarchy.h"
#include "relume/relight/relighter.h"

namespace relume::ibr {

void checkImageObject(const Scene& scene, const ImageObject& o) {
  const ImageFan& f = *o.fan;
  // The placed bounding box as a closed box of six faces (turned with the object).
  glm::dvec3 c[8];
  for (int i = 0; i < 8; ++i)
    c[i] = o.place.toWorld(f, glm::dvec3(i & 1 ? f.boundsMax.x : f.boundsMin.x, i & 2 ? f.boundsMax.y : f.boundsMin.y,
                                         i & 4 ? f.boundsMax.z : f.boundsMin.z));
  // Shrunk by a hair so that an object standing on the floor does not count as cutting it.
  glm::dvec3 mid(0.0);
  for (const auto& p : c) mid += p / 8.0;
  for (auto& p : c) p = mid + (p - mid) * (1.0 - 1e-4);
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  VirtualObject box;
  box.name = o.name;
  for (const auto& fc : faces) box.polygons.push_back({c[fc[0]], c[fc[1]], c[fc[2]], c[fc[3]]});
  try {
    checkVirtualObject(scene, box);
  } catch (const Error& e) {
    throw Error(o.fanFile, "image-based object '" + o.name + "'", e.problem());
  }
}

std::vector<DrawStats> drawImageObjects(RelightSession& session, const std::vector<ImageObject>& objects,
                                        const Camera& camera, ImageRGB& image, std::vector<uint8_t>* mask) {
  if (objects.empty()) return std::vector<DrawStats>();
  session.syncEngine();
  std::vector<ObjectLighting> lights;
  for (const auto& o : objects) lights.push_back(lightingAt(session.engine(), o.place.toWorld(*o.fan, o.fan->centre)));
  return drawImageObjects(static_cast<const RelightSession&>(session), objects, lights, camera, image, mask);
}

std::vector<DrawStats> drawImageObjects(const RelightSession& session, const std::vector<ImageObject>& objects,
                                        const std::vector<ObjectLighting>& lights, const Camera& camera, ImageRGB& image,
                                        std::vector<uint8_t>* mask) {
  std::vector<DrawStats> stats(objects.size());
  if (objects.empty()) return stats;
  if (lights.size() != objects.size()) throw Error("", "image-based objects", "one lighting per object expected");
  const auto& h = session.engine();
  const RoomView room = roomView(h, camera);
  if (mask) mask->assign(size_t(camera.width) * camera.height, 0);
  // The light arriving there: on real surfaces what the display's B / D is made of (irradiance),
  // and on a virtual object's faces too (their radiosity is reflectance x irradiance, so the share
  // taken off is the same).
  const IrradianceAt irradiance = [&](int surface, const glm::dvec3& p) {
    return glm::dvec3(h.irradiance(h.findLeaf(surface, h.toUV(surface, p))));
  };
  for (size_t i = 0; i < objects.size(); ++i)
    stats[i].shadowPixels =
        drawShadows(*objects[i].fan, objects[i].place, lights[i], h, camera, room, irradiance, image).shadowPixels;
  std::vector<size_t> order(objects.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  const glm::dvec3 eye = camera.center();
  auto dist = [&](size_t i) { return glm::length(objects[i].place.toWorld(*objects[i].fan, objects[i].fan->centre) - eye); };
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return dist(a) > dist(b); });
  for (size_t i : order) {
    const DrawStats d = drawObject(*objects[i].fan, objects[i].place, lights[i], camera, room, image, mask);
    stats[i].view = d.view;
    stats[i].objectPixels = d.objectPixels;
  }
  return stats;
}

}  // namespace relume::ibr
