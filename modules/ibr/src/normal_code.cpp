#include "relume/ibr/normal_code.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <vector>

namespace relume::ibr {

namespace {

// Grid cell (i, j), 0..16 each, has its centre at ((2i - 16) / 17, (2j - 16) / 17); it is a code
// when the centre lies inside the unit circle: (i - 8)^2 + (j - 8)^2 <= 72 (225 cells).
constexpr int kHalf = kNormalGrid / 2;
constexpr int kMaxR2 = 72;

struct Grid {
  std::array<glm::vec3, kNormalCodes> normal;
  std::array<int16_t, kNormalGrid * kNormalGrid> code;  // -1: cell outside the circle
  Grid() {
    int k = 0;
    for (int j = 0; j < kNormalGrid; ++j)
      for (int i = 0; i < kNormalGrid; ++i) {
        const int a = i - kHalf, b = j - kHalf;
        if (a * a + b * b > kMaxR2) {
          code[j * kNormalGrid + i] = -1;
          continue;
        }
        const float x = 2.f * float(a) / kNormalGrid, y = 2.f * float(b) / kNormalGrid;
        normal[k] = glm::vec3(x, y, std::sqrt(std::max(0.f, 1.f - x * x - y * y)));
        code[j * kNormalGrid + i] = int16_t(k++);
      }
  }
};

const Grid& grid() {
  static const Grid g;
  return g;
}

glm::vec3 lifted(glm::vec2 xy) {
  const float r2 = glm::dot(xy, xy);
  if (!(r2 <= 1.f)) {
    if (!(r2 > 0.f) || !std::isfinite(r2)) return glm::vec3(0.f, 0.f, 1.f);  // NaN: towards the viewer
    const glm::vec2 u = xy / std::sqrt(r2);
    return glm::vec3(u, 0.f);
  }
  return glm::vec3(xy, std::sqrt(1.f - r2));
}

int cellOf(float c) { return std::clamp(int(std::floor((c + 1.f) * 0.5f * kNormalGrid)), 0, kNormalGrid - 1); }

}  // namespace

const std::array<glm::vec3, kNormalCodes>& byteToNormal() { return grid().normal; }

uint8_t encodeNormal(glm::vec2 xy) {
  const Grid& g = grid();
  const glm::vec3 n = lifted(xy);
  const glm::vec2 p(n.x, n.y);
  // Start from the code nearest in the plane around the cell holding (x, y); its 3-D (chord)
  // distance d bounds the search: a code at chord distance < d lies within d in the plane too.
  const int ci = cellOf(p.x), cj = cellOf(p.y);
  int best = -1;
  float bestDot = -2.f;
  auto consider = [&](int i, int j) {
    if (i < 0 || j < 0 || i >= kNormalGrid || j >= kNormalGrid) return;
    const int k = g.code[j * kNormalGrid + i];
    if (k < 0) return;
    const float d = glm::dot(n, g.normal[k]);
    if (d > bestDot || (d == bestDot && k < best)) {
      bestDot = d;
      best = k;
    }
  };
  for (int r = 0; best < 0; ++r)  // the nearest ring of cells holding a code
    for (int j = cj - r; j <= cj + r; ++j)
      for (int i = ci - r; i <= ci + r; ++i)
        if (std::max(std::abs(i - ci), std::abs(j - cj)) == r) consider(i, j);
  // chord^2 = 2 - 2 dot; cells whose centres lie within the chord in the plane (a cell is 2/17).
  const float chord = std::sqrt(std::max(0.f, 2.f - 2.f * bestDot));
  const int reach = int(std::ceil(chord * kNormalGrid * 0.5f)) + 1;
  for (int j = cj - reach; j <= cj + reach; ++j)
    for (int i = ci - reach; i <= ci + reach; ++i) consider(i, j);
  return uint8_t(best);
}

void encodeNormalImage(std::span<const glm::vec2> normals, std::span<const uint8_t> mask, int width, int height,
                       bool dither, std::span<uint8_t> codes) {
  const auto& table = byteToNormal();
  const size_t n = size_t(width) * size_t(height);
  if (!dither) {
    for (size_t i = 0; i < n; ++i) codes[i] = mask[i] ? encodeNormal(normals[i]) : kNoNormal;
    return;
  }
  // The error is carried in all three components of the normal, not only in x and y: shading is
  // linear in the normal (n . l), so keeping the local mean of the 3-D normal keeps the local mean
  // of the shade under any light. Carrying x and y alone keeps their mean but not z's (z is concave
  // in x and y, so a mix of codes around a wanted normal has a lower mean z), which darkens a
  // surface lit from the viewer's side: on a smooth sphere lit head-on, 3 x 3-filtered shading from
  // x-y dithering is 31 dB, from 3-D dithering 39 dB. The wanted normal is kept within the unit
  // ball (the codes lie on the sphere, so an error pushing outward beyond it could never be paid
  // back), and the code chosen is the one nearest its direction, as plain coding chooses.
  std::vector<glm::vec3> next(size_t(width) + 2, glm::vec3(0.f)), cur(size_t(width) + 2, glm::vec3(0.f));
  for (int y = 0; y < height; ++y) {
    std::swap(cur, next);
    std::fill(next.begin(), next.end(), glm::vec3(0.f));
    for (int x = 0; x < width; ++x) {
      const size_t i = size_t(y) * width + x;
      if (!mask[i]) {
        codes[i] = kNoNormal;
        continue;
      }
      glm::vec3 want = lifted(normals[i]) + cur[x + 1];
      const float len = glm::length(want);
      if (len > 1.f) want /= len;
      // Its direction, on the viewer's side (encodeNormal takes x and y of a unit normal).
      glm::vec3 dir(want.x, want.y, std::max(0.f, want.z));
      const float dl = glm::length(dir);
      const uint8_t c = dl > 1e-6f ? encodeNormal(glm::vec2(dir) / dl) : encodeNormal(glm::vec2(0.f));
      codes[i] = c;
      const glm::vec3 err = want - table[c];
      auto inside = [&](int xx, int yy) { return xx >= 0 && xx < width && yy < height && mask[size_t(yy) * width + xx]; };
      if (inside(x + 1, y)) cur[x + 2] += err * (7.f / 16.f);
      if (inside(x - 1, y + 1)) next[x] += err * (3.f / 16.f);
      if (inside(x, y + 1)) next[x + 1] += err * (5.f / 16.f);
      if (inside(x + 1, y + 1)) next[x + 2] += err * (1.f / 16.f);
    }
  }
}

int longestCodeRun(std::span<const uint8_t> codes, int width, int height, int onlyRow) {
  int best = 0;
  for (int y = 0; y < height; ++y) {
    if (onlyRow >= 0 && y != onlyRow) continue;
    int run = 0, last = -1;
    for (int x = 0; x < width; ++x) {
      const int c = codes[size_t(y) * size_t(width) + size_t(x)];
      run = (c != kNoNormal && c == last) ? run + 1 : 1;
      last = c;
      if (c != kNoNormal) best = std::max(best, run);
    }
  }
  return best;
}

}  // namespace relume::ibr
