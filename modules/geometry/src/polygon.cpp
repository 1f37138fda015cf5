#include "relume/geometry/polygon.h"

#include <glm/geometric.hpp>

namespace relume {

glm::dvec3 areaVector(std::span<const glm::dvec3> v) {
  glm::dvec3 n(0.0);
  const size_t k = v.size();
  for (size_t i = 0; i < k; ++i) n += glm::cross(v[i], v[(i + 1) % k]);
  return 0.5 * n;
}

double polygonArea(const std::vector<glm::dvec3>& v) { return glm::length(areaVector(v)); }

glm::dvec3 polygonNormal(const std::vector<glm::dvec3>& v) {
  const glm::dvec3 a = areaVector(v);
  const double l = glm::length(a);
  return l > 0 ? a / l : glm::dvec3(0, 0, 1);
}

glm::dvec3 polygonCentroid(std::span<const glm::dvec3> v) {
  // Area-weighted centroid of the triangle fan (exact for planar polygons).
  glm::dvec3 c(0.0);
  double total = 0;
  for (size_t i = 1; i + 1 < v.size(); ++i) {
    const double a = glm::length(glm::cross(v[i] - v[0], v[i + 1] - v[0]));
    c += a * (v[0] + v[i] + v[i + 1]) / 3.0;
    total += a;
  }
  if (total <= 0) {
    for (const auto& p : v) c += p;
    return v.empty() ? c : c / double(v.size());
  }
  return c / total;
}

PlaneFrame PlaneFrame::of(const std::vector<glm::dvec3>& verts) {
  PlaneFrame f;
  f.normal = polygonNormal(verts);
  f.origin = verts[0];
  glm::dvec3 e = verts[1] - verts[0];
  e -= f.normal * glm::dot(e, f.normal);
  f.u = glm::normalize(e);
  f.v = glm::cross(f.normal, f.u);
  return f;
}

glm::dvec2 PlaneFrame::toUV(const glm::dvec3& p) const {
  const glm::dvec3 d = p - origin;
  return {glm::dot(d, u), glm::dot(d, v)};
}

double polygonArea2D(const std::vector<glm::dvec2>& p) {
  double a = 0;
  for (size_t i = 0, k = p.size(); i < k; ++i) {
    const auto& q = p[i];
    const auto& r = p[(i + 1) % k];
    a += q.x * r.y - r.x * q.y;
  }
  return 0.5 * a;
}

glm::dvec2 polygonCentroid2D(const std::vector<glm::dvec2>& p) {
  double a = 0;
  glm::dvec2 c(0.0);
  for (size_t i = 0, k = p.size(); i < k; ++i) {
    const auto& q = p[i];
    const auto& r = p[(i + 1) % k];
    const double w = q.x * r.y - r.x * q.y;
    a += w;
    c += (q + r) * w;
  }
  if (std::abs(a) < 1e-300) {
    glm::dvec2 m(0.0);
    for (const auto& q : p) m += q;
    return p.empty() ? m : m / double(p.size());
  }
  return c / (3.0 * a);
}

namespace {
template <class Inside, class Cut>
std::vector<glm::dvec2> clipEdge(const std::vector<glm::dvec2>& in, Inside inside, Cut cut) {
  std::vector<glm::dvec2> out;
  out.reserve(in.size() + 2);
  for (size_t i = 0, k = in.size(); i < k; ++i) {
    const auto& a = in[i];
    const auto& b = in[(i + 1) % k];
    const bool ia = inside(a), ib = inside(b);
    if (ia) out.push_back(a);
    if (ia != ib) out.push_back(cut(a, b));
  }
  return out;
}
}  // namespace

std::vector<glm::dvec2> clipToRect(const std::vector<glm::dvec2>& poly, glm::dvec2 lo, glm::dvec2 hi) {
  std::vector<glm::dvec2> p = poly;
  for (int axis = 0; axis < 2 && !p.empty(); ++axis) {
    const double l = lo[axis], h = hi[axis];
    p = clipEdge(
        p, [&](const glm::dvec2& q) { return q[axis] >= l; },
        [&](const glm::dvec2& a, const glm::dvec2& b) {
          const double s = (l - a[axis]) / (b[axis] - a[axis]);
          glm::dvec2 r = a + s * (b - a);
          r[axis] = l;
          return r;
        });
    if (p.empty()) break;
    p = clipEdge(
        p, [&](const glm::dvec2& q) { return q[axis] <= h; },
        [&](const glm::dvec2& a, const glm::dvec2& b) {
          const double s = (h - a[axis]) / (b[axis] - a[axis]);
          glm::dvec2 r = a + s * (b - a);
          r[axis] = h;
          return r;
        });
  }
  return p;
}

void clipToHalfSpace(std::span<const glm::dvec3> poly, const glm::dvec3& p, const glm::dvec3& n,
                     std::vector<glm::dvec3>& out) {
  out.clear();
  for (size_t i = 0, k = poly.size(); i < k; ++i) {
    const auto& a = poly[i];
    const auto& b = poly[(i + 1) % k];
    const double da = glm::dot(n, a - p), db = glm::dot(n, b - p);
    if (da >= 0) out.push_back(a);
    if ((da >= 0) != (db >= 0)) out.push_back(a + (da / (da - db)) * (b - a));
  }
}

std::vector<glm::dvec3> clipToHalfSpace(std::span<const glm::dvec3> poly, const glm::dvec3& p, const glm::dvec3& n) {
  std::vector<glm::dvec3> out;
  out.reserve(poly.size() + 1);
  clipToHalfSpace(poly, p, n, out);
  return out;
}

bool insideConvex2D(const std::vector<glm::dvec2>& poly, glm::dvec2 p, double eps) {
  // Runs per sample point of every link and per texel: no division for the wrap-around, and the
  // edge's length (a square root) only for a point on the outer side of its line.
  const size_t k = poly.size();
  for (size_t i = 0; i < k; ++i) {
    const auto& a = poly[i];
    const auto& b = poly[i + 1 < k ? i + 1 : 0];
    const glm::dvec2 e = b - a, d = p - a;
    const double c = e.x * d.y - e.y * d.x;
    if ((c < 0 || eps < 0) && c < -eps * glm::length(e)) return false;
  }
  return true;
}

bool insidePolygon(const std::vector<glm::dvec3>& verts, const glm::dvec3& x) {
  if (verts.size() < 3) return false;
  // The frame from the first edge of any length (a repeated vertex has none).
  const glm::dvec3 n = polygonNormal(verts);
  glm::dvec3 t(0.0);
  for (size_t i = 0; i < verts.size() && glm::dot(t, t) <= 1e-24; ++i) {
    t = verts[(i + 1) % verts.size()] - verts[i];
    t -= n * glm::dot(t, n);
  }
  if (glm::dot(t, t) <= 1e-24) return false;
  t = glm::normalize(t);
  const glm::dvec3 u = glm::cross(n, t);
  auto flat = [&](const glm::dvec3& q) { return glm::dvec2(glm::dot(q - verts[0], t), glm::dot(q - verts[0], u)); };
  const glm::dvec2 p = flat(x);
  bool inside = false;
  for (size_t i = 0, j = verts.size() - 1; i < verts.size(); j = i++) {
    const glm::dvec2 a = flat(verts[i]), b = flat(verts[j]);
    if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x) inside = !inside;
  }
  return inside;
}

}  // namespace relume
