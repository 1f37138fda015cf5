#pragma once
// The dynamic irradiance volume (Grosch, Eble, Mueller 2007, §5.1-5.2 and §6.2-6.3; after
// Greger et al. 1998): a grid of points inside the room, at each the indirect light arriving from
// every direction as nine spherical-harmonic coefficients per colour, one set per basis solution
// (each sky region, the ground, the sun of the current sky). The windows' own light is left out
// (rays that leave through a window carry nothing): only light the room's surfaces reflect is
// held, the direct daylight is sampled through the windows apart. For a new sky the coefficients
// are the bases' weighted sum (Eq. 4), for the grid points an object needs; an object is shaded
// with transfer coefficients (Eq. 5), radiance = rho / pi x sum L_lm C_lm.
//
// The projection of a solution's light onto the basis functions is radiosity::sh's (one place for
// image-based objects and daylight alike); here each point's rays are cast once and grouped by the
// element they hit, so that every basis is projected by a weighted sum over those elements.
#include <array>
#include <cstdint>
#include <glm/vec3.hpp>
#include <vector>

#include "relume/daylight/sky.h"
#include "relume/geometry/progress.h"
#include "relume/radiosity/sh.h"

namespace relume::daylight {

class DaylightBasis;

struct VolumeOptions {
  int grid = 8;     // points per axis (grid^3 in all), at the centres of the room box's cells
  int rays = 2048;  // directions per point (a Fibonacci sphere)
};

class IrradianceVolume {
 public:
  // Casts every point's rays against the basis's room (virtual objects must not be in it: the
  // volume holds the room's light) and projects every stored basis. Throws relume::Error for a
  // grid below 2 or above 32 points per axis (at 32^3 points the coefficients of 65 bases are
  // ~230 MB, and the rays' hit lists, up to 40 bytes per ray and point, can reach GBs).
  // Progress throughout; Cancel leaves nothing.
  IrradianceVolume(const DaylightBasis& basis, const VolumeOptions& options = {}, Progress& progress = silentProgress());

  int resolution() const { return n_; }
  size_t pointCount() const { return points_.size(); }
  const glm::dvec3& point(size_t p) const { return points_[p]; }
  // Whether point p is in the room's free air. A point buried in furniture or behind a wall sees
  // back faces; it is not, and takes no part in interpolation.
  bool inRoom(size_t p) const { return inRoom_[p] != 0; }
  glm::dvec3 lower() const { return lo_; }
  glm::dvec3 upper() const { return hi_; }
  int basisCount() const { return bases_; }
  // The coefficients of basis k at point p (k < basisCount(): the basis's own numbering, the
  // ground last; radiance per unit radiance of the region).
  radiosity::SH9 basisAt(int k, size_t p) const;

  // Eq. 4 for `sky` at every grid point or, with a box, only at the points a position inside it
  // interpolates from. The sun's term projects the basis's sun solution for the sky's sun (solved
  // and projected once per sun direction). Whatever at() reads for a position in the box is
  // combined, the substitutes of points out of the room included.
  void combine(DaylightBasis& basis, const SkyRadiance& sky, Progress& progress = silentProgress());
  void combine(DaylightBasis& basis, const SkyRadiance& sky, const glm::dvec3& boxLo, const glm::dvec3& boxHi,
               Progress& progress = silentProgress());
  // The combined coefficients at x: trilinear over the surrounding points that are inside the
  // room (weights renormalised; with none of the eight, the point in the room nearest to the
  // nearest of the eight, found once at construction). Positions
  // beyond the outermost points take the border's values.
  radiosity::SH9 at(const glm::dvec3& x) const;
  // The combined coefficients of point p as the last combine() that included it left them (a
  // combine over a box leaves the points outside it as an earlier sky made them).
  const radiosity::SH9& combinedAt(size_t p) const { return combined_[p]; }

  double buildSeconds() const { return buildSeconds_; }

 private:
  int n_ = 8, bases_ = 0;
  glm::dvec3 lo_{0.0}, hi_{0.0};
  std::vector<glm::dvec3> points_;
  std::vector<uint8_t> inRoom_;  // bytes: written from several threads
  std::vector<size_t> substitute_;  // per point: itself if in the room, else the nearest point that is
  // Per point: the elements its rays hit and, per element, the sum of the hitting rays'
  // projection weights (4 pi / rays x Y_lm(d) / pi: a radiosity times it is radiance coefficients).
  struct Hit {
    int node;
    std::array<float, 9> w;
  };
  std::vector<std::vector<Hit>> hits_;
  std::vector<glm::vec3> coeff_;  // [basis][point][9]
  std::vector<glm::vec3> sunCoeff_;  // [point][9], per unit beam irradiance, for sunDirection_
  glm::dvec3 sunDirection_{0.0};
  bool haveSun_ = false;
  std::vector<radiosity::SH9> combined_;
  double buildSeconds_ = 0;
  size_t index(int i, int j, int k) const { return (size_t(k) * size_t(n_) + size_t(j)) * size_t(n_) + size_t(i); }
  void project(const std::vector<glm::vec3>& solution, glm::vec3* out) const;
  void combinePoints(DaylightBasis& basis, const SkyRadiance& sky, const std::vector<size_t>& points, Progress& progress);
};

}  // namespace relume::daylight
