#include "relume/ibr/relit_objects.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <filesystem>
#include <numbers>
#include <map>
#include <cmath>
#include <glm/geometric.hpp>

#include "relume/geometry/error.h"
#include "relume/geometry/polygon.h"
#include "relume/geometry/scene.h"
#include "relume/ibr/fan.h"
#include "relume/radiosity/hierarchy.h"
#include "relume/relight/relighter.h"

namespace relume::ibr {

void appendImageObjects(const Variant& v, const std::string& file, std::vector<ImageObject>& out,
                        const std::string& folder, const std::vector<std::string>& reserved) {
  const std::filesystem::path dir = folder.empty() ? std::filesystem::absolute(std::filesystem::path(file)).parent_path()
                                                   : std::filesystem::absolute(std::filesystem::path(folder));
  for (const auto& b : v.virtualObjects) {
    if (b.fan.empty()) continue;
    ImageObject o;
    o.name = b.name.empty() ? "image_object_" + std::to_string(out.size()) : b.name;
    // A name taken already gets its place in the list (each object is dragged, saved and named in
    // messages by it).
    auto taken = [&](const std::string& n) {
      return std::any_of(out.begin(), out.end(), [&](const ImageObject& x) { return x.name == n; }) ||
             std::find(reserved.begin(), reserved.end(), n) != reserved.end();
    };
    if (taken(o.name)) {
      const std::string base = o.name;
      for (size_t k = out.size() + 1; taken(o.name); ++k) o.name = base + " (" + std::to_string(k) + ")";
    }
    o.fanFile = b.fan.front() == '/' ? b.fan : (dir / b.fan).lexically_normal().string();
    o.fan = readFan(o.fanFile);
    o.place.position = b.position;
    o.place.scale = b.scale;
    o.place.yaw = b.rotationDegrees * std::numbers::pi / 180.0;
    out.push_back(std::move(o));
  }
}

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
  const auto& h = session.engine();
  // The light arriving there: on real surfaces what the display's B / D is made of (irradiance),
  // and on a virtual object's faces too (their radiosity is reflectance x irradiance, so the share
  // taken off is the same).
  const IrradianceAt irradiance = [&](int surface, const glm::dvec3& p) {
    return glm::dvec3(h.irradiance(h.findLeaf(surface, h.toUV(surface, p))));
  };
  return drawImageObjects(h, objects, lights, camera, irradiance, image, mask);
}

