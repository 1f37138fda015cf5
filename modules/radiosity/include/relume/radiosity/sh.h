#pragma once
// The light arriving at a point of a radiosity solution as spherical harmonics (order 2, 9
// coefficients per colour; Ramamoorthi and Hanrahan 2001), and the irradiance they give for any
// normal. The one place that evaluates a solution's incident light at a point: image-based
// objects (their indirect light) and the daylight irradiance volume use it.
#include <array>
#include <glm/vec3.hpp>
#include <vector>

namespace relume {
class RayScene;
}

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

// `count` directions of about equal solid angle over the sphere (a Fibonacci spiral).
std::vector<glm::dvec3> fibonacciSphere(int count);

// The radiance arriving at `point` from every direction, projected: `rays` directions on a
// Fibonacci sphere, each hit's leaf radiosity / pi (front faces; back faces and misses give 0).
// Without emission, emitters' own exitance is left out (their direct light is taken elsewhere);
// only light the surfaces reflect remains.
SH9 incidentRadiance(const HierarchicalRadiosity& h, const glm::dvec3& point, bool withEmission, int rays = 4096);

// Transfer coefficients of a diffuse point (Sloan et al. 2002; Grosch et al. 2007 Eq. 5): C_lm =
// the integral of max(0, n . w) V(w) Y_lm(w) dw, V from rays against `occluders` (an object
// itself: its own shadowing of the room's light); null: unshadowed, C_lm = A_l Y_lm(n) exactly.
using SHTransfer = std::array<double, 9>;
SHTransfer shTransfer(const glm::dvec3& point, const glm::dvec3& n, const RayScene* occluders, int rays = 256);
// sum L_lm C_lm: the irradiance the transfer lets through (clamped at 0; x rho / pi for radiance).
glm::dvec3 shApply(const SH9& light, const SHTransfer& transfer);

}  // namespace relume::radiosity
