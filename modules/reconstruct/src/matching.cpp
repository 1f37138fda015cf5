#include "relume/reconstruct/matching.h"

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

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
                                          const Camera* cb, int count, int radius) {
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
    cv::Mat warped(patch.size(), CV_32F);
    glm::dvec2 prev(-1e9);
    for (double depth = 0.1; depth < 100; depth *= 1.002) {
      glm::dvec2 p;
      const glm::dvec3 centreRay = Rt * glm::dvec3((pa.x - ca->cx()) / ca->fx(), (pa.y - ca->cy()) / ca->fy(), 1.0);
      if (!cb->project(o + centreRay * depth, p)) continue;
      if (glm::length(p - prev) < 0.5) continue;
      prev = p;
      bool ok = true;
      for (int dy = -half; dy <= half && ok; ++dy)
        for (int dx = -half; dx <= half && ok; ++dx) {
          const double px = ax + 0.5 + dx, py = ay + 0.5 + dy;
          const glm::dvec3 X = o + Rt * glm::dvec3((px - ca->cx()) / ca->fx(), (py - ca->cy()) / ca->fy(), 1.0) * depth;
          glm::dvec2 q;
          if (!cb->project(X, q)) ok = false;
          else warped.at<float>(dy + half, dx + half) = float(bilinear(q.x, q.y, ok));
        }
      if (ok) cands.push_back({p, ncc(patch, warped)});
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
