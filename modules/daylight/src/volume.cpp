#include "relume/daylight/volume.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <glm/geometric.hpp>
#include <string>

#include "relume/daylight/basis.h"
#include "relume/geometry/error.h"
#include "relume/geometry/polygon.h"
#include "relume/radiosity/hierarchy.h"
#include "relume/raytrace/ray_scene.h"

namespace relume::daylight {

namespace {
// A point whose rays meet back faces more often than this lies inside something solid.
constexpr double kInsideBackFaces = 0.1;
}  // namespace

IrradianceVolume::IrradianceVolume(const DaylightBasis& basis, const VolumeOptions& options, Progress& progress)
    : n_(options.grid) {
  const auto start = std::chrono::steady_clock::now();
  if (options.grid < 2 || options.grid > 32)
    throw Error("", "irradiance volume", "a grid of " + std::to_string(options.grid) + " points per axis (2 to 32)");
  const auto& h = basis.engine();
  // The room's box: every surface that stops light (windows are openings; objects are not here yet).
  lo_ = glm::dvec3(1e300);
  hi_ = glm::dvec3(-1e300);
  for (const auto& s : h.surfaces()) {
    if (s.opening) continue;
    for (const auto& v : s.vertices) {
      lo_ = glm::min(lo_, v);
      hi_ = glm::max(hi_, v);
    }
  }
  if (!(lo_.x < hi_.x && lo_.y < hi_.y && lo_.z < hi_.z)) throw Error("", "irradiance volume", "the room has no extent");
  points_.resize(size_t(n_) * size_t(n_) * size_t(n_));
  for (int k = 0; k < n_; ++k)
    for (int j = 0; j < n_; ++j)
      for (int i = 0; i < n_; ++i)
        points_[index(i, j, k)] = lo_ + (glm::dvec3(i, j, k) + 0.5) / double(n_) * (hi_ - lo_);
  inRoom_.assign(points_.size(), 1);
  hits_.resize(points_.size());

  // Each point's rays, grouped by the element they hit (front faces only: a back face is the
  // inside of something, and dark).
  const std::vector<glm::dvec3> dirs = radiosity::fibonacciSphere(std::max(options.rays, 64));
  std::vector<std::array<float, 9>> ys(dirs.size());
  const double w = 4.0 / double(dirs.size());  // 4 pi / rays x 1 / pi (radiosity to radiance)
  for (size_t r = 0; r < dirs.size(); ++r) {
    const auto y = radiosity::shBasis(dirs[r]);
    for (size_t c = 0; c < 9; ++c) ys[r][c] = float(w * y[c]);
  }
  progress.report(0, "irradiance volume: casting " + std::to_string(points_.size()) + " points' rays");
  // Chunks of points in parallel; progress is reported between chunks, from this thread only
  // (the CLI's and the workbench's callbacks are not thread-safe), cancellation polled inside.
  const size_t chunk = 64;
  for (size_t first = 0; first < points_.size(); first += chunk) {
    progress.report(0.7 * double(first) / double(points_.size()), "irradiance volume: casting rays");
    const size_t last = std::min(points_.size(), first + chunk);
    tbb::parallel_for(tbb::blocked_range<size_t>(first, last, 4), [&](const tbb::blocked_range<size_t>& range) {
      std::vector<Ray> rays(dirs.size());
      std::vector<RayHit> hit(dirs.size());
      std::vector<std::pair<int, int>> byNode;  // (element, ray)
      for (size_t p = range.begin(); p < range.end(); ++p) {
        progress.poll();
        for (size_t r = 0; r < dirs.size(); ++r) rays[r] = Ray{glm::vec3(points_[p]), glm::vec3(dirs[r]), 0.f, 1e30f};
        h.rayScene().intersect(rays, hit);
        byNode.clear();
        size_t back = 0;
        for (size_t r = 0; r < dirs.size(); ++r) {
          const int s = hit[r].polygon;
          if (s < 0) continue;  // out through a window: the direct daylight, sampled apart
          const auto& surf = h.surfaces()[size_t(s)];
          if (glm::dot(dirs[r], polygonNormal(surf.vertices)) >= 0) {
            ++back;
            continue;
          }
          const glm::dvec3 at = points_[p] + double(hit[r].t) * dirs[r];
          const int leaf = h.findLeaf(s, h.toUV(s, at));
          if (leaf >= 0) byNode.emplace_back(leaf, int(r));
        }
        inRoom_[p] = double(back) <= kInsideBackFaces * double(dirs.size()) ? 1 : 0;
        std::sort(byNode.begin(), byNode.end());
        auto& out = hits_[p];
        for (size_t a = 0; a < byNode.size();) {
          Hit e{byNode[a].first, {}};
          size_t b = a;
          for (; b < byNode.size() && byNode[b].first == e.node; ++b)
            for (size_t c = 0; c < 9; ++c) e.w[c] += ys[size_t(byNode[b].second)][c];
          out.push_back(e);
          a = b;
        }
      }
    });
  }
  // Each point out of the room borrows the nearest point in it (once, here: at() stays cheap and
  // combine(box) knows what at() will read).
  substitute_.assign(points_.size(), points_.size());
  tbb::parallel_for(size_t(0), points_.size(), [&](size_t p) {
    if (inRoom_[p]) {
      substitute_[p] = p;
      return;
    }
    progress.poll();
    double bestD = 1e300;
    for (size_t q = 0; q < points_.size(); ++q) {
      const double d = glm::dot(points_[q] - points_[p], points_[q] - points_[p]);
      if (inRoom_[q] && d < bestD) {
        bestD = d;
        substitute_[p] = q;
      }
    }
  });
  // Every basis projected (the ground last), as the basis numbers them.
  bases_ = basis.basisCount();
  coeff_.assign(size_t(bases_) * points_.size() * 9, glm::vec3(0.f));
  for (int k = 0; k < bases_; ++k) {
    progress.report(0.7 + 0.3 * double(k) / double(bases_), "irradiance volume: projecting basis " + std::to_string(k + 1) +
                                                                 " of " + std::to_string(bases_));
    project(basis.basis(k), coeff_.data() + size_t(k) * points_.size() * 9);
  }
  combined_.assign(points_.size(), radiosity::SH9{});
  buildSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void IrradianceVolume::project(const std::vector<glm::vec3>& solution, glm::vec3* out) const {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, points_.size(), 8), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t p = range.begin(); p < range.end(); ++p) {
      glm::vec3* c = out + 9 * p;
      for (int i = 0; i < 9; ++i) c[i] = glm::vec3(0.f);
      for (const Hit& e : hits_[p]) {
        const glm::vec3 b = size_t(e.node) < solution.size() ? solution[size_t(e.node)] : glm::vec3(0.f);
        for (size_t i = 0; i < 9; ++i) c[i] += e.w[i] * b;
      }
    }
  });
}

