#pragma once
// Form factors: the exact point-to-polygon formula (Lambert / Hottel contour integral) and
// area-to-area factors by Gauss-Legendre quadrature over the receiver.
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <vector>

namespace relume::radiosity {

// Differential area at p (unit normal n) to the convex polygon `poly`. The polygon is clipped to
// the hemisphere above p; a polygon seen from its back contributes 0.
double pointToPolygonFormFactor(const glm::dvec3& p, const glm::dvec3& n,
                                const std::vector<glm::dvec3>& poly);

// The same from an emitter: a two-sided one is seen from either side (its face towards p).
double emitterFormFactor(const glm::dvec3& p, const glm::dvec3& n, const std::vector<glm::dvec3>& poly,
                         bool twoSided);

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
                                           bool twoSided, double tolerance = 0.05, int maxDepth = 6);

// F_{A->B}: fraction of the energy leaving polygon A (diffusely) that arrives at polygon B, with
// no occlusion: the mean over A of the point-to-polygon factor, using an order x order
// Gauss-Legendre rule on each triangle-fan quadrilateral of A (order 1..8).
double polygonToPolygonFormFactor(const std::vector<glm::dvec3>& a, const std::vector<glm::dvec3>& b,
                                  int order = 4);

// Gauss-Legendre nodes on [0,1] and their weights (summing to 1), order 1..8.
void gaussLegendre01(int order, std::vector<double>& nodes, std::vector<double>& weights);

}  // namespace relume::radiosity
