#pragma once
// The light arriving at a point of a radiosity solution as spherical harmonics (order 2, 9
// coefficients per colour; Ramamoorthi and Hanrahan 2001), and the irradiance they give for any
// normal. The one place that evaluates a solution's incident light at a point: image-based
// objects (their indirect light) and the daylight irradiance volume use it.
#include <array>
#include <glm/vec3.hpp>

namespace relume::radiosity {

class HierarchicalRadiosity;

struct SH9 {
  std::array<glm::dvec3, 9> c{};  // radiance coefficients L_lm (RGB), real basis, l = 0..2
};

// The nine real basis functions at a unit direction (order: 00, 1-1, 10, 11, 2-2, 2-1, 20, 21, 22).
std::array<double, 9> shBasis(const glm::dvec3& d);

// Irradiance E(n) = sum_l A_l sum_m L_lm Y_lm(n), A = (pi, 2 pi / 3, pi / 4): exact for the
// projected radiance (the order-2 projection keeps irradiance within a few percent).
glm::dvec3 shIrradiance(const SH9& sh, const glm::dvec3& n);

// The radiance arriving at `point` from every direction, projected: `rays` directions on a
// Fibonacci sphere, each hit's leaf radiosity / pi (front faces; back faces and misses give 0).
// Without emission, emitters' own exitance is left out (their direct light is taken elsewhere);
// only light the surfaces reflect remains.
SH9 incidentRadiance(const HierarchicalRadiosity& h, const glm::dvec3& point, bool withEmission, int rays = 4096);

}  // namespace relume::radiosity
