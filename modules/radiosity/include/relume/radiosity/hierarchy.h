#pragma once
// Hierarchical radiosity with clustering (Hanrahan-Salzman-Aupperle 1991; Smits-Arvo-Greenberg
// 1994; Sillion 1995), as Loscos et al. 2000 §2.3 uses it: per-polygon quadtrees of elements, a
// cluster hierarchy over all polygons whose root is linked to itself, links that carry the form
// factor, the attenuation (visibility) factor and its type, BF / BFV refinement, gather and
// push-pull iterated to a tolerance, RGB throughout.
#include <cstdint>
#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <memory>
#include <string>
#include <vector>

#include "relume/geometry/photometry.h"
#include "relume/geometry/progress.h"
#include "relume/radiosity/form_factor.h"

namespace relume {
class ByteReader;
class ByteWriter;
class RayScene;
struct Scene;
}  // namespace relume

namespace relume::radiosity {

enum class Oracle { BF, BFV };
enum class VisibilityType : uint8_t { Visible = 0, Invisible = 1, Partial = 2 };

struct Options {
  Oracle oracle = Oracle::BFV;
  // Refinement threshold. A link's error is rho_r * B_s * dF, dF the spread of the point-to-source
  // form factor over the receiver's quadrature points (the whole factor when a cluster is involved,
  // since the isotropic cluster kernel is only an estimate). BF uses dF regardless of visibility;
  // BFV weights it by V and takes the whole F on PARTIAL links, so shadow boundaries refine and
  // fully hidden ones do not. A link is refined while its error exceeds epsilon times the scene's
  // mean first-bounce irradiance (emitted power / receiving area). BFV by default: under BF a
  // partly hidden link keeps its unoccluded factor times its mean visibility, which is too much
  // light where the hidden part is the one the kernel favours (the ceiling above a two-sided lamp
  // seen from the floor past the lamp: +3 % on the floor against light tracing, +0.5 % with BFV).
  // Elements near an emitter may also be cut below minArea (see refineLinks).
  double epsilon = 0.003;
  double minArea = 2e-3;     // m^2: elements are not subdivided below this area (near an emitter: down to 1/16 of it)
  int visibilityRays = 16;   // stratified, jittered ray pairs per link
  int quadratureOrder = 2;   // Gauss points per axis on a receiving element for its form factor
  double tolerance = 1e-4;   // stop when max |dB| on leaves <= tolerance * mean leaf radiosity
  int maxIterations = 500;
  int maxRefineRounds = 6;   // refine / solve rounds (B changes, so the oracle is re-asked)
  uint32_t seed = 1;
};

// One polygon as the engine sees it.
struct Surface {
  std::string name;
  std::vector<glm::dvec3> vertices;  // convex, planar, counter-clockwise around the normal
  glm::dvec3 reflectance{0.0};       // diffuse albedo, RGB
  glm::dvec3 exitance{0.0};          // emitted radiosity W/m^2 (pi x radiance), RGB
  bool twoSided = false;             // an emitter that emits `exitance` from both faces
  // An emitter's photometric distribution (see EmitterShape): `exitance` is then its whole flux
  // over its area, shaped by the distribution; null: Lambertian face(s).
  std::shared_ptr<const PhotometricDistribution> photometry;
  // An opening (a window): it occludes nothing and reflects nothing; with `distant` set and an
  // exitance, the light from outside enters through it (see DistantLight). surfacesFromScene
  // leaves windows closed (absorbing, occluding): the daylight basis opens them.
  bool opening = false;
  std::shared_ptr<const DistantLight> distant;
};

// Polygons, albedos and lamps of a scene (lamp polygons reflect nothing).
std::vector<Surface> surfacesFromScene(const Scene& scene);

struct Totals {
  size_t elements = 0, clusters = 0, leaves = 0, links = 0;
  uint64_t rays = 0;
  int iterations = 0;      // gather + push-pull sweeps of the last solve
  double seconds = 0;      // of the last solve()
  size_t linkBytes = 0;    // memory held by the link arrays
  size_t engineBytes = 0;  // links + elements + clusters + per-node radiosity arrays
};

struct SolveStats {
  int iterations = 0;
  double residual = 0;  // last max |dB| / mean leaf radiosity
};

class HierarchicalRadiosity {
 public:
  struct Node {
    int32_t parent = -1;
    int32_t childBegin = 0;  // into children()
    int32_t childCount = 0;
    int32_t surface = -1;    // -1 for clusters
    int32_t level = 0;
    float u0 = 0, v0 = 0, u1 = 0, v1 = 0;  // element rectangle in its surface's plane frame
    float area = 0;
    float radius = 0;  // bounding sphere around `center`
    glm::vec3 center{0.f};
    glm::vec3 bmin{0.f}, bmax{0.f};
    bool subdivided = false;  // element: children created (maybe none inside the polygon)
    bool isCluster() const { return surface < 0; }
    bool isLeaf() const { return childCount == 0; }
  };
  struct Link {
    int32_t receiver = -1, source = -1;
    float formFactor = 0;  // unoccluded kernel: E_receiver += F * V * B_source
    float visibility = 1;  // attenuation factor in [0,1]
    float variation = 0;   // spread of the point kernel over the receiver (the oracle's error)
    VisibilityType type = VisibilityType::Visible;
  };

