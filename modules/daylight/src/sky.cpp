#include "relume/daylight/sky.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <numbers>

#include "relume/geometry/error.h"
#include "relume/geometry/scene.h"

namespace relume::daylight {

namespace {
constexpr double kPi = std::numbers::pi;

double thetaMax(const FisheyeModel& m) { return m.fovDeg * kPi / 360.0; }

// Angle from the optical axis at normalised radius s = r / R, and back.
double thetaOf(const FisheyeModel& m, double s) {
  const double tm = thetaMax(m);
  if (m.projection == FisheyeProjection::Equidistant) return s * tm;
  return 2.0 * std::asin(std::clamp(s * std::sin(tm / 2.0), -1.0, 1.0));
}
double radiusOf(const FisheyeModel& m, double theta) {
  const double tm = thetaMax(m);
  if (m.projection == FisheyeProjection::Equidistant) return theta / tm;
  return std::sin(theta / 2.0) / std::sin(tm / 2.0);
}

}  // namespace

FisheyeModel fisheyeLookingUp(int width, int height, FisheyeProjection projection, double fovDeg) {
  FisheyeModel m;
  m.projection = projection;
  m.fovDeg = fovDeg;
  m.centre = {width / 2.0, height / 2.0};
  m.radius = std::min(width, height) / 2.0;
  // A camera looking up (+Z) with the image's up along +Y has its image right along -X (seen
  // from below, as a sky chart is drawn).
  m.axes = glm::dmat3(glm::dvec3(-1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1));
  return m;
}

FisheyeModel fisheyeFromDescription(const std::string& text, int width, int height, const std::string& file) {
  std::string t;
  for (char c : text) t += char(std::tolower((unsigned char)c));
  const std::string where = "fisheye model '" + text + "'";
  const bool eqd = t.find("equidistant") != std::string::npos, eqs = t.find("equisolid") != std::string::npos;
  if (eqd == eqs) throw Error(file, where, "must name its projection: equidistant or equisolid");
  const size_t deg = t.find("deg");
  double fov = 0;
  if (deg != std::string::npos) {
    size_t start = deg;  // the number before "deg"
    while (start > 0 && (std::isdigit((unsigned char)t[start - 1]) || t[start - 1] == '.' || t[start - 1] == ' ')) --start;
    if (std::sscanf(t.c_str() + start, "%lf", &fov) != 1) fov = 0;
  }
  if (!(fov > 0 && fov <= 360))
    throw Error(file, where, "must give its field of view, e.g. '180 deg'");
  if (t.find("looking up") == std::string::npos)
    throw Error(file, where, "must say 'looking up': Relume reads fisheyes taken looking up at the sky");
  const size_t up = t.find("image up");
  glm::dvec3 u(0.0);
  if (up != std::string::npos) {
    const size_t eq = t.find('=', up);
    std::string axis;
    for (size_t i = eq == std::string::npos ? t.size() : eq + 1; i < t.size() && axis.size() < 2; ++i)
      if (!std::isspace((unsigned char)t[i])) axis += t[i];
    if (axis == "+x") u = {1, 0, 0};
    else if (axis == "-x") u = {-1, 0, 0};
    else if (axis == "+y") u = {0, 1, 0};
    else if (axis == "-y") u = {0, -1, 0};
  }
  if (glm::length(u) == 0) throw Error(file, where, "must say which room axis is the image's up, e.g. 'image up = +Y'");
  FisheyeModel m = fisheyeLookingUp(width, height, eqd ? FisheyeProjection::Equidistant : FisheyeProjection::Equisolid, fov);
  const glm::dvec3 a(0, 0, 1);
  m.axes = glm::dmat3(glm::cross(a, u), u, a);  // a camera's x = y x z, with y = -up
  return m;
}

FisheyeModel equirectangular(int width, int height, const glm::dmat3& axes) {
  FisheyeModel m;
  m.projection = FisheyeProjection::Equirectangular;
  m.fovDeg = 360;
  m.width = width;
  m.height = height;
  m.centre = {width / 2.0, height / 2.0};
  m.radius = 0;
  m.axes = axes;
  return m;
}

std::optional<glm::dvec3> pixelDirection(const FisheyeModel& m, double px, double py) {
  if (m.projection == FisheyeProjection::Equirectangular) {
    if (m.width <= 0 || m.height <= 0 || py < 0 || py > m.height) return std::nullopt;
    const double az = (0.5 - px / m.width) * 2.0 * kPi, el = (0.5 - py / m.height) * kPi;
    return glm::normalize(m.axes * glm::dvec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)));
  }
  const double dx = px - m.centre.x, dy = py - m.centre.y;
  const double r = std::sqrt(dx * dx + dy * dy);
  if (!(m.radius > 0) || r > m.radius) return std::nullopt;
  const double theta = thetaOf(m, r / m.radius);
  const double c = r > 0 ? dx / r : 1.0, s = r > 0 ? -dy / r : 0.0;  // image up is -y
  const glm::dvec3 local(std::sin(theta) * c, std::sin(theta) * s, std::cos(theta));
  return glm::normalize(m.axes * local);
}

