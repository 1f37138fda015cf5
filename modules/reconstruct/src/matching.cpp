#include "relume/reconstruct/matching.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdint>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <functional>

#include <tbb/parallel_for.h>

#include "relume/geometry/error.h"

namespace relume::recon {

namespace {
constexpr int kMatchLevelSize = 800;  // pixels across the coarsest level of a large photo

cv::Mat gray(const Image8& im) {
  cv::Mat rgb(im.height, im.width, CV_8UC3, const_cast<unsigned char*>(im.pixels.data())), g, f;
  cv::cvtColor(rgb, g, cv::COLOR_RGB2GRAY);
  g.convertTo(f, CV_32F);
  return f;
}

double ncc(const cv::Mat& a, const cv::Mat& b) {
  cv::Scalar ma, sa, mb, sb;
  cv::meanStdDev(a, ma, sa);
  cv::meanStdDev(b, mb, sb);
  if (sa[0] < 1e-6 || sb[0] < 1e-6) return -1;
  const double cov = cv::mean((a - ma[0]).mul(b - mb[0]))[0];
  return cov / (sa[0] * sb[0]);
}

std::vector<MatchProposal> pickPeaks(std::vector<MatchProposal> c, int count, int radius) {
  std::sort(c.begin(), c.end(), [](const auto& x, const auto& y) { return x.score > y.score; });
  std::vector<MatchProposal> out;
  for (const auto& m : c) {
    bool far = true;
    for (const auto& o : out) far = far && glm::length(o.pixel - m.pixel) >= radius;
    if (far) out.push_back(m);
    if (int(out.size()) == count) break;
  }
  return out;
}

// The patch around a click and the planes it may lie on, placed at a depth along the click's ray
// and compared with another photo (a plane sweep: Collins 1996; the patch taken on a plane through
// the depth, so that scale and perspective change between the photos are followed).
struct ClickRay {
  static constexpr int half = 7;
  cv::Mat patch;
  glm::dvec3 o{0.0}, centre{0.0};        // camera a's centre; the click's ray (z_cam = 1)
  std::vector<glm::dvec3> rays, normals;  // each patch pixel's ray; the plane hypotheses
  std::vector<double> onPlanes;           // where the ray meets the planes of built polygons

  ClickRay(const cv::Mat& ga, glm::dvec2 pa, const Camera& ca, const glm::dvec3& up, const std::vector<Plane>& planes) {
    const int ax = int(std::floor(pa.x)), ay = int(std::floor(pa.y));
    if (ax - half < 0 || ay - half < 0 || ax + half >= ga.cols || ay + half >= ga.rows)
      throw Error("", "click", "is too close to the photo's border to compare its surroundings");
    patch = ga(cv::Rect(ax - half, ay - half, 2 * half + 1, 2 * half + 1));
    o = ca.center();
    const glm::dmat3 Rt = glm::transpose(ca.R);
    // Plane hypotheses through each depth: parallel to a's image plane, horizontal (floors,
    // table tops), and vertical at six azimuths (walls, fronts): a corner where two surfaces meet
    // matches on the plane of the surface that fills most of its patch.
    const glm::dvec3 z = glm::length(up) > 0 ? glm::normalize(up) : -(Rt * glm::dvec3(0, 1, 0));
    const glm::dvec3 x = glm::normalize(glm::abs(z.x) < 0.9 ? glm::cross(z, glm::dvec3(1, 0, 0)) : glm::cross(z, glm::dvec3(0, 1, 0)));
    const glm::dvec3 y = glm::cross(z, x);
    normals = {Rt * glm::dvec3(0, 0, 1), z};
    for (int k = 0; k < 6; ++k) {
      const double az = k * std::numbers::pi / 6;
      normals.push_back(std::cos(az) * x + std::sin(az) * y);
    }
    // The planes of polygons already built: their orientations join the hypotheses (a room's
    // surfaces are seldom at the six azimuths), unless one is within about 2.5 degrees already.
    for (const auto& pl : planes) {
      const glm::dvec3 n = glm::normalize(pl.normal);
      bool known = false;
      for (const auto& m : normals) known = known || std::abs(glm::dot(n, m)) > 0.999;
      if (!known) normals.push_back(n);
    }
    for (int dy = -half; dy <= half; ++dy)
      for (int dx = -half; dx <= half; ++dx)
        rays.push_back(Rt * glm::dvec3((ax + 0.5 + dx - ca.cx()) / ca.fx(), (ay + 0.5 + dy - ca.cy()) / ca.fy(), 1.0));
    centre = Rt * glm::dvec3((pa.x - ca.cx()) / ca.fx(), (pa.y - ca.cy()) / ca.fy(), 1.0);
    // The clicked corner may lie on a built plane: exactly where the ray meets it.
    for (const auto& pl : planes) {
      const double dn = glm::dot(pl.normal, centre);
      if (std::abs(dn) < 1e-9) continue;
      const double t = glm::dot(pl.normal, pl.point - o) / dn;
      if (t > kNear && t < kFar) onPlanes.push_back(t);
    }
    std::sort(onPlanes.begin(), onPlanes.end());
  }
  static constexpr double kNear = 0.1, kFar = 100;  // depths swept, in the cameras' units

