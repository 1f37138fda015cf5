#include "relume/daylight/relight.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <atomic>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <set>
#include <string>

#include "relume/geometry/binary.h"
#include "relume/geometry/error.h"
#include "relume/geometry/polygon.h"
#include "relume/radiosity/form_factor.h"
#include "relume/radiosity/hierarchy.h"
#include "relume/radiosity/sh.h"
#include "relume/raytrace/outside.h"
#include "relume/raytrace/ray_scene.h"
#include "relume/relight/relighter.h"
#include "relume/relight/solution_render.h"

namespace relume::daylight {

std::vector<Polygon> variantObjects(const Scene& room, const Variant& variant, const std::string& file,
                                    std::vector<std::string>* groups) {
  std::vector<Polygon> faces;
  if (groups) groups->clear();
  std::set<std::string> names;
  std::vector<VirtualObject> made;  // checked against each other as they come
  for (size_t k = 0; k < variant.virtualObjects.size(); ++k) {
    const auto& b = variant.virtualObjects[k];
    if (!b.fan.empty()) throw Error(file, "virtual object " + b.name, "image-based objects under daylight are drawn by relume relight --sky and the "
                                                        "Sky panel (after the render); relume evaluate does not draw them yet");
    const VirtualObject o = b.mesh.empty() ? boxObject(b.name, b.boxMin, b.boxMax, b.albedo) : meshObject(b.name, b.mesh, b.albedo);
    try {
      checkVirtualObject(room, o);
      std::vector<const VirtualObject*> before;
      for (const auto& m : made) before.push_back(&m);
      checkVirtualObjectsApart(room, o, before);
    } catch (const Error& e) {
      throw Error(file, e.element(), e.problem());  // the file the object was given in
    }
    made.push_back(o);
    // Each object's faces one group, named for the user: an unnamed object or a repeated name
    // gets the object's place in the list.
    std::string name = o.name.empty() ? "object " + std::to_string(k + 1) : o.name;
    if (!names.insert(name).second) names.insert(name += " (" + std::to_string(k + 1) + ")");
    if (groups) groups->push_back(name);
    for (const auto& f : o.polygons) {
      Polygon poly;
      poly.name = poly.group = name;
      poly.vertices = f;
      poly.albedo = o.albedo;
      faces.push_back(poly);
    }
  }
  return faces;
}

std::vector<BasisLamp> variantLamps(const Variant& variant, const std::string& file) {
  std::vector<BasisLamp> lamps;
  for (size_t i = 0; i < variant.virtualLamps.size(); ++i) {
    const Lamp& l = variant.virtualLamps[i];
    const std::string name = l.name.empty() ? "virtual_lamp_" + std::to_string(i) : l.name;
    if (l.photometry)
      throw Error(file, "virtual lamp " + name, "a photometric lamp (IES / EULUMDAT) is not lit under daylight yet: give it "
                                                "without its photometry file, or relight without a sky");
    lamps.push_back({name, variant.virtualLampPolygons.at(i), std::numbers::pi * l.radiance, l.twoSided});
  }
  return lamps;
}

namespace {
constexpr double kPi = std::numbers::pi;

glm::vec3 get(const ImageRGB& im, size_t i) { return {im.pixels[3 * i], im.pixels[3 * i + 1], im.pixels[3 * i + 2]}; }
void put(ImageRGB& im, size_t i, const glm::vec3& v) {
  im.pixels[3 * i] = v.x;
  im.pixels[3 * i + 1] = v.y;
  im.pixels[3 * i + 2] = v.z;
}

// The direction of v's first edge of non-zero length (a polygon may repeat a vertex).
glm::dvec3 firstEdge(const std::vector<glm::dvec3>& v) {
  for (size_t i = 0; i < v.size(); ++i) {
    const glm::dvec3 e = v[(i + 1) % v.size()] - v[i];
    if (glm::dot(e, e) > 1e-24) return glm::normalize(e);
  }
  return {1, 0, 0};
}

// x (in the plane of the convex or concave polygon v) if it lies inside v, else the nearest point
// of v's outline moved 1 % of the way towards v's centroid.
glm::dvec3 ontoFace(const std::vector<glm::dvec3>& v, const glm::dvec3& x) {
  if (insidePolygon(v, x)) return x;
  glm::dvec3 best = v[0], centroid(0.0);
  double bestD = 1e300;
  for (size_t i = 0, j = v.size() - 1; i < v.size(); j = i++) {
    const glm::dvec3 e = v[j] - v[i];
    const double s = std::clamp(glm::dot(x - v[i], e) / std::max(glm::dot(e, e), 1e-300), 0.0, 1.0);
    const glm::dvec3 q = v[i] + s * e;
    if (glm::dot(q - x, q - x) < bestD) {
      bestD = glm::dot(q - x, q - x);
      best = q;
    }
    centroid += v[i] / double(v.size());
  }
  return best + 0.01 * (centroid - best);
}

}  // namespace

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

namespace {

// The sun's direct light over a pixel's footprint (4 x 4 camera rays over 1.5 pixels, as a
// renderer's or a camera's pixel filter spreads a sunlit edge), each point towards another
// direction of the sun's disc (for the penumbra): the rays that reach the sky through the windows
// past the room, each with its share of the pixel (cosine / 16). They depend on the room, the
// camera and the sun only: the interactive path keeps them per pixel while objects move.
struct SunRay {
  glm::vec3 from;  // the room's point (lifted off its surface)
  uint8_t disc;    // which of the sun disc's directions
  float share;
};

void footprintSunRays(const radiosity::HierarchicalRadiosity& h, const std::vector<int>& windows, const Camera& camera,
                      size_t px, size_t py, const std::vector<glm::dvec3>& sunDisc, std::vector<SunRay>& out) {
  const double x = double(px) + 0.5, y = double(py) + 0.5;
  const glm::dvec3 eye = camera.center();
  constexpr int k = 4;
  Ray rays[k * k];
  RayHit hits[k * k];
  for (int j = 0; j < k * k; ++j) {
    const double dx = ((j % k) + 0.5) / k * 1.5 - 0.75, dy = ((j / k) + 0.5) / k * 1.5 - 0.75;
    rays[j] = Ray{glm::vec3(eye), glm::vec3(camera.rayDirection(x + dx, y + dy)), 0.f, 1e30f};
  }
  h.rayScene().intersect(rays, hits);
  out.clear();
  for (int j = 0; j < k * k; ++j) {
    if (hits[j].polygon < 0) continue;
    const glm::dvec3 n = polygonNormal(h.surfaces()[size_t(hits[j].polygon)].vertices);
    if (glm::dot(n, glm::dvec3(rays[j].direction)) > 0) continue;  // a back face: dark
    const size_t disc = size_t((j * 7) % (k * k));  // footprint and disc decorrelated
    const glm::dvec3& sj = sunDisc[disc];
    const double c = glm::dot(n, sj);
    if (c <= 0) continue;
    const glm::dvec3 from = eye + double(hits[j].t) * glm::dvec3(rays[j].direction) + 1e-4 * n;
    const double t = throughWindow(h, windows, from, sj);
    if (t <= 0 || h.rayScene().occluded(glm::vec3(from), glm::vec3(from + t * sj), 1e-4f)) continue;
    out.push_back({glm::vec3(from), uint8_t(disc), float(c / (k * k))});
  }
}

// The mean cosine of the footprint's rays that reach the sky (the sun's share of the pixel).
double footprintSun(const radiosity::HierarchicalRadiosity& h, const std::vector<int>& windows, const Camera& camera,
                    size_t px, size_t py, const std::vector<glm::dvec3>& sunDisc) {
  thread_local std::vector<SunRay> rays;
  footprintSunRays(h, windows, camera, px, py, sunDisc, rays);
  double open = 0;
  for (const auto& r : rays) open += r.share;
  return open;
}

// A depth map of the virtual objects seen from one light sample (the paper's shadow maps, on the
// CPU): perspective from a point on a window, or orthographic along one of the sun's directions,
// framing the objects' bounding sphere. Each texel keeps the nearest object depth along the view
// axis; a point is in the objects' shadow when the texel its direction falls in holds something
// nearer than itself. Texels are sampled at their centres, as a GPU rasterises.
class ObjectShadowMap {
 public:
  static constexpr int kSize = 128;
  // Perspective from `eye` (outside the sphere), or orthographic along `dir` when `eye` is null.
  ObjectShadowMap(const glm::dvec3* eye, const glm::dvec3& dir, const glm::dvec3& centre, double radius,
                  const std::vector<std::vector<glm::dvec3>>& polygons) {
    f_ = glm::normalize(eye ? centre - *eye : dir);
    r_ = glm::normalize(glm::cross(f_, std::abs(f_.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0)));
    u_ = glm::cross(r_, f_);
    ortho_ = eye == nullptr;
    const double reach = 1.02 * radius;
    if (ortho_) {
      origin_ = centre - 2 * reach * f_;
      scale_ = 1 / reach;
    } else {
      origin_ = *eye;
      const double d = glm::length(centre - *eye);
      scale_ = std::sqrt(std::max(d * d - reach * reach, 1e-12)) / reach;  // 1 / tan of the half-angle
    }
    depth_.assign(size_t(kSize) * kSize, std::numeric_limits<float>::infinity());
    for (const auto& poly : polygons)
      for (size_t t = 1; t + 1 < poly.size(); ++t) raster(project(poly[0]), project(poly[t]), project(poly[t + 1]));
  }
  // Whether the objects lie between the light sample and x (nearer than x by more than `bias`;
  // with `cosine`, the cosine between the surface at x and the direction to the light, the bias
  // grows by the depth one and a half texels of that surface span, as a GPU's slope-scaled bias:
  // a face must not shadow itself).
  bool blocks(const glm::dvec3& x, double bias, double cosine = 1) const {
    const glm::dvec3 p = project(x);
    if (p.z <= 0) return false;
    const int i = int(std::floor(p.x)), j = int(std::floor(p.y));
    if (i < 0 || j < 0 || i >= kSize || j >= kSize) return false;
    if (cosine < 1) {
      const double texel = 2 * (ortho_ ? 1.0 : p.z) / (scale_ * kSize);
      const double c = std::max(cosine, 0.05);
      bias += 1.5 * texel * std::sqrt(1 - c * c) / c;
    }
    return depth_[size_t(j) * kSize + size_t(i)] < p.z - bias;
  }