std::vector<DrawStats> drawImageObjects(const radiosity::HierarchicalRadiosity& h, const std::vector<ImageObject>& objects,
                                        const std::vector<ObjectLighting>& lights, const Camera& camera,
                                        const IrradianceAt& irradiance, ImageRGB& image, std::vector<uint8_t>* mask,
                                        const ImageRGB* perPointCap, const RayScene* occluders) {
  std::vector<DrawStats> stats(objects.size());
  if (objects.empty()) return stats;
  if (lights.size() != objects.size()) throw Error("", "image-based objects", "one lighting per object expected");
  const RoomView room = roomView(h, camera, occluders);
  if (mask) mask->assign(size_t(camera.width) * camera.height, 0);
  for (size_t i = 0; i < objects.size(); ++i)
    stats[i].shadowPixels =
        drawShadows(*objects[i].fan, objects[i].place, lights[i], h, camera, room, irradiance, image, perPointCap).shadowPixels;
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

std::vector<SurfaceShadow> shadowMaps(const radiosity::HierarchicalRadiosity& h, const std::vector<ImageObject>& objects,
                                      const std::vector<ObjectLighting>& lights, double texel) {
  if (objects.size() != lights.size()) throw Error("", "image-based objects", "one lighting per object expected");
  std::vector<ObjectShadows> casters;
  for (size_t i = 0; i < objects.size(); ++i) {
    casters.emplace_back(*objects[i].fan, objects[i].place, lights[i]);
    if (casters.back().empty()) casters.pop_back();
  }
  std::vector<SurfaceShadow> out;
  if (casters.empty() || !(texel > 0)) return out;
  const std::vector<char> emitters = emittingSurfaces(h);
  const auto& surfaces = h.surfaces();
  std::vector<SurfaceShadow> maps(surfaces.size());
  tbb::parallel_for(size_t(0), surfaces.size(), [&](size_t s) {
    const auto& surf = surfaces[s];
    if (emitters[s] || surf.vertices.size() < 3) return;
    const int sid = int(s);
    glm::dvec2 lo(1e300), hi(-1e300);
    for (const auto& v : surf.vertices) {
      const glm::dvec2 uv = h.toUV(sid, v);
      lo = glm::min(lo, uv);
      hi = glm::max(hi, uv);
    }
    const int W = std::max(1, int(std::ceil((hi.x - lo.x) / texel))), H = std::max(1, int(std::ceil((hi.y - lo.y) / texel)));
    if (size_t(W) * size_t(H) > 50'000'000) return;  // a surface of more than 11 000 m^2 at 1.5 cm: no map
    const glm::dvec3 n = polygonNormal(surf.vertices);
    std::vector<glm::vec3> keep;  // allocated once some tile is within an object's reach
    int x0 = W, y0 = H, x1 = -1, y1 = -1;
    // In tiles of 8 x 8 texels: only the objects whose shadow may reach a tile are asked about
    // its texels (most of a room is out of every object's reach).
    constexpr int kTile = 8;
    std::vector<std::pair<const ObjectShadows*, ObjectShadows::Casters>> near;
    for (int ty = 0; ty < H; ty += kTile)
      for (int tx = 0; tx < W; tx += kTile) {
        const int tw = std::min(kTile, W - tx), th = std::min(kTile, H - ty);
        const glm::dvec2 mid = lo + texel * glm::dvec2(tx + 0.5 * tw, ty + 0.5 * th);
        const double reach = 0.5 * texel * std::hypot(double(tw), double(th));
        near.clear();
        for (const auto& c : casters)
          if (const auto which = c.castersNear(h.toWorld(sid, mid), reach)) near.emplace_back(&c, which);
        if (near.empty()) continue;
        if (keep.empty()) keep.assign(size_t(W) * H, glm::vec3(1.f));
        for (int y = ty; y < ty + th; ++y)
          for (int x = tx; x < tx + tw; ++x) {
        const glm::dvec2 uv = lo + texel * glm::dvec2(x + 0.5, y + 0.5);
        const glm::dvec3 X = h.toWorld(sid, uv);
        // Each object's share kept, multiplied (as drawImageObjects applies one object's shadow
        // after the other): where two hide the same lamp its light is not taken off twice.
        glm::dvec3 kept(1.0), total(-1.0);
        for (const auto& [c, which] : near) {
          const glm::dvec3 taken = c->taken(h, sid, X, n, which);
          if (taken == glm::dvec3(0.0)) continue;
          if (total.x < 0) {
            // The irradiance shown there (texels beyond the polygon's edge, which the display's
            // filtering reads, take the leaf nearest inside).
            const int leaf = h.findLeaf(sid, uv);
            if (leaf < 0) break;
            total = glm::dvec3(h.irradiance(leaf));
          }
          for (int ch = 0; ch < 3; ++ch) kept[ch] *= total[ch] > 0 ? std::clamp(1.0 - taken[ch] / total[ch], 0.0, 1.0) : 1.0;
        }
        if (kept == glm::dvec3(1.0)) continue;
        keep[size_t(y) * W + x] = glm::vec3(kept);
        x0 = std::min(x0, x);
        y0 = std::min(y0, y);
        x1 = std::max(x1, x);
        y1 = std::max(y1, y);
          }
      }
    if (x1 < 0) return;
    x0 = std::max(0, x0 - 1);
    y0 = std::max(0, y0 - 1);
    x1 = std::min(W - 1, x1 + 1);
    y1 = std::min(H - 1, y1 + 1);
    SurfaceShadow& m = maps[s];
    m.surface = sid;
    m.texel = texel;
    m.origin = lo + texel * glm::dvec2(x0, y0);
    m.width = x1 - x0 + 1;
    m.height = y1 - y0 + 1;
    m.keep.resize(size_t(m.width) * m.height);
    for (int y = 0; y < m.height; ++y)
      for (int x = 0; x < m.width; ++x) m.keep[size_t(y) * m.width + x] = keep[size_t(y + y0) * W + x + x0];
  });
  for (auto& m : maps)
    if (m.surface >= 0) out.push_back(std::move(m));
  return out;
}

std::vector<SurfaceShadow> multiplyShadowMaps(const std::vector<const std::vector<SurfaceShadow>*>& maps) {
  std::map<int, std::vector<const SurfaceShadow*>> bySurface;
  for (const auto* list : maps)
    if (list)
      for (const auto& m : *list) bySurface[m.surface].push_back(&m);
  std::vector<SurfaceShadow> out;
  for (const auto& [surface, parts] : bySurface) {
    if (parts.size() == 1) {
      out.push_back(*parts[0]);
      continue;
    }
    // Texel offsets from the first map's origin (whole numbers: one grid per surface).
    const SurfaceShadow& ref = *parts[0];
    const double t = ref.texel;
    auto offset = [&](const SurfaceShadow& m) {
      return glm::ivec2(int(std::lround((m.origin.x - ref.origin.x) / t)), int(std::lround((m.origin.y - ref.origin.y) / t)));
    };
    glm::ivec2 lo(0), hi(ref.width, ref.height);
    for (const auto* m : parts) {
      lo = glm::min(lo, offset(*m));
      hi = glm::max(hi, offset(*m) + glm::ivec2(m->width, m->height));
    }
    SurfaceShadow u;
    u.surface = surface;
    u.texel = t;
    u.origin = ref.origin + t * glm::dvec2(lo);
    u.width = hi.x - lo.x;
    u.height = hi.y - lo.y;
    u.keep.assign(size_t(u.width) * u.height, glm::vec3(1.f));
    for (const auto* m : parts) {
      const glm::ivec2 o = offset(*m) - lo;
      for (int y = 0; y < m->height; ++y)
        for (int x = 0; x < m->width; ++x) u.keep[size_t(y + o.y) * u.width + x + o.x] *= m->keep[size_t(y) * m->width + x];
    }
    out.push_back(std::move(u));
  }
  return out;
}

}  // namespace relume::ibr
