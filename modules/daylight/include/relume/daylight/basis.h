#pragma once
// Basis radiosity solutions (Grosch, Eble, Mueller 2007, §5 and §6.1) on Relume's one engine.
//
// The paper puts an area emitter of unit radiance on each region of a hemisphere around the
// scene. Here the room's windows are the emitters instead: a window is an opening whose radiance
// towards a point of the room is the sky's radiance along the direction from that point out
// through the window (radiosity::DistantLight). Why: it needs no geometry outside the room (a
// hemisphere of emitters tens of metres across would make the top of the cluster hierarchy and
// its isotropic estimates useless), the direction is exact for every receiving point (a hemisphere
// at a finite distance is exact only at its centre), and where the light falls is decided by the
// window's own outline, which is the room's model.
//
// Basis k < N: region k of the sky (daylight::SkyRegions) at unit radiance, all else dark. Basis
// N: the ground, every direction below the horizon at unit radiance (the outside ground as a
// uniform diffuse reflector); the model's outside polygons (a ground plane beyond the window) are
// left out of the engine, so the ground's light comes from this basis only, never twice. The sun:
// a parallel beam of unit irradiance through the windows, solved for the direction of a given
// sky's sun (it moves from sky to sky, and a fixed basis would blur the patch it lights). All
// solutions share one hierarchy and one link set, refined once for one sky (the photos' own) so
// that its sun patch is resolved. Lamps are dark in every solution (each lamp is its own term).
#include <glm/vec3.hpp>
#include <memory>
#include <string>
#include <vector>

#include "relume/daylight/sky.h"
#include "relume/geometry/polygon.h"
#include "relume/geometry/progress.h"

namespace relume {
class ByteReader;
class ByteWriter;
struct Scene;
namespace radiosity {
class HierarchicalRadiosity;
struct DistantLight;
struct Options;
}  // namespace radiosity
}  // namespace relume

namespace relume::daylight {

// A virtual lamp beside the sky (Loscos §4.4: a lamp the user adds, each its own term of the sum):
// a planar polygon emitting `exitance` (W/m^2, pi x radiance) from its front face (the side its
// vertices turn anticlockwise towards), or from both faces.
struct BasisLamp {
  std::string name;
  std::vector<glm::dvec3> polygon;
  glm::dvec3 exitance{0.0};
  bool twoSided = false;
};

struct BasisOptions {
  int regions = 64;
  // The outside ground's albedo; the area mean of the model's upward-facing outside polygons'
  // albedos when it has any (day101's ground), this value otherwise.
  double groundReflectance = 0.2;
  // Pieces of a window that a receiving point sees no wider than this take one direction's radiance.
  double pieceDeg = 1.5;
  // Engine options (refinement threshold, smallest element, rays); null: the engine's defaults.
  // The oracle is BF whatever these say: the sky's links are refined by their own rules (the sun patch's outline,
  // the region cones, the hot-source rule); BFV on top of them was measured worse, not better:
  // the daylight sample room's unseen ceiling estimated 12 % high (BF: within 10 %), a box's sun
  // shadow with 5x the jumps between neighbouring pixels, and the daylight tests 25-40 % slower.
  std::shared_ptr<const radiosity::Options> engine;
};

class DaylightBasis {
 public:
  // Builds the room's hierarchy (windows as openings, lamps dark, outside polygons left out),
  // refines it for `refineFor` (its regions' radiance and its sun) and solves every basis.
  // Throws relume::Error naming the scene's file when the room has no window, or a window does
  // not face into the room. Progress throughout; Cancel leaves nothing behind.
  DaylightBasis(const Scene& scene, const SkyRadiance& refineFor, const BasisOptions& options = {},
                Progress& progress = silentProgress());
  // The same basis from what write() kept (a project's daylight solution): made from the same
  // scene, sky and options, nothing refined or solved. Throws relume::Error naming the reader's
  // file when the bytes are damaged or were made for another room, sky or options.
  DaylightBasis(const Scene& scene, const SkyRadiance& refineFor, const BasisOptions& options, ByteReader& kept);
  // The hierarchy and every solution solved so far (the bases, the sun's, the lamps'), for the
  // constructor above. Refused (relume::Error) while virtual objects or lamps are added.
  void write(ByteWriter& out) const;
  ~DaylightBasis();
  DaylightBasis(const DaylightBasis&) = delete;
  DaylightBasis& operator=(const DaylightBasis&) = delete;

