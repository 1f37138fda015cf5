#include "relume/daylight/relight.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <map>
#include <memory>
#include <numbers>
#include <string>

#include "relume/geometry/error.h"
#include "relume/geometry/polygon.h"
#include "relume/radiosity/form_factor.h"
#include "relume/radiosity/hierarchy.h"
#include "relume/raytrace/ray_scene.h"
#include "relume/relight/solution_render.h"

namespace relume::daylight {

namespace {
constexpr double kPi = std::numbers::pi;

glm::vec3 get(const ImageRGB& im, size_t i) { return {im.pixels[3 * i], im.pixels[3 * i + 1], im.pixels[3 * i + 2]}; }
void put(ImageRGB& im, size_t i, const glm::vec3& v) {
  im.pixels[3 * i] = v.x;
  im.pixels[3 * i + 1] = v.y;
  im.pixels[3 * i + 2] = v.z;
}

// Where the ray from p along d leaves through one of the windows (out through the face that looks
// into the room): the distance, or -1.
double throughWindow(const radiosity::HierarchicalRadiosity& h, const std::vector<int>& windows, const glm::dvec3& p,
                     const glm::dvec3& d) {
  double best = -1;
  for (int w : windows) {
    const auto& v = h.surfaces()[size_t(w)].vertices;
    const glm::dvec3 n = polygonNormal(v);
    if (glm::dot(d, n) >= 0) continue;
    const double t = radiosity::rayThroughPolygon(p, d, v, n);
    if (t > 0 && (best < 0 || t < best)) best = t;
  }
  return best;
}
}  // namespace

SeenPixels seePixels(const DaylightBasis& basis, const Camera& cam) {
  const auto& h = basis.engine();
  SeenPixels px;
  px.camera = cam;
  px.width = cam.width;
  px.height = cam.height;
  const size_t n = size_t(cam.width) * size_t(cam.height);
  px.surface.assign(n, -1);
  px.leaf.assign(n, -1);
  px.uv.assign(n, glm::dvec2(0.0));
  px.point.assign(n, glm::dvec3(0.0));
  px.normal.assign(n, glm::dvec3(0.0));
  const glm::dvec3 eye = cam.center();
  tbb::parallel_for(tbb::blocked_range<int>(0, cam.height, 8), [&](const tbb::blocked_range<int>& rows) {
    std::vector<Ray> rays(size_t(cam.width));
    std::vector<RayHit> hits(size_t(cam.width));
    for (int y = rows.begin(); y < rows.end(); ++y) {
      for (int x = 0; x < cam.width; ++x)
        rays[size_t(x)] = Ray{glm::vec3(eye), glm::vec3(cam.rayDirection(x + 0.5, y + 0.5)), 0.f, 1e30f};
      h.rayScene().intersect(rays, hits);
      for (int x = 0; x < cam.width; ++x) {
        const RayHit& hit = hits[size_t(x)];
        if (hit.polygon < 0 || basis.isLamp(hit.polygon) || h.surfaces()[size_t(hit.polygon)].opening) continue;
        const size_t i = size_t(y) * size_t(cam.width) + size_t(x);
        const glm::dvec3 p = eye + double(hit.t) * glm::dvec3(rays[size_t(x)].direction);
        glm::dvec3 nrm = polygonNormal(h.surfaces()[size_t(hit.polygon)].vertices);
        if (glm::dot(nrm, eye - p) < 0) continue;  // a back face: nothing a photo shows
        px.surface[i] = hit.polygon;
        px.uv[i] = h.toUV(hit.polygon, p);
        px.leaf[i] = h.findLeaf(hit.polygon, px.uv[i]);
        px.point[i] = p;
        px.normal[i] = nrm;
      }
    }
  });
  return px;
}

ImageRGB irradianceImage(DaylightBasis& basis, const SeenPixels& px, const SkyRadiance& sky, Progress& progress) {
  const bool sun = sky.sun.found && sky.sun.direction.z > 0;
  const std::vector<glm::vec3> rest = basis.irradiance(sky, false, progress);
  const auto& h = basis.engine();
  const auto corners = leafCornerValues(h, rest);
  ImageRGB out(px.width, px.height);
  const glm::dvec3 s = sun ? glm::normalize(sky.sun.direction) : glm::dvec3(0, 0, 1);
  const glm::vec3 sunE(sky.sun.irradiance);
  const auto& windows = basis.windows();
  // Directions over the sun's disc (0.53 degrees across; a fisheye's few pixels cannot resolve it),
  // 16 of equal area, so that shadow edges get the penumbra the sun gives them.
  std::vector<glm::dvec3> sunDisc;
  {
    const glm::dvec3 t = glm::normalize(glm::cross(s, std::abs(s.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0)));
    const glm::dvec3 u = glm::cross(s, t);
    const double radius = 0.5 * 0.53 * kPi / 180;
    for (int j = 0; j < 16; ++j) {
      const double r = radius * std::sqrt((j + 0.5) / 16), a = j * kPi * (3 - std::sqrt(5.0));
      sunDisc.push_back(glm::normalize(s + r * (std::cos(a) * t + std::sin(a) * u)));
    }
  }
  tbb::parallel_for(tbb::blocked_range<size_t>(0, px.surface.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i < r.end(); ++i) {
      if (px.surface[i] < 0) continue;
      // The leaf as it is now: a sun solution may have refined the hierarchy since the pixels were seen.
      int leaf = px.leaf[i];
      if (leaf < 0 || !h.nodes()[size_t(leaf)].isLeaf()) leaf = h.findLeaf(px.surface[i], px.uv[i]);
      glm::vec3 e = leaf >= 0 ? interpolateCorners(h.nodes()[size_t(leaf)], corners[size_t(leaf)], px.uv[i]) : glm::vec3(0.f);
      e = glm::max(e, glm::vec3(0.f));
      if (sun) {
        // The pixel's footprint: 4 x 4 camera rays over 1.5 pixels, each point's direct sun.
        const double x = double(i % size_t(px.width)) + 0.5, y = double(i / size_t(px.width)) + 0.5;
        const glm::dvec3 eye = px.camera.center();
        double sum = 0;
        constexpr int k = 4;
        Ray rays[k * k];
        RayHit hits[k * k];
        for (int j = 0; j < k * k; ++j) {
          const double dx = ((j % k) + 0.5) / k * 1.5 - 0.75, dy = ((j / k) + 0.5) / k * 1.5 - 0.75;
          rays[j] = Ray{glm::vec3(eye), glm::vec3(px.camera.rayDirection(x + dx, y + dy)), 0.f, 1e30f};
        }
        h.rayScene().intersect(rays, hits);
        for (int j = 0; j < k * k; ++j) {
          if (hits[j].polygon < 0) continue;
          const glm::dvec3 n = polygonNormal(h.surfaces()[size_t(hits[j].polygon)].vertices);
          if (glm::dot(n, glm::dvec3(rays[j].direction)) > 0) continue;  // a back face: dark
          const glm::dvec3& sj = sunDisc[size_t((j * 7) % (k * k))];  // footprint and disc decorrelated
          const double c = glm::dot(n, sj);
          if (c <= 0) continue;
          const glm::dvec3 from = eye + double(hits[j].t) * glm::dvec3(rays[j].direction) + 1e-4 * n;
          const double t = throughWindow(h, windows, from, sj);
          if (t > 0 && !h.rayScene().occluded(glm::vec3(from), glm::vec3(from + t * sj), 1e-4f)) sum += c;
        }
        e += sunE * float(sum / (k * k));
      }
      put(out, i, e);
    }
  });
  return out;
}

