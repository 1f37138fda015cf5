#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>

#include "relume/ibr/mesh.h"

namespace relume::ibr {

Mesh bumpyBall(int nu, int nv, double r, double bump) {
  Mesh m;
  m.name = "bumpy ball";
  auto at = [&](double th, double ph) {
    const double rr = r * (1 + bump * std::sin(3 * th) * std::cos(4 * ph));
    return glm::vec3(float(rr * std::sin(th) * std::cos(ph)), float(rr * std::sin(th) * std::sin(ph)),
                     float(rr * std::cos(th) + r * (1 + bump)));
  };
  m.positions.push_back(at(0, 0));
  for (int j = 1; j < nv; ++j)
    for (int i = 0; i < nu; ++i) m.positions.push_back(at(std::numbers::pi * j / nv, 2 * std::numbers::pi * i / nu));
  m.positions.push_back(at(std::numbers::pi, 0));
  const unsigned bottom = unsigned(m.positions.size() - 1);
  auto ring = [&](int j, int i) { return unsigned(1 + (j - 1) * nu + (i % nu)); };
  for (int i = 0; i < nu; ++i) m.triangles.push_back({0u, ring(1, i), ring(1, i + 1)});
  for (int j = 1; j + 1 < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      m.triangles.push_back({ring(j, i), ring(j + 1, i), ring(j + 1, i + 1)});
      m.triangles.push_back({ring(j, i), ring(j + 1, i + 1), ring(j, i + 1)});
    }
  for (int i = 0; i < nu; ++i) m.triangles.push_back({bottom, ring(nv - 1, i + 1), ring(nv - 1, i)});
  std::vector<glm::vec3> vn(m.positions.size(), glm::vec3(0.f));
  for (const auto& t : m.triangles) {
    const glm::vec3 n = glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
    for (int k = 0; k < 3; ++k) vn[t[k]] += n;
  }
  m.cornerNormals.reserve(3 * m.triangles.size());
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) m.cornerNormals.push_back(glm::normalize(vn[t[k]]));
  m.triangleAlbedo.assign(m.triangles.size(), glm::vec3(kDefaultAlbedo));
  return m;
}

}  // namespace relume::ibr