  const SkyRegions& regions() const { return regions_; }
  int basisCount() const { return int(bases_.size()); }  // regions + 1 (the ground, last)
  int groundBasis() const { return regions_.size(); }
  // Per node of engine(): the radiosity for unit radiance of basis k (the windows' own emission
  // included on their nodes).
  const std::vector<glm::vec3>& basis(int k) const { return bases_[size_t(k)]; }
  // The radiosity per unit irradiance (normal to the beam) of a sun in `direction` (towards the
  // sun); the last direction's solution is kept.
  const std::vector<glm::vec3>& sunSolution(const glm::dvec3& direction, Progress& progress = silentProgress());
  // The room's lamps beside the sky (Loscos §4.4's per-lamp terms in the same sum): per scene lamp
  // the radiosity per unit exitance of that lamp alone (windows dark), solved on first use on the
  // shared hierarchy with its links refined for the lamp (the other solutions hold their values on
  // the new elements, as for the sun), and the exitance it shines with now (W/m^2 in the photos'
  // units, pi x radiance; zero, the default, is off: the photos are taken with the lamps off).
  int lampCount() const { return int(lampSurface_.size()); }
  const std::vector<glm::vec3>& lampSolution(int lamp, Progress& progress = silentProgress());
  void setLampExitance(int lamp, const glm::dvec3& exitance);
  const glm::dvec3& lampExitance(int lamp) const { return lampExitance_.at(size_t(lamp)); }
  bool anyLampOn() const;
  int lampOfSurface(int surface) const;  // the scene lamp on this polygon (-1: none)
  // Eq. 3 with the lamps: B = sum_k L_k B_k + L_ground B_ground + E_sun B_sun + sum_l M_l B_lamp_l.
  std::vector<glm::vec3> combine(const SkyRadiance& sky, Progress& progress = silentProgress());
  // Per node: the irradiance under `sky` (B / rho of the combination; 0 where nothing reflects;
  // without the direct sun it is exact on leaves only, which is what the display interpolates),
  // with or without the sun's direct light (the element-level share of its beam, for a caller
  // that takes the direct sun per point instead, with its exact shadows).
  std::vector<glm::vec3> irradiance(const SkyRadiance& sky, bool directSun, Progress& progress = silentProgress());
  // Per node: the sun solution's direct irradiance per unit beam irradiance (links from the
  // windows, own and ancestors'); valid after sunSolution().
  const std::vector<glm::vec3>& sunDirect() const { return sunDirect_; }
  // The ground's radiance under `sky`: its albedo x the horizontal irradiance / pi.
  glm::dvec3 groundRadiance(const SkyRadiance& sky) const;
  double groundReflectance() const { return groundReflectance_; }

  // A solution for any light through the windows (all windows alike), on the same links: the
  // windows' F (and V for a beam) recomputed, then gather and push-pull to the tolerance.
  std::vector<glm::vec3> solveFor(std::shared_ptr<const radiosity::DistantLight> light, Progress& progress = silentProgress());

