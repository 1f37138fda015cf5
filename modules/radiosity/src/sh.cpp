#include "relume/radiosity/sh.h"

#include <algorithm>
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

namespace {
// The clamped cosine's zonal coefficients per band, A_l (Ramamoorthi and Hanrahan 2001).
constexpr double kPi = std::numbers::pi;
constexpr double kBand[9] = {kPi, 2 * kPi / 3, 2 * kPi / 3, 2 * kPi / 3, kPi / 4, kPi / 4, kPi / 4, kPi / 4, kPi / 4};
}  // namespace

glm::dvec3 shIrradiance(const SH9& sh, const glm::dvec3& n) {
  SHTransfer c;
  const auto y = shBasis(n);
  for (int i = 0; i < 9; ++i) c[size_t(i)] = kBand[i] * y[size_t(i)];
  return shApply(sh, c);
}

glm::dvec3 shApply(const SH9& light, const SHTransfer& transfer) {
  glm::dvec3 e(0.0);
  for (size_t i = 0; i < 9; ++i) e += transfer[i] * light.c[i];
  return glm::max(e, glm::dvec3(0.0));
}

SHTransfer shTransfer(const glm::dvec3& point, const glm::dvec3& n, const RayScene* occluders, int rays) {
  SHTransfer c{};
  if (!occluders) {
    const auto y = shBasis(n);
    for (size_t i = 0; i < 9; ++i) c[i] = kBand[i] * y[i];
    return c;
  }
  // Cosine-distributed directions about n (stratified on a Fibonacci spiral of the unit disc,
  // lifted to the hemisphere): each unblocked direction adds pi / rays x Y_lm(w), since
  // the integral of max(0, n . w) f(w) dw = pi x the cosine-weighted mean of f.
  const int count = std::max(rays, 1);
  const glm::dvec3 t = glm::normalize(glm::cross(n, std::abs(n.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0)));
  const glm::dvec3 u = glm::cross(n, t);
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  std::vector<Ray> rs(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i) {
    const double r = std::sqrt((i + 0.5) / count), phi = golden * i;
    const glm::dvec3 d = r * std::cos(phi) * t + r * std::sin(phi) * u + std::sqrt(std::max(0.0, 1 - r * r)) * n;
    rs[size_t(i)] = Ray{glm::vec3(point + 1e-4 * n), glm::vec3(d), 1e-5f, 1e30f};
  }
  std::vector<RayHit> hits(rs.size());
  occluders->intersect(rs, hits);
  for (size_t i = 0; i < rs.size(); ++i) {
    if (hits[i].polygon >= 0) continue;
    const auto y = shBasis(glm::dvec3(rs[i].direction));
    for (size_t k = 0; k < 9; ++k) c[k] += kPi / count * y[k];
  }
  return c;
}

std::vector<glm::dvec3> fibonacciSphere(int count) {
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  std::vector<glm::dvec3> d(size_t(std::max(count, 1)));
  for (size_t i = 0; i < d.size(); ++i) {
    const double z = 1.0 - (2.0 * double(i) + 1.0) / double(d.size());
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z)), phi = golden * double(i);
    d[i] = {r * std::cos(phi), r * std::sin(phi), z};
  }
  return d;
}

SH9 incidentRadiance(const HierarchicalRadiosity& h, const glm::dvec3& point, bool withEmission, int rays) {
  const std::vector<glm::dvec3> dirs = fibonacciSphere(rays);
  std::vector<Ray> rs(dirs.size());
  for (size_t i = 0; i < rs.size(); ++i) rs[i] = Ray{glm::vec3(point), glm::vec3(dirs[i]), 1e-5f, 1e30f};
  std::vector<RayHit> hits(rs.size());
  h.rayScene().intersect(rs, hits);
  SH9 sh;
  const double w = 4.0 * kPi / double(rs.size());
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
