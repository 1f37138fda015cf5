// The hierarchical solution against a brute-force one computed here: every polygon meshed
// uniformly, the full form-factor matrix (point-to-polygon factors averaged over 2x2 points on
// each receiver, visibility from 16 random ray pairs), solved by Jacobi iteration to 1e-7.
#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <cstdio>
#include <random>

#include "relume/geometry/polygon.h"
#include "relume/radiosity/form_factor.h"
#include "relume/radiosity/hierarchy.h"
#include "relume/raytrace/ray_scene.h"
#include "support/test_rooms.h"

using namespace relume;
using namespace relume::radiosity;

namespace {
struct Patch {
  int surface;
  std::vector<glm::dvec3> verts;
  double area;
  glm::dvec3 normal;
};

// Room surfaces in `size` patches, furniture (under 1 m^2) in half that.
std::vector<Patch> uniformMesh(const std::vector<Surface>& surfaces, double roomSize) {
  std::vector<Patch> out;
  for (size_t s = 0; s < surfaces.size(); ++s) {
    const auto& v = surfaces[s].vertices;  // quads only in this test
    const double size = polygonArea(v) < 1.0 ? 0.5 * roomSize : roomSize;
    const glm::dvec3 u = v[1] - v[0], w = v[3] - v[0];
    const int nu = std::max(1, int(std::ceil(glm::length(u) / size)));
    const int nw = std::max(1, int(std::ceil(glm::length(w) / size)));
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nw; ++j) {
        const glm::dvec3 o = v[0] + u * (double(i) / nu) + w * (double(j) / nw);
        std::vector<glm::dvec3> q = {o, o + u / double(nu), o + u / double(nu) + w / double(nw), o + w / double(nw)};
        out.push_back({int(s), q, polygonArea(q), polygonNormal(q)});
      }
  }
  return out;
}
}  // namespace

TEST(BruteForce, HierarchicalSolutionWithinThreePercentPerPolygon) {
  const auto surfaces = test::furnishedRoom();
  // Brute force.
  const auto patches = uniformMesh(surfaces, 0.2);
  const size_t n = patches.size();
  std::vector<std::vector<glm::dvec3>> polys;
  for (const auto& s : surfaces) polys.push_back(s.vertices);
  RayScene rays(polys);
  std::vector<float> K(n * n, 0.f);  // E_i = sum_j K_ij B_j
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> U(0, 1);
  auto randomPoint = [&](const Patch& p) {
    const double a = U(rng), b = U(rng);
    return glm::vec3(p.verts[0] + a * (p.verts[1] - p.verts[0]) + b * (p.verts[3] - p.verts[0]) + 1e-4 * p.normal);
  };
  std::vector<glm::vec3> pa(16), pb(16);
  for (size_t i = 0; i < n; ++i) {
    const Patch& P = patches[i];
    for (size_t j = 0; j < n; ++j) {
      const Patch& Q = patches[j];
      if (P.surface == Q.surface) continue;
      double F = 0;
      for (double a : {0.25, 0.75})
        for (double b : {0.25, 0.75}) {
          const glm::dvec3 x = P.verts[0] + a * (P.verts[1] - P.verts[0]) + b * (P.verts[3] - P.verts[0]);
          F += 0.25 * pointToPolygonFormFactor(x, P.normal, Q.verts);
        }
      if (F <= 0) continue;
      for (int k = 0; k < 16; ++k) {
        pa[k] = randomPoint(P);
        pb[k] = randomPoint(Q);
      }
      K[i * n + j] = float(F * rays.visibility(pa, pb, 1e-5f));
    }
  }
  std::vector<glm::dvec3> B(n), Bn(n);
  for (size_t i = 0; i < n; ++i) B[i] = surfaces[patches[i].surface].exitance;
  for (int it = 0; it < 500; ++it) {
    double change = 0;
    for (size_t i = 0; i < n; ++i) {
      glm::dvec3 E(0.0);
      for (size_t j = 0; j < n; ++j) E += double(K[i * n + j]) * B[j];
      const Surface& s = surfaces[patches[i].surface];
      Bn[i] = s.exitance + s.reflectance * E;
      change = std::max(change, glm::length(Bn[i] - B[i]));
    }
    B.swap(Bn);
    if (change < 1e-7) break;
  }
  std::vector<glm::dvec3> mean(surfaces.size(), glm::dvec3(0.0));
  std::vector<double> area(surfaces.size(), 0.0);
  for (size_t i = 0; i < n; ++i) {
    mean[patches[i].surface] += B[i] * patches[i].area;
    area[patches[i].surface] += patches[i].area;
  }
  // Hierarchical, default options.
  HierarchicalRadiosity h(surfaces, Options{});
  h.solve();
  for (size_t s = 0; s + 1 < surfaces.size(); ++s) {  // the last surface is the lamp
    const glm::dvec3 ref = mean[s] / area[s];
    const glm::dvec3 got = h.surfaceRadiosity(int(s));
    std::printf("%-14s hierarchical %.5f %.5f %.5f  brute force %.5f %.5f %.5f  (%+.1f%% green)\n",
                surfaces[s].name.c_str(), got.x, got.y, got.z, ref.x, ref.y, ref.z, 100 * (got.y / ref.y - 1));
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(got[c], ref[c], 0.03 * ref[c]) << surfaces[s].name << " channel " << c;
  }
}