std::optional<glm::dvec2> directionPixel(const FisheyeModel& m, const glm::dvec3& direction) {
  const glm::dvec3 local = glm::transpose(m.axes) * glm::normalize(direction);
  if (m.projection == FisheyeProjection::Equirectangular) {
    if (m.width <= 0 || m.height <= 0) return std::nullopt;
    double u = 0.5 - std::atan2(local.y, local.x) / (2.0 * kPi);
    if (u >= 1.0) u -= 1.0;
    const double v = 0.5 - std::asin(std::clamp(local.z, -1.0, 1.0)) / kPi;
    return glm::dvec2(u * m.width, v * m.height);
  }
  const double theta = std::acos(std::clamp(local.z, -1.0, 1.0));
  if (theta > thetaMax(m) + 1e-12) return std::nullopt;
  const double r = radiusOf(m, theta) * m.radius;
  const double h = std::hypot(local.x, local.y);
  const double c = h > 0 ? local.x / h : 1.0, s = h > 0 ? local.y / h : 0.0;
  return glm::dvec2(m.centre.x + r * c, m.centre.y - r * s);
}

double pixelSolidAngle(const FisheyeModel& m, int x, int y) {
  if (m.projection == FisheyeProjection::Equirectangular) {  // exact: a cell of azimuth x sin(elevation)
    if (m.width <= 0 || m.height <= 0 || x < 0 || y < 0 || x >= m.width || y >= m.height) return 0;
    const double top = (0.5 - double(y) / m.height) * kPi, bottom = (0.5 - double(y + 1) / m.height) * kPi;
    return 2.0 * kPi / m.width * (std::sin(top) - std::sin(bottom));
  }
  // Numerically, over 4 x 4 sub-pixels: the solid angle of an image area dA at normalised
  // radius s is sin(theta) dtheta dphi with dphi = dA_tangential / r.
  constexpr int kSub = 4;
  double sum = 0;
  for (int j = 0; j < kSub; ++j)
    for (int i = 0; i < kSub; ++i) {
      const double px = x + (i + 0.5) / kSub, py = y + (j + 0.5) / kSub;
      const double dx = px - m.centre.x, dy = py - m.centre.y;
      const double r = std::sqrt(dx * dx + dy * dy);
      if (r > m.radius || r <= 0) continue;
      const double s = r / m.radius, ds = 1e-6;
      const double theta = thetaOf(m, s);
      const double dthetaDr = (thetaOf(m, std::min(1.0, s + ds)) - thetaOf(m, std::max(0.0, s - ds))) /
                              ((std::min(1.0, s + ds) - std::max(0.0, s - ds)) * m.radius);
      sum += std::sin(theta) * dthetaDr / r / (kSub * kSub);
    }
  return sum;
}

void checkSkyImage(const SkyImage& sky) {
  const ImageRGB& im = sky.image;
  const FisheyeModel& m = sky.model;
  if (im.width <= 0 || im.height <= 0) throw Error(sky.file, "", "the sky image has no pixels");
  if (m.projection == FisheyeProjection::Equirectangular) {
    if (m.width != im.width || m.height != im.height)
      throw Error(sky.file, "panorama",
                  "the model is for " + std::to_string(m.width) + "x" + std::to_string(m.height) + ", the image is " +
                      std::to_string(im.width) + "x" + std::to_string(im.height));
  } else if (!(m.fovDeg > 0 && m.fovDeg <= 360)) {
    throw Error(sky.file, "fisheye", "its field of view must lie in (0, 360] degrees");
  } else if (!(m.radius > 0) || m.centre.x - m.radius < -0.5 || m.centre.y - m.radius < -0.5 ||
      m.centre.x + m.radius > im.width + 0.5 || m.centre.y + m.radius > im.height + 0.5)
    throw Error(sky.file, "fisheye",
                "the image circle (centre " + std::to_string(m.centre.x) + ", " + std::to_string(m.centre.y) + ", radius " +
                    std::to_string(m.radius) + " px) does not lie inside the " + std::to_string(im.width) + "x" +
                    std::to_string(im.height) + " image");
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x) {
      const glm::vec3 c = im.at(x, y);
      for (int k = 0; k < 3; ++k)
        if (!std::isfinite(c[k]) || c[k] < 0)
          throw Error(sky.file, "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ")",
                      "the radiance is " + std::string(std::isfinite(c[k]) ? "negative" : "NaN or infinite") +
                          ": a sky image must hold finite, non-negative radiance");
    }
  // It must see the sky: some of the circle above the horizon.
  bool above = false;
  for (int y = 0; y < im.height && !above; y += 2)
    for (int x = 0; x < im.width && !above; x += 2)
      if (const auto d = pixelDirection(m, x + 0.5, y + 0.5)) above = d->z > 0.05;
  if (!above) throw Error(sky.file, "fisheye", "the image sees only what lies below the horizon: it cannot give the sky");
}