radiosity::SH9 IrradianceVolume::basisAt(int k, size_t p) const {
  radiosity::SH9 sh;
  const glm::vec3* c = coeff_.data() + (size_t(k) * points_.size() + p) * 9;
  for (size_t i = 0; i < 9; ++i) sh.c[i] = glm::dvec3(c[i]);
  return sh;
}

void IrradianceVolume::combine(DaylightBasis& basis, const SkyRadiance& sky, Progress& progress) {
  std::vector<size_t> all(points_.size());
  for (size_t p = 0; p < all.size(); ++p) all[p] = p;
  combinePoints(basis, sky, all, progress);
}

void IrradianceVolume::combine(DaylightBasis& basis, const SkyRadiance& sky, const glm::dvec3& boxLo, const glm::dvec3& boxHi,
                               Progress& progress) {
  // The cells a position inside the box interpolates from: one point beyond it on every side.
  auto cell = [&](double x, int axis, bool up) {
    const double f = std::clamp((x - lo_[axis]) / (hi_[axis] - lo_[axis]) * n_ - 0.5, -2.0, double(n_) + 1);
    return std::clamp(up ? int(std::ceil(f)) + 1 : int(std::floor(f)) - 1, 0, n_ - 1);
  };
  std::vector<size_t> points;
  for (int k = cell(boxLo.z, 2, false); k <= cell(boxHi.z, 2, true); ++k)
    for (int j = cell(boxLo.y, 1, false); j <= cell(boxHi.y, 1, true); ++j)
      for (int i = cell(boxLo.x, 0, false); i <= cell(boxHi.x, 0, true); ++i) {
        const size_t p = index(i, j, k);
        points.push_back(p);
        if (substitute_[p] != p && substitute_[p] < points_.size()) points.push_back(substitute_[p]);
      }
  std::sort(points.begin(), points.end());
  points.erase(std::unique(points.begin(), points.end()), points.end());
  combinePoints(basis, sky, points, progress);
}