  HierarchicalRadiosity(std::vector<Surface> surfaces, Options options = {});
  ~HierarchicalRadiosity();
  HierarchicalRadiosity(const HierarchicalRadiosity&) = delete;
  HierarchicalRadiosity& operator=(const HierarchicalRadiosity&) = delete;

  // Refine and iterate to the tolerance (refine / solve rounds until no link is refined).
  SolveStats solve(Progress& progress = silentProgress());
  // Gather + push-pull to the tolerance with the links as they are: no refinement, no rays.
  SolveStats iterate(Progress& progress = silentProgress());
  // Back to emission only (no irradiance anywhere), so that the next iterate() starts afresh.
  void clearSolution();
  // Changes a surface's emitted radiosity; call iterate() after.
  void setExitance(int surface, const glm::dvec3& exitance);
  void setReflectance(int surface, const glm::dvec3& reflectance);
  // Changes what shines in through an opening: F again for the links leaving it (and V, which for
  // a single beam is taken along the beam); no refinement. Returns the links updated; call
  // iterate() after.
  size_t setDistantLight(int surface, std::shared_ptr<const DistantLight> light);

  // --- seams for what comes next -------------------------------------------------------------
  // Replaces every link whose source lies on an emitting surface and whose receiver is not a
  // leaf by links to the receiver's leaves (clusters opened down to elements); F and V computed.
  void pushLampLinksToLeaves(Progress& progress = silentProgress());
  // Forces refinement of links arriving from `sourceSurfaces` onto `receiverSurfaces`: cluster
  // receivers are opened so that these links land on the polygons, then refined by the oracle.
  void forceRefine(const std::vector<int>& receiverSurfaces, const std::vector<int>& sourceSurfaces,
                   Progress& progress = silentProgress());
  // Subdivides leaf elements (quadtree split, as refinement does); links stay where they are, so
  // call pushLampLinksToLeaves() after to bring lamp links down to the new leaves.
  void subdivideElements(const std::vector<int>& elements);
  // The rectangles (u0, v0, u1, v1) an element would be split into (before clipping).
  std::vector<glm::vec4> splitRects(int element) const;
  // Reflectance of an element and everything below it (per-element reflectance, e.g. from a
  // texture); the surface's own value is left as it was.
  void setElementReflectance(int node, const glm::dvec3& reflectance);
  const glm::vec3& reflectanceOf(int node) const;
  // Moves surfaces (a virtual object) rigidly by `offset` (Drettakis-Sillion 1997): the ray scene
  // is rebuilt, F and V are recomputed for the links with an end on or around the moved surfaces
  // and V for the links whose shaft the old or the new bounds cross; every other link is kept as
  // it is (passive). No refinement. Returns the number of links updated; call iterate() after.
  size_t translateSurfaces(const std::vector<int>& surfaces, const glm::dvec3& offset);
  // The same for a rigid motion: every vertex v goes to rotation (v - pivot) + pivot + offset.
  // `visibilityRays` > 0 overrides the options' ray count for this update (a quick preview while
  // dragging; a later update with the full count, e.g. a zero motion, settles it).
  size_t moveSurfaces(const std::vector<int>& surfaces, const glm::dmat3& rotation, const glm::dvec3& pivot,
                      const glm::dvec3& offset, int visibilityRays = 0);
  // F and V again for the links with an end on `surfaces`, V for the links whose shaft crosses the
  // box, with the full ray count (after previews). Returns the links updated.
  size_t refreshLinks(const std::vector<int>& surfaces, const glm::vec3& boxMin, const glm::vec3& boxMax);
  // Adds polygons to a live hierarchy (a virtual lamp, the faces of a virtual object), without
  // rebuilding it: each becomes a child of the root cluster and an occluder (V redone on the links
  // whose shaft its bounds cross); it is linked to every other surface (as a source, and as a
  // receiver when it reflects), and only these new links are refined by the oracle (they are not
  // pushed to leaves: push-pull carries their light down). Returns the new surfaces' indices; call iterate() after.
  std::vector<int> addSurfaces(const std::vector<Surface>& surfaces, Progress& progress = silentProgress());
  // Removes surfaces from the solution: their links are dropped, they no longer occlude, emit or
  // reflect (V redone on the links their bounds crossed). Their indices stay valid (no vertices,
  // no leaves drawn), so other surfaces keep theirs. Returns the links updated or dropped.
  size_t removeSurfaces(const std::vector<int>& surfaces);
  bool isRemoved(int surface) const { return surfaces_[surface].vertices.empty(); }
  // Links whose shaft (the convex hull of receiver and source bounds) the box crosses.
  std::vector<int> linksCrossingBox(const glm::vec3& boxMin, const glm::vec3& boxMax) const;