ImageRGB distantIrradianceImage(const SeenPixels& px, const SkyRegions& regions, const SkyRadiance& sky,
                                const std::vector<std::vector<glm::dvec3>>& occluders) {
  std::unique_ptr<RayScene> block = occluders.empty() ? nullptr : std::make_unique<RayScene>(occluders);
  struct Dir {
    glm::dvec3 d;
    glm::dvec3 weight;  // radiance x solid angle, or the sun's irradiance
  };
  std::vector<Dir> dirs;
  for (int k = 0; k < regions.size(); ++k) dirs.push_back({regions.centre(k), sky.region[size_t(k)] * regions.solidAngle(k)});
  if (sky.sun.found && sky.sun.direction.z > 0) dirs.push_back({glm::normalize(sky.sun.direction), sky.sun.irradiance});
  ImageRGB out(px.width, px.height);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, px.surface.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i < r.end(); ++i) {
      if (px.surface[i] < 0) continue;
      glm::dvec3 e(0.0);
      const glm::dvec3 from = px.point[i] + 1e-4 * px.normal[i];
      for (const auto& d : dirs) {
        const double c = glm::dot(px.normal[i], d.d);
        if (c <= 0) continue;
        if (block && block->occluded(glm::vec3(from), glm::vec3(from + 100.0 * d.d), 1e-6f)) continue;
        e += c * d.weight;
      }
      put(out, i, glm::vec3(e));
    }
  });
  return out;
}

