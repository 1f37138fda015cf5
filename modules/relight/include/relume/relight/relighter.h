#pragma once
// Relighting a photographed room (Loscos, Drettakis, Robert 2000 §4-5) on the hierarchical
// radiosity engine: reflectance and lamp estimates from the photo textures, texture-based
// refinement along real shadows, unoccluded illumination textures (blocked light added back,
// then reference-patch correction), and the interactive session that displays T x B / D.
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "relume/geometry/progress.h"
#include "relume/geometry/scene.h"
#include "relume/image/image.h"
#include "relume/radiosity/hierarchy.h"
#include "relume/relight/display_mesh.h"
#include "relume/relight/texture.h"

namespace relume {

// §4.3: a region of a polygon painted by the user, whose occluded elements take their reflectance
// from the element at `reference`: for a shadow where neither a similar-coloured frontier element
// nor the polygon's default reference fits (a shadow across two materials, say). The region is a
// union of discs in the polygon's plane coordinates (PlaneFrame::of its vertices), metres; an
// element belongs to it when its centre does.
struct ReferenceRegion {
  std::string polygon;
  std::vector<glm::dvec3> discs;  // u, v, radius
  glm::dvec2 reference{0.0};
  bool contains(glm::dvec2 uv) const;
  bool operator==(const ReferenceRegion&) const = default;
};

struct RelightOptions {
  double meanReflectance = 0.5;      // rho-hat of Eq. 1, given by the user, then refined (§4)
  double colourThreshold = 10.0;     // CIELAB distance (Eq. 4) below which colours are similar
  double visibilityThreshold = 0.2;  // attenuation difference below which visibility is similar
  // Eq. 5 over secondary sources too (direct is always in). Off by default: the paper found it
  // "not decisive", and blocked indirect light is the least reliable estimate (it rests on every
  // reconstructed surface); measured, it over-brightens the unoccluded textures.
  bool blockedIndirect = false;
  bool lampLeastSquares = true;      // per-lamp emittances by least squares when well posed
  bool lampsFromPhoto = true;        // lamps the HDR photos show: their measured radiance wins
  // Inverse global illumination (Yu, Debevec, Malik, Hawkins 1999) for the estimates: every
  // element the photo shows is lit by its lamps (direct, with per-lamp visibility) and by the
  // photographed radiance of what it sees; reflectances and lamp exitances are solved jointly
  // over shadowed and unshadowed elements alike, and the measured indirect light fixes the
  // absolute scale (rho-hat only a fallback). Off: the paper's estimate from rho-hat (§4).
  bool inverseGlobalIllumination = true;
  // Polygons no photo shows take the reflectance of the photographed polygons of their material
  // (OBJ usemtl, scene.json material, a clicked polygon's group); off: the room's mean.
  bool sharedMaterials = true;
  // The photos are photometrically calibrated (linear values in cd/m^2): a lamp with a
  // photometric file (Lamp::photometry) is then known, its exitance the file's luminaire flux over
  // the lamp's area (lm/m^2 = pi x cd/m^2), held fixed like a lamp the HDR photo shows. Off: the
  // file gives the shape only and the strength is estimated like any lamp's.
  bool calibratedPhotos = false;
  // Evaluation only (an oracle, never a user's setting): the scene's lamp radiances are the truth
  // and are used as the lamps' exitances instead of any estimate.
  bool oracleLamps = false;
  // Evaluation only (an oracle): the scene's polygon albedos are the truth and are the engine's
  // reflectances instead of any estimate (the textures still come from the photos). With
  // oracleLamps, what is left between the relit image and the truth is rendering error.
  bool oracleAlbedos = false;
  // §4.3 (step 2). Paper: every occluded element takes its reference's reflectance. Weighted:
  // the two estimates of the unoccluded colour are combined by inverse variance — step 1's error
  // grows with the blocked fraction b as b / (1 - b) (the blocked light is an estimate; what is
  // seen is the rest), the reference's is the colour mismatch, taken as equal at b = 1/2.
  // Chosen (the default): Weighted, but only where the user chose a reference — inside a painted
  // region its reference, on a polygon given a reference patch that patch (no automatic frontier
  // search). Elsewhere step 1 stands: with shadows refined
  // along the texture and the blocked light traced per element, it is closer than a neighbour of
  // similar colour (measured: the sample room's unoccluded image 32.1 -> 33.4 dB on the shadow
  // mask, lamp edits 1.7-3.5 dB closer; see docs/architecture.md).
  enum class Reference { Off, Paper, Weighted, Chosen } reference = Reference::Chosen;
  int textureRefineLevels = 4;       // passes of Fig. 12
  double textureMinArea = 4e-4;      // m^2: texture-based refinement stops there
  double occludedFraction = 0.02;    // an element is occluded when more of its direct light is blocked
  radiosity::Options engine;         // the radiosity solution (BFV oracle by default)
  double interactiveEpsilon = 0.02;  // refinement threshold of §4.4's coarser interactive (BFV) mesh
  // Default reference patch per polygon name, chosen by the user (plane coordinates u, v of the
  // polygon's frame, PlaneFrame::of its vertices); polygons not named get one chosen automatically.
  std::map<std::string, glm::dvec2> referenceOverride;
  std::vector<ReferenceRegion> referenceRegions;  // painted by the user (win over both, later over earlier)
};

// A lamp added by the user: an emissive polygon (radiance RGB, exitance = pi x radiance).
struct VirtualLamp {
  std::string name;
  std::vector<glm::dvec3> polygon;
  glm::dvec3 radiance{0.0};
  bool twoSided = false;  // emits from both faces (the same radiance on each)
  // A luminaire's photometric distribution (IES / EULUMDAT), its nadir along the polygon's normal:
  // the lamp then emits pi x radiance x area in all, shaped by it (see radiosity::EmitterShape).
  std::shared_ptr<const PhotometricDistribution> photometry;
};
// A virtual object: a closed set of outward-facing convex polygons with one albedo.
// The most faces a virtual object's mesh may have (each face becomes elements and links of the
// radiosity solution, updated on every move).
inline constexpr size_t kMaxObjectFaces = 20000;

struct VirtualObject {
  std::string name;
  std::vector<std::vector<glm::dvec3>> polygons;
  glm::dvec3 albedo{0.5};
};
// A virtual object from a mesh's faces (e.g. an OBJ): faces of more than 3 vertices fanned into
// triangles (the engine wants convex planar polygons), faces without area dropped. Throws
// relume::Error when nothing is left.
VirtualObject meshObject(const std::string& name, const std::vector<std::vector<glm::dvec3>>& faces,
                         const glm::dvec3& albedo);
// The centre of its bounding box (the pivot it turns about).
glm::dvec3 objectCentre(const VirtualObject& object);
VirtualObject boxObject(const std::string& name, const glm::dvec3& lo, const glm::dvec3& hi, const glm::dvec3& albedo);

struct LampEstimate {
  std::string name;
  glm::dvec3 equal{0.0};         // Eq. 2, every lamp the same (exitance, W/m^2 units of pi x pixel)
  glm::dvec3 leastSquares{0.0};  // per-lamp fit over unshadowed texels (0 when not solved)
  glm::dvec3 photographed{0.0};  // pi x the median radiance of its texels in the HDR photos
  glm::dvec3 used{0.0};
  glm::dvec3 jointFit{0.0};      // inverse global illumination (0 when not solved)
  double uncertainty = 0;        // relative standard error of the joint fit (0 when not solved)
  bool twoSided = false;         // exitances per face
};

struct RelightEstimates {
  double meanReflectanceGiven = 0, meanReflectanceRefined = 0;
  // "Refined": the mean of the reflectances computed with Eq. 2's lamps. Eq. 2's lamps are then
  // scaled by eq2Scale so that the computed reflectances average the given one.
  double eq2Scale = 1;
  int reflectanceRounds = 0;
  std::string lampModel;  // "equal", "least-squares" or "photographed"
  std::string lampModelReason;
  std::vector<LampEstimate> lamps;  // in scene lamp order
  // Inverse global illumination: the mean reflectance it recovered over the photographed
  // elements (0 when not solved), the elements used, and the photographed share of each
  // element's indirect light (area mean).
  double meanReflectanceRecovered = 0;
  size_t jointFitElements = 0;
  double indirectMeasuredShare = 0;
  // Real polygons no photo shows: those that took their material's reflectance, and those with
  // no photographed polygon of their material (or no material), which took the room's mean.
  std::vector<std::string> unseenByMaterial, unseenWithoutMaterial;
  size_t leavesBeforeTextureRefinement = 0, leavesAfter = 0, texturesSubdivided = 0, subdivisionsCancelled = 0;
  size_t occludedLeaves = 0, frontierLeaves = 0, referencedByFrontier = 0, referencedByDefault = 0,
         referencedByRegion = 0;
  double seconds = 0;        // the whole preprocess
  double stepTwoSeconds = 0;  // the last Preprocessor::redoReferences (0: none since the preprocess)
};

// What preprocessing produces and a project stores.
struct RelightData {
  std::string photo;                    // the photo the textures come from
  double photoExposure = 1.0;           // display gain: 8-bit photo = sRGB(exposure x radiance)
  double colourScale = 1.0;             // texture radiance to Eq. 1 reflectance (for CIELAB)
  std::vector<PolygonTexture> textures;  // per scene polygon
  // The lamps' glow in the photo (linear radiance around each lamp's image, which the textures
  // leave out) and per pixel the lamp it belongs to (-1 none): scaled with its lamp on display.
  ImageRGB glow;
  std::vector<int> glowLamp;
  std::vector<glm::dvec3> lampExitance;  // per scene lamp, as estimated
  std::map<std::string, glm::dvec2> referencePatch;  // per polygon name: uv of its default reference
  std::map<std::string, glm::dvec2> referenceOverride;  // chosen by the user (wins over the above)
  std::vector<ReferenceRegion> referenceRegions;        // painted by the user (as used)
  RelightEstimates estimates;
  RelightOptions options;
};

// The whole preprocess of §4, up to T_final, B and D. Ignores the scene's albedos and lamp
// strengths (a photographed room has none). Throws relume::Error on unusable input.
RelightData preprocessRoom(const Scene& scene, const RelightOptions& options, Progress& progress = silentProgress());

// The same preprocess, keeping its state after §4.2's step 1 (the hierarchy, T_inter, rho_inter,
// the occluded and frontier elements) so that §4.3's step 2 can be redone when the user changes a
// polygon's reference patch or painted regions: only those polygons' step 2, then the final
// reflectance pass (global: a polygon's reflectance lights every other). Holds about as much
// memory as a session.
class Preprocessor {
 public:
  Preprocessor(const Scene& scene, const RelightOptions& options, Progress& progress = silentProgress());
  ~Preprocessor();
  Preprocessor(const Preprocessor&) = delete;
  Preprocessor& operator=(const Preprocessor&) = delete;
  // What preprocessRoom returns, with the reference choices applied last.
  const RelightData& data() const;
  // Step 2 again with these user choices (they replace the options' ones). Returns the polygons
  // whose step 2 was redone (none: nothing changed). Throws relume::Error, before anything
  // changes, on a choice outside its polygon; after a cancel the next call redoes every polygon.
  std::vector<int> redoReferences(const std::map<std::string, glm::dvec2>& overrides,
                                  const std::vector<ReferenceRegion>& regions, Progress& progress = silentProgress());

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

enum class RelightMethod { Full, RatioOnly };

// The mesh a session solves on. Refined: the preprocess's (BF solution, lamp links at leaves,
// texture-based refinement along real shadows; §4.1). Interactive: §4.4's coarser BFV solution,
// lamp links at its leaves for D (fewer elements in shadow, faster updates).
enum class SessionMesh { Refined, Interactive };

// The interactive phase (§4.4-5): a radiosity solution over the room plus virtual lamps and
// objects, D computed with the original lighting, then lamp edits by radiosity steps only.
class RelightSession {
 public:
  RelightSession(const Scene& scene, const RelightData& data, std::vector<VirtualLamp> virtualLamps = {},
                 std::vector<VirtualObject> objects = {}, Progress& progress = silentProgress(),
                 SessionMesh mesh = SessionMesh::Refined);
  ~RelightSession();
  // RGB multiplier of a real lamp's estimated emittance (0 = off, 2 = doubled, tints).
  void setLampScale(int lamp, const glm::dvec3& scale);
  // --- virtual lamps, on the live session (indices: the constructor's, then in order added;
  // removing one shifts the later ones down) ---
  void setVirtualLampRadiance(int lamp, const glm::dvec3& radiance);
  // Adds a lamp to the live session (§4.5): its links to every surface are refined by the oracle,
  // lamp links pushed to leaves; new elements of real polygons keep the original lighting's D and
  // B_orig. Then update(). Throws relume::Error on a degenerate polygon or a bad radiance.
  int addVirtualLamp(const VirtualLamp& lamp, Progress& progress = silentProgress());
  // Moves it (the dynamic-link update: F and V of its links, V of the links its bounds cross).
  size_t moveVirtualLamp(int lamp, const glm::dvec3& offset, Progress& progress = silentProgress());
  void removeVirtualLamp(int lamp, Progress& progress = silentProgress());
  // A new polygon / radiance for lamp `lamp`, put in afresh (its links refined where it now is);
  // checked first, so a refused replacement changes nothing. Keeps its index.
  void replaceVirtualLamp(int lamp, const VirtualLamp& replacement, Progress& progress = silentProgress());
  size_t virtualLampCount() const;
  const VirtualLamp& virtualLamp(int lamp) const;
  int virtualLampSurface(int lamp) const;  // the engine's surface

