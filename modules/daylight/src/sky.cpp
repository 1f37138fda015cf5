#include "relume/daylight/sky.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "relume/geometry/error.h"
#include "relume/geometry/scene.h"

namespace relume::daylight {

namespace {
constexpr double kPi = std::numbers::pi;

double thetaMax(const FisheyeModel& m) { return m.fovDeg * kPi / 360.0; }

// An angle in degrees for a message: "180", "187.5".
std::string degrees(double d) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", d);
  return buf;
}

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

// A calibrated fisheye's view at image point (px, py): the angle from the axis and the unit
// direction in the image plane (x right, y up), or nothing outside its circle or field of view.
struct LensPoint {
  double theta, c, s;
};
std::optional<LensPoint> calibratedPoint(const FisheyeModel& m, double px, double py) {
  if (m.radius > 0 && std::hypot(px - m.circleCentre.x, py - m.circleCentre.y) > m.radius) return std::nullopt;
  const double x = (px - m.centre.x) / m.focal.x, y = (py - m.centre.y) / m.focal.y;
  const double td = std::hypot(x, y);
  const double theta = fisheyeTheta(m, td);
  if (!(theta <= thetaMax(m))) return std::nullopt;
  return LensPoint{theta, td > 0 ? x / td : 1.0, td > 0 ? -y / td : 0.0};
}

// d theta_d / d theta of a calibrated fisheye at angle t.
double thetaDSlope(const FisheyeModel& m, double t) {
  const double t2 = t * t;
  return 1 + t2 * (3 * m.k[0] + t2 * (5 * m.k[1] + t2 * (7 * m.k[2] + t2 * 9 * m.k[3])));
}

}  // namespace

double fisheyeThetaD(const FisheyeModel& m, double theta) {
  const double t2 = theta * theta;
  return theta * (1 + t2 * (m.k[0] + t2 * (m.k[1] + t2 * (m.k[2] + t2 * m.k[3]))));
}

double fisheyeTheta(const FisheyeModel& m, double thetaD) {
  // theta_d(theta) rises monotonically up to the field of view's edge (fisheyeCalibrated checks):
  // Newton's method from theta = theta_d, kept within [0, the edge], with bisection should a step
  // leave the bracket. Beyond the edge's theta_d: infinity (outside the view).
  const double hi = thetaMax(m);
  if (!(thetaD > 0)) return 0;
  if (fisheyeThetaD(m, hi) < thetaD) return std::numeric_limits<double>::infinity();
  double lo = 0, up = hi, t = std::min(thetaD, hi);
  for (int i = 0; i < 60; ++i) {
    const double f = fisheyeThetaD(m, t) - thetaD;
    if (std::abs(f) < 1e-14) break;
    (f > 0 ? up : lo) = t;
    const double d = thetaDSlope(m, t);
    double next = d > 0 ? t - f / d : 0.5 * (lo + up);
    if (!(next > lo && next < up)) next = 0.5 * (lo + up);
    t = next;
  }
  return t;
}

FisheyeModel fisheyeCalibrated(const FisheyeLens& lens, double fovDeg, const std::string& file) {
  if (!(lens.fx > 0 && lens.fy > 0 && std::isfinite(lens.fx) && std::isfinite(lens.fy)))
    throw Error(file, "fisheye lens", "its focal lengths must be positive numbers of pixels");
  if (!(fovDeg > 0 && fovDeg <= 360)) throw Error(file, "fisheye lens", "its field of view must lie in (0, 360] degrees");
  for (double v : {lens.cx, lens.cy, lens.k[0], lens.k[1], lens.k[2], lens.k[3], lens.circleX, lens.circleY, lens.circleRadius})
    if (!std::isfinite(v)) throw Error(file, "fisheye lens", "its principal point, distortion and circle must be numbers");
  FisheyeModel m;
  m.projection = FisheyeProjection::OpenCvFisheye;
  m.fovDeg = fovDeg;
  m.centre = {lens.cx, lens.cy};
  m.focal = {lens.fx, lens.fy};
  for (int i = 0; i < 4; ++i) m.k[i] = lens.k[i];
  m.circleCentre = {lens.circleX, lens.circleY};
  m.radius = std::max(0.0, lens.circleRadius);
  m.axes = glm::dmat3(glm::dvec3(-1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1));
  // The mapping must rise with the angle over the whole view (steps of 0.1 degree), or one pixel
  // would see two directions.
  double last = 0;
  for (int i = 1; i <= 1000; ++i) {
    const double td = fisheyeThetaD(m, thetaMax(m) * i / 1000);
    if (!(td > last))
      throw Error(file, "fisheye lens",
                  "its distortion (k1..k4) folds the image back on itself before the edge of its " + degrees(fovDeg) +
                      "-degree view: not a lens there (calibrate it again with the board nearer the image's edge, or "
                      "give a smaller field of view)");
    last = td;
  }
  return m;
}