std::vector<glm::dvec3> reflectancesFromPhoto(const SeenPixels& px, const ImageRGB& photo, const ImageRGB& irradiance,
                                              size_t polygons, int minPixels) {
  std::vector<glm::dvec3> l(polygons, glm::dvec3(0.0)), e(polygons, glm::dvec3(0.0));
  std::vector<int> count(polygons, 0);
  for (size_t i = 0; i < px.surface.size(); ++i) {
    const int s = px.surface[i];
    if (s < 0 || size_t(s) >= polygons) continue;
    l[size_t(s)] += glm::dvec3(get(photo, i));
    e[size_t(s)] += glm::dvec3(get(irradiance, i));
    ++count[size_t(s)];
  }
  std::vector<glm::dvec3> out(polygons, glm::dvec3(-1.0));
  for (size_t s = 0; s < polygons; ++s) {
    if (count[s] < minPixels) continue;
    for (int c = 0; c < 3; ++c)
      if (e[s][c] > 0) out[s][c] = std::clamp(kPi * l[s][c] / e[s][c], 0.0, 0.98);
  }
  return out;
}

ImageRGB differentialRender(const ImageRGB& photo, const ImageRGB& ePhoto, const ImageRGB& eNew, const SeenPixels& seenNew,
                            int firstVirtual, const std::vector<glm::dvec3>& virtualAlbedo) {
  const size_t n = seenNew.surface.size();
  if (photo.pixels.size() != 3 * n || ePhoto.pixels.size() != 3 * n || eNew.pixels.size() != 3 * n)
    throw Error("", "differential rendering", "the photo is " + std::to_string(photo.width) + "x" + std::to_string(photo.height) +
                                                  ", the camera sees " + std::to_string(seenNew.width) + "x" +
                                                  std::to_string(seenNew.height));
  ImageRGB out = photo;
  for (size_t i = 0; i < seenNew.surface.size(); ++i) {
    const int s = seenNew.surface[i];
    if (s >= firstVirtual && size_t(s - firstVirtual) < virtualAlbedo.size()) {
      put(out, i, glm::vec3(virtualAlbedo[size_t(s - firstVirtual)] / kPi) * get(eNew, i));
      continue;
    }
    if (s < 0) continue;
    const glm::vec3 a = get(ePhoto, i), b = get(eNew, i), ph = get(photo, i);
    glm::vec3 v = ph;
    // Where the photo's irradiance is too small to divide by, the simulation cannot say.
    for (int c = 0; c < 3; ++c)
      if (a[c] > 1e-6f) v[c] = ph[c] * (b[c] / a[c]);
    put(out, i, v);
  }
  return out;
}

