#include "relume/reconstruct/matching.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "relume/geometry/error.h"

namespace relume::recon {

namespace {
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
}  // namespace

std::vector<MatchProposal> proposeMatches(const Image8& a, glm::dvec2 pa, const Image8& b, const Camera* ca,
                                          const Camera* cb, int count, int radius, const glm::dvec3& up) {
  const int half = 7;
  const cv::Mat ga = gray(a), gb = gray(b);
  const int ax = int(std::floor(pa.x)), ay = int(std::floor(pa.y));
  if (ax - half < 0 || ay - half < 0 || ax + half >= a.width || ay + half >= a.height)
    throw Error("", "click", "is too close to the photo's border to compare its surroundings");
  const cv::Mat patch = ga(cv::Rect(ax - half, ay - half, 2 * half + 1, 2 * half + 1));
  std::vector<MatchProposal> cands;
  if (ca && cb) {
    // Plane sweep along the ray of pa: at each depth the patch is taken as a plane parallel to
    // a's image plane, its pixels projected into b and sampled there (scale and perspective
    // change between the photos are followed), scored by NCC.
    const glm::dvec3 o = ca->center();
    const glm::dmat3 Rt = glm::transpose(ca->R);
    auto bilinear = [&](double x, double y, bool& ok) {
      x -= 0.5, y -= 0.5;  // pixel centres at +0.5
      const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
      if (x0 < 0 || y0 < 0 || x0 + 1 >= b.width || y0 + 1 >= b.height) {
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
  } else {
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
        if (peak && s > 0.3f) cands.push_back({glm::dvec2(x + half + 0.5, y + half + 0.5), double(s)});
      }
  }
  return pickPeaks(std::move(cands), count, radius);
}

}  // namespace relume::recon