namespace {
// The circle through `pts` by least squares: Kasa's algebraic fit (about the points' mean), then
// Gauss-Newton on the points' distances from it.
ImageCircle fitCircle(const std::vector<glm::dvec2>& pts) {
  glm::dvec2 mean(0.0);
  for (const auto& p : pts) mean += p;
  mean /= double(pts.size());
  glm::dmat3 a(0.0);
  glm::dvec3 b(0.0);
  for (const auto& q : pts) {
    const glm::dvec2 p = q - mean;
    const glm::dvec3 row(p.x, p.y, 1.0);
    a += glm::outerProduct(row, row);
    b -= row * glm::dot(p, p);
  }
  const glm::dvec3 def = glm::inverse(a) * b;
  ImageCircle c;
  c.centre = mean + glm::dvec2(-def.x / 2, -def.y / 2);
  c.radius = std::sqrt(std::max(0.0, def.x * def.x / 4 + def.y * def.y / 4 - def.z));
  for (int it = 0; it < 20; ++it) {
    glm::dmat3 n(0.0);
    glm::dvec3 g(0.0);
    for (const auto& p : pts) {
      const glm::dvec2 d = p - c.centre;
      const double len = std::max(1e-9, glm::length(d));
      const glm::dvec3 j(-d.x / len, -d.y / len, -1.0);
      const double r = len - c.radius;
      n += glm::outerProduct(j, j);
      g += j * r;
    }
    const glm::dvec3 step = glm::inverse(n) * g;
    c.centre -= glm::dvec2(step.x, step.y);
    c.radius -= step.z;
    if (glm::length(step) < 1e-9) break;
  }
  double ss = 0;
  for (const auto& p : pts) ss += std::pow(glm::length(p - c.centre) - c.radius, 2);
  c.rms = std::sqrt(ss / double(pts.size()));
  c.points = int(pts.size());
  return c;
}
}  // namespace

