#include "relume/geometry/validate.h"

#include <cmath>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <sstream>

#include "relume/geometry/error.h"

namespace relume {

namespace {

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

std::string fmt(double x) {
  std::ostringstream s;
  s.precision(4);
  s << x;
  return s.str();
}

void checkPolygon(const Scene& scene, const Polygon& p, const ValidationOptions& opt) {
  const std::string where = "polygon '" + p.name + "'";
  auto fail = [&](const std::string& what) { throw Error(scene.sourceFile, where, what); };
  for (size_t i = 0; i < p.vertices.size(); ++i)
    if (!finite(p.vertices[i]))
      fail("vertex " + std::to_string(i) + " has a NaN or infinite coordinate");
  if (p.kind != PolygonKind::Light && !finite(p.albedo)) fail("albedo is NaN or infinite");
  if (p.kind != PolygonKind::Light && p.kind != PolygonKind::Window)
    for (int c = 0; c < 3; ++c)
      if (p.albedo[c] < 0 || p.albedo[c] > 1) fail("albedo " + fmt(p.albedo[c]) + " is outside [0, 1]");
  // Distinct vertices (consecutive duplicates do not count).
  std::vector<glm::dvec3> v;
  for (const auto& q : p.vertices)
    if (v.empty() || glm::length(q - v.back()) > 1e-12) v.push_back(q);
  if (v.size() > 1 && glm::length(v.front() - v.back()) <= 1e-12) v.pop_back();
  if (v.size() < 3)
    fail("has " + std::to_string(v.size()) + " distinct vertices; a polygon needs at least 3");
  const double area = polygonArea(v);
  if (!(area > opt.minArea)) fail("has zero area (" + fmt(area) + " m^2)");
  const glm::dvec3 n = polygonNormal(v);
  const glm::dvec3 c = polygonCentroid(v);
  double diameter = 0;
  for (const auto& a : v)
    for (const auto& b : v) diameter = std::max(diameter, glm::length(a - b));
  for (size_t i = 0; i < v.size(); ++i) {
    const double d = std::abs(glm::dot(v[i] - c, n));
    if (d > opt.planarityTolerance * diameter)
      fail("is not planar: vertex " + std::to_string(i) + " lies " + fmt(d) + " m off its plane");
  }
  for (size_t i = 0, k = v.size(); i < k; ++i) {
    const glm::dvec3 e0 = v[(i + 1) % k] - v[i];
    const glm::dvec3 e1 = v[(i + 2) % k] - v[(i + 1) % k];
    const double turn = glm::dot(glm::cross(e0, e1), n);
    if (turn < -1e-9 * diameter * diameter)
      fail("is not convex at vertex " + std::to_string((i + 1) % k) +
           " (split it into convex polygons)");
  }
}

// A shell polygon is one whose plane has the whole scene on one side. Its normal must point
// towards the scene (into the room); a contact face (a box bottom lying on the floor) is exempt.
void checkShellOrientation(const Scene& scene) {
  glm::dvec3 lo(1e300), hi(-1e300);
  std::vector<glm::dvec3> all;  // every vertex, with the polygon it belongs to
  std::vector<size_t> owner;
  for (size_t i = 0; i < scene.polygons.size(); ++i)
    for (const auto& q : scene.polygons[i].vertices) {
      lo = glm::min(lo, q);
      hi = glm::max(hi, q);
      all.push_back(q);
      owner.push_back(i);
    }
  const double size = glm::length(hi - lo);
  const double tol = 1e-6 * size;
  for (size_t i = 0; i < scene.polygons.size(); ++i) {
    const auto& p = scene.polygons[i];
    if (p.kind == PolygonKind::Window) continue;
    const glm::dvec3 n = polygonNormal(p.vertices);
    const glm::dvec3 o = p.vertices[0];
    // Most polygons have some of the scene in front: stop at the first such vertex (this keeps
    // the check near-linear in the scene's size rather than quadratic).
    double mn = 0;
    bool inFront = false;
    for (size_t k = 0; k < all.size() && !inFront; ++k) {
      if (owner[k] == i) continue;
      const double d = glm::dot(all[k] - o, n);
      inFront = d > tol;
      mn = std::min(mn, d);
    }
    if (inFront || mn >= -100 * tol) continue;
    // The whole scene behind it: wrong unless a polygon lies on its plane facing the other way
    // (a contact face).
    bool oppositeCoplanar = false;
    for (size_t j = 0; j < scene.polygons.size() && !oppositeCoplanar; ++j) {
      if (j == i) continue;
      const auto& q = scene.polygons[j];
      bool allOnPlane = true;
      for (const auto& x : q.vertices) allOnPlane = allOnPlane && std::abs(glm::dot(x - o, n)) <= tol;
      oppositeCoplanar = allOnPlane && glm::dot(polygonNormal(q.vertices), n) < -0.999;
    }
    if (!oppositeCoplanar)
      throw Error(scene.sourceFile, "polygon '" + p.name + "'",
                  "its normal points out of the room (the rest of the scene lies behind it); "
                  "reverse its vertex order");
  }
}

void checkCamera(const Scene& scene, const Photo& ph) {
  const std::string where = "photo '" + ph.name + "'";
  const Camera& c = ph.camera;
  for (int i = 0; i < 3; ++i)
    if (!finite(c.K[i]) || !finite(c.R[i]))
      throw Error(scene.sourceFile, where, "camera K or R holds a NaN or infinite number");
  if (!finite(c.t)) throw Error(scene.sourceFile, where, "camera t holds a NaN or infinite number");
  if (!(c.fx() > 0 && c.fy() > 0))
    throw Error(scene.sourceFile, where, "camera K has a non-positive focal length");
  if (c.width <= 0 || c.height <= 0)
    throw Error(scene.sourceFile, where, "image width and height must be positive");
  const glm::dmat3 rtr = glm::transpose(c.R) * c.R;
  double dev = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) dev = std::max(dev, std::abs(rtr[i][j] - (i == j ? 1.0 : 0.0)));
  if (dev > 1e-3)
    throw Error(scene.sourceFile, where,
                "camera R is not a rotation: R^T R differs from the identity by " + fmt(dev));
  if (glm::determinant(c.R) < 0)
    throw Error(scene.sourceFile, where, "camera R is a reflection (determinant -1), not a rotation");
}

}  // namespace

