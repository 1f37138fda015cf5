#pragma once
// Form factors: the exact point-to-polygon formula (Lambert / Hottel contour integral) and
// area-to-area factors by Gauss-Legendre quadrature over the receiver.
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <memory>
#include <vector>

#include "relume/geometry/photometry.h"

namespace relume::radiosity {

// How an emitter polygon sends its exitance out: from the face its normal points to (Lambertian),
// from both faces alike, or with a luminaire's photometric distribution over all directions. A
// distribution is applied in the far field, as photometry is measured: the radiance towards a
// point is that of the direction from the polygon's centre, relative to a Lambertian face of the
// same exitance, w = pi I(C, gamma) / (Phi |cos gamma|), gamma from the polygon's normal (the
// nadir) and C from its first edge (C0) towards C90 = C0 x nadir (counter-clockwise seen from
// above a downlight). Its exitance is then the whole flux over the polygon's area.
struct EmitterShape {
  bool twoSided = false;
  std::shared_ptr<const PhotometricDistribution> photometry;
  glm::dvec3 centre{0.0}, nadir{0.0, 0.0, -1.0}, c0{1.0, 0.0, 0.0}, c90{0.0, 1.0, 0.0};
  double flux = 1.0;    // the distribution's own (lm)
  double peak = 1.0;    // pi I_max / flux: the most the kernel F w exceeds a Lambertian face's (1 for one)
  bool upward = false;  // the distribution sends light behind the polygon's plane (gamma > 90)

  EmitterShape(bool twoSidedFaces = false) : twoSided(twoSidedFaces) {}  // NOLINT: a plain face is a bool
  // The distribution placed on `polygon` (convex, its normal the nadir); null: Lambertian faces.
  EmitterShape(const std::vector<glm::dvec3>& polygon, bool twoSidedFaces,
               std::shared_ptr<const PhotometricDistribution> distribution);

  // Does it light what lies behind its plane?
  bool emitsBehind() const { return photometry ? upward : twoSided; }
  // Faces whose exitance count towards its power (a distribution's exitance is all of it).
  double faces() const { return twoSided && !photometry ? 2.0 : 1.0; }
  // Radiance towards p relative to a Lambertian face of the same exitance (1 without a distribution).
  double weight(const glm::dvec3& p) const;
};

// Differential area at p (unit normal n) to the convex polygon `poly`. The polygon is clipped to
// the hemisphere above p; a polygon seen from its back contributes 0.
double pointToPolygonFormFactor(const glm::dvec3& p, const glm::dvec3& n,
                                const std::vector<glm::dvec3>& poly);

// The same from an emitter: a two-sided one is seen from either side (its face towards p), a
// photometric one weighted by its distribution towards p.
double emitterFormFactor(const glm::dvec3& p, const glm::dvec3& n, const std::vector<glm::dvec3>& poly,
                         const EmitterShape& shape);

// The point factor from an emitter averaged over an element: the rectangle [uv0, uv1] of a plane
// (world = origin + u * du + v * dv, unit normal n) clipped to the convex polygon uvPolygon (plane
// coordinates). Adaptive: a cell is split while the factor varies across it by more than
// `tolerance` of its largest value, or while the emitter hangs closer in front of it than the
// cell is wide (a peak its sample points could all miss), down to `maxDepth` levels. `minimum` and
// `maximum` get the extremes of the samples (the kernel's spread over the element).
struct ElementFactor {
  double mean = 0, minimum = 0, maximum = 0;
};
ElementFactor emitterFormFactorOverElement(const glm::dvec3& origin, const glm::dvec3& du, const glm::dvec3& dv,
                                           const glm::dvec3& n, const std::vector<glm::dvec2>& uvPolygon,
                                           glm::dvec2 uv0, glm::dvec2 uv1, const std::vector<glm::dvec3>& emitter,
                                           const EmitterShape& shape, double tolerance = 0.05, int maxDepth = 6);

// F_{A->B}: fraction of the energy leaving polygon A (diffusely) that arrives at polygon B, with
// no occlusion: the mean over A of the point-to-polygon factor, using an order x order
// Gauss-Legendre rule on each triangle-fan quadrilateral of A (order 1..8).
double polygonToPolygonFormFactor(const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b,
                                  int order = 4);

// Gauss-Legendre nodes on [0,1] and their weights (summing to 1), order 1..8.
void gaussLegendre01(int order, std::vector<double>& nodes, std::vector<double>& weights);

}  // namespace relume::radiosity