  // Virtual objects (Loscos §4.4 on the basis): polygons added to the live hierarchy (their links
  // refined, V redone where they cross), or removed again; every basis is solved again on the same
  // links, so that the room's solution changes only where they change it. Returns the new
  // surfaces' indices (after every polygon of the scene, in order). A Cancel while adding takes
  // them out again.
  std::vector<int> addObjects(const std::vector<Polygon>& polygons, Progress& progress = silentProgress());
  // The same with virtual lamps: their polygons are added after the objects' (they block light and
  // reflect none) and become lamps after the scene's (lampCount() grows; lampOfSurface, isLamp
  // and the combination take them in), shining with their exitance. Their solutions are solved
  // on first use, as the scene lamps' are. Throws relume::Error when a lamp has no area or a
  // negative or non-finite exitance, before anything is added.
  std::vector<int> addObjects(const std::vector<Polygon>& polygons, const std::vector<BasisLamp>& lamps,
                              Progress& progress = silentProgress());
  // Takes surfaces added by addObjects out again (virtual lamps among them stop being lamps).
  // The surfaces of the latest addObjects are taken out by putting the hierarchy and the
  // solutions back as they were before it: exact, and nothing is solved; any other set (an
  // earlier add's, or these after another add) is removed from the hierarchy and every basis
  // solved again. After a put-back the indices are free again: the next addObjects may return
  // the same ones, so a caller drops the ids it removed.
  void removeObjects(const std::vector<int>& surfaces, Progress& progress = silentProgress());
  int sceneLampCount() const { return sceneLamps_; }  // lamps 0 .. sceneLampCount() - 1 are the scene's

  const radiosity::HierarchicalRadiosity& engine() const { return *engine_; }
  const std::vector<int>& windows() const { return windows_; }
  bool isLamp(int surface) const { return surface >= 0 && size_t(surface) < lamp_.size() && lamp_[size_t(surface)]; }
  const std::vector<int>& outside() const { return outside_; }  // polygons left out of the engine
  // The area mean of a per-node solution over a surface's leaves.
  glm::dvec3 surfaceMean(const std::vector<glm::vec3>& b, int surface) const;
  double secondsPerBasis() const { return secondsPerBasis_; }
  double refineSeconds() const { return refineSeconds_; }
  // Counts the times any solution was solved again (the bases, the sun's for a new direction, a
  // lamp's) or a lamp's strength changed: a result made from the combination is current while
  // this is what it was then.
  unsigned revision() const { return revision_; }

 private:
  SkyRegions regions_;
  BasisOptions options_;
  std::unique_ptr<radiosity::HierarchicalRadiosity> engine_;
  std::vector<int> windows_, outside_;
  std::vector<std::vector<glm::vec3>> bases_;
  std::vector<glm::vec3> sun_, sunDirect_;
  glm::dvec3 sunDirection_{0.0};
  bool haveSun_ = false;
  double groundReflectance_ = 0.2;
  double secondsPerBasis_ = 0, refineSeconds_ = 0;
  unsigned revision_ = 0;
  void solveBases(Progress& progress);
  void setUp(const Scene& scene, const SkyRadiance& refineFor);  // everything before refining
  void extendToNodes();
  std::vector<bool> lamp_;  // per surface: a lamp (dark here, each lamp its own term)
  int sceneLamps_ = 0;
  size_t sceneSurfaces_ = 0;  // the engine's surfaces before any object is added
  std::vector<int> lampSurface_;                      // per scene lamp: its polygon (engine surface)
  std::vector<glm::dvec3> lampExitance_;              // per scene lamp: as it shines now
  std::vector<std::vector<glm::vec3>> lampSolution_;  // per scene lamp: empty until solved
  std::shared_ptr<const radiosity::DistantLight> refineLight_;
  // For the latest addObjects whose surfaces are still in: the hierarchy and every solution as
  // they were before it, put back when exactly those surfaces are removed (no solve, and none of
  // their elements left behind). One only: it holds a copy of the links and the solutions.
  struct Undo;
  std::shared_ptr<Undo> undo_;
  void putBack(Undo&& u);
  mutable std::vector<double> horizontal_;  // per region: projected solid angle on a horizontal plane
};

// Whether a cone of directions (unit `axis`, `halfAngle` radians) can reach sky region `cell`:
// false only when every direction in the cone lies outside it (a conservative test).
bool coneMeetsCell(const glm::dvec3& axis, double halfAngle, const SkyRegions::Cell& cell);
// Whether every direction in the cone lies inside sky region `cell` (SkyRegions::regionOf says so),
// with a margin for rounding at the cell's edges: false whenever that is not certain.
bool coneInsideCell(const glm::dvec3& axis, double halfAngle, const SkyRegions::Cell& cell);

}  // namespace relume::daylight
