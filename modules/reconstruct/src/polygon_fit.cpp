#include "relume/reconstruct/polygon_fit.h"

#include <glm/geometric.hpp>
#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>

#include "relume/geometry/error.h"

namespace relume::recon {

glm::dvec3 Plane::project(const glm::dvec3& p) const { return p - normal * glm::dot(p - point, normal); }

Plane fitPlane(const std::vector<glm::dvec3>& pts, const std::string& what) {
  if (pts.size() < 3)
    throw Error("", what, "has " + std::to_string(pts.size()) + " point(s); a polygon needs three or more");
  glm::dvec3 c(0.0);
  for (const auto& p : pts) c += p;
  c /= double(pts.size());
  cv::Matx33d S = cv::Matx33d::zeros();
  for (const auto& p : pts) {
    const glm::dvec3 d = p - c;
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) S(r, k) += d[r] * d[k];
  }
  cv::Mat evals, evecs;
  cv::eigen(cv::Mat(S), evals, evecs);  // descending
  const double l0 = evals.at<double>(0), l1 = evals.at<double>(1), l2 = evals.at<double>(2);
  if (l0 <= 0 || l1 < 1e-6 * l0)
    throw Error("", what, "its points are collinear (or coincide): they do not span a plane; pick a point off the line");
  Plane pl;
  pl.point = c;
  pl.normal = glm::normalize(glm::dvec3(evecs.at<double>(2, 0), evecs.at<double>(2, 1), evecs.at<double>(2, 2)));
  pl.rms = std::sqrt(std::max(l2, 0.0) / double(pts.size()));
  return pl;
}

