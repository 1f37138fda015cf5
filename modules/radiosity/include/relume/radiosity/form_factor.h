#pragma once
// Form factors: the exact point-to-polygon formula (Lambert / Hottel contour integral) and
// area-to-area factors by Gauss-Legendre quadrature over the receiver.
#include <functional>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <memory>
#include <vector>

#include "relume/geometry/photometry.h"

namespace relume::radiosity {

// Light from infinitely far away that enters through an opening (a window): the radiance arriving
// along each direction (the sky, the ground) and parallel beams (the sun). The opening's exitance
// B scales it: the radiance arriving along d is B / pi x radiance(d), a beam's irradiance normal
// to it B / pi x irradiance. Directions are unit vectors from the room out through the opening.
struct DistantLight {
  std::function<double(const glm::dvec3&)> radiance;  // null: no diffuse part
  // Optional: false when no direction within `halfAngle` (radians) of `axis` carries light, so
  // that the pieces of the opening seen there are skipped (a sky region's basis is dark elsewhere).
  std::function<bool(const glm::dvec3& axis, double halfAngle)> mayShine;
  // Optional: true when radiance() is the same along every direction within `halfAngle` of
  // `axis` (a sky region's basis inside its cell). A piece seen within such a cone is not cut
  // further for the cosine-weighted factor: the exact factor of the whole piece is the sum of its
  // parts', so only the pieces across a change of radiance are cut down to pieceDeg.
  std::function<bool(const glm::dvec3& axis, double halfAngle)> uniform;
  struct Beam {
    glm::dvec3 direction{0.0, 0.0, 1.0};  // towards the source
    double irradiance = 1.0;
  };
  std::vector<Beam> beams;
  // The opening is cut into pieces that the receiving point sees no wider than this (degrees);
  // within a piece the radiance is taken along the direction of its centre.
  double pieceDeg = 1.5;
};

// The point factor of an opening: (1 / pi) x the radiance-weighted projected solid angle of
// `poly` seen from p (normal n), plus each beam's irradiance x cos / pi where its ray from p
// passes through `poly`; 0 unless p lies in front of the opening's face (its normal points into
// the room).
double distantFormFactor(const glm::dvec3& p, const glm::dvec3& n, const std::vector<glm::dvec3>& poly,
                         const DistantLight& light, bool withBeams = true);
// Where the ray from p along d crosses the convex polygon (its normal nPoly, vertices
// counter-clockwise about it): the distance along d, or -1 when it passes beside or behind.
double rayThroughPolygon(const glm::dvec3& p, const glm::dvec3& d, const std::vector<glm::dvec3>& poly,
                         const glm::dvec3& nPoly);
// (1 / pi) x the radiance integrated over the solid angle of `poly` seen from p, without the
// cosine (what an isotropic receiver gathers, times 4), beams counted whole.
double distantSolidAngleFactor(const glm::dvec3& p, const std::vector<glm::dvec3>& poly, const DistantLight& light);

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
  // An opening: what shines in through it (see DistantLight), instead of a face or a distribution.
  std::shared_ptr<const DistantLight> distant;
  double transmitted = 1.0;  // an opening's exitance over B: (1 / pi) x its light's projected integral

  EmitterShape(bool twoSidedFaces = false) : twoSided(twoSidedFaces) {}  // NOLINT: a plain face is a bool
  // The distribution placed on `polygon` (convex, its normal the nadir); null: Lambertian faces.
  EmitterShape(const std::vector<glm::dvec3>& polygon, bool twoSidedFaces,
               std::shared_ptr<const PhotometricDistribution> distribution,
               std::shared_ptr<const DistantLight> distantLight = nullptr);

  // Does it light what lies behind its plane?
  bool emitsBehind() const { return distant ? false : photometry ? upward : twoSided; }
  // Faces whose exitance count towards its power (a distribution's exitance is all of it; an
  // opening's is what its light brings in).
  double faces() const { return distant ? transmitted : twoSided && !photometry ? 2.0 : 1.0; }
  // Radiance towards p relative to a Lambertian face of the same exitance (1 without a distribution).
  double weight(const glm::dvec3& p) const;
};

// Differential area at p (unit normal n) to the convex polygon `poly`. The polygon is clipped to
// the hemisphere above p; a polygon seen from its back contributes 0.
double pointToPolygonFormFactor(const glm::dvec3& p, const glm::dvec3& n,
                                const std::vector<glm::dvec3>& poly);

// The same from an emitter: a two-sided one is seen from either side (its face towards p), a
// photometric one weighted by its distribution towards p, an opening by its distant light.
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