  // --- virtual objects ---
  // Adds an object to the live session (checked against the room first: relume::Error if it cuts
  // a real polygon or leaves the room).
  int addObject(const VirtualObject& object, Progress& progress = silentProgress());
  // Moves a virtual object rigidly: by `offset`, turned by `turnRadians` about the vertical (+z)
  // through its bounding-box centre. Links whose shafts its old or new bounds cross are updated,
  // the others kept; then radiosity steps. Throws relume::Error (and leaves it where it was) when
  // the new place intersects the room. Returns the links updated.
  size_t moveObject(int object, const glm::dvec3& offset, Progress& progress = silentProgress());
  size_t moveObject(int object, const glm::dvec3& offset, double turnRadians, Progress& progress = silentProgress());
  // The same, turned about `pivot` (then moved by `offset`): with a pivot that follows the
  // offsets, a turn is undone exactly by its opposite whatever the object's shape.
  size_t moveObjectAbout(int object, const glm::dvec3& offset, double turnRadians, const glm::dvec3& pivot,
                         Progress& progress = silentProgress());
  // While an object is dragged: its moves recompute visibility with few rays (a preview, about
  // four times cheaper); settleObject() then redoes its links with the full count.
  void setDragPreview(bool on);
  size_t settleObject(int object, Progress& progress = silentProgress());
  void removeObject(int object, Progress& progress = silentProgress());
  size_t objectCount() const;
  const VirtualObject& object(int object) const;  // where it is now
  const std::vector<int>& objectSurfaces(int object) const;

