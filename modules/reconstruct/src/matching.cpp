#include "relume/reconstruct/matching.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdint>

#include <algorithm>
#include <cmath>
#include <numbers>

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

// Candidates along the epipolar line of `pa` (a's pixel) in b, one level of the photos' pyramids.
// `window` > 0: only the depths whose projection lies within `window` pixels of `near`.
std::vector<MatchProposal> sweep(const cv::Mat& ga, glm::dvec2 pa, const cv::Mat& gb, const Camera& cam_a, const Camera& cam_b,
                                 const glm::dvec3& up, glm::dvec2 near, double window) {
  const int half = 7;
  const Camera* ca = &cam_a;
  const Camera* cb = &cam_b;
  const int ax = int(std::floor(pa.x)), ay = int(std::floor(pa.y));
  if (ax - half < 0 || ay - half < 0 || ax + half >= ga.cols || ay + half >= ga.rows)
    throw Error("", "click", "is too close to the photo's border to compare its surroundings");
  const cv::Mat patch = ga(cv::Rect(ax - half, ay - half, 2 * half + 1, 2 * half + 1));
  std::vector<MatchProposal> cands;
  {
    // Plane sweep along the ray of pa: at each depth the patch is taken as a plane parallel to
    // a's image plane, its pixels projected into b and sampled there (scale and perspective
    // change between the photos are followed), scored by NCC.
    const glm::dvec3 o = ca->center();
    const glm::dmat3 Rt = glm::transpose(ca->R);
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
    // Plane hypotheses through each depth: parallel to a's image plane, horizontal (floors,
    // table tops), and vertical at six azimuths (walls, fronts): a corner where two surfaces meet
    // matches on the plane of the surface that fills most of its patch.
    const glm::dvec3 z = glm::length(up) > 0 ? glm::normalize(up) : -(Rt * glm::dvec3(0, 1, 0));
    const glm::dvec3 x = glm::normalize(glm::abs(z.x) < 0.9 ? glm::cross(z, glm::dvec3(1, 0, 0)) : glm::cross(z, glm::dvec3(0, 1, 0)));
    const glm::dvec3 y = glm::cross(z, x);
    std::vector<glm::dvec3> normals{Rt * glm::dvec3(0, 0, 1), z};
    for (int k = 0; k < 6; ++k) {
      const double az = k * std::numbers::pi / 6;
      normals.push_back(std::cos(az) * x + std::sin(az) * y);
    }
    std::vector<glm::dvec3> rays;  // world direction of each patch pixel's ray (z_cam = 1)
    for (int dy = -half; dy <= half; ++dy)
      for (int dx = -half; dx <= half; ++dx)
        rays.push_back(Rt * glm::dvec3((ax + 0.5 + dx - ca->cx()) / ca->fx(), (ay + 0.5 + dy - ca->cy()) / ca->fy(), 1.0));
    const glm::dvec3 centreRay = Rt * glm::dvec3((pa.x - ca->cx()) / ca->fx(), (pa.y - ca->cy()) / ca->fy(), 1.0);
    // The depths along the ray whose points fall at least half a pixel apart in b.
    std::vector<std::pair<glm::dvec3, glm::dvec2>> steps;
    {
      glm::dvec2 prev(-1e9);
      for (double depth = 0.1; depth < 100; depth *= 1.002) {
        glm::dvec2 p;
        const glm::dvec3 X0 = o + centreRay * depth;
        if (!cb->project(X0, p) || glm::length(p - prev) < 0.5) continue;
        if (window > 0 && glm::length(p - near) > window) continue;
        prev = p;
        steps.emplace_back(X0, p);
      }
    }
    // The best NCC over the plane hypotheses at a step, on every `stride`-th pixel of the patch.
    auto score = [&](const glm::dvec3& X0, int stride) {
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
            if (ok && !cb->project(o + rays[size_t(i)] * (h / dn), q)) ok = false;
            if (ok) {
              pb_.at<float>(r, c) = float(bilinear(q.x, q.y, ok));
              pa_.at<float>(r, c) = patch.at<float>(r * stride, c * stride);
            }
          }
        if (ok) best = std::max(best, ncc(pa_, pb_));
      }
      return best;
    };
    // Coarse to fine: every step on a quarter of the patch's pixels, then the full patch around
    // the 16 best local maxima (a point's proposals come from these).
    if (window > 0) {  // a few steps only: all with the full patch
      for (const auto& st : steps) {
        const double sc = score(st.first, 1);
        if (sc > -2) cands.push_back({st.second, sc});
      }
      return cands;
    }
    std::vector<double> coarse(steps.size());
    for (size_t k = 0; k < steps.size(); ++k) coarse[k] = score(steps[k].first, 2);
    std::vector<size_t> peaks;
    for (size_t k = 0; k < steps.size(); ++k)
      if (coarse[k] > -2 && (k == 0 || coarse[k] >= coarse[k - 1]) && (k + 1 == steps.size() || coarse[k] >= coarse[k + 1]))
        peaks.push_back(k);
    std::sort(peaks.begin(), peaks.end(), [&](size_t x, size_t y) { return coarse[x] > coarse[y]; });
    if (peaks.size() > 16) peaks.resize(16);
    std::vector<uint8_t> done(steps.size(), 0);
    for (size_t k : peaks)
      for (size_t j = k >= 2 ? k - 2 : 0; j <= std::min(steps.size() - 1, k + 2); ++j) {
        if (done[j]) continue;
        done[j] = 1;
        const double sc = score(steps[j].first, 1);
        if (sc > -2) cands.push_back({steps[j].second, sc});
      }
  }
  return cands;
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
                                          const Camera* cb, int count, int radius, const glm::dvec3& up) {
  return proposeMatches(prepareForMatching(a), pa, prepareForMatching(b), ca, cb, count, radius, up);
}