  glm::dvec3 at(double t) const { return o + centre * t; }

  // The best NCC over the plane hypotheses with the patch at depth t, seen in photo gb through
  // camera cb, on every `stride`-th pixel of the patch; -2 where no hypothesis can be placed.
  double score(double t, const cv::Mat& gb, const Camera& cb, int stride) const {
    auto bilinear = [&](double x, double y, bool& ok) {
      x -= 0.5, y -= 0.5;  // pixel centres at +0.5
      const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
      if (x0 < 0 || y0 < 0 || x0 + 1 >= gb.cols || y0 + 1 >= gb.rows) {
        ok = false;
        return 0.0;
      }
      const double fx = x - x0, fy = y - y0;
      return (1 - fy) * ((1 - fx) * gb.at<float>(y0, x0) + fx * gb.at<float>(y0, x0 + 1)) +
             fy * ((1 - fx) * gb.at<float>(y0 + 1, x0) + fx * gb.at<float>(y0 + 1, x0 + 1));
    };
    const glm::dvec3 X0 = at(t);
    const int side = (2 * half) / stride + 1;
    cv::Mat pa_(side, side, CV_32F), pb_(side, side, CV_32F);
    double best = -2;
    for (const auto& n : normals) {
      const double h = glm::dot(n, X0 - o);
      bool ok = true;
      for (int r = 0; r < side && ok; ++r)
        for (int c = 0; c < side && ok; ++c) {
          const int i = (r * stride) * (2 * half + 1) + c * stride;
          const double dn = glm::dot(n, rays[size_t(i)]);
          // Seen at a grazing angle from a, the plane is no model of the patch.
          if (std::abs(dn) < 0.2 * glm::length(rays[size_t(i)]) || h / dn <= 0) ok = false;
          glm::dvec2 q;
          if (ok && !cb.project(o + rays[size_t(i)] * (h / dn), q)) ok = false;
          if (ok) {
            pb_.at<float>(r, c) = float(bilinear(q.x, q.y, ok));
            pa_.at<float>(r, c) = patch.at<float>(r * stride, c * stride);
          }
        }
      if (ok) best = std::max(best, ncc(pa_, pb_));
    }
    return best;
  }
};

// One photo the click is looked for in: its grey levels and camera (at the level swept).
struct SweepPhoto {
  cv::Mat grey;
  Camera camera;
};

// The photos' scores of one depth as one: the mean of the better half (rounded up) of the photos
// where the patch could be placed, so that photos where the point is hidden do not outvote those
// that see it (Kang, Szeliski and Chai 2001's view selection); -2 where none could.
double combined(std::vector<double> s) {
  s.erase(std::remove(s.begin(), s.end(), -2.0), s.end());
  if (s.empty()) return -2;
  const size_t m = (s.size() + 1) / 2;
  std::partial_sort(s.begin(), s.begin() + long(m), s.end(), std::greater<>());
  double sum = 0;
  for (size_t k = 0; k < m; ++k) sum += s[k];
  return sum / double(m);
}

struct DepthScore {
  double t = 0, score = -2;
};

// Depths along the click's ray scored in every photo at once (multi-baseline stereo: Okutomi and
// Kanade 1993 — a wrong depth may look right in one photo, seldom in all). The depths are those
// at which the point moves at least half a pixel in one of the photos, and those on built planes.
// `window` > 0: only the depths whose projection into photos[0] lies within `window` of `near`,
// each scored on the full patch; else every depth on a quarter of the patch, then the full patch
// around the 16 best local maxima.
std::vector<DepthScore> sweepDepths(const ClickRay& ray, const std::vector<SweepPhoto>& photos, glm::dvec2 near, double window) {
  std::vector<double> steps;
  {
    std::vector<glm::dvec2> prev(photos.size(), glm::dvec2(-1e9));
    size_t next = 0;
    auto add = [&](double t, bool exact) {
      bool moved = exact, seen = false;
      std::vector<glm::dvec2> p(photos.size());
      for (size_t j = 0; j < photos.size(); ++j) {
        if (!photos[j].camera.project(ray.at(t), p[j])) continue;
        seen = true;
        moved = moved || glm::length(p[j] - prev[j]) >= 0.5;
      }
      if (!seen || !moved) return;
      if (window > 0 && !(photos[0].camera.project(ray.at(t), p[0]) && glm::length(p[0] - near) <= window)) return;
      for (size_t j = 0; j < photos.size(); ++j)
        if (photos[j].camera.project(ray.at(t), p[j])) prev[j] = p[j];
      steps.push_back(t);
    };
    for (double t = ClickRay::kNear; t < ClickRay::kFar; t *= 1.002) {
      while (next < ray.onPlanes.size() && ray.onPlanes[next] <= t) add(ray.onPlanes[next++], true);
      add(t, false);
    }
  }
  auto scoreAt = [&](double t, int stride) {
    std::vector<double> s(photos.size());
    for (size_t j = 0; j < photos.size(); ++j) s[j] = ray.score(t, photos[j].grey, photos[j].camera, stride);
    return combined(std::move(s));
  };
  std::vector<DepthScore> out;
  if (window > 0) {  // a few steps only: all with the full patch
    for (double t : steps) out.push_back({t, scoreAt(t, 1)});
    return out;
  }
  // Each photo scored where the point has moved half a pixel in it since its last score (the
  // steps are as fine as the photo with the widest baseline needs), its score held in between.
  std::vector<std::vector<double>> per(photos.size(), std::vector<double>(steps.size(), -2.0));
  tbb::parallel_for(size_t(0), photos.size(), [&](size_t j) {
    glm::dvec2 last(-1e9);
    double held = -2;
    for (size_t k = 0; k < steps.size(); ++k) {
      glm::dvec2 p;
      if (!photos[j].camera.project(ray.at(steps[k]), p)) {
        last = glm::dvec2(-1e9);
        continue;
      }
      if (glm::length(p - last) >= 0.5 || std::binary_search(ray.onPlanes.begin(), ray.onPlanes.end(), steps[k])) {
        held = ray.score(steps[k], photos[j].grey, photos[j].camera, 2);
        last = p;
      }
      per[j][k] = held;
    }
  });
  std::vector<double> coarse(steps.size());
  for (size_t k = 0; k < steps.size(); ++k) {
    std::vector<double> s(photos.size());
    for (size_t j = 0; j < photos.size(); ++j) s[j] = per[j][k];
    coarse[k] = combined(std::move(s));
  }
  std::vector<size_t> peaks;
  for (size_t k = 0; k < steps.size(); ++k)
    if (coarse[k] > -2 && (k == 0 || coarse[k] >= coarse[k - 1]) && (k + 1 == steps.size() || coarse[k] >= coarse[k + 1]))
      peaks.push_back(k);
  std::sort(peaks.begin(), peaks.end(), [&](size_t x, size_t y) { return coarse[x] > coarse[y]; });
  if (peaks.size() > 16) peaks.resize(16);
  std::vector<size_t> fine;
  std::vector<uint8_t> done(steps.size(), 0);
  for (size_t k : peaks)
    for (size_t j = k >= 2 ? k - 2 : 0; j <= std::min(steps.size() - 1, k + 2); ++j)
      if (!done[j]) {
        done[j] = 1;
        fine.push_back(j);
      }
  out.resize(fine.size());
  tbb::parallel_for(size_t(0), fine.size(), [&](size_t i) { out[i] = {steps[fine[i]], scoreAt(steps[fine[i]], 1)}; });
  return out;
}

// The scored depths as proposals in one photo.
std::vector<MatchProposal> inPhoto(const ClickRay& ray, const std::vector<DepthScore>& depths, const Camera& camera) {
  std::vector<MatchProposal> out;
  for (const auto& d : depths) {
    glm::dvec2 p;
    if (d.score > -2 && camera.project(ray.at(d.t), p) && p.x >= 0 && p.y >= 0 && p.x <= camera.width && p.y <= camera.height)
      out.push_back({p, d.score});
  }
  return out;
}

// Candidates anywhere in b (no cameras): template matching of the patch around pa.
std::vector<MatchProposal> searchAnywhere(const cv::Mat& ga, glm::dvec2 pa, const cv::Mat& gb) {
  const int half = 7;
  const int ax = int(std::floor(pa.x)), ay = int(std::floor(pa.y));
  if (ax - half < 0 || ay - half < 0 || ax + half >= ga.cols || ay + half >= ga.rows)
    throw Error("", "click", "is too close to the photo's border to compare its surroundings");
  const cv::Mat patch = ga(cv::Rect(ax - half, ay - half, 2 * half + 1, 2 * half + 1));
  std::vector<MatchProposal> cands;
  cv::Mat res;
  cv::matchTemplate(gb, patch, res, cv::TM_CCOEFF_NORMED);
  for (int y = 0; y < res.rows; ++y)
    for (int x = 0; x < res.cols; ++x) {
      const float s = res.at<float>(y, x);
      bool peak = true;
      for (int dy = -1; dy <= 1 && peak; ++dy)
        for (int dx = -1; dx <= 1 && peak; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if ((dx || dy) && xx >= 0 && yy >= 0 && xx < res.cols && yy < res.rows && res.at<float>(yy, xx) > s) peak = false;
        }
      // The patch's top-left pixel at (x, y): the click's place within its pixel carries over.
      if (peak && s > 0.3f) cands.push_back({glm::dvec2(x + half + 0.5, y + half + 0.5) + (pa - glm::dvec2(ax + 0.5, ay + 0.5)), double(s)});
    }
  return cands;
}

// The camera of a pyramid level 2^-level as large (pixel centres stay at +0.5: x' = x / 2^level).
Camera scaled(const Camera& c, int level) {
  if (level == 0) return c;
  Camera s = c;
  const double f = std::ldexp(1.0, -level);
  s.K[0][0] *= f;
  s.K[1][1] *= f;
  s.K[2][0] *= f;
  s.K[2][1] *= f;
  s.width = int(c.width * f);
  s.height = int(c.height * f);
  return s;
}

cv::Mat levelMat(const MatchImage& im, size_t level) {
  return cv::Mat(im.heights[level], im.widths[level], CV_32F, const_cast<float*>(im.levels[level].data()));
}
}  // namespace

namespace {
MatchImage pyramid(cv::Mat g);
}

MatchImage prepareForMatching(const Image8& image) { return pyramid(gray(image)); }

MatchImage prepareForMatching(const Image8& image, const ColmapCamera& cam) {
  if (!cam.hasDistortion()) return prepareForMatching(image);
  if (cam.width != image.width || cam.height != image.height)
    throw Error("", "photo", "is " + std::to_string(image.width) + "x" + std::to_string(image.height) + " but its camera is " +
                                 std::to_string(cam.width) + "x" + std::to_string(cam.height));
  cv::Mat mapx(image.height, image.width, CV_32F), mapy(image.height, image.width, CV_32F);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const glm::dvec2 d = distortedPixel(cam, glm::dvec2(x + 0.5, y + 0.5));
      mapx.at<float>(y, x) = float(d.x - 0.5);
      mapy.at<float>(y, x) = float(d.y - 0.5);
    }
  cv::Mat out;
  cv::remap(gray(image), out, mapx, mapy, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  return pyramid(out);
}

glm::dvec2 pinholePixel(const ColmapCamera& cam, glm::dvec2 distorted) {
  const glm::dvec2 n = cam.undistort(distorted);
  return {cam.fx() * n.x + cam.cx(), cam.fy() * n.y + cam.cy()};
}

glm::dvec2 distortedPixel(const ColmapCamera& cam, glm::dvec2 pinhole) {
  return cam.distort(glm::dvec2((pinhole.x - cam.cx()) / cam.fx(), (pinhole.y - cam.cy()) / cam.fy()));
}

namespace {
MatchImage pyramid(cv::Mat g) {
  MatchImage m;
  m.width = g.cols;
  m.height = g.rows;
  for (;;) {
    m.widths.push_back(g.cols);
    m.heights.push_back(g.rows);
    m.levels.emplace_back(reinterpret_cast<const float*>(g.data), reinterpret_cast<const float*>(g.data) + g.total());
    if (std::max(g.cols, g.rows) <= kMatchLevelSize || g.cols < 64 || g.rows < 64) break;
    // 2x2 means of the even part (an odd last row or column is left out): x' = x / 2 exactly.
    cv::Mat h;
    cv::resize(g(cv::Rect(0, 0, g.cols & ~1, g.rows & ~1)), h, cv::Size(g.cols / 2, g.rows / 2), 0, 0, cv::INTER_AREA);
    g = h;
  }
  return m;
}
}  // namespace

std::vector<MatchProposal> proposeMatches(const Image8& a, glm::dvec2 pa, const Image8& b, const Camera* ca,
                                          const Camera* cb, int count, int radius, const glm::dvec3& up,
                                          const std::vector<Plane>& planes) {
  return proposeMatches(prepareForMatching(a), pa, prepareForMatching(b), ca, cb, count, radius, up, planes);
}

namespace {
// Proposals in every photo from one sweep over them all (each photo's proposals ranked by the
// photos' combined score). Large photos: the sweep runs on the coarsest level (400-800 pixels
// across, where a patch sees as much of the scene as at 640 x 480); each photo's best peaks are
// then placed at full size, among the depths within a coarse pixel and a half of each.
std::vector<std::vector<MatchProposal>> sweepInPhotos(const MatchImage& a, glm::dvec2 pa, const Camera& ca,
                                                      const std::vector<const MatchImage*>& photos,
                                                      const std::vector<const Camera*>& cameras, int count, int radius,
                                                      const glm::dvec3& up, const std::vector<Plane>& planes) {
  size_t level = a.levels.size() - 1;
  for (const auto* p : photos) level = std::min(level, p->levels.size() - 1);
  auto at = [&](size_t lv) {
    std::vector<SweepPhoto> sp;
    for (size_t j = 0; j < photos.size(); ++j) sp.push_back({levelMat(*photos[j], lv), scaled(*cameras[j], int(lv))});
    return sp;
  };
  std::vector<std::vector<MatchProposal>> out(photos.size());
  auto full = [&] {
    const ClickRay ray(levelMat(a, 0), pa, ca, up, planes);
    const auto depths = sweepDepths(ray, at(0), {}, 0);
    for (size_t j = 0; j < photos.size(); ++j) out[j] = pickPeaks(inPhoto(ray, depths, *cameras[j]), count, radius);
    return out;
  };
  if (level == 0) return full();
  const double f = std::ldexp(1.0, -int(level));
  std::optional<ClickRay> coarseRay;
  try {
    coarseRay.emplace(levelMat(a, level), pa * f, scaled(ca, int(level)), up, planes);
  } catch (const Error&) {
    return full();  // too near the border at the coarse level: the full-size sweep alone
  }
  const auto depths = sweepDepths(*coarseRay, at(level), {}, 0);
  const ClickRay ray(levelMat(a, 0), pa, ca, up, planes);
  tbb::parallel_for(size_t(0), photos.size(), [&](size_t j) {
    const Camera cj = scaled(*cameras[j], int(level));
    const SweepPhoto photo{levelMat(*photos[j], 0), *cameras[j]};
    std::vector<MatchProposal> fine;
    for (const auto& c : pickPeaks(inPhoto(*coarseRay, depths, cj), 2 * count, std::max(2, int(radius * f)))) {
      const auto near = sweepDepths(ray, {photo}, c.pixel / f, 1.5 / f);
      if (near.empty()) continue;
      const auto best = *std::max_element(near.begin(), near.end(), [](const auto& x, const auto& y) { return x.score < y.score; });
      glm::dvec2 p;
      if (best.score > -2 && cameras[j]->project(ray.at(best.t), p)) fine.push_back({p, c.score});  // ranked as swept
    }
    out[j] = pickPeaks(std::move(fine), count, radius);
  });
  return out;
}
}  // namespace

std::vector<MatchProposal> proposeMatches(const MatchImage& a, glm::dvec2 pa, const MatchImage& b, const Camera* ca,
                                          const Camera* cb, int count, int radius, const glm::dvec3& up,
                                          const std::vector<Plane>& planes) {
  if (a.levels.empty() || b.levels.empty()) throw Error("", "photo", "is empty");
  if (!(ca && cb)) return pickPeaks(searchAnywhere(levelMat(a, 0), pa, levelMat(b, 0)), count, radius);
  return sweepInPhotos(a, pa, *ca, {&b}, {cb}, count, radius, up, planes)[0];
}

std::vector<std::vector<MatchProposal>> proposeMatchesInPhotos(const MatchImage& a, glm::dvec2 pa, const Camera& ca,
                                                               const std::vector<const MatchImage*>& photos,
                                                               const std::vector<const Camera*>& cameras, int count,
                                                               int radius, const glm::dvec3& up,
                                                               const std::vector<Plane>& planes) {
  if (photos.size() != cameras.size()) throw Error("", "photos", "one camera per photo is needed");
  if (a.levels.empty()) throw Error("", "photo", "is empty");
  for (size_t j = 0; j < photos.size(); ++j)
    if (!photos[j] || photos[j]->levels.empty() || !cameras[j]) throw Error("", "photo " + std::to_string(j), "is empty or has no camera");
  try {
    return sweepInPhotos(a, pa, ca, photos, cameras, count, radius, up, planes);
  } catch (const Error&) {
    return std::vector<std::vector<MatchProposal>>(photos.size());  // the click too near a border
  }
}

}  // namespace relume::recon