void IrradianceVolume::combinePoints(DaylightBasis& basis, const SkyRadiance& sky, const std::vector<size_t>& points,
                                     Progress& progress) {
  if (sky.region.size() + 1 != size_t(bases_))
    throw Error("", "sky", "averaged over " + std::to_string(sky.region.size()) + " regions, the irradiance volume has " +
                               std::to_string(bases_ - 1));
  const bool sun = sky.sun.found && sky.sun.direction.z > 0;
  if (sun) {
    const glm::dvec3 d = glm::normalize(sky.sun.direction);
    if (!haveSun_ || glm::dot(d, sunDirection_) < 1 - 1e-12) {
      haveSun_ = false;
      const std::vector<glm::vec3>& s = basis.sunSolution(d, progress);
      sunCoeff_.assign(points_.size() * 9, glm::vec3(0.f));
      project(s, sunCoeff_.data());
      sunDirection_ = d;
      haveSun_ = true;
    }
  }
  // Eq. 4: L_lm(x) = sum_i L_i L_lm^(i)(x), the ground and the sun two more terms.
  std::vector<glm::vec3> weight(static_cast<size_t>(bases_));
  for (size_t k = 0; k + 1 < size_t(bases_); ++k) weight[k] = glm::vec3(sky.region[k]);
  weight.back() = glm::vec3(basis.groundRadiance(sky));
  const glm::vec3 sunE = sun ? glm::vec3(sky.sun.irradiance) : glm::vec3(0.f);
  const size_t stride = points_.size() * 9;
  for (size_t p : points) {
    glm::vec3 c[9] = {};
    const glm::vec3* src = coeff_.data() + 9 * p;
    for (size_t k = 0; k < size_t(bases_); ++k, src += stride) {
      const glm::vec3 wk = weight[k];
      if (wk == glm::vec3(0.f)) continue;
      for (size_t i = 0; i < 9; ++i) c[i] += wk * src[i];
    }
    if (sun)
      for (size_t i = 0; i < 9; ++i) c[i] += sunE * sunCoeff_[9 * p + i];
    for (size_t i = 0; i < 9; ++i) combined_[p].c[i] = glm::dvec3(c[i]);
  }
}

radiosity::SH9 IrradianceVolume::at(const glm::dvec3& x) const {
  int i0[3];
  double f[3];
  for (int a = 0; a < 3; ++a) {
    const double g = std::clamp((x[a] - lo_[a]) / (hi_[a] - lo_[a]) * n_ - 0.5, 0.0, double(n_ - 1));
    i0[a] = std::min(int(g), n_ - 2);
    f[a] = g - i0[a];
  }
  radiosity::SH9 sh;
  double total = 0;
  for (int corner = 0; corner < 8; ++corner) {
    const int di = corner & 1, dj = (corner >> 1) & 1, dk = (corner >> 2) & 1;
    const size_t p = index(i0[0] + di, i0[1] + dj, i0[2] + dk);
    if (!inRoom_[p]) continue;
    const double w = (di ? f[0] : 1 - f[0]) * (dj ? f[1] : 1 - f[1]) * (dk ? f[2] : 1 - f[2]);
    if (w <= 0) continue;
    for (size_t c = 0; c < 9; ++c) sh.c[c] += w * combined_[p].c[c];
    total += w;
  }
  if (total > 1e-9) {
    for (auto& c : sh.c) c /= total;
    return sh;
  }
  // None of the eight is in the room: the substitute of the nearest of them.
  const size_t nearest = index(i0[0] + (f[0] >= 0.5), i0[1] + (f[1] >= 0.5), i0[2] + (f[2] >= 0.5));
  const size_t best = substitute_[nearest];
  return best < points_.size() ? combined_[best] : radiosity::SH9{};
}

}  // namespace relume::daylight