SkyImage readFisheyeLookingUp(const std::string& path) {
  int w = 0, h = 0;
  imageSize(path, w, h);
  return readSkyImage(path, fisheyeLookingUp(w, h));
}

SkyImage readRoomSky(const Scene& room, const std::string& name) {
  if (room.skies.empty()) throw Error(room.sourceFile, "daylight", "the room lists no measured sky");
  const std::string want = !name.empty() ? name : room.photoSky.empty() ? room.skies.front().name : room.photoSky;
  const SkyCapture* cap = room.findSky(want);
  if (!cap) throw Error(room.sourceFile, "--sky", "the room has no sky named '" + want + "'");
  const std::string file = cap->fisheye.front() == '/' ? cap->fisheye : room.baseDir + "/" + cap->fisheye;
  int w = 0, h = 0;
  imageSize(file, w, h);
  return readSkyImage(file, fisheyeFromDescription(cap->fisheyeModel, w, h, file));
}

SkyImage readSkyImage(const std::string& path, const FisheyeModel& model) {
  SkyImage sky{readImageLinear(path), model, path};
  checkSkyImage(sky);
  return sky;
}

SkyRegions::SkyRegions(int n) {
  if (n < 1 || n > 100000) throw Error("", "sky regions", "the number of regions must be from 1 to 100000");
  // Bands of equal elevation width; square-ish cells give about n = 8 B^2 / pi.
  const int bands = std::max(1, int(std::lround(std::sqrt(kPi * n / 8.0))));
  bandWidth_ = (kPi / 2) / bands;
  std::vector<double> omega(static_cast<size_t>(bands));
  std::vector<int> count(static_cast<size_t>(bands));
  for (int b = 0; b < bands; ++b) omega[size_t(b)] = 2 * kPi * (std::sin((b + 1) * bandWidth_) - std::sin(b * bandWidth_));
  int total = 0;
  for (int b = 0; b < bands; ++b) total += count[size_t(b)] = std::max(1, int(std::lround(n * omega[size_t(b)] / (2 * kPi))));
  // Make the counts sum to n: take from or give to the band whose cells are furthest from 2 pi / n.
  while (total != n) {
    int best = -1;
    double worst = 0;
    for (int b = 0; b < bands; ++b) {
      const int c = count[size_t(b)] + (total < n ? 1 : -1);
      if (c < 1) continue;
      const double err = std::abs(omega[size_t(b)] / c - 2 * kPi / n) - std::abs(omega[size_t(b)] / count[size_t(b)] - 2 * kPi / n);
      if (best < 0 || err < worst) best = b, worst = err;
    }
    if (best < 0) break;
    count[size_t(best)] += total < n ? 1 : -1;
    total += total < n ? 1 : -1;
  }
  for (int b = 0; b < bands; ++b) {
    bandStart_.push_back(int(cells_.size()));
    const int c = count[size_t(b)];
    for (int k = 0; k < c; ++k)
      cells_.push_back({b * bandWidth_, (b + 1) * bandWidth_, 2 * kPi * k / c, 2 * kPi * (k + 1) / c});
  }
  bandStart_.push_back(int(cells_.size()));
}

int SkyRegions::regionOf(const glm::dvec3& d) const {
  const glm::dvec3 u = glm::normalize(d);
  if (u.z < 0) return -1;
  const double elev = std::asin(std::clamp(u.z, 0.0, 1.0));
  const int bands = int(bandStart_.size()) - 1;
  const int b = std::clamp(int(elev / bandWidth_), 0, bands - 1);
  double az = std::atan2(u.y, u.x);
  if (az < 0) az += 2 * kPi;
  const int c = bandStart_[size_t(b) + 1] - bandStart_[size_t(b)];
  return bandStart_[size_t(b)] + std::clamp(int(az / (2 * kPi) * c), 0, c - 1);
}