ImageCircle findImageCircle(const ImageRGB& im, const std::string& file) {
  const int w = im.width, h = im.height;
  if (w < 16 || h < 16) throw Error(file, "image circle", "the image is too small to find its circle in");
  std::vector<double> lum(size_t(w) * size_t(h));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double l = luminance(glm::dvec3(im.at(x, y)));
      lum[size_t(y) * size_t(w) + size_t(x)] = std::isfinite(l) ? std::max(0.0, l) : 0.0;
    }
  auto medianOf = [&](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  // The disc's level (a box a quarter of the shorter side across at the centre) and the border's
  // (boxes an eighth of it in the four corners, which a circle inside the image leaves dark).
  const int side = std::min(w, h), q = std::max(2, side / 8);
  std::vector<double> centre, corners;
  for (int y = h / 2 - q; y < h / 2 + q; ++y)
    for (int x = w / 2 - q; x < w / 2 + q; ++x) centre.push_back(lum[size_t(y) * size_t(w) + size_t(x)]);
  for (int y = 0; y < q; ++y)
    for (int x = 0; x < q; ++x)
      for (const auto& [cx, cy] : {std::pair{x, y}, {w - 1 - x, y}, {x, h - 1 - y}, {w - 1 - x, h - 1 - y}})
        corners.push_back(lum[size_t(cy) * size_t(w) + size_t(cx)]);
  const double disc = medianOf(centre), border = medianOf(corners);
  if (!(disc > 0) || border > 0.05 * disc)
    throw Error(file, "image circle",
                "no dark border around a lit disc (the corners are " + std::to_string(int(std::lround(100 * border / std::max(disc, 1e-30)))) +
                    " % as bright as the centre): the circle fills or overflows the image; give it as --circle CX,CY,R");
  const double level = border + 0.1 * (disc - border);
  auto at = [&](double x, double y) {  // bilinear, pixel centres at +0.5
    const double fx = std::clamp(x - 0.5, 0.0, w - 1.0), fy = std::clamp(y - 0.5, 0.0, h - 1.0);
    const int x0 = std::min(int(fx), w - 2), y0 = std::min(int(fy), h - 2);
    const double u = fx - x0, v = fy - y0;
    auto L = [&](int xx, int yy) { return lum[size_t(yy) * size_t(w) + size_t(xx)]; };
    return (1 - v) * ((1 - u) * L(x0, y0) + u * L(x0 + 1, y0)) + v * ((1 - u) * L(x0, y0 + 1) + u * L(x0 + 1, y0 + 1));
  };
  // Along each ray from the image's centre, walking in from the image's edge: where the luminance
  // first rises through the level and stays above it for two more pixels (a stray bright pixel of
  // the border is no edge). A ray that starts lit at the image's edge has no edge point: the circle
  // runs beyond the image there.
  const glm::dvec2 o(w / 2.0, h / 2.0);
  std::vector<glm::dvec2> pts;
  constexpr double kStep = 0.25;
  for (int a = 0; a < 720; ++a) {
    const double ang = a * kPi / 360, dx = std::cos(ang), dy = std::sin(ang);
    const double tx = dx > 0 ? (w - 0.5 - o.x) / dx : dx < 0 ? (0.5 - o.x) / dx : 1e30;
    const double ty = dy > 0 ? (h - 0.5 - o.y) / dy : dy < 0 ? (0.5 - o.y) / dy : 1e30;
    const double tmax = std::min(tx, ty);
    auto lit = [&](double t) { return at(o.x + t * dx, o.y + t * dy) > level; };
    if (lit(tmax)) continue;
    for (double t = tmax - kStep; t > 4; t -= kStep) {
      if (!lit(t) || !lit(t - 1) || !lit(t - 2)) continue;
      // The edge itself: where the luminance is half way between the border's just outside and the
      // disc's just inside (a pixel half covered by the disc), whatever the sky's brightness there.
      auto L = [&](double u) { return at(o.x + u * dx, o.y + u * dy); };
      // (The disc's side taken 3 px in and carried to the edge along its slope there.)
      const double out = L(std::min(tmax, t + 2)), in = 2 * L(t - 3) - L(t - 5), half = 0.5 * (out + in);
      double tc = -1;
      for (double u = std::min(tmax, t + 2); u > t - 3; u -= 1.0 / 16) {
        const double a0 = L(u), a1 = L(u - 1.0 / 16);
        if (a1 >= half && a0 < half) {
          tc = u - (half - a0) / (a1 - a0) / 16;
          break;
        }
      }
      if (tc > 0) pts.emplace_back(o.x + tc * dx, o.y + tc * dy);
      break;
    }
  }
  auto tooLittle = [&](size_t n) {
    return Error(file, "image circle",
                 "the edge of the lit disc was found over too little of it (" + std::to_string(n) +
                     " points): give the circle as --circle CX,CY,R");
  };
  if (pts.size() < 24) throw tooLittle(pts.size());
  // A start that points off the circle along a whole arc (a tree line, a roof) cannot pull: of 300
  // circles through three edge points (spread over the list), the one most points lie within a
  // pixel of; then least squares over those, and points more than three robust deviations off it
  // dropped until none is.
  ImageCircle c;
  {
    size_t best = 0;
    uint32_t seed = 12345;
    auto next = [&] { return size_t((seed = seed * 1664525u + 1013904223u) >> 8) % pts.size(); };
    for (int trial = 0; trial < 300; ++trial) {
      const ImageCircle t = fitCircle({pts[next()], pts[next()], pts[next()]});
      if (!(t.radius > 2) || !std::isfinite(t.radius)) continue;
      size_t inliers = 0;
      for (const auto& p : pts) inliers += std::abs(glm::length(p - t.centre) - t.radius) < 1.0 ? 1 : 0;
      if (inliers > best) best = inliers, c = t;
    }
    std::vector<glm::dvec2> near;
    for (const auto& p : pts)
      if (std::abs(glm::length(p - c.centre) - c.radius) < 1.0) near.push_back(p);
    if (near.size() < 24) throw tooLittle(near.size());
    pts = std::move(near);
    c = fitCircle(pts);
  }
  for (int round = 0; round < 3; ++round) {  // (three rounds at most; the first usually settles it)
    std::vector<double> dev;
    for (const auto& p : pts) dev.push_back(std::abs(glm::length(p - c.centre) - c.radius));
    const double keep = std::max(0.25, 3 * 1.4826 * medianOf(dev));
    std::vector<glm::dvec2> kept;
    for (size_t i = 0; i < pts.size(); ++i)
      if (dev[i] <= keep) kept.push_back(pts[i]);
    if (kept.size() == pts.size()) break;
    if (kept.size() < 24) throw tooLittle(kept.size());
    pts = std::move(kept);
    c = fitCircle(pts);
  }
  bool quadrant[4] = {false, false, false, false};
  for (const auto& p : pts) quadrant[(p.x >= c.centre.x ? 0 : 1) + (p.y >= c.centre.y ? 0 : 2)] = true;
  if (int(quadrant[0]) + int(quadrant[1]) + int(quadrant[2]) + int(quadrant[3]) < 3) throw tooLittle(pts.size());
  if (!(c.radius > 2) || c.rms > 1.5)
    throw Error(file, "image circle",
                "the edge of the lit disc is no circle (its points lie " + std::to_string(c.rms) +
                    " px off the best one): give it as --circle CX,CY,R");
  return c;
}

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

