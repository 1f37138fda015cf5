#include "relume/relight/compare.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "relume/geometry/error.h"
#include "relume/geometry/polygon.h"
#include "relume/geometry/scene.h"

namespace relume {

namespace {
float luminance(const glm::vec3& c) { return (c.x + c.y + c.z) / 3.f; }

ImageRGB boxBlur(const ImageRGB& img, int radius) {
  ImageRGB out(img.width, img.height);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      glm::vec3 s(0.f);
      int n = 0;
      for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if (xx < 0 || yy < 0 || xx >= img.width || yy >= img.height) continue;
          s += img.at(xx, yy);
          ++n;
        }
      out.set(x, y, s / float(n));
    }
  return out;
}
}  // namespace

ImageRGB boxDownsample(const ImageRGB& img, int f) {
  ImageRGB out(img.width / f, img.height / f);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      glm::vec3 s(0.f);
      for (int dy = 0; dy < f; ++dy)
        for (int dx = 0; dx < f; ++dx) s += img.at(x * f + dx, y * f + dy);
      out.set(x, y, s / float(f * f));
    }
  return out;
}

CompareMasks benchmarkMasks(const ImageRGB& photo, const ImageRGB& unoccluded) {
  if (photo.width != unoccluded.width || photo.height != unoccluded.height)
    throw Error("", "comparison", "the photo and truth/unoccluded differ in size");
  if (photo.width < 4 || photo.height < 4) throw Error("", "comparison", "images must be at least 4x4 pixels");
  const ImageRGB p = boxDownsample(photo, 4), u = boxDownsample(unoccluded, 4);
  CompareMasks m;
  m.width = p.width;
  m.height = p.height;
  const size_t n = size_t(p.width) * p.height;
  std::vector<float> lum(n);
  for (size_t i = 0; i < n; ++i) lum[i] = luminance(p.at(int(i % p.width), int(i / p.width)));
  std::vector<float> sorted = lum;
  std::nth_element(sorted.begin(), sorted.begin() + n / 2, sorted.end());
  const float median = sorted[n / 2];
  const ImageRGB pb = boxBlur(p, 2), ub = boxBlur(u, 2);
  m.all.assign(n, 0);
  m.shadow.assign(n, 0);
  for (size_t i = 0; i < n; ++i) {
    const int x = int(i % p.width), y = int(i / p.width);
    m.all[i] = lum[i] <= 20.f * median;
    const float lu = luminance(ub.at(x, y)), lp = luminance(pb.at(x, y));
    m.shadow[i] = m.all[i] && std::abs(lu - lp) > 0.08f * lu;
  }
  return m;
}

Comparison compareImages(const ImageRGB& rendering, const ImageRGB& truth, const std::vector<uint8_t>& mask) {
  if (rendering.width != truth.width || rendering.height != truth.height)
    throw Error("", "comparison", "the rendering is " + std::to_string(rendering.width) + "x" + std::to_string(rendering.height) +
                                      ", the truth " + std::to_string(truth.width) + "x" + std::to_string(truth.height));
  const ImageRGB r = boxDownsample(rendering, 4), t = boxDownsample(truth, 4);
  if (mask.size() != size_t(r.width) * r.height)
    throw Error("", "comparison", "the mask does not match the images' size");
  Comparison c;
  glm::dvec3 num(0.0), den(0.0);
  std::vector<float> tv;
  for (size_t i = 0; i < mask.size(); ++i) {
    if (!mask[i]) continue;
    const glm::dvec3 a(r.at(int(i % r.width), int(i / r.width))), b(t.at(int(i % t.width), int(i / t.width)));
    num += a * b;
    den += a * a;
    tv.push_back(float(b.x));
    tv.push_back(float(b.y));
    tv.push_back(float(b.z));
    ++c.pixels;
  }
  if (c.pixels == 0) return c;
  for (int k = 0; k < 3; ++k) c.gain[k] = den[k] > 0 ? num[k] / den[k] : 1.0;
  double se = 0;
  for (size_t i = 0; i < mask.size(); ++i) {
    if (!mask[i]) continue;
    const glm::dvec3 a(r.at(int(i % r.width), int(i / r.width))), b(t.at(int(i % t.width), int(i / t.width)));
    const glm::dvec3 d = a * c.gain - b;
    se += glm::dot(d, d);
  }
  const double mse = se / (3.0 * c.pixels);
  const size_t k = std::min(tv.size() - 1, size_t(std::floor(0.999 * double(tv.size() - 1))));
  std::nth_element(tv.begin(), tv.begin() + k, tv.end());
  const double peak = tv[k];
  c.psnr = mse > 0 ? 10 * std::log10(peak * peak / mse) : 99.0;
  return c;
}

namespace {
// How far polygon `a`'s centre is from polygon `b` when a lies in b's plane (normals within 15
// degrees, the centre within 5 cm of the plane): 0 inside b, else the distance to b's centre;
// negative when not in its plane.
double inPlaneDistance(const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b) {
  if (a.size() < 3 || b.size() < 3) return -1;
  const glm::dvec3 na = polygonNormal(a), nb = polygonNormal(b), c = polygonCentroid(a);
  if (!(glm::dot(na, nb) >= std::cos(15.0 * 3.14159265358979323846 / 180.0))) return -1;
  if (!(std::abs(glm::dot(c - b[0], nb)) <= 0.05)) return -1;
  return insidePolygon(b, c) ? 0.0 : glm::length(c - polygonCentroid(b));
}
}  // namespace

BundleMatch matchToBundle(const Scene& model, const Scene& bundle) {
  BundleMatch m;
  auto centre = [](const Scene& s, int polygon) {
    return polygon >= 0 && size_t(polygon) < s.polygons.size() && !s.polygons[size_t(polygon)].vertices.empty()
               ? polygonCentroid(s.polygons[size_t(polygon)].vertices)
               : glm::dvec3(std::nan(""));
  };
  for (const auto& lamp : model.lamps) {
    int best = bundle.findLamp(lamp.name);
    if (best < 0) {
      double bestDist = 0.5;
      const glm::dvec3 c = centre(model, lamp.polygon);
      for (size_t j = 0; j < bundle.lamps.size(); ++j) {
        const double d = glm::length(c - centre(bundle, bundle.lamps[j].polygon));
        if (d <= bestDist) best = int(j), bestDist = d;
      }
    }
    m.lamp.push_back(best);
  }
  // A polygon of the same kind in its plane: the one of the same name, else of those that hold its
  // centre the one nearest its size (a poster on a wall holds a wall's centre too), else the
  // nearest, all within 0.5 m.
  for (const auto& p : model.polygons) {
    int named = -1, best = -1;
    double bestDist = 0.5, bestSize = 0;
    const double area = polygonArea(p.vertices);
    for (size_t j = 0; j < bundle.polygons.size(); ++j) {
      const Polygon& b = bundle.polygons[j];
      if (b.kind != p.kind) continue;
      const double d = inPlaneDistance(p.vertices, b.vertices);
      if (d < 0 || d > 0.5) continue;
      if (b.name == p.name && named < 0) named = int(j);
      const double size = std::abs(std::log(std::max(1e-12, polygonArea(b.vertices)) / std::max(1e-12, area)));
      if (best < 0 || d < bestDist || (d == bestDist && size < bestSize)) best = int(j), bestDist = d, bestSize = size;
    }
    m.polygon.push_back(named >= 0 ? named : best);
  }
  return m;
}

}  // namespace relume