double SkyRegions::solidAngle(int k) const {
  const Cell& c = cells_.at(size_t(k));
  return (c.azim1 - c.azim0) * (std::sin(c.elev1) - std::sin(c.elev0));
}

glm::dvec3 SkyRegions::centre(int k) const {
  const Cell& c = cells_.at(size_t(k));
  const double e = 0.5 * (c.elev0 + c.elev1), a = 0.5 * (c.azim0 + c.azim1);
  return {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
}

SkyRadiance averageSky(const SkyImage& sky, const SkyRegions& regions, const SkyOptions& options) {
  const ImageRGB& im = sky.image;
  struct Px {
    int x, y;
    glm::dvec3 dir, L;
    double omega;
  };
  std::vector<Px> px;
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x) {
      const auto d = pixelDirection(sky.model, x + 0.5, y + 0.5);
      if (!d || d->z < 0) continue;
      const double w = pixelSolidAngle(sky.model, x, y);
      if (w > 0) px.push_back({x, y, *d, glm::dvec3(im.at(x, y)), w});
    }
  SkyRadiance out;
  out.region.assign(size_t(regions.size()), glm::dvec3(0.0));
  if (px.empty()) return out;
  // The sun: pixels far brighter than the sky's median, near the brightest one.
  std::vector<double> lum(px.size());
  for (size_t i = 0; i < px.size(); ++i) lum[i] = luminance(px[i].L);
  std::vector<double> sorted = lum;
  std::nth_element(sorted.begin(), sorted.begin() + long(sorted.size() / 2), sorted.end());
  const double median = sorted[sorted.size() / 2];
  const size_t brightest = size_t(std::max_element(lum.begin(), lum.end()) - lum.begin());
  std::vector<char> isSun(px.size(), 0);
  if (lum[brightest] > options.sunThreshold * std::max(median, 1e-30)) {
    // Every pixel within the sun's circle belongs to it (a lens and a pixel filter spread a disc
    // smaller than a pixel over its neighbours, below any threshold), less the sky behind it: the
    // median of the ring from one to two circle radii, which also fills the circle in the
    // region means.
    const double cosR = std::cos(options.sunRadiusDeg * kPi / 180), cos2R = std::cos(2 * options.sunRadiusDeg * kPi / 180);
    std::vector<glm::dvec3> ring;
    for (size_t i = 0; i < px.size(); ++i) {
      const double c = glm::dot(px[i].dir, px[brightest].dir);
      if (c < cosR && c >= cos2R) ring.push_back(px[i].L);
    }
    glm::dvec3 background(0.0);
    if (!ring.empty()) {
      std::vector<double> ch(ring.size());
      for (int c = 0; c < 3; ++c) {
        for (size_t i = 0; i < ring.size(); ++i) ch[i] = ring[i][c];
        std::nth_element(ch.begin(), ch.begin() + long(ch.size() / 2), ch.end());
        background[c] = ch[ch.size() / 2];
      }
    }
    out.sunBackground = background;
    for (size_t i = 0; i < px.size(); ++i)
      if (glm::dot(px[i].dir, px[brightest].dir) >= cosR) isSun[i] = 1;
    out.sun.found = true;
    // Clipped: the sun's brightest pixel at exactly half float's largest value (an EXR saved as
    // half float), or a plateau — two or more of its pixels at exactly the same peak in some
    // channel, as a camera's saturated pixels are. Per channel, the value it clipped at.
    glm::dvec3 clipAt(std::numeric_limits<double>::infinity());
    for (int c = 0; c < 3; ++c) {
      double peak = 0;
      int atPeak = 0;
      for (size_t i = 0; i < px.size(); ++i) {
        if (!isSun[i]) continue;
        if (px[i].L[c] > peak) peak = px[i].L[c], atPeak = 0;
        if (px[i].L[c] == peak) ++atPeak;
      }
      if (peak == 65504.0 || (atPeak >= 2 && peak > options.sunThreshold * std::max(median, 1e-30))) {
        clipAt[c] = peak;
        out.sun.clipped = true;
      }
    }
    // A clipped channel of a pixel holds only a lower bound of its radiance, and a pixel clipped
    // in some channels but not all is whiter than the sun. The sun's pixels that clipped nowhere
    // (its disc's edge, spread over the neighbours by the lens and the pixel filter) show its
    // colour; each clipped pixel takes that colour, scaled to what its unclipped channels measure
    // (or, when every channel clipped, to the least scale its clipped values allow: the light stays
    // understated there, never overstated).
    std::vector<glm::dvec3> excess(px.size(), glm::dvec3(0.0));
    glm::dvec3 colour(0.0);
    for (size_t i = 0; i < px.size(); ++i) {
      if (!isSun[i]) continue;
      excess[i] = glm::max(px[i].L - background, glm::dvec3(0.0));
      if (px[i].L.x < clipAt.x && px[i].L.y < clipAt.y && px[i].L.z < clipAt.z) colour += excess[i];
    }
    const double top = std::max({colour.x, colour.y, colour.z});
    if (out.sun.clipped && top > 0) {
      colour /= top;  // its largest channel 1
      out.sun.colourFromUnclipped = true;
      for (size_t i = 0; i < px.size(); ++i) {
        if (!isSun[i]) continue;
        double known = 0, knownWeight = 0, bound = 0;
        bool any = false;
        for (int c = 0; c < 3; ++c) {
          if (!(colour[c] > 0)) continue;
          if (px[i].L[c] >= clipAt[c]) {
            any = true;
            bound = std::max(bound, excess[i][c] / colour[c]);
          } else {
            known += excess[i][c];
            knownWeight += colour[c];
          }
        }
        if (!any) continue;
        const double scale = knownWeight > 0 ? std::max(known / knownWeight, 0.0) : bound;
        for (int c = 0; c < 3; ++c)
          if (px[i].L[c] >= clipAt[c]) excess[i][c] = std::max(excess[i][c], scale * colour[c]);
      }
    }
    glm::dvec3 weighted(0.0);
    for (size_t i = 0; i < px.size(); ++i)
      if (isSun[i]) {
        out.sun.irradiance += excess[i] * px[i].omega;
        out.sun.solidAngle += px[i].omega;
        weighted += px[i].dir * (luminance(excess[i]) * px[i].omega);
        ++out.sun.pixels;
      }
    // No excess anywhere (a clipped sky): the brightest pixel's direction.
    out.sun.direction = glm::length(weighted) > 0 ? glm::normalize(weighted) : px[brightest].dir;
  }
  // Region means of the rest.
  std::vector<double> weight(size_t(regions.size()), 0.0);
  for (size_t i = 0; i < px.size(); ++i) {
    const int k = regions.regionOf(px[i].dir);
    if (k < 0) continue;
    out.region[size_t(k)] += (isSun[i] ? out.sunBackground : px[i].L) * px[i].omega;  // the sky behind the sun
    weight[size_t(k)] += px[i].omega;
  }
  for (int k = 0; k < regions.size(); ++k) {
    if (weight[size_t(k)] > 0) {
      out.region[size_t(k)] /= weight[size_t(k)];
      continue;
    }
    // No pixel centre in it (a tiny image): what the image shows at its centre.
    if (const auto p = directionPixel(sky.model, regions.centre(k))) {
      const int x = std::clamp(int(p->x), 0, im.width - 1), y = std::clamp(int(p->y), 0, im.height - 1);
      out.region[size_t(k)] = glm::dvec3(im.at(x, y));
    }
  }
  return out;
}