void validateScene(const Scene& scene, const ValidationOptions& options) {
  if (scene.polygons.empty()) throw Error(scene.sourceFile, "", "the scene holds no polygons");
  if (scene.polygons.size() > kMaxRoomPolygons)
    throw Error(scene.sourceFile, "",
                "has " + std::to_string(scene.polygons.size()) + " polygons; Relume relights rooms of up to " +
                    std::to_string(kMaxRoomPolygons) +
                    " (each keeps its own textures and radiosity hierarchy): model the room with planes for the walls "
                    "and boxes for the furniture, as the paper does");
  for (const auto& p : scene.polygons)
    if (p.vertices.size() > kMaxPolygonVertices)
      throw Error(scene.sourceFile, "polygon '" + p.name + "'",
                  "has " + std::to_string(p.vertices.size()) + " vertices; a polygon may have up to " +
                      std::to_string(kMaxPolygonVertices));
  for (const auto& p : scene.polygons) checkPolygon(scene, p, options);
  for (const auto& l : scene.lamps) {
    const std::string where = "lamp '" + l.name + "'";
    if (l.polygon < 0 || l.polygon >= int(scene.polygons.size()))
      throw Error(scene.sourceFile, where, "has no polygon");
    if (!finite(l.radiance)) throw Error(scene.sourceFile, where, "radiance is NaN or infinite");
    if (l.radiance.x < 0 || l.radiance.y < 0 || l.radiance.z < 0)
      throw Error(scene.sourceFile, where, "radiance is negative");
  }
  checkShellOrientation(scene);
  for (const auto& ph : scene.photos) checkCamera(scene, ph);
}

}  // namespace relume