 private:
  glm::dvec3 origin_, r_, u_, f_;
  double scale_ = 1;
  bool ortho_ = false;
  std::vector<float> depth_;
  // Texel coordinates and depth along the view axis.
  glm::dvec3 project(const glm::dvec3& x) const {
    const glm::dvec3 v = x - origin_;
    const double z = glm::dot(v, f_);
    const double w = ortho_ ? 1.0 : std::max(z, 1e-9);
    const double half = 0.5 * kSize;
    return {(glm::dot(v, r_) / w * scale_ + 1) * half, (glm::dot(v, u_) / w * scale_ + 1) * half, z};
  }
  void raster(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    const double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (std::abs(area) < 1e-12) return;
    const int x0 = std::max(0, int(std::floor(std::min({a.x, b.x, c.x})))), x1 = std::min(kSize - 1, int(std::ceil(std::max({a.x, b.x, c.x}))));
    const int y0 = std::max(0, int(std::floor(std::min({a.y, b.y, c.y})))), y1 = std::min(kSize - 1, int(std::ceil(std::max({a.y, b.y, c.y}))));
    // Depth interpolated perspective-correctly (1 / z is linear on the image; z itself when orthographic).
    const double ka = ortho_ ? a.z : 1 / a.z, kb = ortho_ ? b.z : 1 / b.z, kc = ortho_ ? c.z : 1 / c.z;
    // The barycentric weights are linear in the texel's centre: w = w0 + wx px + wy py. Per row,
    // only the span where all three can be >= 0 (widened by a texel against rounding) is visited;
    // inside it each texel's weights are computed as a whole (the test at the edges unchanged).
    const double inv = 1 / area;
    const double a0 = (b.x * c.y - b.y * c.x) * inv, ax = (b.y - c.y) * inv, ay = (c.x - b.x) * inv;
    const double b0 = (c.x * a.y - c.y * a.x) * inv, bx = (c.y - a.y) * inv, by = (a.x - c.x) * inv;
    for (int y = y0; y <= y1; ++y) {
      const double py = y + 0.5;
      double lo = x0, hi = x1;
      // w = p + q px >= 0 for the three weights (the third is 1 - wa - wb).
      const double pa = a0 + ay * py, pb = b0 + by * py, pc = 1 - pa - pb, qc = -ax - bx;
      for (const auto& [p0, q] : {std::pair{pa, ax}, std::pair{pb, bx}, std::pair{pc, qc}}) {
        if (q > 0)
          lo = std::max(lo, std::floor(-p0 / q - 0.5) - 1);
        else if (q < 0)
          hi = std::min(hi, std::ceil(-p0 / q - 0.5) + 1);
        else if (p0 < 0)
          hi = lo - 1;
      }
      if (!(lo <= hi)) continue;  // (then both lie in [x0, x1])
      for (int x = int(lo); x <= int(hi); ++x) {
        const double px = x + 0.5;
        const double wa = ((b.x - px) * (c.y - py) - (b.y - py) * (c.x - px)) / area;
        const double wb = ((c.x - px) * (a.y - py) - (c.y - py) * (a.x - px)) / area;
        const double wc = 1 - wa - wb;
        if (wa < 0 || wb < 0 || wc < 0) continue;
        const double k = wa * ka + wb * kb + wc * kc;
        const float z = float(ortho_ ? k : 1 / k);
        float& d = depth_[size_t(y) * kSize + size_t(x)];
        d = std::min(d, z);
      }
    }
  }
};

// 16 directions of equal area over the sun's disc (0.53 degrees across; a fisheye's few pixels
// cannot resolve it), so that shadow edges get the penumbra the sun gives them.
std::vector<glm::dvec3> sunDiscDirections(const glm::dvec3& sun) {
  const glm::dvec3 s = glm::normalize(sun);
  const glm::dvec3 t = glm::normalize(glm::cross(s, std::abs(s.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0)));
  const glm::dvec3 u = glm::cross(s, t);
  const double radius = 0.5 * 0.53 * kPi / 180;
  std::vector<glm::dvec3> d;
  for (int j = 0; j < 16; ++j) {
    const double r = radius * std::sqrt((j + 0.5) / 16), a = j * kPi * (3 - std::sqrt(5.0));
    d.push_back(glm::normalize(s + r * (std::cos(a) * t + std::sin(a) * u)));
  }
  return d;
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
  px.lamp.assign(n, -1);
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
        if (hit.polygon < 0 || h.surfaces()[size_t(hit.polygon)].opening) continue;
        const size_t i = size_t(y) * size_t(cam.width) + size_t(x);
        const glm::dvec3 p = eye + double(hit.t) * glm::dvec3(rays[size_t(x)].direction);
        glm::dvec3 nrm = polygonNormal(h.surfaces()[size_t(hit.polygon)].vertices);
        if (basis.isLamp(hit.polygon)) {
          const auto& s = h.surfaces()[size_t(hit.polygon)];
          const int l = basis.lampOfSurface(hit.polygon);
          if (s.twoSided || s.photometry || glm::dot(nrm, eye - p) > 0) {
            px.lamp[i] = l;
            continue;
          }
          // The back of a one-sided virtual lamp is a dark object (the render gives it albedo 0);
          // a room lamp's back is what the photo shows there.
          if (l < basis.sceneLampCount()) continue;
          nrm = -nrm;
        } else if (glm::dot(nrm, eye - p) < 0) {
          continue;  // a back face: nothing a photo shows
        }
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

namespace {
// The irradiance per pixel in two parts: the sun's direct light, and everything else (the sky
// through the windows, the ground, the room's own reflections).
struct IrradianceParts {
  ImageRGB rest, sun;
};

IrradianceParts irradianceParts(DaylightBasis& basis, const SeenPixels& px, const SkyRadiance& sky, Progress& progress) {
  const bool sun = sky.sun.found && sky.sun.direction.z > 0;
  const std::vector<glm::vec3> rest = basis.irradiance(sky, false, progress);
  const auto& h = basis.engine();
  const auto corners = leafCornerValues(h, rest);
  IrradianceParts out{ImageRGB(px.width, px.height), ImageRGB(px.width, px.height)};
  const glm::vec3 sunE(sky.sun.irradiance);
  const auto& windows = basis.windows();
  const std::vector<glm::dvec3> sunDisc = sunDiscDirections(sun ? sky.sun.direction : glm::dvec3(0, 0, 1));
  tbb::parallel_for(tbb::blocked_range<size_t>(0, px.surface.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i < r.end(); ++i) {
      if (px.surface[i] < 0) continue;
      // The leaf as it is now: a sun solution may have refined the hierarchy since the pixels were seen.
      int leaf = px.leaf[i];
      if (leaf < 0 || !h.nodes()[size_t(leaf)].isLeaf()) leaf = h.findLeaf(px.surface[i], px.uv[i]);
      glm::vec3 e = leaf >= 0 ? interpolateCorners(h.nodes()[size_t(leaf)], corners[size_t(leaf)], px.uv[i]) : glm::vec3(0.f);
      put(out.rest, i, glm::max(e, glm::vec3(0.f)));
      if (sun) put(out.sun, i, sunE * float(footprintSun(h, windows, px.camera, i % size_t(px.width), i / size_t(px.width), sunDisc)));
    }
  });
  return out;
}

ImageRGB sum(ImageRGB a, const ImageRGB& b) {
  for (size_t i = 0; i < a.pixels.size(); ++i) a.pixels[i] += b.pixels[i];
  return a;
}
}  // namespace

ImageRGB irradianceImage(DaylightBasis& basis, const SeenPixels& px, const SkyRadiance& sky, Progress& progress) {
  IrradianceParts parts = irradianceParts(basis, px, sky, progress);
  return sum(std::move(parts.rest), parts.sun);
}

UnseenFit fitUnseenReflectance(const SeenPixels& px, const ImageRGB& photo, const ImageRGB& restA, const ImageRGB& restB,
                               const ImageRGB& sun, double a, double b, const glm::dvec3& sunDirection, const glm::dvec3& sunIrradiance,
                               const std::vector<bool>& usable) {
  UnseenFit fit;
  const size_t polygons = usable.size();
  // Per polygon and channel: photo radiance, irradiance without the sun at a and at b, over the
  // shaded (index 0) and the wholly sunlit (1) pixels; the sun's irradiance over the sunlit.
  struct Sums {
    glm::dvec3 l[2]{}, ea[2]{}, eb[2]{}, sun{0.0};
    long n[2]{0, 0};
  };
  std::vector<Sums> sums(polygons);
  const double sunLum = luminance(sunIrradiance);
  for (size_t i = 0; i < px.surface.size(); ++i) {
    const int s = px.surface[i];
    if (s < 0 || size_t(s) >= polygons || !usable[size_t(s)]) continue;
    const glm::dvec3 es(get(sun, i));
    const double full = sunLum * std::max(0.0, glm::dot(px.normal[i], glm::normalize(sunDirection)));
    int k;
    if (luminance(es) <= 0)
      k = 0;
    else if (full > 0 && luminance(es) >= 0.98 * full)
      k = 1;
    else
      continue;  // penumbra, or the footprint's edge: neither
    Sums& m = sums[size_t(s)];
    m.l[k] += glm::dvec3(get(photo, i));
    m.ea[k] += glm::dvec3(get(restA, i));
    m.eb[k] += glm::dvec3(get(restB, i));
    if (k == 1) m.sun += es;
    ++m.n[k];
  }
  constexpr long kMinPixels = 50;
  double changeA = 0, changeB = 0;
  for (const Sums& m : sums)
    if (m.n[0] >= kMinPixels && m.n[1] >= kMinPixels) {
      ++fit.polygons;
      fit.shadedPixels += m.n[0];
      fit.sunlitPixels += m.n[1];
      changeA += luminance(m.ea[0]);
      changeB += luminance(m.eb[0]);
    }
  fit.sensitivity = changeA > 0 ? std::abs(changeB - changeA) / changeA : 0;
  // Too little to go on: no polygon both sunlit and shaded, or the unseen polygons hardly light
  // the shaded pixels (then their reflectance hardly matters either).
  if (fit.polygons == 0) {
    fit.why = "no polygon the photo shows is both sunlit and shaded";
    return fit;
  }
  if (fit.sensitivity < 0.01) {
    fit.why = "they hardly light what the photo shows";
    return fit;
  }
  // g(rho): the pixel-weighted mean log ratio of the shaded to the sunlit estimate, in luminance;
  // it falls as rho rises (the shaded pixels' light grows faster than the sunlit pixels').
  auto g = [&](double rho) {
    const double t = (rho - a) / (b - a);
    double acc = 0, weight = 0;
    for (const Sums& m : sums) {
      const double l0 = luminance(m.l[0]), l1 = luminance(m.l[1]);
      if (m.n[0] < kMinPixels || m.n[1] < kMinPixels || l0 <= 0 || l1 <= 0) continue;
      const double eShaded = luminance(m.ea[0] + t * (m.eb[0] - m.ea[0]));
      const double eSunlit = luminance(m.ea[1] + t * (m.eb[1] - m.ea[1]) + m.sun);
      const double w = double(std::min(m.n[0], m.n[1]));
      acc += w * (eShaded > 0 ? std::log(l0 / eShaded) : 50.0) - w * std::log(l1 / std::max(eSunlit, 1e-30));
      weight += w;
    }
    return weight > 0 ? acc / weight : std::numeric_limits<double>::quiet_NaN();
  };
  double lo = 0.02, hi = 0.98;
  const double gLo = g(lo), gHi = g(hi);
  if (std::isnan(gLo)) {
    fit.why = "the photo is black where it would be measured";
    return fit;
  }
  // No root inside: no reflectance makes the two agree, so the model (or the sky's sun) is off
  // somewhere, and a bound would be no measurement.
  if (gLo <= 0 || gHi >= 0) {
    fit.rho = glm::dvec3(gLo <= 0 ? lo : hi);
    fit.why = "no reflectance in [0.02, 0.98] makes the sunlit and shaded pixels agree";
    return fit;
  }
  for (int it = 0; it < 50; ++it) {
    const double mid = 0.5 * (lo + hi);
    (g(mid) > 0 ? lo : hi) = mid;
  }
  fit.rho = glm::dvec3(0.5 * (lo + hi));
  fit.ok = true;
  return fit;
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
    if (!(e[s].x > 0 && e[s].y > 0 && e[s].z > 0)) continue;  // a channel with no light says nothing
    for (int c = 0; c < 3; ++c) out[s][c] = std::clamp(kPi * l[s][c] / e[s][c], 0.0, 0.98);
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
    : photo_(photo), camera_(camera), photoSky_(photoSky) {
  checkPhoto(scene);
  Scene room = scene;
  const size_t n = room.polygons.size();
  for (auto& poly : room.polygons) poly.albedo = glm::dvec3(0.5);
  // Polygons outside (beyond a window: the ground) are not seen from inside: they take the
  // ground's albedo the user gives (default 0.2, an open ground's), never an estimate.
  std::vector<bool> outside(n, false);
  reflectances_.assign(n, glm::dvec3(0.5));
  estimated_.assign(n, false);
  for (int s : outsidePolygons(room)) {
    outside[size_t(s)] = true;
    room.polygons[size_t(s)].albedo = reflectances_[size_t(s)] = glm::dvec3(options.groundReflectance);
  }
  // Each polygon's reflectance from the shown polygons' estimates: its own where the photo shows
  // it, else its material's; the rest (`shared`) take `unseen`, or the shown polygons' mean.
  std::vector<bool> shared(n, false);
  auto assign = [&](const std::vector<glm::dvec3>& rho, const glm::dvec3* unseen) {
    std::map<std::string, std::pair<glm::dvec3, double>> byMaterial;
    glm::dvec3 all(0.0);
    double allArea = 0;
    for (size_t s = 0; s < n; ++s) {
      if (rho[s].x < 0) continue;
      const double a = polygonArea(room.polygons[s].vertices);
      auto& m = byMaterial[room.polygons[s].material];
      m.first += a * rho[s];
      m.second += a;
      all += a * rho[s];
      allArea += a;
    }
    const glm::dvec3 mean = allArea > 0 ? all / allArea : glm::dvec3(0.5);
    for (size_t s = 0; s < n; ++s) {
      if (room.polygons[s].kind != PolygonKind::Real || outside[s]) continue;
      const auto m = byMaterial.find(room.polygons[s].material);
      estimated_[s] = rho[s].x >= 0;
      shared[s] = !estimated_[s] && (m == byMaterial.end() || room.polygons[s].material.empty());
      room.polygons[s].albedo = estimated_[s] ? rho[s] : !shared[s] ? m->second.first / m->second.second : unseen ? *unseen : mean;
      reflectances_[s] = room.polygons[s].albedo;
    }
    return mean;
  };
  const bool sunlit = photoSky.sun.found && photoSky.sun.direction.z > 0;
  // A fourth round measures the unseen polygons' reflectance when the photos' sun can tell it
  // (a clipped sun's irradiance is only a lower bound, whose error the fit would take up).
  const bool sunUsable = sunlit && !photoSky.sun.clipped;
  const int rounds = sunUsable ? 4 : 3;
  auto solve = [&](int round) {
    Progress stage(progress, double(round) / rounds, double(round + 1) / rounds);
    stage.report(0, "estimating reflectances under the photos' sky (round " + std::to_string(round + 1) + " of " +
                        std::to_string(rounds) + ")");
    basis_ = std::make_unique<DaylightBasis>(room, photoSky, options, stage);
    seen_ = seePixels(*basis_, camera);
    return irradianceParts(*basis_, seen_, photoSky, stage);
  };
  // Round 1: every polygon at 0.5.
  IrradianceParts e = solve(0);
  std::vector<glm::dvec3> rho = reflectancesFromPhoto(seen_, photo, sum(e.rest, e.sun), n);
  const std::vector<glm::dvec3> first = rho;
  // The update after round 2 is the geometric mean of the reflectance round 2 was solved with and
  // pi L / E (half the step in log space). A wall lit mostly by the other walls has E nearly
  // proportional to their reflectances, and the plain update swings about the answer from round
  // to round (seen: a back wall at 0.75/0.88/0.88, 0.89/0.69/0.55, 0.74/0.89/0.83, ... against
  // 0.72/0.70/0.64); with one update left, a swing cannot be told from a step in the right
  // direction, and the half step lands near the answer for a swinging wall, while a polygon lit
  // directly loses only half of a correction that is small already (its direct light does not
  // depend on the reflectances round 1 guessed).
  auto damped = [&](std::vector<glm::dvec3> r) {
    for (size_t s = 0; s < n; ++s)
      if (r[s].x >= 0 && first[s].x >= 0) r[s] = glm::sqrt(r[s] * first[s]);
    return r;
  };
  // Round 2: the shown polygons at their estimates, the unseen at the shown polygons' mean.
  const glm::dvec3 mean = assign(rho, nullptr);
  const bool anyShared = std::find(shared.begin(), shared.end(), true) != shared.end();
  // The unseen polygons' reflectance is measured grey, in luminance: no photo shows their colour,
  // and a fit per channel would take up any error in the colour of the sun against the sky's (a
  // few pixels of a fisheye give it). Round 2 solves them grey at the shown polygons' mean
  // luminance; if the fit then fails, the final round gives them the mean itself.
  const double ga = luminance(mean);
  if (!anyShared)
    unseenFit_.why = "every polygon is shown by the photo or shares a shown polygon's material";
  else if (!sunUsable)
    unseenFit_.why = !sunlit ? "the photos' sky has no sun" : "the photos' sun is clipped in the sky image";
  std::vector<bool> usable(n);
  for (size_t s = 0; s < n; ++s) usable[s] = estimated_[s] && !outside[s];
  bool fitUnseen = anyShared && sunUsable;
  if (fitUnseen) {
    const glm::dvec3 grey(ga);
    assign(rho, &grey);
  }
  e = solve(1);
  rho = damped(reflectancesFromPhoto(seen_, photo, sum(e.rest, e.sun), n));
  if (fitUnseen) {
    // Worth a round only if some shown polygon is both sunlit and shaded.
    const UnseenFit probe = fitUnseenReflectance(seen_, photo, e.rest, e.rest, e.sun, ga, ga + 0.3, photoSky.sun.direction,
                                                 photoSky.sun.irradiance, usable);
    if (probe.polygons == 0) {
      unseenFit_.why = probe.why;
      fitUnseen = false;
    }
  }
  if (fitUnseen) {
    // Round 3: the same, with the unseen polygons 0.3 lighter (or darker); the final assign()
    // sets them again.
    const double b = ga < 0.6 ? ga + 0.3 : ga - 0.3;
    for (size_t s = 0; s < n; ++s)
      if (shared[s]) room.polygons[s].albedo = glm::dvec3(b);
    IrradianceParts eb = solve(2);
    unseenFit_ = fitUnseenReflectance(seen_, photo, e.rest, eb.rest, e.sun, ga, b, photoSky.sun.direction,
                                      photoSky.sun.irradiance, usable);
    if (unseenFit_.ok) {
      // The shown polygons' estimates again, with the irradiance the fitted unseen reflectance gives.
      ImageRGB at = e.rest;
      const double t = (unseenFit_.rho.x - ga) / (b - ga);
      for (size_t i = 0; i < at.pixels.size(); ++i)
        at.pixels[i] = std::max(0.f, float(e.rest.pixels[i] + t * (eb.rest.pixels[i] - e.rest.pixels[i])));
      rho = damped(reflectancesFromPhoto(seen_, photo, sum(std::move(at), e.sun), n));
    }
  }
  assign(rho, unseenFit_.ok ? &unseenFit_.rho : nullptr);
  e = solve(rounds - 1);  // the last round (the third when the fit took no round of its own: progress skips one)
  ePhoto_ = sum(std::move(e.rest), e.sun);
}

void DaylightRelighting::checkPhoto(const Scene& scene) const {
  if (photo_.width != camera_.width || photo_.height != camera_.height)
    throw Error(scene.sourceFile, "main photo", "its image is " + std::to_string(photo_.width) + "x" + std::to_string(photo_.height) +
                                                    ", its camera " + std::to_string(camera_.width) + "x" + std::to_string(camera_.height));
}

namespace {
constexpr char kSessionMagic[8] = {'R', 'L', 'D', 'Y', 'S', 'E', 'S', '1'};

// FNV-1a over what the estimates were made from: the photo's pixels, the camera, the photos' sky.
uint64_t sessionFingerprint(const ImageRGB& photo, const Camera& camera, const SkyRadiance& sky) {
  uint64_t h = 1469598103934665603ull;
  auto bytes = [&](const void* p, size_t n) {
    for (size_t i = 0; i < n; ++i) h = (h ^ static_cast<const uint8_t*>(p)[i]) * 1099511628211ull;
  };
  auto f64 = [&](double v) { bytes(&v, 8); };
  auto vec = [&](const glm::dvec3& v) { f64(v.x), f64(v.y), f64(v.z); };
  f64(photo.width), f64(photo.height);
  bytes(photo.pixels.data(), photo.pixels.size() * sizeof(photo.pixels[0]));
  for (int c = 0; c < 3; ++c) vec(camera.K[c]), vec(camera.R[c]);
  vec(camera.t);
  f64(double(sky.region.size()));
  for (const auto& r : sky.region) vec(r);
  f64(sky.sun.found), f64(sky.sun.clipped), vec(sky.sun.direction), vec(sky.sun.irradiance), vec(sky.sunBackground);
  return h;
}
}  // namespace

void DaylightRelighting::save(const std::string& file) const {
  ByteWriter w;
  w.raw(kSessionMagic, 8);
  w.u64(sessionFingerprint(photo_, camera_, photoSky_));
  w.u64(reflectances_.size());
  for (const auto& r : reflectances_)
    for (int c = 0; c < 3; ++c) w.f64(r[c]);
  for (bool e : estimated_) w.u32(e ? 1u : 0u);
  w.u32(unseenFit_.ok ? 1u : 0u);
  for (int c = 0; c < 3; ++c) w.f64(unseenFit_.rho[c]);
  w.u64(uint64_t(unseenFit_.polygons));
  w.u64(uint64_t(unseenFit_.shadedPixels));
  w.u64(uint64_t(unseenFit_.sunlitPixels));
  w.f64(unseenFit_.sensitivity);
  w.text(unseenFit_.why);
  // The photo's irradiance as the session made it (its sun solved then: the basis may since hold
  // another sun's, and opening must solve nothing).
  w.array(ePhoto_.pixels);
  try {
    basis_->write(w);
  } catch (const Error& e) {
    throw Error(file, e.element(), e.problem());
  }
  w.seal();
  writeFileAtomically(file, w.bytes);
}

DaylightRelighting::DaylightRelighting(const Scene& scene, const ImageRGB& photo, const Camera& camera, const SkyRadiance& photoSky,
                                       const BasisOptions& options, const std::string& keptFile, Progress& progress)
    : photo_(photo), camera_(camera), photoSky_(photoSky) {
  checkPhoto(scene);
  progress.report(0, "opening the kept daylight solution");
  const std::vector<uint8_t> bytes = readFileBytes(keptFile);
  ByteReader in(bytes, keptFile);
  const char* part = "daylight solution";
  in.need(8, part);
  if (std::memcmp(bytes.data(), kSessionMagic, 8) != 0) in.fail("", "is not a kept daylight solution (relume daylight-basis -o writes them)");
  if (!in.sealed()) in.fail("", "the file is damaged (its checksum does not match)");
  in.pos = 8;
  if (in.u64(part) != sessionFingerprint(photo, camera, photoSky))
    in.fail(part, "was made for another photo, camera or sky of the photos (solve it again)");
  const size_t n = scene.polygons.size();
  if (in.u64(part) != n) in.fail(part, "was made for a room of another number of polygons (solve it again)");
  reflectances_.resize(n);
  for (auto& r : reflectances_)
    for (int c = 0; c < 3; ++c) r[c] = in.f64(part);
  estimated_.resize(n);
  for (size_t s = 0; s < n; ++s) estimated_[s] = in.u32(part) != 0;
  unseenFit_.ok = in.u32(part) != 0;
  for (int c = 0; c < 3; ++c) unseenFit_.rho[c] = in.f64(part);
  unseenFit_.polygons = int(std::min<uint64_t>(in.u64(part), uint64_t(std::numeric_limits<int>::max())));
  unseenFit_.shadedPixels = long(std::min<uint64_t>(in.u64(part), uint64_t(std::numeric_limits<long>::max())));
  unseenFit_.sunlitPixels = long(std::min<uint64_t>(in.u64(part), uint64_t(std::numeric_limits<long>::max())));
  unseenFit_.sensitivity = in.f64(part);
  unseenFit_.why = in.text(part);
  ePhoto_ = ImageRGB(photo.width, photo.height);
  ePhoto_.pixels = in.array<float>(part, ePhoto_.pixels.size());
  if (ePhoto_.pixels.size() != size_t(photo.width) * size_t(photo.height) * 3)
    in.fail(part, "the photo's irradiance is not the photo's size (damaged)");
  // The room as the last round of estimation solved it.
  Scene room = scene;
  for (size_t s = 0; s < n; ++s) room.polygons[s].albedo = reflectances_[s];
  basis_ = std::make_unique<DaylightBasis>(room, photoSky, options, in);
  in.expectEnd();
  progress.report(0.5, "looking up the photo's pixels");
  seen_ = seePixels(*basis_, camera);
}

std::string keptSolutionFile(const Scene& scene) {
  const std::filesystem::path src(scene.sourceFile);
  if (src.filename() != "project.json") return {};
  return (src.parent_path() / "daylight" / "solution.bin").string();
}

std::unique_ptr<DaylightRelighting> openDaylightRelighting(const Scene& scene, const ImageRGB& photo, const Camera& camera,
                                                           const SkyRadiance& photoSky, const BasisOptions& options,
                                                           Progress& progress, std::string* how) {
  const std::string kept = keptSolutionFile(scene);
  std::string said;
  std::error_code ec;
  if (!kept.empty() && std::filesystem::exists(kept, ec)) {
    try {
      auto out = std::make_unique<DaylightRelighting>(scene, photo, camera, photoSky, options, kept, progress);
      if (how) *how = "opened the project's kept daylight solution " + kept;
      return out;
    } catch (const Cancelled&) {
      throw;
    } catch (const std::exception& e) {
      said = std::string("the kept daylight solution is not used (") + e.what() + "): estimating and solving again";
    }
  }
  auto out = std::make_unique<DaylightRelighting>(scene, photo, camera, photoSky, options, progress);
  if (how) *how = said;
  return out;
}

namespace {
// One window sample's light on a room pixel past the room: the sample, the sky region its
// direction looks into (-1: the ground), and cos x cos x area / r^2.
struct WindowLight {
  uint16_t sample;
  int16_t region;
  float weight;
};
}  // namespace

struct DaylightRelighting::InteractiveCache {
  size_t samples = 0;  // the window samples the entries were made with
  std::vector<std::vector<WindowLight>> window;
  std::vector<uint8_t> windowReady;
  glm::dvec3 sunDirection{0.0};
  std::vector<std::vector<SunRay>> sunRays;
  std::vector<uint8_t> sunReady;
};

DaylightRelighting::~DaylightRelighting() = default;

namespace {
// The lamps switched on show their own radiance (exitance / pi; the photo shows them off) where
// the camera sees their emitting faces.
// A virtual lamp's pixels show the lamp alone (the photo there shows what stands behind it).
void paintLamps(ImageRGB& out, const SeenPixels& px, const DaylightBasis& basis) {
  if (px.lamp.size() != size_t(out.width) * size_t(out.height)) return;
  for (size_t i = 0; i < px.lamp.size(); ++i) {
    const int l = px.lamp[i];
    if (l < 0) continue;
    const glm::vec3 own(basis.lampExitance(l) / std::numbers::pi);
    put(out, i, l >= basis.sceneLampCount() ? own : get(out, i) + own);
  }
}
}  // namespace

ImageRGB DaylightRelighting::render(const SkyRadiance& sky, const std::vector<Polygon>& objects, DaylightMethod method,
                                    Progress& progress, const std::vector<BasisLamp>& lamps) {
  if (method == DaylightMethod::Distant && (basis_->anyLampOn() || !lamps.empty()))
    throw Error("", "daylight", "the distant method is the sky at infinity alone: switch the lamps off for it");
  if (method == DaylightMethod::Volume && !lamps.empty())
    throw Error("", "virtual lamp", "the volume method lights the room from the solved bases alone: for a virtual lamp, use "
                                    "the near-field method");
  if (method == DaylightMethod::Volume) return renderVolume(sky, objects, progress);
  std::vector<glm::dvec3> albedos;
  std::vector<std::vector<glm::dvec3>> occluders;
  for (const auto& o : objects) {
    albedos.push_back(o.albedo);
    occluders.push_back(o.vertices);
  }
  albedos.resize(objects.size() + lamps.size(), glm::dvec3(0.0));  // a virtual lamp's back reflects nothing
  std::vector<int> ids;
  SeenPixels seen = seen_;
  if (!objects.empty() || !lamps.empty()) {
    Progress stage(progress, 0.0, 0.6);
    ids = basis_->addObjects(objects, lamps, stage);
  }
  const int firstVirtual = ids.empty() ? int(basis_->engine().surfaces().size()) : ids.front();
  ImageRGB out;
  try {  // from here on, whatever goes wrong takes the objects out again
    if (!ids.empty()) seen = seePixels(*basis_, camera_);
    if (method == DaylightMethod::NearField) {
      Progress stage(progress, 0.6, 0.9);
      eLast_ = irradianceImage(*basis_, seen, sky, stage);
      out = differentialRender(photo_, ePhoto_, eLast_, seen, firstVirtual, albedos);
      paintLamps(out, seen, *basis_);
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

namespace {
bool sameSky(const SkyRadiance& a, const SkyRadiance& b) {
  return a.region == b.region && a.sun.found == b.sun.found && a.sun.direction == b.sun.direction &&
         a.sun.irradiance == b.sun.irradiance;
}
}  // namespace

IrradianceVolume& DaylightRelighting::volume(Progress& progress) {
  if (!volume_) volume_ = std::make_unique<IrradianceVolume>(*basis_, interactive_.volume, progress);
  return *volume_;
}

void DaylightRelighting::setInteractive(const InteractiveOptions& options) {
  if (options.volume.grid != interactive_.volume.grid || options.volume.rays != interactive_.volume.rays) volume_.reset();
  const int samples = std::clamp(options.directSamples, 1, 1024);
  if (samples != interactive_.directSamples) cache_.reset();
  interactive_ = options;
  interactive_.directSamples = samples;
}

glm::vec3 DaylightRelighting::relitPixel(size_t i, const glm::vec3& e) const {
  const glm::vec3 a = get(ePhoto_, i), ph = get(photo_, i);
  glm::vec3 v = ph;
  for (int c = 0; c < 3; ++c)
    if (a[c] > 1e-6f) v[c] = ph[c] * (std::max(e[c], 0.f) / a[c]);
  return v;
}

std::vector<DirectSample> windowSamples(const radiosity::HierarchicalRadiosity& h, const std::vector<int>& windows, int count) {
  std::vector<DirectSample> ws;
  double total = 0;
  for (int w : windows) total += polygonArea(h.surfaces()[size_t(w)].vertices);
  for (int w : windows) {
    const auto& v = h.surfaces()[size_t(w)].vertices;
    const double a = polygonArea(v);
    const int m = std::max(1, int(std::lround(count * a / std::max(total, 1e-12))));
    const glm::dvec3 n = polygonNormal(v);
    // Per fan triangle its share of the window's samples (at least one), spread evenly over it
    // (a Fibonacci lattice on the unit square, folded onto the triangle), each standing for the
    // triangle's area over its count: unbiased whatever the counts and the window's shape.
    for (size_t t = 1; t + 1 < v.size(); ++t) {
      const double at = 0.5 * glm::length(glm::cross(v[t] - v[0], v[t + 1] - v[0]));
      if (at <= 0) continue;
      const int mt = std::max(1, int(std::lround(m * at / std::max(a, 1e-12))));
      for (int i = 0; i < mt; ++i) {
        double u = (i + 0.5) / mt, s2 = std::fmod(0.5 + i * 0.6180339887498949, 1.0);
        if (u + s2 > 1) {
          u = 1 - u;
          s2 = 1 - s2;
        }
        ws.push_back({v[0] + u * (v[t] - v[0]) + s2 * (v[t + 1] - v[0]), n, at / mt});
      }
    }
  }
  return ws;
}

namespace {
// Per window: the centre and radius of its bounding sphere.
std::vector<std::pair<glm::dvec3, double>> windowSpheres(const radiosity::HierarchicalRadiosity& h,
                                                         const std::vector<int>& windows) {
  std::vector<std::pair<glm::dvec3, double>> out;
  for (int w : windows) {
    const auto& v = h.surfaces()[size_t(w)].vertices;
    glm::dvec3 c(0.0);
    for (const auto& q : v) c += q / double(v.size());
    double r = 0;
    for (const auto& q : v) r = std::max(r, glm::length(q - c));
    out.push_back({c, r});
  }
  return out;
}

// Could a sphere (centre, radius) block any of the windows' light that reaches x: does it meet
// the cone from x to some window's sphere? `grow` widens both spheres: then it answers for every
// point within `grow` of x (a segment from such a point to a window point lies within `grow` of
// the same segment moved to x). (Angles compared by cosines: this runs for every pixel.)
bool sphereMayShadow(const std::vector<std::pair<glm::dvec3, double>>& windowCones, const glm::dvec3& centre, double radius,
                     const glm::dvec3& x, double grow) {
  const glm::dvec3 toObj = centre - x;
  const double dObj = glm::length(toObj), rObj = radius + grow;
  if (dObj <= rObj) return true;
  const double sb = rObj / dObj, cb = std::sqrt(1 - sb * sb);
  for (const auto& [c, rw] : windowCones) {
    const glm::dvec3 toWin = c - x;
    const double dWin = glm::length(toWin), r = rw + grow;
    if (dWin <= r) return true;
    if (dObj - rObj >= dWin + r) continue;  // the sphere lies beyond the window
    const double sa = r / dWin, ca = std::sqrt(1 - sa * sa);
    // angle <= alpha + beta, i.e. cos(angle) >= cos(alpha + beta) (alpha + beta < pi here)
    if (glm::dot(toObj, toWin) / (dObj * dWin) >= ca * cb - sa * sb) return true;
  }
  return false;
}
}  // namespace

void DaylightRelighting::updateRoom(const SkyRadiance& sky, Progress& progress) {
  // The room under this sky (cached: the sky changes far less often than an object moves).
  // It is made again when the sky changes, or when a NearField render (objects solved into the
  // bases and taken out again) or another sun re-solved what it was made from.
  if (!eRoom_.pixels.empty() && sameSky(sky, roomSky_) && roomRevision_ == basis_->revision()) return;
  IrradianceParts parts = irradianceParts(*basis_, seen_, sky, progress);
  eRoomSun_ = parts.sun;
  eRoom_ = sum(std::move(parts.rest), parts.sun);
  roomSky_ = sky;
  roomRevision_ = basis_->revision();  // after: the sky's sun may have been solved just now
  roomOut_ = photo_;
  for (size_t i = 0; i < seen_.surface.size(); ++i)
    if (seen_.surface[i] >= 0) put(roomOut_, i, relitPixel(i, get(eRoom_, i)));
  paintLamps(roomOut_, seen_, *basis_);
  ++roomVersion_;
}

const InteractiveSky& DaylightRelighting::interactiveSky(const SkyRadiance& sky, Progress& progress) {
  {
    Progress stage(progress, 0.0, 0.7);
    volume(stage);
  }
  {
    Progress stage(progress, 0.7, 1.0);
    updateRoom(sky, stage);
  }
  // Kept while the room's light and the sample count stay (an object's drag asks for it every move).
  if (skyCache_ && skyCacheRoom_ == roomVersion_ && skyCache_->window.size() == skyCacheSamples_ &&
      skyCacheRequested_ == interactive_.directSamples)
    return *skyCache_;
  auto made = std::make_unique<InteractiveSky>();
  InteractiveSky& out = *made;
  out.window = windowSamples(basis_->engine(), basis_->windows(), interactive_.directSamples);
  out.sun = sky.sun.found && sky.sun.direction.z > 0;
  if (out.sun) {
    out.sunIrradiance = sky.sun.irradiance;
    const std::vector<glm::dvec3> disc = sunDiscDirections(sky.sun.direction);
    for (size_t j = 0; j < 4; ++j) out.sunDirections.push_back(disc[4 * j]);
  }
  // The regions' radiance per direction, fine enough that a region (64 over the hemisphere:
  // about 15 degrees across) spans many texels.
  const glm::dvec3 groundL = basis_->groundRadiance(sky);
  out.radiance = ImageRGB(256, 128);
  for (int v = 0; v < out.radiance.height; ++v)
    for (int u = 0; u < out.radiance.width; ++u) {
      const double phi = 2 * kPi * (u + 0.5) / out.radiance.width - kPi, theta = kPi * (v + 0.5) / out.radiance.height;
      const glm::dvec3 d(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
      const int k = basis_->regions().regionOf(d);
      out.radiance.set(u, v, glm::vec3(k >= 0 ? sky.region[size_t(k)] : groundL));
    }
  out.room = roomOut_;
  out.sunLight = eRoomSun_;
  out.gain = ImageRGB(photo_.width, photo_.height);
  for (size_t i = 0; i < seen_.surface.size(); ++i) {
    if (seen_.surface[i] < 0) continue;
    const glm::vec3 a = get(ePhoto_, i), ph = get(photo_, i);
    glm::vec3 g(0.f);
    for (int c = 0; c < 3; ++c)
      if (a[c] > 1e-6f) g[c] = ph[c] / a[c];  // as relitPixel: where the photo had no light, nothing changes
    put(out.gain, i, g);
  }
  skyCache_ = std::move(made);
  skyCacheRoom_ = roomVersion_;
  skyCacheSamples_ = skyCache_->window.size();
  skyCacheRequested_ = interactive_.directSamples;
  return *skyCache_;
}

ShadowReach DaylightRelighting::shadowReach(const InteractiveSky& light, const glm::dvec3& centre, double radius) {
  return shadowReach(light.window, light.sun, light.sun ? light.sunDirections.front() : glm::dvec3(0, 0, 1), centre, radius);
}

ShadowReach DaylightRelighting::shadowReach(const std::vector<DirectSample>& ws, bool sun, const glm::dvec3& sunDirection,
                                            const glm::dvec3& centre, double radius) {
  constexpr int kTile = ShadowReach::kTile;
  const int width = seen_.width, height = seen_.height;
  ShadowReach out;
  out.tilesX = (width + kTile - 1) / kTile;
  out.tilesY = (height + kTile - 1) / kTile;
  out.words = int((ws.size() + 1 + 31) / 32);
  const size_t tiles = size_t(out.tilesX) * size_t(out.tilesY);
  out.bits.assign(tiles * size_t(out.words), 0);
  // The tiles' points with a pixel's border (the sun's footprint test looks one pixel out), once.
  if (tileSpheres_.size() != tiles) {
    tileSpheres_.assign(tiles, glm::dvec4(0, 0, 0, -1));
    tileGap_.assign(tiles, 0);
    for (size_t tile = 0; tile < tiles; ++tile) {
      const int x0 = int(tile % size_t(out.tilesX)) * kTile, y0 = int(tile / size_t(out.tilesX)) * kTile;
      const int x1 = std::min(width, x0 + kTile), y1 = std::min(height, y0 + kTile);
      glm::dvec3 lo(1e300), hi(-1e300);
      for (int y = std::max(0, y0 - 1); y < std::min(height, y1 + 1); ++y)
        for (int x = std::max(0, x0 - 1); x < std::min(width, x1 + 1); ++x) {
          const size_t i = size_t(y) * size_t(width) + size_t(x);
          if (seen_.surface[i] < 0) {
            tileGap_[tile] = 1;
            continue;
          }
          lo = glm::min(lo, seen_.point[i]);
          hi = glm::max(hi, seen_.point[i]);
        }
      if (lo.x <= hi.x) tileSpheres_[tile] = glm::dvec4(0.5 * (lo + hi), 0.5 * glm::length(hi - lo) + 1e-6);
    }
  }
  // Per window sample the cone from it around the sphere (none: it lies inside, every point may
  // be shadowed), widened by a shadow map's texel: a texel that holds some of the objects covers
  // directions up to a texel's width beside them.
  struct SampleCone {
    glm::dvec3 apex{0.0}, axis{0.0};
    double sinB = 1, cosB = 0;
    bool all = true;
  };
  std::vector<SampleCone> cones(ws.size());
  for (size_t m = 0; m < ws.size(); ++m) {
    const glm::dvec3 toObj = centre - ws[m].point;
    const double d = glm::length(toObj);
    if (d <= radius) continue;
    const double sb = std::min(1.0, 1.05 * radius / d);
    cones[m] = {ws[m].point, toObj / d, sb, std::sqrt(1 - sb * sb), false};
  }
  const auto windowCones = windowSpheres(basis_->engine(), basis_->windows());
  const glm::dvec3 sunDir = glm::normalize(sunDirection);
  tbb::parallel_for(size_t(0), tiles, [&](size_t tile) {
    const glm::dvec4 sphere = tileSpheres_[tile];
    if (sphere.w < 0) return;
    uint32_t* bits = out.bits.data() + tile * size_t(out.words);
    const glm::dvec3 tc(sphere);
    const double tr = sphere.w;
    if (sphereMayShadow(windowCones, centre, radius, tc, tr))
      for (size_t m = 0; m < ws.size(); ++m) {
        const SampleCone& k = cones[m];
        bool in = k.all;
        if (!in) {
          const glm::dvec3 v = tc - k.apex;
          const double dv = glm::length(v);
          if (dv <= tr) {
            in = true;
          } else {
            const double sa = tr / dv, ca = std::sqrt(1 - sa * sa);
            in = glm::dot(v, k.axis) / dv >= ca * k.cosB - sa * k.sinB;
          }
        }
        if (in) bits[m / 32] |= uint32_t(1) << (m % 32);
      }
    // The sun: every pixel's test widened by the tile's sphere (its point within tr of tc, its
    // footprint's spread within 2 tr); a pixel beside a gap asks its own.
    if (sun) {
      bool may = tileGap_[tile] != 0;
      if (!may) {
        const glm::dvec3 toC = centre - tc;
        const double along = glm::dot(toC, sunDir), perp2 = glm::dot(toC, toC) - along * along;
        const double reach0 = radius + 0.01 * (glm::length(toC) + tr) + 3 * tr + 0.05;
        may = along >= -reach0 && perp2 <= reach0 * reach0;
      }
      if (may) bits[ws.size() / 32] |= uint32_t(1) << (ws.size() % 32);
    }
  });
  return out;
}

namespace {
// The objects' faces as polygons, and their bounding box.
std::vector<std::vector<glm::dvec3>> facesAndBounds(const std::vector<Polygon>& objects, glm::dvec3& lo, glm::dvec3& hi) {
  std::vector<std::vector<glm::dvec3>> polys;
  lo = glm::dvec3(1e300);
  hi = glm::dvec3(-1e300);
  for (const auto& o : objects) {
    polys.push_back(o.vertices);
    for (const auto& v : o.vertices) {
      lo = glm::min(lo, v);
      hi = glm::max(hi, v);
    }
  }
  return polys;
}
}  // namespace

ObjectIndirect DaylightRelighting::objectIndirect(const SkyRadiance& sky, const std::vector<Polygon>& objects,
                                                  Progress& progress) {
  checkInteractiveObjects(objects);
  ObjectIndirect out;
  if (objects.empty()) return out;
  volume(progress);
  glm::dvec3 lo, hi;
  const std::vector<std::vector<glm::dvec3>> polys = facesAndBounds(objects, lo, hi);
  const RayScene objectScene(polys);
  volume_->combine(*basis_, sky, lo, hi);
  // Both sides of every face: a face seen from behind (a single panel, not a closed solid) is lit
  // by what its back sees.
  out.front.resize(objects.size());
  out.back.resize(objects.size());
  for (size_t o = 0; o < objects.size(); ++o) {
    const auto& v = objects[o].vertices;
    const glm::dvec3 nrm = polygonNormal(v);
    glm::dvec3 mid(0.0);
    for (const auto& q : v) mid += q / double(v.size());
    for (const auto& q : v) {
      const glm::dvec3 x = q + 0.02 * (mid - q);  // just inside the corner: an edge's own faces are not its shadow
      const radiosity::SH9 l = volume_->at(x);
      out.front[o].push_back(radiosity::shApply(l, radiosity::shTransfer(x, nrm, &objectScene, 64)));
      out.back[o].push_back(radiosity::shApply(l, radiosity::shTransfer(x, -nrm, &objectScene, 64)));
    }
  }
  return out;
}

std::vector<std::vector<glm::dvec3>> DaylightRelighting::roomPolygons() const {
  const auto& h = basis_->engine();
  const auto& windows = basis_->windows();
  std::vector<std::vector<glm::dvec3>> out;
  for (size_t s = 0; s < h.surfaces().size(); ++s)
    if (std::find(windows.begin(), windows.end(), int(s)) == windows.end()) out.push_back(h.surfaces()[s].vertices);
  return out;
}

void DaylightRelighting::checkInteractiveObjects(const std::vector<Polygon>& objects) const {
  if (!objects.empty() && basis_->anyLampOn())
    throw Error("", "virtual object", "the interactive path lights virtual objects by daylight only: with a lamp on, use the "
                                      "near-field method");
  for (size_t o = 0; o < objects.size(); ++o)
    if (objects[o].vertices.size() < 3 || !(polygonArea(objects[o].vertices) > 1e-12))
      throw Error("", "virtual object", "face " + std::to_string(o + 1) + " (" + objects[o].name + ") has no area");
}

ImageRGB DaylightRelighting::renderVolume(const SkyRadiance& sky, const std::vector<Polygon>& objects, Progress& progress) {
  checkInteractiveObjects(objects);
  const auto& h = basis_->engine();
  const auto& windows = basis_->windows();
  {
    Progress stage(progress, 0.0, 0.7);
    volume(stage);
  }
  {
    Progress stage(progress, 0.7, 0.95);
    updateRoom(sky, stage);
  }
  const bool sun = sky.sun.found && sky.sun.direction.z > 0;
  const glm::dvec3 groundL = basis_->groundRadiance(sky);
  // The direct daylight's samples: points spread evenly over the windows by area (the same for
  // every pixel: the paper's set of shadow maps), and the sun's disc.
  const std::vector<DirectSample> ws = windowSamples(h, windows, interactive_.directSamples);
  const std::vector<glm::dvec3> sunDisc = sunDiscDirections(sun ? sky.sun.direction : glm::dvec3(0, 0, 1));

  touched_ = 0;
  const size_t n = seen_.surface.size();
  if (objects.empty()) {
    eLast_ = eRoom_;
    return roomOut_;
  }
  ImageRGB out = roomOut_;
  auto ratio = [&](size_t i, const glm::vec3& eNew) { put(out, i, relitPixel(i, eNew)); };

  // The objects: their own ray scene, their box and bounding sphere, the volume combined for the
  // grid points they need, and per vertex the indirect light (Eq. 5, their own shadowing).
  glm::dvec3 lo, hi;
  const std::vector<std::vector<glm::dvec3>> polys = facesAndBounds(objects, lo, hi);
  const RayScene objectScene(polys);
  std::vector<size_t> firstTriangle;  // the scene's fan triangles, polygon after polygon
  for (size_t o = 0, t = 0; o < polys.size(); t += polys[o].size() >= 3 ? polys[o].size() - 2 : 0, ++o) firstTriangle.push_back(t);
  const glm::dvec3 centre = 0.5 * (lo + hi);
  const double radius = 0.5 * glm::length(hi - lo);
  const ObjectIndirect indirect = objectIndirect(sky, objects);
  const auto& vertexE = indirect.front;
  const auto& vertexBackE = indirect.back;
  // Could the objects block the sun anywhere in pixel i's footprint? Its rays hit the room within
  // the hull of the 3 x 3 pixel centres around it (the footprint spans 1.5 pixels), so a sun line
  // through the centre's point that passes farther from the sphere than the radius plus that
  // spread (and the sun disc's 0.27 degrees) cannot meet them; a neighbour that shows no surface
  // asks the rays. The neighbours are looked at only when the centre's line passes within 5 cm of
  // that reach (this runs for every pixel): a footprint that spans a depth edge of more than 5 cm
  // may miss the objects' sun shadow on its far side.
  const glm::dvec3 sunDir = sun ? glm::normalize(sky.sun.direction) : glm::dvec3(0, 0, 1);
  auto sunMayBeBlocked = [&](size_t i) {
    const glm::dvec3& p = seen_.point[i];
    const glm::dvec3 toC = centre - p;
    const double along = glm::dot(toC, sunDir), perp2 = glm::dot(toC, toC) - along * along;
    const double reach0 = radius + 0.01 * glm::length(toC);
    if (along < -(reach0 + 0.05)) return false;  // the objects lie behind the sun's rays
    if (perp2 > (reach0 + 0.05) * (reach0 + 0.05)) return false;
    const int px = int(i % size_t(seen_.width)), py = int(i / size_t(seen_.width));
    double spread = 0;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int qx = px + dx, qy = py + dy;
        if (qx < 0 || qy < 0 || qx >= seen_.width || qy >= seen_.height) continue;
        const size_t q = size_t(qy) * size_t(seen_.width) + size_t(qx);
        if (seen_.surface[q] < 0) return true;
        spread = std::max(spread, glm::length(seen_.point[q] - p));
      }
    if (along < -(reach0 + spread)) return false;
    return perp2 <= (reach0 + spread) * (reach0 + spread);
  };
  // Could the objects block any of the window's light that reaches x: does their bounding sphere
  // meet the cone from x to some window? (Angles compared by cosines: this runs for every pixel
  // of the room.)
  const auto windowCones = windowSpheres(h, windows);
  auto mayBeShadowed = [&](const glm::dvec3& x) { return sphereMayShadow(windowCones, centre, radius, x, 0); };

  // The objects' shadow maps: one per window sample (perspective from it), one per direction of
  // the sun's disc (orthographic). A sample inside the bounding sphere gets none: its rays ask the
  // objects directly.
  std::vector<std::unique_ptr<ObjectShadowMap>> windowMaps(ws.size()), sunMaps(sunDisc.size());
  tbb::parallel_for(size_t(0), ws.size() + (sun ? sunDisc.size() : 0), [&](size_t m) {
    if (m < ws.size()) {
      if (glm::length(ws[m].point - centre) > 1.05 * radius)
        windowMaps[m] = std::make_unique<ObjectShadowMap>(&ws[m].point, glm::dvec3(0.0), centre, radius, polys);
    } else {
      const size_t d = m - ws.size();
      sunMaps[d] = std::make_unique<ObjectShadowMap>(nullptr, -sunDisc[d], centre, radius, polys);
    }
  });
  constexpr double kBias = 1e-3;  // metres: the objects' faces against the room's surfaces they touch

  // What a room pixel receives from each window sample and the sun, past the room alone, depends
  // on the room, the camera and the samples only: kept per pixel the first time an object's
  // shadow may reach it (the window samples for the session's sample count, the sun's rays for
  // its direction), so that moving an object asks only the objects' maps.
  if (!cache_ || cache_->samples != ws.size()) {
    cache_ = std::make_unique<InteractiveCache>();
    cache_->samples = ws.size();
    cache_->window.resize(n);
    cache_->windowReady.assign(n, 0);
  }
  InteractiveCache& cache = *cache_;
  if (sun && (cache.sunRays.size() != n || glm::dot(cache.sunDirection, glm::normalize(sky.sun.direction)) < 1 - 1e-12)) {
    cache.sunRays.assign(n, {});
    cache.sunReady.assign(n, 0);
    cache.sunDirection = glm::normalize(sky.sun.direction);
  }
  auto windowLight = [&](size_t i) -> const std::vector<WindowLight>& {
    auto& out = cache.window[i];
    if (cache.windowReady[i]) return out;
    out.clear();
    const glm::dvec3 from = seen_.point[i] + 1e-4 * seen_.normal[i];
    for (size_t m = 0; m < ws.size(); ++m) {
      const glm::dvec3 d = ws[m].point - from;
      const double r2 = glm::dot(d, d);
      const glm::dvec3 dir = d / std::sqrt(r2);
      const double cx = glm::dot(seen_.normal[i], dir), cw = -glm::dot(ws[m].normal, dir);
      if (cx <= 0 || cw <= 0) continue;
      if (h.rayScene().occluded(glm::vec3(from), glm::vec3(ws[m].point), 1e-5f)) continue;
      out.push_back({uint16_t(m), int16_t(basis_->regions().regionOf(dir)), float(cx * cw * ws[m].area / r2)});
    }
    out.shrink_to_fit();
    cache.windowReady[i] = 1;
    return out;
  };
  auto regionRadiance = [&](int k) { return k >= 0 ? sky.region[size_t(k)] : groundL; };

  // The room's shadows on the objects (the window frame's, the table's): whether the room lets
  // each window sample through is found on a lattice over every object face (5 cm apart, 2 to 16
  // points a side: the window's light on a face changes slowly, each sample's shadow edge being
  // one small step of many) and interpolated bilinearly per pixel; the sun's sharp edges are rays
  // per pixel. Lattice points off a face that is not a rectangle are moved onto it. (The room is
  // not in the objects' scene, so one lattice serves both sides.)
  const size_t words = (ws.size() + 63) / 64;
  struct Lattice {
    glm::dvec3 origin, t, u;
    double lt = 1, lu = 1;
    int nt = 2, nu = 2;
    std::vector<uint64_t> bits;  // per point, `words` words
    std::vector<int16_t> regions;  // per point, per window sample: the sky region it lies in (-1: the ground)
  };
  std::vector<Lattice> lattices(objects.size());
  for (size_t o = 0; o < objects.size(); ++o) {
    const auto& v = objects[o].vertices;
    Lattice& l = lattices[o];
    const glm::dvec3 nrm = polygonNormal(v);
    l.t = firstEdge(v);
    l.u = glm::normalize(glm::cross(nrm, l.t));
    double t0 = 1e300, t1 = -1e300, u0 = 1e300, u1 = -1e300;
    for (const auto& q : v) {
      t0 = std::min(t0, glm::dot(q - v[0], l.t)), t1 = std::max(t1, glm::dot(q - v[0], l.t));
      u0 = std::min(u0, glm::dot(q - v[0], l.u)), u1 = std::max(u1, glm::dot(q - v[0], l.u));
    }
    // Just inside the outline: a point on an edge would see along the neighbouring face.
    const double it = 0.01 * (t1 - t0), iu = 0.01 * (u1 - u0);
    l.origin = v[0] + (t0 + it) * l.t + (u0 + iu) * l.u;
    l.lt = std::max(t1 - t0 - 2 * it, 1e-9);
    l.lu = std::max(u1 - u0 - 2 * iu, 1e-9);
    l.nt = std::clamp(int(std::ceil(l.lt / 0.05)) + 1, 2, 16);
    l.nu = std::clamp(int(std::ceil(l.lu / 0.05)) + 1, 2, 16);
    l.bits.assign(size_t(l.nt) * size_t(l.nu) * words, 0);
    l.regions.assign(size_t(l.nt) * size_t(l.nu) * ws.size(), -1);
  }
  {
    std::vector<std::pair<size_t, int>> points;  // (object, lattice point)
    for (size_t o = 0; o < objects.size(); ++o)
      for (int k = 0; k < lattices[o].nt * lattices[o].nu; ++k) points.push_back({o, k});
    tbb::parallel_for(size_t(0), points.size(), [&](size_t pi) {
      const auto [o, k] = points[pi];
      Lattice& l = lattices[o];
      const glm::dvec3 x = ontoFace(objects[o].vertices, l.origin + (double(k % l.nt) / (l.nt - 1)) * l.lt * l.t +
                                                             (double(k / l.nt) / (l.nu - 1)) * l.lu * l.u);
      uint64_t* bits = l.bits.data() + size_t(k) * words;
      for (size_t m = 0; m < ws.size(); ++m) {
        l.regions[size_t(k) * ws.size() + m] = int16_t(basis_->regions().regionOf(ws[m].point - x));
        if (!h.rayScene().occluded(glm::vec3(x), glm::vec3(ws[m].point), 1e-5f)) bits[m / 64] |= uint64_t(1) << (m % 64);
      }
    });
  }

  // The direct daylight on point x of object o (normal nrm, towards the camera): the window
  // samples (past the room: the lattice) and four directions of the sun's disc (past the room:
  // rays), past the objects by their shadow maps (slope-scaled bias: a face does not shadow itself).
  auto direct = [&](size_t o, const glm::dvec3& x, const glm::dvec3& nrm) {
    const Lattice& l = lattices[o];
    const double gs = std::clamp(glm::dot(x - l.origin, l.t) / l.lt, 0.0, 1.0) * (l.nt - 1);
    const double gu = std::clamp(glm::dot(x - l.origin, l.u) / l.lu, 0.0, 1.0) * (l.nu - 1);
    const int a0 = std::min(int(gs), l.nt - 2), b0 = std::min(int(gu), l.nu - 2);
    const double fs = gs - a0, fu = gu - b0;
    const uint64_t* corner[4];
    double wgt[4];
    for (int c = 0; c < 4; ++c) {
      corner[c] = l.bits.data() + size_t((b0 + (c >> 1)) * l.nt + a0 + (c & 1)) * words;
      wgt[c] = ((c & 1) ? fs : 1 - fs) * ((c >> 1) ? fu : 1 - fu);
    }
    auto roomLets = [&](size_t bit) {
      double v = 0;
      for (int c = 0; c < 4; ++c)
        if (corner[c][bit / 64] >> (bit % 64) & 1) v += wgt[c];
      return v;
    };
    // The sky regions the samples are seen in, from the nearest lattice point.
    int nearest = 0;
    for (int c = 1; c < 4; ++c)
      if (wgt[c] > wgt[nearest]) nearest = c;
    const int16_t* region = l.regions.data() + size_t((b0 + (nearest >> 1)) * l.nt + a0 + (nearest & 1)) * ws.size();
    glm::dvec3 e(0.0);
    const glm::dvec3 from = x + 1e-4 * nrm;
    for (size_t m = 0; m < ws.size(); ++m) {
      const glm::dvec3 d = ws[m].point - from;
      const double r2 = glm::dot(d, d);
      const glm::dvec3 dir = d / std::sqrt(r2);
      const double cx = glm::dot(nrm, dir), cw = -glm::dot(ws[m].normal, dir);
      if (cx <= 0 || cw <= 0) continue;
      const double vis = roomLets(m);
      if (vis <= 0) continue;
      const ObjectShadowMap* map = windowMaps[m].get();
      if (map ? map->blocks(x, kBias, cx) : objectScene.occluded(glm::vec3(from), glm::vec3(ws[m].point), 1e-5f)) continue;
      e += regionRadiance(region[m]) * cx * cw * ws[m].area / r2 * vis;
    }
    for (size_t j = 0; sun && j < 4; ++j) {
      const glm::dvec3& sd = sunDisc[4 * j];
      const double c = glm::dot(nrm, sd);
      if (c <= 0) continue;
      if (sunMaps[4 * j]->blocks(x, kBias, c)) continue;
      const double t = throughWindow(h, windows, from, sd);
      if (t <= 0 || h.rayScene().occluded(glm::vec3(from), glm::vec3(from + t * sd), 1e-5f)) continue;
      e += sky.sun.irradiance * c / 4.0;
    }
    return e;
  };
  // The part of a room pixel's direct daylight that the objects take away.
  auto blocked = [&](size_t i, bool windowShadow, bool sunShadow, const uint32_t* reach) {
    glm::dvec3 e(0.0);
    const glm::dvec3& x = seen_.point[i];
    if (windowShadow)
      for (const WindowLight& l : windowLight(i)) {
        if (!(reach[l.sample / 32] >> (l.sample % 32) & 1)) continue;  // its shadow cannot reach here
        const ObjectShadowMap* map = windowMaps[l.sample].get();
        if (map ? map->blocks(x, kBias) : objectScene.occluded(glm::vec3(x + 1e-4 * seen_.normal[i]), glm::vec3(ws[l.sample].point), 1e-5f))
          e += regionRadiance(l.region) * double(l.weight);
      }
    if (sunShadow) {
      auto& rays = cache.sunRays[i];
      if (!cache.sunReady[i]) {
        footprintSunRays(h, windows, seen_.camera, i % size_t(seen_.width), i / size_t(seen_.width), sunDisc, rays);
        rays.shrink_to_fit();
        cache.sunReady[i] = 1;
      }
      double share = 0;
      for (const SunRay& r : rays)
        if (sunMaps[r.disc]->blocks(glm::dvec3(r.from), kBias)) share += r.share;
      e += sky.sun.irradiance * share;
    }
    return e;
  };

  // Pixels: the objects where they are in front of the room; the room where their shadow may fall.
  // In tiles of 8 x 8 pixels, each asked first whether any of its pixels can show the objects (a
  // ray of the tile meets their bounding sphere) or their shadow (the tile's points, a sphere, may
  // lie in the window's or the sun's shadow of that sphere); a tile that can do neither keeps the
  // room's pixels. Per tile also the window samples whose shadow map can reach it: the rest are
  // not looked up for its pixels.
  const glm::dvec3 eye = seen_.camera.center();
  const glm::dvec3 toCentre = centre - eye;
  const double eyeDist = glm::length(toCentre);
  constexpr int kTile = ShadowReach::kTile;
  const int width = seen_.width, height = seen_.height;
  const int tilesX = (width + kTile - 1) / kTile, tilesY = (height + kTile - 1) / kTile;
  const ShadowReach reachOf = shadowReach(ws, sun, sunDir, centre, radius);
  eLast_ = eRoom_;
  std::atomic<size_t> touched{0};
  tbb::parallel_for(tbb::blocked_range<int>(0, tilesX * tilesY, 8), [&](const tbb::blocked_range<int>& r) {
    for (int tile = r.begin(); tile < r.end(); ++tile) {
      const int x0 = (tile % tilesX) * kTile, y0 = (tile / tilesX) * kTile;
      const int x1 = std::min(width, x0 + kTile), y1 = std::min(height, y0 + kTile);
      // Could a ray of the tile meet the objects' sphere? A pinhole's rays over the tile lie within
      // the cone around the middle one through the corners' (widened a little for safety).
      const glm::dvec3 mid = seen_.camera.rayDirection(0.5 * (x0 + x1), 0.5 * (y0 + y1));
      double cosTile = 1;
      for (int c = 0; c < 4; ++c)
        cosTile = std::min(cosTile, glm::dot(mid, seen_.camera.rayDirection(c & 1 ? x1 : x0, c & 2 ? y1 : y0)));
      const double tileAngle = 1.1 * std::acos(std::clamp(cosTile, -1.0, 1.0)) + 1e-4;
      const bool objectHere = eyeDist <= radius || std::acos(std::clamp(glm::dot(mid, toCentre) / eyeDist, -1.0, 1.0)) <=
                                                       tileAngle + std::asin(std::min(1.0, radius / eyeDist));
      const uint32_t* reach = reachOf.bits.data() + size_t(tile) * size_t(reachOf.words);
      const bool shadowHere = reachOf.any(size_t(tile));
      if (!objectHere && !shadowHere) continue;
      size_t count = 0;
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
          const size_t i = size_t(y) * size_t(width) + size_t(x);
          const double roomT = seen_.surface[i] >= 0 ? glm::length(seen_.point[i] - eye) : 1e30;
          if (objectHere) {
            const glm::dvec3 dir = seen_.camera.rayDirection(x + 0.5, y + 0.5);
            // The ray meets the objects' bounding sphere before the room's surface: ask the objects.
            const double b = -glm::dot(toCentre, dir), disc = b * b - (glm::dot(toCentre, toCentre) - radius * radius);
            if (disc >= 0 && -b - std::sqrt(disc) < roomT) {
              const RayHit hit = objectScene.intersect(Ray{glm::vec3(eye), glm::vec3(dir), 0.f, float(roomT)});
              if (hit.polygon >= 0) {
                const size_t o = size_t(hit.polygon);
                const auto& v = objects[o].vertices;
                glm::dvec3 nrm = polygonNormal(v);
                const bool back = glm::dot(nrm, dir) > 0;
                if (back) nrm = -nrm;
                const glm::dvec3 p = eye + double(hit.t) * dir;
                const size_t t = size_t(hit.triangle) - firstTriangle[o];
                const double bu = hit.barycentric.x, bv = hit.barycentric.y;
                const auto& ve = back ? vertexBackE[o] : vertexE[o];
                const glm::dvec3 ind = (1 - bu - bv) * ve[0] + bu * ve[t + 1] + bv * ve[t + 2];
                const glm::dvec3 e = ind + direct(o, p, nrm);
                put(out, i, glm::vec3(objects[o].albedo / kPi * e));
                put(eLast_, i, glm::vec3(e));
                ++count;
                continue;
              }
            }
          }
          if (seen_.surface[i] < 0 || !shadowHere) continue;
          const bool windowShadow = mayBeShadowed(seen_.point[i]), sunShadow = sun && sunMayBeBlocked(i);
          if (!windowShadow && !sunShadow) continue;
          const glm::vec3 e = get(eRoom_, i) - glm::vec3(blocked(i, windowShadow, sunShadow, reach));
          put(eLast_, i, e);
          ratio(i, e);
          ++count;
        }
      touched += count;
    }
  });
  touched_ = touched;
  return out;
}

}  // namespace relume::daylight