namespace {
double cross2(glm::dvec2 o, glm::dvec2 a, glm::dvec2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

// Andrew's monotone chain; counter-clockwise, collinear points dropped.
std::vector<int> hull2D(const std::vector<glm::dvec2>& p) {
  std::vector<int> idx(p.size());
  for (size_t i = 0; i < p.size(); ++i) idx[i] = int(i);
  std::sort(idx.begin(), idx.end(), [&](int a, int b) { return p[a].x < p[b].x || (p[a].x == p[b].x && p[a].y < p[b].y); });
  std::vector<int> h(2 * p.size());
  size_t k = 0;
  for (int i : idx) {
    while (k >= 2 && cross2(p[h[k - 2]], p[h[k - 1]], p[i]) <= 0) --k;
    h[k++] = i;
  }
  for (size_t t = k + 1, j = idx.size() - 1; j-- > 0;) {
    const int i = idx[j];
    while (k >= t && cross2(p[h[k - 2]], p[h[k - 1]], p[i]) <= 0) --k;
    h[k++] = i;
  }
  h.resize(k > 0 ? k - 1 : 0);
  return h;
}
}  // namespace

std::vector<glm::dvec3> convexPolygon(const std::vector<glm::dvec3>& pts, const Plane& plane, const glm::dvec3& viewer,
                                      const std::string& what, const PolygonConstraints& constraints) {
  if (pts.size() < 3) throw Error("", what, "needs three or more corners");
  glm::dvec3 n = plane.normal;
  if (glm::dot(viewer - plane.point, n) < 0) n = -n;
  glm::dvec3 u = glm::cross(std::abs(n.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0), n);
  u = glm::normalize(u);
  const glm::dvec3 v = glm::cross(n, u);
  std::vector<glm::dvec2> p2;
  for (const auto& p : pts) {
    const glm::dvec3 d = p - plane.point;
    p2.emplace_back(glm::dot(d, u), glm::dot(d, v));
  }
  std::vector<int> h = hull2D(p2);
  if (h.size() < 3) throw Error("", what, "its points are collinear: they enclose no area");
  if (constraints.keepOrder && h.size() == pts.size()) {
    // The given order, if it walks around the hull (in either direction) from the first corner.
    const size_t n = pts.size();
    auto idx = [&](long k) { return size_t(((k % long(n)) + long(n)) % long(n)); };
    auto isOrder = [&](long dir) {
      // Every turn to the left and one turn in all (a star order turns left but twice around).
      double turning = 0;
      for (size_t i = 0; i < n; ++i) {
        const glm::dvec2 a = p2[idx(long(i) * dir)], b = p2[idx((long(i) + 1) * dir)], c = p2[idx((long(i) + 2) * dir)];
        if (cross2(a, b, c) <= 0) return false;
        const glm::dvec2 e1 = b - a, e2 = c - b;
        turning += std::atan2(e1.x * e2.y - e1.y * e2.x, glm::dot(e1, e2));
      }
      return std::abs(turning - 2 * M_PI) < 1e-6;
    };
    std::vector<int> given(n);
    if (isOrder(1)) {
      for (size_t i = 0; i < n; ++i) given[i] = int(i);
      h = given;
    } else if (isOrder(-1)) {
      for (size_t i = 0; i < n; ++i) given[i] = int(idx(-long(i)));
      h = given;
    }
  }
  std::vector<glm::dvec3> out;
  for (int i : h) out.push_back(plane.point + u * p2[i].x + v * p2[i].y);
  if (constraints.rectangle) {
    if (out.size() != 4)
      throw Error("", what, "a rectangle needs four corners on its convex outline (have " + std::to_string(out.size()) + ")");
    out = rectify(out, what);
  }
  return out;
}

std::vector<glm::dvec3> rectify(const std::vector<glm::dvec3>& q, const std::string& what) {
  if (q.size() != 4) throw Error("", what, "a rectangle needs exactly four corners");
  for (int i = 0; i < 4; ++i)
    if (glm::length(q[(i + 1) % 4] - q[i]) < 1e-9) throw Error("", what, "two corners of the rectangle coincide");
  if (polygonArea(q) < 1e-12) throw Error("", what, "the corners enclose no area");
  const glm::dvec3 n = polygonNormal(q);
  glm::dvec3 c(0.0);
  for (const auto& p : q) c += 0.25 * p;
  glm::dvec3 u = glm::normalize(q[1] - q[0]);
  const glm::dvec3 v0 = glm::cross(n, u);
  // Axis angle from the mean of 4*theta over the edges (edges along either axis agree mod 90 deg).
  double sx = 0, sy = 0;
  for (int i = 0; i < 4; ++i) {
    const glm::dvec3 e = q[(i + 1) % 4] - q[i];
    const double th = std::atan2(glm::dot(e, v0), glm::dot(e, u));
    const double len = glm::length(e);
    sx += len * std::cos(4 * th);
    sy += len * std::sin(4 * th);
  }
  const double th = std::atan2(sy, sx) / 4;
  const glm::dvec3 a = u * std::cos(th) + v0 * std::sin(th), b = glm::cross(n, a);
  // Each edge runs along a or b; the side's coordinate is the mean of its two corners.
  std::vector<glm::dvec2> uv;
  for (const auto& p : q) uv.emplace_back(glm::dot(p - c, a), glm::dot(p - c, b));
  std::vector<glm::dvec2> out = uv;
  for (int i = 0; i < 4; ++i) {
    const int j = (i + 1) % 4;
    const glm::dvec2 e = uv[j] - uv[i];
    if (std::abs(e.x) > std::abs(e.y)) {  // along a: shared b coordinate
      const double m = 0.5 * (uv[i].y + uv[j].y);
      out[i].y = m;
      out[j].y = m;
    } else {
      const double m = 0.5 * (uv[i].x + uv[j].x);
      out[i].x = m;
      out[j].x = m;
    }
  }
  std::vector<glm::dvec3> r;
  for (const auto& p : out) r.push_back(c + a * p.x + b * p.y);
  if (polygonArea(r) < 1e-12) throw Error("", what, "the corners do not form a rectangle (opposite sides cross)");
  return r;
}

int PickedPolygons::add(const std::string& name, const std::string& group, bool lamp, const std::vector<glm::dvec3>& pts,
                        const glm::dvec3& viewer, const PolygonConstraints& constraints) {
  const Plane pl = fitPlane(pts, "polygon " + name);
  Entry e;
  e.polygon.name = name;
  e.polygon.group = group;
  e.polygon.material = group;
  e.polygon.kind = lamp ? PolygonKind::Light : PolygonKind::Real;
  e.polygon.vertices = convexPolygon(pts, pl, viewer, "polygon " + name, constraints);
  e.viewer = viewer;
  entries_[next_] = std::move(e);
  return next_++;
}

int PickedPolygons::addExact(Polygon polygon) {
  if (polygon.vertices.size() < 3 || polygonArea(polygon.vertices) < 1e-12)
    throw Error("", "polygon " + polygon.name, "needs three or more corners enclosing an area");
  Entry e;
  e.viewer = polygonCentroid(polygon.vertices) + polygonNormal(polygon.vertices);
  e.polygon = std::move(polygon);
  entries_[next_] = std::move(e);
  return next_++;
}

PickedPolygons::Entry& PickedPolygons::entry(int id) {
  auto it = entries_.find(id);
  if (it == entries_.end()) throw Error("", "polygon id " + std::to_string(id), "no such polygon");
  return it->second;
}
const Polygon& PickedPolygons::get(int id) const {
  auto it = entries_.find(id);
  if (it == entries_.end()) throw Error("", "polygon id " + std::to_string(id), "no such polygon");
  return it->second.polygon;
}
std::vector<int> PickedPolygons::ids() const {
  std::vector<int> r;
  for (const auto& [id, e] : entries_) r.push_back(id);
  return r;
}

void PickedPolygons::moveVertex(int id, int vertex, const glm::dvec3& to) {
  Entry& e = entry(id);
  if (vertex < 0 || vertex >= int(e.polygon.vertices.size()))
    throw Error("", "polygon " + e.polygon.name, "has no vertex " + std::to_string(vertex));
  std::vector<glm::dvec3> pts = e.polygon.vertices;
  pts[vertex] = to;
  const Plane pl = fitPlane(pts, "polygon " + e.polygon.name);
  // Keep the vertex order (the user's vertex numbers) while the polygon stays convex.
  std::vector<glm::dvec3> proj;
  for (const auto& p : pts) proj.push_back(pl.project(p));
  glm::dvec3 n = pl.normal;
  if (glm::dot(e.viewer - pl.point, n) < 0) n = -n;
  bool convex = true;
  for (size_t i = 0; i < proj.size() && convex; ++i) {
    const glm::dvec3 a = proj[i], b = proj[(i + 1) % proj.size()], c = proj[(i + 2) % proj.size()];
    convex = glm::dot(glm::cross(b - a, c - b), n) > 0;
  }
  e.polygon.vertices = convex ? proj : convexPolygon(pts, pl, e.viewer, "polygon " + e.polygon.name);
}

void PickedPolygons::remove(int id) {
  entry(id);
  entries_.erase(id);
}

void PickedPolygons::merge(int a, int b, double tolerance) {
  if (a == b) throw Error("", "polygon id " + std::to_string(a), "cannot be merged with itself");
  Entry& ea = entry(a);
  const Entry& eb = entry(b);
  std::vector<glm::dvec3> pts = ea.polygon.vertices;
  pts.insert(pts.end(), eb.polygon.vertices.begin(), eb.polygon.vertices.end());
  const Plane pl = fitPlane(pts, "polygons " + ea.polygon.name + " + " + eb.polygon.name);
  for (const auto& p : pts)
    if (std::abs(glm::dot(p - pl.point, pl.normal)) > tolerance)
      throw Error("", "polygons " + ea.polygon.name + " + " + eb.polygon.name,
                  "are not coplanar (a corner lies " + std::to_string(std::abs(glm::dot(p - pl.point, pl.normal))) +
                      " m off their common plane)");
  ea.polygon.vertices = convexPolygon(pts, pl, ea.viewer, "polygon " + ea.polygon.name);
  entries_.erase(b);
}

void PickedPolygons::snapToCommonPlane(const std::vector<int>& ids) {
  std::vector<glm::dvec3> pts;
  for (int id : ids) {
    const auto& v = entry(id).polygon.vertices;
    pts.insert(pts.end(), v.begin(), v.end());
  }
  const Plane pl = fitPlane(pts, "common plane");
  for (int id : ids) {
    Entry& e = entry(id);
    std::vector<glm::dvec3> proj;
    for (const auto& p : e.polygon.vertices) proj.push_back(pl.project(p));
    e.polygon.vertices = convexPolygon(proj, pl, e.viewer, "polygon " + e.polygon.name);
  }
}

}  // namespace relume::recon
