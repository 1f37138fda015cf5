#include "relume/radiosity/sh.h"

#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>
#include <vector>

#include "relume/radiosity/hierarchy.h"
#include "relume/radiosity/form_factor.h"
#include "relume/raytrace/ray_scene.h"

namespace relume::radiosity {

std::array<double, 9> shBasis(const glm::dvec3& d) {
  const double x = d.x, y = d.y, z = d.z;
  return {0.282094791773878,       0.488602511902920 * y,         0.488602511902920 * z,
          0.488602511902920 * x,   1.092548430592079 * x * y,     1.092548430592079 * y * z,
          0.315391565252520 * (3 * z * z - 1), 1.092548430592079 * x * z, 0.546274215296040 * (x * x - y * y)};
}

glm::dvec3 shIrradiance(const SH9& sh, const glm::dvec3& n) {
  constexpr double pi = std::numbers::pi;
  const double a[9] = {pi, 2 * pi / 3, 2 * pi / 3, 2 * pi / 3, pi / 4, pi / 4, pi / 4, pi / 4, pi / 4};
  const auto y = shBasis(n);
  glm::dvec3 e(0.0);
  for (int i = 0; i < 9; ++i) e += a[i] * y[i] * sh.c[i];
  return glm::max(e, glm::dvec3(0.0));
}

SH9 incidentRadiance(const HierarchicalRadiosity& h, const glm::dvec3& point, bool withEmission, int rays) {
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  std::vector<Ray> rs(size_t(std::max(rays, 1)));
  for (size_t i = 0; i < rs.size(); ++i) {
    const double z = 1.0 - (2.0 * double(i) + 1.0) / double(rs.size());
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z)), phi = golden * double(i);
    rs[i] = Ray{glm::vec3(point), glm::vec3(r * std::cos(phi), r * std::sin(phi), z), 1e-5f, 1e30f};
  }
  std::vector<RayHit> hits(rs.size());
  h.rayScene().intersect(rs, hits);
  SH9 sh;
  const double w = 4.0 * std::numbers::pi / double(rs.size());
  for (size_t i = 0; i < rs.size(); ++i) {
    const RayHit& hit = hits[i];
    if (hit.polygon < 0) continue;
    const auto& s = h.surfaces()[size_t(hit.polygon)];
    const glm::dvec3 d(rs[i].direction);
    const glm::dvec3 n = glm::cross(s.vertices[1] - s.vertices[0], s.vertices[2] - s.vertices[0]);
    const bool front = glm::dot(d, n) < 0;
    const bool emitter = glm::dot(s.exitance, s.exitance) > 0;
    if (!front && !(emitter && s.twoSided)) continue;
    const glm::dvec3 p = glm::dvec3(point) + double(hit.t) * d;
    glm::dvec3 b(h.radiosity(h.findLeaf(hit.polygon, h.toUV(hit.polygon, p))));
    if (emitter && !withEmission) b = glm::max(b - s.exitance, glm::dvec3(0.0));
    if (emitter && withEmission && s.photometry) {  // a distribution's radiance depends on direction
      const EmitterShape shape(s.vertices, s.twoSided, s.photometry);
      b = b - s.exitance + s.exitance * shape.weight(point);
    }
    const auto y = shBasis(d);
    for (int k = 0; k < 9; ++k) sh.c[k] += (w * y[k] / std::numbers::pi) * b;
  }
  return sh;
}

}  // namespace relume::radiosity