FisheyeModel fisheyeFromDescription(const std::string& text, int width, int height, const std::string& file,
                                    const FisheyeLens& lens) {
  std::string t;
  for (char c : text) t += char(std::tolower((unsigned char)c));
  const std::string where = "fisheye model '" + text + "'";
  const bool calibrated = lens.fx > 0;
  const bool eqd = t.find("equidistant") != std::string::npos, eqs = t.find("equisolid") != std::string::npos;
  if (calibrated && (lens.width != width || lens.height != height))
    throw Error(file, "fisheye lens",
                "the calibrated lens it is read through was calibrated on " +
                    std::to_string(lens.width) + "x" + std::to_string(lens.height) + " images, the fisheye is " +
                    std::to_string(width) + "x" + std::to_string(height));
  if (!calibrated && eqd == eqs) throw Error(file, where, "must name its projection: equidistant or equisolid");
  const size_t deg = t.find("deg");
  double fov = 0;
  if (deg != std::string::npos) {
    size_t start = deg;  // the number before "deg"
    while (start > 0 && (std::isdigit((unsigned char)t[start - 1]) || t[start - 1] == '.' || t[start - 1] == ' ')) --start;
    if (std::sscanf(t.c_str() + start, "%lf", &fov) != 1) fov = 0;
  }
  if (calibrated && deg == std::string::npos) fov = 180;
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
  FisheyeModel m = calibrated ? fisheyeCalibrated(lens, fov, file)
                              : fisheyeLookingUp(width, height, eqd ? FisheyeProjection::Equidistant : FisheyeProjection::Equisolid, fov);
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
  if (m.projection == FisheyeProjection::OpenCvFisheye) {
    const auto p = calibratedPoint(m, px, py);
    if (!p) return std::nullopt;
    return glm::normalize(m.axes * glm::dvec3(std::sin(p->theta) * p->c, std::sin(p->theta) * p->s, std::cos(p->theta)));
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
  const double h = std::hypot(local.x, local.y);
  const double c = h > 0 ? local.x / h : 1.0, s = h > 0 ? local.y / h : 0.0;
  if (m.projection == FisheyeProjection::OpenCvFisheye) {
    const double td = fisheyeThetaD(m, theta);
    const glm::dvec2 p(m.centre.x + m.focal.x * td * c, m.centre.y - m.focal.y * td * s);
    if (m.radius > 0 && glm::length(p - m.circleCentre) > m.radius + 1e-9) return std::nullopt;
    return p;
  }
  const double r = radiusOf(m, theta) * m.radius;
  return glm::dvec2(m.centre.x + r * c, m.centre.y - r * s);
}

double pixelSolidAngle(const FisheyeModel& m, int x, int y) {
  if (m.projection == FisheyeProjection::Equirectangular) {  // exact: a cell of azimuth x sin(elevation)
    if (m.width <= 0 || m.height <= 0 || x < 0 || y < 0 || x >= m.width || y >= m.height) return 0;
    const double top = (0.5 - double(y) / m.height) * kPi, bottom = (0.5 - double(y + 1) / m.height) * kPi;
    return 2.0 * kPi / m.width * (std::sin(top) - std::sin(bottom));
  }
  constexpr int kSub = 4;
  if (m.projection == FisheyeProjection::OpenCvFisheye) {
    // Over 4 x 4 sub-pixels: in the focal-length units (a, b) = ((x - cx) / fx, (y - cy) / fy),
    // with theta_d = |(a, b)| and phi its angle, da db = theta_d dtheta_d dphi and dtheta_d =
    // theta_d'(theta) dtheta, so dOmega = sin(theta) dtheta dphi = sin(theta) / (theta_d
    // theta_d'(theta)) da db, and da db = dx dy / (fx fy).
    double sum = 0;
    for (int j = 0; j < kSub; ++j)
      for (int i = 0; i < kSub; ++i) {
        const double px = x + (i + 0.5) / kSub, py = y + (j + 0.5) / kSub;
        const auto p = calibratedPoint(m, px, py);
        if (!p) continue;
        const double td = std::hypot((px - m.centre.x) / m.focal.x, (py - m.centre.y) / m.focal.y), t = p->theta;
        const double slope = thetaDSlope(m, t);
        if (!(slope > 0)) continue;  // (the fold check samples every 0.1 degree: never here in practice)
        const double perArea = td > 1e-12 ? std::sin(t) / (td * slope) : 1.0;
        sum += perArea / (m.focal.x * m.focal.y) / (kSub * kSub);
      }
    return sum;
  }
  // Numerically, over 4 x 4 sub-pixels: the solid angle of an image area dA at normalised
  // radius s is sin(theta) dtheta dphi with dphi = dA_tangential / r.
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
  } else if (m.projection == FisheyeProjection::OpenCvFisheye) {
    // The sky the lens is to see (out to the horizon, or to the edge of a smaller field of view)
    // must fall inside the image and inside its image circle, all round: else part of the sky would
    // be missing and its regions left dark. Within half a pixel, as for the ideal lenses: a
    // calibration's principal point and a fitted circle are that uncertain.
    const double need = std::min(thetaMax(m), kPi / 2) - 1e-6;
    FisheyeModel open = m;
    open.radius = 0;  // the pixel of each direction, the circle tested here with its slack
    for (int a = 0; a < 720; ++a) {
      const double az = a * kPi / 360;
      const glm::dvec3 local(std::sin(need) * std::cos(az), std::sin(need) * std::sin(az), std::cos(need));
      auto p = directionPixel(open, m.axes * local);
      if (p && m.radius > 0 && glm::length(*p - m.circleCentre) > m.radius + 0.5) p.reset();
      if (!p || p->x < -0.5 || p->y < -0.5 || p->x > im.width + 0.5 || p->y > im.height + 0.5)
        throw Error(sky.file, "fisheye",
                    "through the calibrated lens, the sky " + degrees(need * 180 / kPi) + " degrees from its axis (the " +
                        (need < kPi / 2 - 1e-3 ? std::string("edge of its field of view") : std::string("horizon")) +
                        ") falls " + (p ? "outside the " + std::to_string(im.width) + "x" + std::to_string(im.height) + " image"
                                        : std::string("outside its image circle")) +
                        ": part of the sky would be missing (a fisheye for the sky must see it all round; give a smaller "
                        "field of view if the lens sees less)");
    }
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

SkyImage readFisheyeLookingUp(const std::string& path, const FisheyeLens& lens) {
  int w = 0, h = 0;
  imageSize(path, w, h);
  return readSkyImage(path, lens.fx > 0 ? fisheyeFromDescription("180 deg, looking up, image up = +Y", w, h, path, lens)
                                        : fisheyeLookingUp(w, h));
}

SkyImage readRoomSky(const Scene& room, const std::string& name) {
  if (room.skies.empty()) throw Error(room.sourceFile, "daylight", "the room lists no measured sky");
  const std::string want = !name.empty() ? name : room.photoSky.empty() ? room.skies.front().name : room.photoSky;
  const SkyCapture* cap = room.findSky(want);
  if (!cap) throw Error(room.sourceFile, "--sky", "the room has no sky named '" + want + "'");
  const std::string file = cap->fisheye.front() == '/' ? cap->fisheye : room.baseDir + "/" + cap->fisheye;
  int w = 0, h = 0;
  imageSize(file, w, h);
  return readSkyImage(file, fisheyeFromDescription(cap->fisheyeModel, w, h, file, cap->lens));
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