glm::dvec3 planeIrradiance(const SkyRegions& regions, const SkyRadiance& sky, const glm::dvec3& normal) {
  const glm::dvec3 n = glm::normalize(normal);
  glm::dvec3 e(0.0);
  constexpr int kSub = 16;  // per region: 16 x 16 sub-cells
  for (int k = 0; k < regions.size(); ++k) {
    const auto& c = regions.cell(k);
    double projected = 0;
    for (int j = 0; j < kSub; ++j)
      for (int i = 0; i < kSub; ++i) {
        const double e0 = c.elev0 + (c.elev1 - c.elev0) * j / kSub, e1 = c.elev0 + (c.elev1 - c.elev0) * (j + 1) / kSub;
        const double a = c.azim0 + (c.azim1 - c.azim0) * (i + 0.5) / kSub, em = 0.5 * (e0 + e1);
        const glm::dvec3 d(std::cos(em) * std::cos(a), std::cos(em) * std::sin(a), std::sin(em));
        const double omega = (c.azim1 - c.azim0) / kSub * (std::sin(e1) - std::sin(e0));
        projected += std::max(0.0, glm::dot(d, n)) * omega;
      }
    e += sky.region[size_t(k)] * projected;
  }
  if (sky.sun.found) e += sky.sun.irradiance * std::max(0.0, glm::dot(sky.sun.direction, n));
  return e;
}

}  // namespace relume::daylight