DaylightRelighting::DaylightRelighting(const Scene& scene, const ImageRGB& photo, const Camera& camera,
                                       const SkyRadiance& photoSky, const BasisOptions& options, Progress& progress)
    : photo_(photo), camera_(camera) {
  if (photo.width != camera.width || photo.height != camera.height)
    throw Error(scene.sourceFile, "main photo", "its image is " + std::to_string(photo.width) + "x" + std::to_string(photo.height) +
                                                    ", its camera " + std::to_string(camera.width) + "x" + std::to_string(camera.height));
  Scene room = scene;
  for (auto& poly : room.polygons) poly.albedo = glm::dvec3(0.5);
  // Polygons outside (beyond a window: the ground) are not seen from inside: they take the
  // ground's albedo the user gives (default 0.2, an open ground's), never an estimate.
  std::vector<bool> outside(room.polygons.size(), false);
  for (int s : outsidePolygons(room)) {
    outside[size_t(s)] = true;
    room.polygons[size_t(s)].albedo = glm::dvec3(options.groundReflectance);
  }
  reflectances_.assign(room.polygons.size(), glm::dvec3(0.5));
  estimated_.assign(room.polygons.size(), false);
  constexpr int rounds = 3;
  for (int round = 0; round < rounds; ++round) {
    Progress stage(progress, double(round) / rounds, double(round + 1) / rounds);
    stage.report(0, "estimating reflectances under the photos' sky (round " + std::to_string(round + 1) + " of " +
                        std::to_string(rounds) + ")");
    basis_ = std::make_unique<DaylightBasis>(room, photoSky, options, stage);
    seen_ = seePixels(*basis_, camera);
    ePhoto_ = irradianceImage(*basis_, seen_, photoSky, stage);
    if (round + 1 == rounds) break;
    const auto rho = reflectancesFromPhoto(seen_, photo, ePhoto_, room.polygons.size());
    std::map<std::string, std::pair<glm::dvec3, double>> byMaterial;
    glm::dvec3 all(0.0);
    double allArea = 0;
    for (size_t s = 0; s < rho.size(); ++s) {
      if (rho[s].x < 0) continue;
      const double a = polygonArea(room.polygons[s].vertices);
      auto& m = byMaterial[room.polygons[s].material];
      m.first += a * rho[s];
      m.second += a;
      all += a * rho[s];
      allArea += a;
    }
    for (size_t s = 0; s < rho.size(); ++s) {
      if (room.polygons[s].kind != PolygonKind::Real || outside[s]) continue;
      const auto m = byMaterial.find(room.polygons[s].material);
      estimated_[s] = rho[s].x >= 0;
      room.polygons[s].albedo = rho[s].x >= 0 ? rho[s]
                                : m != byMaterial.end() && !room.polygons[s].material.empty() ? m->second.first / m->second.second
                                : allArea > 0 ? all / allArea
                                              : glm::dvec3(0.5);
      reflectances_[s] = room.polygons[s].albedo;
    }
  }
}

DaylightRelighting::~DaylightRelighting() = default;

ImageRGB DaylightRelighting::render(const SkyRadiance& sky, const std::vector<Polygon>& objects, DaylightMethod method,
                                    Progress& progress) {
  std::vector<glm::dvec3> albedos;
  std::vector<std::vector<glm::dvec3>> occluders;
  for (const auto& o : objects) {
    albedos.push_back(o.albedo);
    occluders.push_back(o.vertices);
  }
  std::vector<int> ids;
  SeenPixels seen = seen_;
  if (!objects.empty()) {
    Progress stage(progress, 0.0, 0.6);
    ids = basis_->addObjects(objects, stage);
    seen = seePixels(*basis_, camera_);
  }
  const int firstVirtual = ids.empty() ? int(basis_->engine().surfaces().size()) : ids.front();
  ImageRGB out;
  try {
    if (method == DaylightMethod::NearField) {
      Progress stage(progress, 0.6, 0.9);
      eLast_ = irradianceImage(*basis_, seen, sky, stage);
      out = differentialRender(photo_, ePhoto_, eLast_, seen, firstVirtual, albedos);
    } else if (objects.empty()) {
      out = photo_;  // the sky at infinity changes nothing the photo shows of the room
    } else {
      eLast_ = distantIrradianceImage(seen, basis_->regions(), sky, occluders);
      out = differentialRender(photo_, distantIrradianceImage(seen, basis_->regions(), sky, {}), eLast_, seen, firstVirtual,
                               albedos);
    }
  } catch (...) {
    if (!ids.empty()) basis_->removeObjects(ids);
    throw;
  }
  if (!ids.empty()) basis_->removeObjects(ids);  // not cancellable: the room must come back whole
  return out;
}

}  // namespace relume::daylight
