// Normal coding (Dinh, Metoyer, Turk §3, after Glassner): the 225 codes, nearest-code encoding
// against brute force, and Floyd-Steinberg dithering against the banding of plain coding.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <random>
#include <vector>

#include "relume/ibr/normal_code.h"

using namespace relume::ibr;

TEST(NormalCode, TwoHundredTwentyFiveUnitNormalsFacingTheViewerOnASeventeenGrid) {
  const auto& t = byteToNormal();
  ASSERT_EQ(t.size(), 225u);
  for (const auto& n : t) {
    EXPECT_NEAR(glm::length(n), 1.f, 1e-6f);
    EXPECT_GT(n.z, 0.f);
    // Grid centres: x and y are (2i - 16) / 17.
    for (float c : {n.x, n.y}) {
      const float i = (c * 17.f + 16.f) / 2.f;
      EXPECT_NEAR(i, std::round(i), 1e-4f);
    }
  }
  // (0, 0, 1) is a code; (1, 0, 0) is not (the rim is left out).
  EXPECT_TRUE(std::any_of(t.begin(), t.end(), [](const glm::vec3& n) { return n.z == 1.f; }));
  EXPECT_FALSE(std::any_of(t.begin(), t.end(), [](const glm::vec3& n) { return n.x > 0.999f; }));
  // Every code encodes to itself.
  for (size_t k = 0; k < t.size(); ++k) EXPECT_EQ(encodeNormal(glm::vec2(t[k].x, t[k].y)), k);
}

TEST(NormalCode, EncodingPicksTheNearestOfTheCodesForAnyNormalFacingTheViewer) {
  const auto& t = byteToNormal();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  int checked = 0;
  while (checked < 100000) {
    glm::vec3 n(u(rng), u(rng), u(rng));
    const float l = glm::length(n);
    if (l > 1.f || l < 1e-3f) continue;
    n /= l;
    n.z = std::abs(n.z);
    int best = 0;
    for (int k = 1; k < 225; ++k)
      if (glm::dot(n, t[size_t(k)]) > glm::dot(n, t[size_t(best)])) best = k;
    const uint8_t c = encodeNormal(glm::vec2(n.x, n.y));
    // Equal dot products (ties) may pick either.
    ASSERT_FLOAT_EQ(glm::dot(n, t[c]), glm::dot(n, t[size_t(best)])) << n.x << " " << n.y << " " << n.z;
    ++checked;
  }
}

namespace {
// A sphere's normal image (width x width), its silhouette as the mask.
void sphereNormals(int w, std::vector<glm::vec2>& xy, std::vector<uint8_t>& mask) {
  xy.assign(size_t(w) * w, glm::vec2(0.f));
  mask.assign(size_t(w) * w, 0);
  for (int y = 0; y < w; ++y)
    for (int x = 0; x < w; ++x) {
      const float a = (x + 0.5f) / w * 2 - 1, b = 1 - (y + 0.5f) / w * 2;
      if (a * a + b * b >= 0.98f) continue;
      xy[size_t(y) * w + x] = glm::vec2(a, b);
      mask[size_t(y) * w + x] = 1;
    }
}


// PSNR of Lambertian shading max(0, n . l) from the codes against the exact normals', over the
// pixels whose 3 x 3 neighbourhood lies inside the mask, optionally after a 3 x 3 box filter of both.
double shadingPsnr(const std::vector<glm::vec2>& xy, const std::vector<uint8_t>& mask, const std::vector<uint8_t>& codes,
                   int w, glm::vec3 l, bool filter) {
  l = glm::normalize(l);
  std::vector<double> truth(xy.size(), 0.0), coded(xy.size(), 0.0);
  for (size_t i = 0; i < xy.size(); ++i) {
    if (!mask[i]) continue;
    const glm::vec3 n(xy[i], std::sqrt(std::max(0.f, 1.f - glm::dot(xy[i], xy[i]))));
    truth[i] = std::max(0.f, glm::dot(n, l));
    coded[i] = std::max(0.f, glm::dot(byteToNormal()[codes[i]], l));
  }
  double se = 0;
  size_t n = 0;
  for (int y = 1; y + 1 < w; ++y)
    for (int x = 1; x + 1 < w; ++x) {
      bool inside = true;
      double t = 0, c = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const size_t j = size_t(y + dy) * w + x + dx;
          inside = inside && mask[j];
          t += truth[j] / 9;
          c += coded[j] / 9;
        }
      if (!inside) continue;
      if (!filter) {
        t = truth[size_t(y) * w + x];
        c = coded[size_t(y) * w + x];
      }
      se += (t - c) * (t - c);
      ++n;
    }
  return 10 * std::log10(1.0 / (se / double(n)));
}
}  // namespace

