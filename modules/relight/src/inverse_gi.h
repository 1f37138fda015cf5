#pragma once
// Inverse global illumination (Yu, Debevec, Malik, Hawkins 1999) for a photographed room whose
// lamps are seen by few or no photos: per element the photo gives its radiosity y, the geometry
// its visible direct form factor G_l to each lamp, and the photographed radiance of everything it
// sees its indirect irradiance I (measured, not simulated). With one reflectance rho_s per
// polygon and one exitance m_l per lamp,
//     y = rho_s (sum_l m_l G_l + I)   <=>   a_s y - sum_l G_l m_l = I,   a_s = 1 / rho_s,
// which is linear in (a, m): one weighted least-squares problem per colour channel. The measured
// indirect light (the right-hand side) fixes the absolute scale; the real shadows — elements
// where some lamps are blocked and others are not — separate the lamps.
#include <glm/vec3.hpp>
#include <optional>
#include <string>
#include <vector>

namespace relume::detail {

struct JointFitRow {
  int polygon = -1;
  double area = 0;
  glm::dvec3 y{0.0};      // photographed radiosity (pi x radiance)
  std::vector<double> G;  // per lamp: form factor x visibility (unit exitance)
  glm::dvec3 I{0.0};      // indirect irradiance (measured)
  // Per lamp: the indirect irradiance it brings per unit exitance where no photo measured it
  // (simulated), per channel; empty: none.
  std::vector<glm::dvec3> S;
};

struct JointFitResult {
  bool ok = false;
  std::string reason;                   // why not, when !ok
  std::vector<glm::dvec3> reflectance;  // per polygon (0 where no row)
  std::vector<glm::dvec3> exitance;     // per lamp
  std::vector<double> uncertainty;      // per lamp: relative standard error (mean of the channels)
  std::vector<double> polygonWeight;    // per polygon: its robust weight (1: fits the model well)
  double meanReflectance = 0;           // area mean over the rows (grey)
};

// `guess`: per lamp a starting exitance (the relative weights of the first round); `fixed`:
// lamps whose exitance is known (photographed), held.
JointFitResult jointFit(const std::vector<JointFitRow>& rows, size_t polygons, const std::vector<glm::dvec3>& guess,
                        const std::vector<std::optional<glm::dvec3>>& fixed);

// Small dense solve (Gaussian elimination with partial pivoting); false when singular.
bool solveDense(std::vector<std::vector<double>> A, std::vector<double> b, std::vector<double>& x);

}  // namespace relume::detail
