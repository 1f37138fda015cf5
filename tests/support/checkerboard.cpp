#include "support/checkerboard.h"

#include <cmath>
#include <glm/matrix.hpp>

#include "relume/reconstruct/colmap_model.h"

namespace relume::test {

using recon::ColmapCamera;

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
          const glm::dvec3 d = Rt * glm::dvec3(n, 1.0), o = cam.center();
          const double t = -o.z / d.z;  // board plane z = 0
          double val = 0.5;
          if (t > 0) {
            const glm::dvec3 p = o + d * t;
            const double u = p.x / sq + 1, w = p.y / sq + 1;  // squares start one square before corner 0
            if (u >= -1 && w >= -1 && u < cols + 2 && w < rows + 2) {
              const bool inside = u >= 0 && w >= 0 && u < cols + 1 && w < rows + 1;
              val = inside ? ((int(std::floor(u)) + int(std::floor(w))) % 2 ? 0.95 : 0.05) : 0.95;
            }
          }
          v += val / 9;
        }
      for (int c = 0; c < 3; ++c) im.pixels[(size_t(y) * im.width + x) * 3 + c] = (unsigned char)std::lround(v * 255);
    }
  return im;
}

}  // namespace relume::test