std::vector<MatchProposal> proposeMatches(const MatchImage& a, glm::dvec2 pa, const MatchImage& b, const Camera* ca,
                                          const Camera* cb, int count, int radius, const glm::dvec3& up) {
  if (a.levels.empty() || b.levels.empty()) throw Error("", "photo", "is empty");
  if (!(ca && cb)) return pickPeaks(searchAnywhere(levelMat(a, 0), pa, levelMat(b, 0)), count, radius);
  // Large photos: the sweep runs on the coarsest level (400-800 pixels across, where a
  // patch sees as much of the scene as at 640 x 480), each of its best peaks is then refined at
  // full size among the depths that fall within a coarse pixel and a half of it.
  const size_t level = std::min(a.levels.size(), b.levels.size()) - 1;
  if (level == 0) return pickPeaks(sweep(levelMat(a, 0), pa, levelMat(b, 0), *ca, *cb, up, {}, 0), count, radius);
  const double f = std::ldexp(1.0, -int(level));
  std::vector<MatchProposal> coarse;
  try {
    coarse = pickPeaks(sweep(levelMat(a, level), pa * f, levelMat(b, level), scaled(*ca, int(level)), scaled(*cb, int(level)), up, {}, 0),
                       2 * count, std::max(2, int(radius * f)));
  } catch (const Error&) {
    // Too near the border at the coarse level: the full-size sweep alone.
    return pickPeaks(sweep(levelMat(a, 0), pa, levelMat(b, 0), *ca, *cb, up, {}, 0), count, radius);
  }
  std::vector<MatchProposal> fine;
  for (const auto& c : coarse) {
    const auto near = sweep(levelMat(a, 0), pa, levelMat(b, 0), *ca, *cb, up, c.pixel / f, 1.5 / f);
    if (near.empty()) continue;
    fine.push_back(*std::max_element(near.begin(), near.end(), [](const auto& x, const auto& y) { return x.score < y.score; }));
  }
  return pickPeaks(std::move(fine), count, radius);
}

std::vector<std::vector<MatchProposal>> proposeMatchesInPhotos(const MatchImage& a, glm::dvec2 pa, const Camera& ca,
                                                               const std::vector<const MatchImage*>& photos,
                                                               const std::vector<const Camera*>& cameras, int count,
                                                               int radius, const glm::dvec3& up) {
  if (photos.size() != cameras.size()) throw Error("", "photos", "one camera per photo is needed");
  std::vector<std::vector<MatchProposal>> out(photos.size());
  tbb::parallel_for(size_t(0), photos.size(), [&](size_t i) {
    try {
      out[i] = proposeMatches(a, pa, *photos[i], &ca, cameras[i], count, radius, up);
    } catch (const Error&) {
      out[i].clear();
    }
  });
  return out;
}

}  // namespace relume::recon
