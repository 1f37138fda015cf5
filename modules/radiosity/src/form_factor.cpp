#include "relume/radiosity/form_factor.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>
#include <span>
#include <stdexcept>

#include "relume/geometry/polygon.h"

namespace relume::radiosity {

namespace {

// The angle between two vectors from y = |a x b| >= 0 and x = a . b: atan2(y, x) in [0, pi].
// Every edge of every point-to-polygon factor takes one (per link, per sample and per pixel), and
// libm's atan2 was a tenth of a preprocess; this one reduces to |t| <= tan(pi/8) and sums a
// degree-19 odd polynomial (least squares on Chebyshev nodes for atan(t) / t in t^2), within
// 2e-15 rad of atan2 everywhere (FormFactor.PointToARectangleAtAnyOffsetIsTheCornerSum holds it
// to 1e-13 on the factor).
double angleBetween(double y, double x) {
  constexpr double kPi = std::numbers::pi, kTanPi8 = 0.41421356237309503;
  const double ax = std::abs(x);
  const bool steep = y > ax;
  double t = steep ? ax / y : (ax > 0 ? y / ax : 0.0);  // in [0, 1]
  double base = 0.0;
  if (t > kTanPi8) {  // atan(t) = pi/4 + atan((t - 1) / (t + 1))
    t = (t - 1.0) / (t + 1.0);
    base = kPi / 4;
  }
  const double s = t * t;
  double q = -0.025319569902978106;
  q = q * s + 0.050250848444916695;
  q = q * s - 0.06506110657432282;
  q = q * s + 0.07673561000925172;
  q = q * s - 0.0908953279279796;
  q = q * s + 0.11111049029805933;
  q = q * s - 0.14285712667540879;
  q = q * s + 0.1999999997849008;
  q = q * s - 0.3333333333322229;
  q = q * s + 1.0000000000000004;
  double a = base + t * q;  // atan of the ratio, in [0, pi/4]
  if (steep) a = kPi / 2 - a;
  return x < 0 ? kPi - a : a;
}

// The polygons below are spans: the pieces an opening is cut into live in buffers kept per thread
// (no allocation per piece: the distant-light factors run per link and per pixel, and cut each
// opening into tens of pieces).
double formFactorOf(const glm::dvec3& p, const glm::dvec3& n, std::span<const glm::dvec3> poly) {
  const size_t count = poly.size();
  if (count < 3) return 0.0;
  // A polygon whose front does not face p sends nothing towards it.
  const glm::dvec3 an = areaVector(poly);
  if (glm::dot(an, p - poly[0]) <= 0.0) return 0.0;
  // Keep the part above p's tangent plane (a tiny lift avoids the singular contour). Usually the
  // whole polygon lies above it: then it is used as it is (no copy; this runs per pixel and per
  // link).
  const glm::dvec3 lifted = p + n * 1e-12;
  bool whole = true;
  for (size_t i = 0; i < count; ++i) whole = whole && glm::dot(n, poly[i] - lifted) >= 0;
  std::vector<glm::dvec3> clippedStore;
  const glm::dvec3* clipped = poly.data();
  size_t k = count;
  if (!whole) {
    clipToHalfSpace(poly, lifted, n, clippedStore);
    k = clippedStore.size();
    if (k < 3) return 0.0;
    clipped = clippedStore.data();
  }
  // Lambert's contour integral: F = 1/(2 pi) sum_i gamma_i * n . (R_i x R_{i+1}) / |R_i x R_{i+1}|,
  // gamma_i the angle between R_i and R_{i+1}: atan2(|R_i x R_{i+1}|, R_i . R_{i+1}) (angleBetween).
  double sum = 0.0;
  for (size_t i = 0; i < k; ++i) {
    const glm::dvec3 r0 = clipped[i] - p;
    const glm::dvec3 r1 = clipped[(i + 1) % k] - p;
    if (glm::dot(r0, r0) < 1e-30 || glm::dot(r1, r1) < 1e-30) continue;
    const glm::dvec3 c = glm::cross(r0, r1);
    const double cl = glm::length(c);
    if (cl < 1e-300) continue;
    sum += angleBetween(cl, glm::dot(r0, r1)) * glm::dot(n, c) / cl;
  }
  // The polygon faces p, so every term has the orientation's sign: the magnitude is the factor.
  return std::abs(sum) / (2.0 * std::numbers::pi);
}

}  // namespace

double pointToPolygonFormFactor(const glm::dvec3& p, const glm::dvec3& n,
                                const std::vector<glm::dvec3>& poly) {
  return formFactorOf(p, n, poly);
}

namespace {

constexpr int kMaxPieceDepth = 14;

// Cuts the convex polygon `poly` into pieces that p sees no wider than `maxAngle` (radians)
// and sums visit(piece, centroid direction) over them; pieces whose cone
// `light.mayShine` rules out are skipped whole. The two halves of a piece of depth d are made in
// levels[d] (a piece of depth d + 1 lives there), one after the other: each is summed whole before
// the next is cut, and the piece they are cut from stays in levels[d - 1]. The levels are reused
// from call to call, so no piece allocates (nothing this calls runs TBB work, so no other call
// can interleave on the thread).
// With `wholeWhereUniform`, a piece that `light.uniform` says is lit alike across its cone is
// visited whole (for a visit that is additive over pieces: the cosine-weighted factor).
template <class Visit>
double overPieces(const glm::dvec3& p, std::span<const glm::dvec3> poly, const DistantLight& light,
                  double maxAngle, bool wholeWhereUniform, int depth, std::vector<std::vector<glm::dvec3>>& levels,
                  Visit&& visit) {
  const size_t count = poly.size();
  if (count < 3) return 0.0;
  const glm::dvec3 c = polygonCentroid(poly);
  double radius = 0;
  size_t far = 0;
  for (size_t i = 0; i < count; ++i) {
    const double r = glm::length(poly[i] - c);
    if (r > radius) {
      radius = r;
      far = i;
    }
  }
  const double dist = glm::length(c - p);
  if (!(dist > 0)) return 0.0;
  const glm::dvec3 axis = (c - p) / dist;
  const bool uniformCheck = wholeWhereUniform && light.uniform;
  if (light.mayShine || uniformCheck) {
    const double half = radius >= dist ? std::numbers::pi : std::asin(radius / dist);
    if (light.mayShine && !light.mayShine(axis, half)) return 0.0;
    if (uniformCheck && light.uniform(axis, half)) return visit(poly, axis);
  }
  if (2.0 * radius <= maxAngle * dist || depth >= kMaxPieceDepth) return visit(poly, axis);
  // Halve across the longest extent (through the centroid).
  const glm::dvec3 cut = glm::normalize(poly[far] - c);
  std::vector<glm::dvec3>& half = levels[size_t(depth)];
  clipToHalfSpace(poly, c, cut, half);
  const double a = overPieces(p, half, light, maxAngle, wholeWhereUniform, depth + 1, levels, visit);
  clipToHalfSpace(poly, c, -cut, half);
  return a + overPieces(p, half, light, maxAngle, wholeWhereUniform, depth + 1, levels, visit);
}

// Beams through the opening towards p: sum of irradiance x cosine(n) / pi (n null: cosine 1).
double beamsThrough(const glm::dvec3& p, const glm::dvec3* n, const std::vector<glm::dvec3>& poly,
                    const glm::dvec3& nPoly, const DistantLight& light) {
  double f = 0;
  for (const auto& beam : light.beams) {
    const double c = n ? glm::dot(*n, beam.direction) : 1.0;
    if (!(c > 0) || !(beam.irradiance > 0) || glm::dot(beam.direction, nPoly) >= 0.0) continue;
    if (rayThroughPolygon(p, beam.direction, poly, nPoly) > 0) f += beam.irradiance * c / std::numbers::pi;
  }
  return f;
}

// Both factors of an opening: with a normal n, cosine-weighted; without (n null), each piece seen
// along its own direction (a small piece's projected solid angle so is its solid angle).
double distantFactor(const glm::dvec3& p, const glm::dvec3* n, const std::vector<glm::dvec3>& poly,
                     const DistantLight& light, bool withBeams) {
  if (poly.size() < 3) return 0.0;
  const glm::dvec3 nPoly = polygonNormal(poly);
  if (glm::dot(nPoly, p - poly[0]) <= 0.0) return 0.0;  // behind the opening (outside the room)
  double f = withBeams ? beamsThrough(p, n, poly, nPoly, light) : 0.0;
  if (light.radiance) {
    const double maxAngle = std::max(1e-3, light.pieceDeg * std::numbers::pi / 180.0);
    thread_local std::vector<std::vector<glm::dvec3>> levels(kMaxPieceDepth);
    // Without a normal each piece is seen along its own direction, which only small pieces allow:
    // those are cut down to pieceDeg everywhere.
    f += overPieces(p, poly, light, maxAngle, n != nullptr, 0, levels, [&](std::span<const glm::dvec3> piece, const glm::dvec3& d) {
                      const double l = light.radiance(d);
                      return l > 0 ? l * formFactorOf(p, n ? *n : d, piece) : 0.0;
                    });
  }
  return f;
}

}  // namespace

double rayThroughPolygon(const glm::dvec3& p, const glm::dvec3& d, const std::vector<glm::dvec3>& poly,
                         const glm::dvec3& nPoly) {
  const double dn = glm::dot(d, nPoly);
  if (dn == 0.0 || poly.size() < 3) return -1.0;
  const double t = glm::dot(nPoly, poly[0] - p) / dn;
  if (!(t > 0)) return -1.0;
  const glm::dvec3 x = p + t * d;
  for (size_t i = 0; i < poly.size(); ++i) {
    const glm::dvec3& a = poly[i];
    const glm::dvec3& b = poly[(i + 1) % poly.size()];
    if (glm::dot(glm::cross(b - a, x - a), nPoly) < 0.0) return -1.0;
  }
  return t;
}

double distantFormFactor(const glm::dvec3& p, const glm::dvec3& n, const std::vector<glm::dvec3>& poly,
                         const DistantLight& light, bool withBeams) {
  return distantFactor(p, &n, poly, light, withBeams);
}

double distantSolidAngleFactor(const glm::dvec3& p, const std::vector<glm::dvec3>& poly, const DistantLight& light) {
  return distantFactor(p, nullptr, poly, light, true);
}

EmitterShape::EmitterShape(const std::vector<glm::dvec3>& polygon, bool twoSidedFaces,
                           std::shared_ptr<const PhotometricDistribution> distribution,
                           std::shared_ptr<const DistantLight> distantLight)
    : twoSided(twoSidedFaces), photometry(std::move(distribution)), distant(std::move(distantLight)) {
  if (distant) {
    photometry = nullptr;
    twoSided = false;
    if (polygon.size() < 3 || !(polygonArea(polygon) > 0)) return;
    // What enters per unit area over B: (1 / pi) x the radiance over the outer hemisphere, each
    // direction weighted by its cosine to the opening, plus the beams that cross it.
    const glm::dvec3 out = -polygonNormal(polygon);
    const glm::dvec3 t = glm::normalize(std::abs(out.x) < 0.9 ? glm::cross(out, glm::dvec3(1, 0, 0))
                                                              : glm::cross(out, glm::dvec3(0, 1, 0)));
    const glm::dvec3 b = glm::cross(out, t);
    double sum = 0;
    if (distant->radiance) {
      constexpr int nt = 90, np = 180;
      const double dt = 0.5 * std::numbers::pi / nt, dp = 2 * std::numbers::pi / np;
      for (int i = 0; i < nt; ++i) {
        const double th = (i + 0.5) * dt;
        for (int j = 0; j < np; ++j) {
          const double ph = (j + 0.5) * dp;
          const glm::dvec3 d = std::cos(th) * out + std::sin(th) * (std::cos(ph) * t + std::sin(ph) * b);
          sum += distant->radiance(d) * std::cos(th) * std::sin(th) * dt * dp;
        }
      }
    }
    for (const auto& beam : distant->beams) sum += beam.irradiance * std::max(0.0, glm::dot(beam.direction, out));
    transmitted = sum / std::numbers::pi;
    return;
  }
  if (!photometry || polygon.size() < 3) {
    photometry = nullptr;
    return;
  }
  centre = glm::dvec3(0.0);
  for (const auto& v : polygon) centre += v / double(polygon.size());
  const glm::dvec3 area = areaVector(polygon);
  // C0 along the first edge of some length (a repeated first vertex gives none).
  glm::dvec3 edge(0.0);
  for (size_t i = 0; i < polygon.size() && glm::length(edge) <= 1e-9; ++i)
    edge = polygon[(i + 1) % polygon.size()] - polygon[i];
  flux = photometry->flux();
  if (!(glm::length(area) > 0) || !(glm::length(edge) > 1e-9) || !std::isfinite(flux) || !(flux > 0)) {
    photometry = nullptr;  // no plane, or a dark distribution: no shape to give
    return;
  }
  nadir = glm::normalize(area);
  c0 = edge - glm::dot(edge, nadir) * nadir;
  if (!(glm::length(c0) > 1e-12)) c0 = std::abs(nadir.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  c0 = glm::normalize(c0 - glm::dot(c0, nadir) * nadir);
  c90 = glm::cross(c0, nadir);
  peak = std::numbers::pi * *std::max_element(photometry->candela.begin(), photometry->candela.end()) / flux;
  upward = flux - photometry->downwardFlux() > 1e-6 * flux;
}

double EmitterShape::weight(const glm::dvec3& p) const {
  if (!photometry) return 1.0;
  const glm::dvec3 d = p - centre;
  const double len = glm::length(d);
  if (len <= 0) return 0.0;
  const double cg = glm::dot(d, nadir) / len;
  const double gamma = std::acos(std::clamp(cg, -1.0, 1.0)) * 180.0 / std::numbers::pi;
  double c = std::atan2(glm::dot(d, c90), glm::dot(d, c0)) * 180.0 / std::numbers::pi;
  if (c < 0) c += 360.0;
  // The point kernel carries |cos gamma| already: at grazing angles F -> 0 and F w stays finite.
  return std::numbers::pi * photometry->intensity(c, gamma) / (flux * std::max(std::abs(cg), 1e-3));
}

double emitterFormFactor(const glm::dvec3& p, const glm::dvec3& n, const std::vector<glm::dvec3>& poly,
                         const EmitterShape& shape) {
  if (shape.distant) return distantFormFactor(p, n, poly, *shape.distant);
  double f = 0.0;
  if (!shape.emitsBehind() || poly.size() < 3 || glm::dot(areaVector(poly), p - poly[0]) > 0.0)
    f = pointToPolygonFormFactor(p, n, poly);
  else  // seen from behind: the back face, i.e. the same polygon wound the other way
    f = pointToPolygonFormFactor(p, n, std::vector<glm::dvec3>(poly.rbegin(), poly.rend()));
  return f > 0.0 && shape.photometry ? f * shape.weight(p) : f;
}

ElementFactor emitterFormFactorOverElement(const glm::dvec3& origin, const glm::dvec3& du, const glm::dvec3& dv,
                                           const glm::dvec3& n, const std::vector<glm::dvec2>& uvPolygon,
                                           glm::dvec2 uv0, glm::dvec2 uv1, const std::vector<glm::dvec3>& emitter,
                                           const EmitterShape& shape, double tolerance, int maxDepth) {
  glm::dvec3 centre(0.0);
  double radius = 0;
  for (const auto& v : emitter) centre += v / double(emitter.size());
  for (const auto& v : emitter) radius = std::max(radius, glm::length(v - centre));
  // 2 x 2 Gauss points per cell.
  constexpr double g0 = 0.5 - 0.5 / 1.7320508075688772, g1 = 0.5 + 0.5 / 1.7320508075688772;
  ElementFactor out;
  out.minimum = 1e300;
  double integral = 0, inside = 0;
  auto cell = [&](auto&& self, glm::dvec2 a, glm::dvec2 b, int depth) -> void {
    double f[4], fmin = 1e300, fmax = 0;
    bool in[4];
    int count = 0;
    for (int k = 0; k < 4; ++k) {
      const glm::dvec2 uv(a.x + ((k & 1) ? g1 : g0) * (b.x - a.x), a.y + ((k & 2) ? g1 : g0) * (b.y - a.y));
      in[k] = uvPolygon.size() < 3 || insideConvex2D(uvPolygon, uv, 1e-9);
      f[k] = in[k] ? emitterFormFactor(origin + uv.x * du + uv.y * dv, n, emitter, shape) : 0.0;
      if (!in[k]) continue;
      ++count;
      fmin = std::min(fmin, f[k]);
      fmax = std::max(fmax, f[k]);
    }
    if (depth < maxDepth) {
      const double size = std::max((b.x - a.x) * glm::length(du), (b.y - a.y) * glm::length(dv));
      const glm::dvec3 mid = origin + 0.5 * (a.x + b.x) * du + 0.5 * (a.y + b.y) * dv;
      const glm::dvec3 d = centre - mid;
      const double ahead = glm::dot(d, n);
      const double lateral = glm::length(d - ahead * n);
      const bool nearPeak = ahead > 0 && ahead < size && lateral < 0.75 * size + radius;
      const bool partial = count > 0 && count < 4 && depth < 3;  // the polygon's edge crosses the cell
      if ((count > 0 && fmax - fmin > tolerance * fmax && fmax > 1e-6) || nearPeak || partial) {
        const glm::dvec2 m = 0.5 * (a + b);
        self(self, a, m, depth + 1);
        self(self, {m.x, a.y}, {b.x, m.y}, depth + 1);
        self(self, {a.x, m.y}, {m.x, b.y}, depth + 1);
        self(self, m, b, depth + 1);
        return;
      }
    }
    const double w = 0.25 * (b.x - a.x) * (b.y - a.y);
    for (int k = 0; k < 4; ++k)
      if (in[k]) {
        integral += w * f[k];
        inside += w;
      }
    if (count > 0) {
      out.minimum = std::min(out.minimum, fmin);
      out.maximum = std::max(out.maximum, fmax);
    }
  };
  cell(cell, uv0, uv1, 0);
  if (inside <= 0) {  // the rectangle misses the polygon: its centre stands for it
    const glm::dvec2 c = 0.5 * (uv0 + uv1);
    out.mean = out.minimum = out.maximum = emitterFormFactor(origin + c.x * du + c.y * dv, n, emitter, shape);
    return out;
  }
  out.mean = integral / inside;
  return out;
}

void gaussLegendre01(int order, std::vector<double>& nodes, std::vector<double>& weights) {
  order = std::clamp(order, 1, 8);
  nodes.assign(order, 0.0);
  weights.assign(order, 0.0);
  // Newton iteration on the Legendre polynomial P_order.
  for (int i = 0; i < order; ++i) {
    double x = std::cos(std::numbers::pi * (i + 0.75) / (order + 0.5));
    double dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = x;
      for (int k = 2; k <= order; ++k) {
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      if (order == 1) {
        p1 = x;
        p0 = 1.0;
      }
      dp = order * (x * p1 - p0) / (x * x - 1.0);
      const double dx = p1 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-15) break;
    }
    nodes[i] = 0.5 * (1.0 - x);
    weights[i] = 1.0 / ((1.0 - x * x) * dp * dp);  // 2/((1-x^2)P'^2), halved for [0,1]
  }
}

double polygonToPolygonFormFactor(const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b,
                                  int order) {
  std::vector<double> x, w;
  gaussLegendre01(order, x, w);
  const glm::dvec3 n = polygonNormal(a);
  double total = 0.0, areaSum = 0.0;
  // Fan of triangles (a0, ai, ai+1), each mapped from the unit square by the Duffy map
  // (s, t) -> a0 + s (ai - a0) + s t (ai+1 - ai), Jacobian 2 * area * s.
  for (size_t i = 1; i + 1 < a.size(); ++i) {
    const glm::dvec3 e1 = a[i] - a[0], e2 = a[i + 1] - a[i];
    const double area = 0.5 * glm::length(glm::cross(a[i] - a[0], a[i + 1] - a[0]));
    if (area <= 0) continue;
    double tri = 0.0;
    for (size_t s = 0; s < x.size(); ++s)
      for (size_t t = 0; t < x.size(); ++t) {
        const glm::dvec3 q = a[0] + x[s] * e1 + x[s] * x[t] * e2;
        tri += w[s] * w[t] * 2.0 * x[s] * pointToPolygonFormFactor(q, n, b);
      }
    total += tri * area;
    areaSum += area;
  }
  return areaSum > 0 ? total / areaSum : 0.0;
}

}  // namespace relume::radiosity