TEST(NormalCode, DitheringKeepsTheLocalMeanNormalAndShadingCloserThanPlainCoding) {
  const int w = 256;
  std::vector<glm::vec2> xy;
  std::vector<uint8_t> mask;
  sphereNormals(w, xy, mask);
  std::vector<uint8_t> plain(xy.size()), dithered(xy.size());
  encodeNormalImage(xy, mask, w, w, false, plain);
  encodeNormalImage(xy, mask, w, w, true, dithered);
  // Bands: runs of one code along a row (one code, one shade under any light).
  const int runPlain = longestCodeRun(plain, w, w), runDithered = longestCodeRun(dithered, w, w);
  std::printf("longest run of one code along a row: plain %d, dithered %d pixels (middle row: %d, %d)\n", runPlain,
              runDithered, longestCodeRun(plain, w, w, w / 2), longestCodeRun(dithered, w, w, w / 2));
  EXPECT_LT(runDithered, runPlain);
  // Averaged over 4 x 4 blocks (what the eye and a display filter see), the dithered normals are
  // much nearer the true ones than plain coding's.
  double errPlain = 0, errDithered = 0;
  int blocks = 0;
  for (int by = 0; by + 4 <= w; by += 4)
    for (int bx = 0; bx + 4 <= w; bx += 4) {
      glm::dvec2 truth(0.0), p(0.0), d(0.0);
      bool full = true;
      for (int y = by; y < by + 4; ++y)
        for (int x = bx; x < bx + 4; ++x) {
          const size_t i = size_t(y) * w + x;
          full = full && mask[i];
          if (!mask[i]) continue;
          truth += glm::dvec2(xy[i]);
          p += glm::dvec2(byteToNormal()[plain[i]].x, byteToNormal()[plain[i]].y);
          d += glm::dvec2(byteToNormal()[dithered[i]].x, byteToNormal()[dithered[i]].y);
        }
      if (!full) continue;
      errPlain += glm::length(p - truth) / 16;
      errDithered += glm::length(d - truth) / 16;
      ++blocks;
    }
  std::printf("mean error of 4x4 block-mean normals: plain %.4f, dithered %.4f\n", errPlain / blocks, errDithered / blocks);
  EXPECT_LT(errDithered, 0.5 * errPlain);
  // Shading from the codes against exact shading, per pixel and after a 3 x 3 box filter, for
  // three lights: the filtered dithered shading much closer than the filtered plain (6 dB: the
  // error is carried in all of the normal's components, so the mean shade is kept, not only the
  // mean x and y — dithering x and y alone gains only 3.3 dB for the first light).
  for (const glm::vec3 l : {glm::vec3(0.6f, 0.f, 0.8f), glm::vec3(0.5f, 0.5f, 0.7f), glm::vec3(-0.9f, 0.2f, 0.4f)}) {
    const double pp = shadingPsnr(xy, mask, plain, w, l, false), pf = shadingPsnr(xy, mask, plain, w, l, true);
    const double dp = shadingPsnr(xy, mask, dithered, w, l, false), df = shadingPsnr(xy, mask, dithered, w, l, true);
    std::printf("light (%.1f, %.1f, %.1f): plain %.1f dB per pixel, %.1f dB filtered; dithered %.1f dB, %.1f dB filtered\n",
                l.x, l.y, l.z, pp, pf, dp, df);
    EXPECT_GT(df, pf + 6.0);
  }
  // Outside the mask: no code.
  for (size_t i = 0; i < mask.size(); ++i)
    if (!mask[i]) ASSERT_EQ(dithered[i], kNoNormal);
}
