#include "support/checkerboard.h"

#include <algorithm>
#include <cmath>
#include <vector>
#include <glm/matrix.hpp>

#include "relume/reconstruct/colmap_model.h"

namespace relume::test {

using recon::ColmapCamera;

namespace {
// The board's grey along a world ray from `o`: the squares (cols + 1 x rows + 1 of them from one
// square before corner 0), a white border a square wide, mid-grey beyond.
double boardAlong(const glm::dvec3& o, const glm::dvec3& d, int cols, int rows, double sq) {
  const double t = -o.z / d.z;  // board plane z = 0
  if (!(t > 0)) return 0.5;
  const glm::dvec3 p = o + d * t;
  const double u = p.x / sq + 1, w = p.y / sq + 1;
  if (!(u >= -1 && w >= -1 && u < cols + 2 && w < rows + 2)) return 0.5;
  const bool inside = u >= 0 && w >= 0 && u < cols + 1 && w < rows + 1;
  return inside ? ((int(std::floor(u)) + int(std::floor(w))) % 2 ? 0.95 : 0.05) : 0.95;
}
}  // namespace

Image8 renderFisheyeCheckerboard(const Camera& cam, double f, double cx, double cy, const double (&k)[4], int cols, int rows,
                                 double sq) {
  Image8 im;
  im.width = cam.width;
  im.height = cam.height;
  im.pixels.resize(size_t(im.width) * im.height * 3);
  const glm::dmat3 Rt = glm::transpose(cam.R);
  auto thetaD = [&](double t) {
    const double t2 = t * t;
    return t * (1 + t2 * (k[0] + t2 * (k[1] + t2 * (k[2] + t2 * k[3]))));
  };
  // theta from theta_d through a table of the model (the test's own inverse), 0 to 100 degrees.
  constexpr int kTable = 4096;
  const double top = 100 * M_PI / 180;
  std::vector<double> table(kTable + 1);
  for (int i = 0; i <= kTable; ++i) table[size_t(i)] = thetaD(top * i / kTable);
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x) {
      double v = 0;
      for (int sy = 0; sy < 3; ++sy)
        for (int sx = 0; sx < 3; ++sx) {
          const double a = (x + (sx + 0.5) / 3 - cx) / f, b = (y + (sy + 0.5) / 3 - cy) / f, td = std::hypot(a, b);
          if (td >= table.back()) continue;  // beyond the lens: black
          const size_t j = size_t(std::upper_bound(table.begin(), table.end(), td) - table.begin()) - 1;
          const double th = top * (double(j) + (td - table[j]) / (table[j + 1] - table[j])) / kTable;
          const glm::dvec3 dc = td > 0 ? glm::dvec3(std::sin(th) * a / td, std::sin(th) * b / td, std::cos(th)) : glm::dvec3(0, 0, 1);
          v += boardAlong(cam.center(), Rt * dc, cols, rows, sq) / 9;
        }
      for (int c = 0; c < 3; ++c) im.pixels[(size_t(y) * im.width + x) * 3 + c] = (unsigned char)std::lround(v * 255);
    }
  return im;
}

Image8 renderCheckerboard(const Camera& cam, double k1, int cols, int rows, double sq) {
  Image8 im;
  im.width = cam.width;
  im.height = cam.height;
  im.pixels.resize(size_t(im.width) * im.height * 3);
  ColmapCamera cc{1, "RADIAL", cam.width, cam.height, {cam.fx(), cam.cx(), cam.cy(), k1, 0}};
  const glm::dmat3 Rt = glm::transpose(cam.R);
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x) {
      double v = 0;
      for (int sy = 0; sy < 3; ++sy)
        for (int sx = 0; sx < 3; ++sx) {
          const glm::dvec2 n = cc.undistort({x + (sx + 0.5) / 3, y + (sy + 0.5) / 3});
          v += boardAlong(cam.center(), Rt * glm::dvec3(n, 1.0), cols, rows, sq) / 9;
        }
      for (int c = 0; c < 3; ++c) im.pixels[(size_t(y) * im.width + x) * 3 + c] = (unsigned char)std::lround(v * 255);
    }
  return im;
}

}  // namespace relume::test