  // --- results ------------------------------------------------------------------------------
  const std::vector<Surface>& surfaces() const { return surfaces_; }
  const std::vector<Node>& nodes() const { return nodes_; }
  const std::vector<int32_t>& children() const { return children_; }
  const std::vector<Link>& links() const { return links_; }
  int surfaceRoot(int surface) const { return surfaceRoot_[surface]; }
  int rootCluster() const { return 0; }
  const glm::vec3& radiosity(int node) const { return B_[node]; }
  // Total irradiance arriving at a node (its own links plus all its ancestors').
  glm::vec3 irradiance(int node) const;
  // Area means over a surface's leaves.
  glm::dvec3 surfaceRadiosity(int surface) const;
  glm::dvec3 surfaceIrradiance(int surface) const;
  // The leaf element of `surface` containing plane-frame coordinates uv (the deepest node).
  int findLeaf(int surface, glm::dvec2 uv) const;
  // Plane frame of a surface (to map world points to the elements' uv).
  glm::dvec2 toUV(int surface, const glm::dvec3& p) const;
  glm::dvec3 toWorld(int surface, glm::dvec2 uv) const;
  const Options& options() const { return options_; }
  Totals totals() const;
  bool isEmitter(int surface) const;
  // Does `node` (or a cluster containing it) contain emitting surfaces only?
  bool sourceIsEmitter(int node) const;
  const RayScene& rayScene() const;
  // The refinement threshold's scale (the mean first-bounce irradiance solve() last computed from
  // the emitters): later refinements (addSurfaces, forceRefine) measure links against it. A caller
  // that solved once for a light at another scale puts the earlier value back with this.
  double refinementScale() const;
  void setRefinementScale(double eRef);

  // Everything refining, adding, removing and solving change (surfaces, elements, links, the
  // solution, the refinement scale), kept aside and put back exactly: a caller that adds
  // surfaces for a while (virtual objects) gets the hierarchy back as it was, without the
  // elements a removal leaves behind and without solving again. Holds a copy of the links.
  struct State;
  std::shared_ptr<const State> saveState() const;
  void restoreState(const State& state);
  // The same as bytes, for a project to keep (so that opening it refines and solves nothing):
  // writeState appends elements, links, radiosity and the refinement scale, with a fingerprint of
  // the surfaces and options; readState puts them into an engine made from the same surfaces and
  // options, with the same surfaces removed. Throws relume::Error naming the reader's file when the
  // bytes are damaged or were written for other surfaces or options; the engine is then unchanged.
  void writeState(ByteWriter& out) const;
  void readState(ByteReader& in);

 struct Impl;  // engine internals (opaque to users)

 private:
  std::unique_ptr<Impl> impl_;
  std::vector<Surface> surfaces_;
  Options options_;
  std::vector<Node> nodes_;
  std::vector<int32_t> children_;
  std::vector<int32_t> surfaceRoot_;
  std::vector<Link> links_;
  std::vector<glm::vec3> B_, E_, Edown_;

  double pushPull();
  void rebuildRays();
  // Recomputes V (and F where flagged 2) of the links flagged in `redo`; returns how many.
  size_t redoLinks(const std::vector<uint8_t>& redo, int visibilityRays = 0);
  void refitClusters(std::vector<uint8_t>& touched);

  friend struct Builder;
  friend bool refineLinks(struct RefineContext& ctx, Progress& progress);
};

}  // namespace relume::radiosity