  // New reflectance maps and T_final for the room's polygons (after Preprocessor::redoReferences):
  // element reflectances from the maps, D and B_orig with the original lighting again, then
  // update(). Lamps, virtual lamps and objects stay as they are.
  void setReflectanceMaps(const std::vector<PolygonTexture>& textures, Progress& progress = silentProgress());
  // Brings the display up to date after edits. After a lamp edit alone: the per-lamp solutions
  // weighted by the lamps' scales (no radiosity steps; they are rebuilt first if the geometry
  // changed since). After a geometry change: radiosity steps (gather + push-pull) until stable.
  radiosity::SolveStats update(Progress& progress = silentProgress());
  // The room seen through `camera`: texture x B / D (Full) or original texture x B / B_orig.
  ImageRGB render(const Camera& camera, RelightMethod method, Progress& progress = silentProgress()) const;
  // The unoccluded illumination texture seen through `camera` (original lamps, shadows removed).
  ImageRGB renderUnoccluded(const Camera& camera) const;
  // The session's mesh for a GPU display (rebuild it after anything that changes the mesh or
  // moves surfaces: a virtual lamp added, an object moved) and the corner values to interpolate
  // on it (refresh after every lighting change); see display_mesh.h.
  DisplayMesh displayMesh() const;
  std::vector<glm::vec4> displayCorners(const DisplayMesh& mesh) const;
  // Per vertex of `mesh` its leaf's bilinear B, D and B_orig at the vertex (kDisplayVertexLight
  // floats): what a display interpolates across the triangles (refresh after every lighting
  // change).
  std::vector<float> displayVertexLight(const DisplayMesh& mesh) const;
  // Lamp scales as set, and the photo camera whose view shows the lamps' glow layer.
  glm::dvec3 lampScale(int lamp) const;
  size_t lampCount() const;
  const Camera& photoCamera() const;
  // The engine. Its radiosity is that of the last radiosity steps: lamp edits alone update the
  // display (per-lamp sums), not the engine's B.
  const radiosity::HierarchicalRadiosity& engine() const;
  radiosity::HierarchicalRadiosity& engine();
  double insertSeconds() const;  // virtual lamp forced refinement + update
  // --- for inspection ---
  // Makes the engine's own radiosity current after lamp edits made by per-lamp sums (radiosity
  // steps; nothing when it is current already).
  void syncEngine(Progress& progress = silentProgress());
  // Per engine node: D, the display factor under the original lighting (irradiance plus blocked
  // light on real surfaces, radiosity on the others), and B_orig; zero for clusters.
  glm::vec3 displayFactor(int node) const;
  glm::vec3 originalShading(int node) const;
  // What the display's ratio B / D is made of at a node now: irradiance on real surfaces,
  // radiosity on lamps and virtual surfaces (after syncEngine).
  glm::vec3 shading(int node) const;
  // The reflectance map and T_final of a scene polygon.
  const PolygonTexture& texture(int polygon) const;
  size_t realPolygonCount() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Checks a virtual object against the room: inside the room's bounds and not cutting through
// any real polygon. Throws relume::Error naming the object.
void checkVirtualObject(const Scene& scene, const VirtualObject& object);
// Checks a virtual object against the others in the room with it: no edge of one crosses a face
// of another (both shrunk by 1 mm towards their centres, so that objects may touch: a vase
// standing on a box, two boxes side by side). Throws relume::Error naming both.
void checkVirtualObjectsApart(const Scene& scene, const VirtualObject& object, const std::vector<const VirtualObject*>& others);

// The display gain g of a photo with both encodings (8-bit photo ~ sRGB(g x radiance), fitted
// over the pixels neither dark nor clipped); 1 without its linear (EXR) image.
double photoExposure(const Scene& scene, const Photo& photo);

}  // namespace relume
