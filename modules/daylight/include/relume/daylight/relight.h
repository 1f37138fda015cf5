#pragma once
// The photographed room under another sky and virtual objects under any sky, by differential
// rendering (Grosch et al. 2007 §7.2 after Debevec 1998 and Gibson-Murta 2000; for the real room
// itself beyond the paper): every pixel of a real surface becomes photo x E_new / E_photo, E the
// irradiance the simulation gives at the point the pixel sees — so the photo keeps everything
// real (its textures, its noise, what the model lacks) and only what the simulation says changes
// is applied: sunlit patches that move, the light a virtual object blocks (shadows only where the
// room did not already shadow), what it reflects. The sun's direct light is taken per pixel (a
// ray through the windows, exact shadows), the rest from the basis solutions. A virtual object's
// own pixels are its albedo x E / pi.
//
// The sky images and the photos are taken to be in the same radiometric units (an HDR pair of
// known exposures); reflectances are estimated from the photo under its own sky.
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "relume/daylight/basis.h"
#include "relume/daylight/volume.h"
#include "relume/geometry/camera.h"
#include "relume/geometry/scene.h"
#include "relume/image/image.h"

namespace relume::daylight {

// What a camera sees of a basis's room: per pixel the polygon (-1: nothing, a window or a lamp),
// its leaf element when seen (a later sun solution may refine it), the plane coordinates, the
// point and the normal facing the camera.
struct SeenPixels {
  Camera camera;
  int width = 0, height = 0;
  std::vector<int> surface, leaf;
  std::vector<glm::dvec2> uv;
  std::vector<glm::dvec3> point, normal;
  std::vector<int> lamp;  // the scene lamp whose emitting face the pixel shows (-1: none)
};
SeenPixels seePixels(const DaylightBasis& basis, const Camera& camera);

// Irradiance per pixel under `sky` (linear RGB, W/m^2 in the sky image's units): the direct sun
// per pixel (the mean of 4 x 4 rays over a 1.5-pixel footprint, as a renderer's or a camera's
// pixel filter spreads a sunlit edge, each towards another point of the sun's 0.53-degree disc,
// for the penumbra), everything else interpolated from the leaves' corners as
// the display does.
ImageRGB irradianceImage(DaylightBasis& basis, const SeenPixels& px, const SkyRadiance& sky,
                         Progress& progress = silentProgress());

// The distant-illumination baseline (no window, no room): the sky at infinity over each pixel's
// hemisphere (one direction per region and the sun), blocked only by `occluders` (polygons, e.g.
// the virtual objects; none: nothing blocks).
ImageRGB distantIrradianceImage(const SeenPixels& px, const SkyRegions& regions, const SkyRadiance& sky,
                                const std::vector<std::vector<glm::dvec3>>& occluders);

// Per polygon of the basis's scene: the reflectance pi x (sum of the photo's radiance) / (sum of
// the irradiance) over the pixels showing it (at least `minPixels`; others: nothing, returned
// as -1 in every channel).
std::vector<glm::dvec3> reflectancesFromPhoto(const SeenPixels& px, const ImageRGB& photo, const ImageRGB& irradiance,
                                              size_t polygons, int minPixels = 50);

// The reflectance of the polygons no photo shows (the ceiling over a camera, the wall behind it),
// measured rather than guessed — inverse global illumination in the sense of Yu et al. 1999: the
// shown polygons' sunlit and shaded pixels share one reflectance, and the shaded pixels' light is
// the sky's through the windows plus what the room reflects, to which the unseen polygons add in
// proportion to their reflectance. Given each pixel's irradiance without the sun with the unseen
// polygons grey at reflectance `a` (restA) and at `b` (restB), all else equal (affine in between
// to first order), and the sun's own (`sun`), the grey reflectance in [0.02, 0.98] at which the
// shown polygons' (those `usable`) shaded and wholly sunlit estimates agree in luminance: the
// pixel-weighted mean log ratio, found by bisection. Grey because no photo shows those polygons'
// colour; a fit per channel would take up any error in the colour of the sun against the sky's.
// Not `ok` (and `why` says so) when no usable polygon has 50 shaded and 50 wholly sunlit pixels,
// when the unseen polygons change the shaded pixels' light by under 1 %, or when no value in
// [0.02, 0.98] makes the two estimates agree.
struct UnseenFit {
  bool ok = false;
  glm::dvec3 rho{0.0};
  int polygons = 0;  // shown polygons both sunlit and shaded
  long shadedPixels = 0, sunlitPixels = 0;
  double sensitivity = 0;  // relative change of the shaded pixels' light from a to b
  std::string why;         // when not ok: why not, in words
};
UnseenFit fitUnseenReflectance(const SeenPixels& px, const ImageRGB& photo, const ImageRGB& restA, const ImageRGB& restB,
                               const ImageRGB& sun, double a, double b, const glm::dvec3& sunDirection,
                               const glm::dvec3& sunIrradiance, const std::vector<bool>& usable);

// Differential rendering: per pixel of a real surface photo x eNew / ePhoto (both seen through
// the same camera; ePhoto with the photo's room, eNew with the variant's, objects included);
// pixels where `seenNew` shows a virtual object (a surface index >= `firstVirtual`) are
// albedo x eNew / pi.
ImageRGB differentialRender(const ImageRGB& photo, const ImageRGB& ePhoto, const ImageRGB& eNew, const SeenPixels& seenNew,
                            int firstVirtual, const std::vector<glm::dvec3>& virtualAlbedo);

// The whole path for a daylight room: reflectances estimated from the main photo under the
// photos' sky (pi L / E per polygon over its pixels, three rounds of basis solutions; polygons the
// photo does not show take their material's; the rest share one reflectance, measured by
// fitUnseenReflectance from a fourth round when the photos' sun lights some shown polygon in part,
// else the shown polygons' mean), then any sky and any
// virtual objects rendered into the photo, near-field (the basis solutions, the windows' own
// light) or distant (the sky at infinity, the objects the only occluders, the room as
// photographed) — Grosch's comparison.
//
// Volume is the paper's interactive method (§6.3, §7): the room's light is the bases' for the sky
// (nothing solved again), a virtual object's indirect light comes from the irradiance volume
// (Eq. 4 over the grid points it needs, Eq. 5 per vertex with its own shadowing), its direct
// daylight and the shadows it casts on the room from `directSamples` points spread over the
// windows (weighted by cos x cos x area / r^2) and the sun (on the object's own pixels four
// directions of its disc; on the room the same 4 x 4-ray footprint as irradianceImage). The
// objects' shadows come from shadow maps (a CPU depth map of the objects per window sample and
// per sun direction, as the paper's); what the room alone lets through is ray cast once per pixel
// and kept, and on the objects comes from a lattice over their faces (window samples) or rays
// (sun). Only pixels its shadows can reach are touched. What the object reflects onto the room
// and the indirect light it blocks are left out, as in the paper. The volume is built from the
// bases as solved when it is first used; it is not rebuilt if a NearField render refines them.
enum class DaylightMethod { NearField, Distant, Volume };

// A variant's virtual objects (boxes and meshes) as polygons with their albedos, for render(),
// each checked against the room as relume::checkVirtualObject checks lamp-lit objects (inside the
// room, not through a wall; a room's outside ground does not make "inside" reach past its walls).
// Refused with a relume::Error naming `file` and the object: an object that fails that check,
// and image-based objects (drawn after render() by ibr::drawImageObjectsInDaylight, which
// `relume relight --sky` and the Sky panel call, giving this only the variant's other objects).
// `groups` (if given) gets each virtual object's group name, in the variant's order: the group of
// its faces (an unnamed object is "object k", a repeated name gets " (k)").
std::vector<Polygon> variantObjects(const Scene& room, const Variant& variant, const std::string& file,
                                    std::vector<std::string>* groups = nullptr);
// A variant's virtual lamps (virtual_lights) for render(): exitance pi x radiance per face.
// Photometric lamps are refused (relume::Error naming `file` and the lamp): not lit by daylight yet.
std::vector<BasisLamp> variantLamps(const Variant& variant, const std::string& file);

// ---- The interactive method's parts, for a GPU renderer (the workbench's daylight viewport) ----
// The same window samples, sun directions, room under the sky, per-vertex indirect light and
// tile culling that render(..., Volume) uses, so that a renderer only has to find what the
// objects block (its shadow maps) and add up the samples as the CPU path does.

// A point of a window standing for `area` of it (normal into the room).
struct DirectSample {
  glm::dvec3 point{0.0}, normal{0.0};
  double area = 0;
};
// About `count` points spread evenly over the windows by area (per fan triangle of a window its
// share, at least one, on a Fibonacci lattice folded onto the triangle): the paper's set of shadow
// maps.
std::vector<DirectSample> windowSamples(const radiosity::HierarchicalRadiosity& engine, const std::vector<int>& windows,
                                        int count);

// Where the ray from p along d leaves the room through one of `windows` (out through the face that
// looks into the room): the distance, or -1. The sun reaches a point only this way.
double throughWindow(const radiosity::HierarchicalRadiosity& engine, const std::vector<int>& windows, const glm::dvec3& p,
                     const glm::dvec3& d);

// The sky's direct light for the interactive method, and the room under it without objects.
struct InteractiveSky {
  std::vector<DirectSample> window;
  // The radiance a window sample shows in each direction (the sky region's; the ground's below
  // the horizon), equirectangular: column u at azimuth 2 pi (u + 0.5) / width - pi from +X towards
  // +Y, row v at polar angle pi (v + 0.5) / height from +Z.
  ImageRGB radiance;
  bool sun = false;
  glm::dvec3 sunIrradiance{0.0};          // on a surface facing the sun
  std::vector<glm::dvec3> sunDirections;  // four directions over the sun's disc, each a quarter of it
  ImageRGB room;  // the photo under the sky, no objects (the camera's pixels)
  ImageRGB gain;  // per pixel photo / the photo's irradiance: radiance per unit irradiance (0: none)
  // Per pixel the sun's direct irradiance in `room` (over the pixel's footprint): the most of the
  // sun's light an object's shadow can take away there.
  ImageRGB sunLight;
};

// Per 8 x 8 tile of the camera's pixels (with a pixel's border), the window samples and the sun
// whose shadow of a sphere may fall on it: bit m of the tile's words for window sample m, bit
// window.size() for the sun. A tile with no bit set keeps the room's pixels.
struct ShadowReach {
  static constexpr int kTile = 8;
  int tilesX = 0, tilesY = 0, words = 0;
  std::vector<uint32_t> bits;  // tile (ty * tilesX + tx) at words * tile
  bool any(size_t tile) const {
    for (int w = 0; w < words; ++w)
      if (bits[tile * size_t(words) + size_t(w)]) return true;
    return false;
  }
};

// Per object face, per vertex: the indirect irradiance on its front (the side its normal faces)
// and on its back, from the irradiance volume (Eq. 4 over the grid points the objects need, Eq. 5
// with their own shadowing), as render(..., Volume) takes it.
struct ObjectIndirect {
  std::vector<std::vector<glm::dvec3>> front, back;
};

struct InteractiveOptions {
  VolumeOptions volume;
  int directSamples = 64;  // 1 to 1024
};

class DaylightRelighting {
 public:
  DaylightRelighting(const Scene& scene, const ImageRGB& photo, const Camera& camera, const SkyRadiance& photoSky,
                     const BasisOptions& options = {}, Progress& progress = silentProgress());
  // The same session from a file save() wrote (nothing estimated, refined or solved: only the
  // photo's pixels are looked up again). Throws relume::Error naming the file when it is damaged or
  // was made for another photo, sky, room or options.
  DaylightRelighting(const Scene& scene, const ImageRGB& photo, const Camera& camera, const SkyRadiance& photoSky,
                     const BasisOptions& options, const std::string& keptFile, Progress& progress = silentProgress());
  // Keeps the estimates (reflectances, the unseen fit) and the basis with every solution solved so
  // far in one file, written atomically, with a fingerprint of the photo and its sky. Refused
  // (relume::Error) while a NearField render's objects are in the basis (never, between renders).
  void save(const std::string& file) const;
  ~DaylightRelighting();
  // The photo under `sky` with `objects` (polygons with their albedos) inserted.
  // Virtual lamps (near-field only: the volume and distant methods light objects by daylight
  // alone, and say so) are added with the objects for this render and shown at their radiance
  // where the camera sees their emitting faces; they block the light as the objects do.
  ImageRGB render(const SkyRadiance& sky, const std::vector<Polygon>& objects, DaylightMethod method,
                  Progress& progress = silentProgress(), const std::vector<BasisLamp>& lamps = {});
  // Per polygon of the scene: the reflectance used (estimated, or taken from its material).
  const std::vector<glm::dvec3>& reflectances() const { return reflectances_; }
  const std::vector<bool>& estimated() const { return estimated_; }  // shown by the photo
  // The reflectance measured for the polygons no photo shows and no shown polygon's material
  // names (not `ok`: they took the shown polygons' mean, or there are none; `why` says which).
  const UnseenFit& unseenFit() const { return unseenFit_; }
  const ImageRGB& photoIrradiance() const { return ePhoto_; }
  const ImageRGB& lastIrradiance() const { return eLast_; }
  DaylightBasis& basis() { return *basis_; }
  // The irradiance volume of the room (built on first use of DaylightMethod::Volume, or here).
  IrradianceVolume& volume(Progress& progress = silentProgress());
  void setInteractive(const InteractiveOptions& options);
  // The room's lamps beside the daylight: the exitance lamp `lamp` (scene order) shines with, W/m^2
  // in the photo's units (pi x radiance; zero: off, as in the photos, the default). Each lamp is
  // one more term of the combination (DaylightBasis::lampSolution); its own pixels show its
  // radiance. NearField renders lamps and objects together; Volume renders the lamps on the room
  // but refuses virtual objects with a lamp on (its objects are lit by daylight only); Distant,
  // the sky at infinity, refuses any lamp on.
  void setLampExitance(int lamp, const glm::dvec3& exitance) { basis_->setLampExitance(lamp, exitance); }
  const InteractiveOptions& interactive() const { return interactive_; }
  // The interactive method's light under `sky` for a GPU renderer, kept (as render() keeps the
  // room relit) until the sky, the bases or the sample count change; valid until the next call.
  const InteractiveSky& interactiveSky(const SkyRadiance& sky, Progress& progress = silentProgress());
  // Counts the room's light made anew (another sky, re-solved bases): a renderer holding the
  // light of an earlier count must take it again.
  unsigned roomVersion() const { return roomVersion_; }
  // The tiles the shadows of a sphere (the objects' bounds) may reach under `light`.
  ShadowReach shadowReach(const InteractiveSky& light, const glm::dvec3& centre, double radius);
  // The objects' indirect light per vertex under `sky` (builds the volume on first use). Refused
  // as render(..., Volume) refuses them: objects with a lamp on, a face with no area.
  ObjectIndirect objectIndirect(const SkyRadiance& sky, const std::vector<Polygon>& objects,
                                Progress& progress = silentProgress());
  // The room's polygons that block light (every surface of the bases' engine but the windows).
  std::vector<std::vector<glm::dvec3>> roomPolygons() const;
  const Camera& camera() const { return camera_; }
  // Pixels the last Volume render worked on for the objects (drawn, or asked for their shadow: in
  // a tile that may be shadowed, where the pixel's own window or sun test says it may), for the bench.
  size_t lastTouchedPixels() const { return touched_; }

 private:
  void checkPhoto(const Scene& scene) const;
  // Refuses (relume::Error) objects the interactive path cannot light: any with a lamp on, a face with no area.
  void checkInteractiveObjects(const std::vector<Polygon>& objects) const;
  ImageRGB renderVolume(const SkyRadiance& sky, const std::vector<Polygon>& objects, Progress& progress);
  ImageRGB photo_, ePhoto_, eLast_;
  InteractiveOptions interactive_;
  std::unique_ptr<IrradianceVolume> volume_;
  SkyRadiance roomSky_;  // the sky eRoom_ was made for
  unsigned roomRevision_ = 0;  // and the basis's revision then (a NearField render re-solves it)
  ImageRGB eRoom_, eRoomSun_;  // (and the sun's direct part of it)
  ImageRGB roomOut_;  // the photo relit under roomSky_, no objects
  // Pixel i of the photo relit to irradiance e (the photo times e over the photo's irradiance).
  glm::vec3 relitPixel(size_t i, const glm::vec3& e) const;
  size_t touched_ = 0;
  // Per 8 x 8 tile of seen_ (with a pixel's border): its points' bounding sphere (w < 0: none)
  // and whether it has a pixel that shows no surface; made on first use.
  std::vector<glm::dvec4> tileSpheres_;
  std::vector<uint8_t> tileGap_;
  void updateRoom(const SkyRadiance& sky, Progress& progress);
  unsigned roomVersion_ = 0;
  std::unique_ptr<InteractiveSky> skyCache_;
  unsigned skyCacheRoom_ = 0;
  size_t skyCacheSamples_ = 0;
  int skyCacheRequested_ = 0;
  ShadowReach shadowReach(const std::vector<DirectSample>& window, bool sun, const glm::dvec3& sunDirection,
                          const glm::dvec3& centre, double radius);
  // The interactive path's per-pixel light past the room alone (relight.cpp), kept while objects move.
  struct InteractiveCache;
  std::unique_ptr<InteractiveCache> cache_;
  Camera camera_;
  SkyRadiance photoSky_;  // the photos' sky the estimates were made under
  std::unique_ptr<DaylightBasis> basis_;
  SeenPixels seen_;
  std::vector<glm::dvec3> reflectances_;
  std::vector<bool> estimated_;
  UnseenFit unseenFit_;
};

// Where a Relume project keeps its daylight session: PROJECT/daylight/solution.bin (empty for a
// scene not read from a project).
std::string keptSolutionFile(const Scene& scene);
// The room's daylight session: from the project's kept solution when it has one made for this
// photo, sky and options, else estimated and solved. `how` (if given) says which: empty when
// there was nothing kept, else that the kept one was opened or, naming the file and the problem,
// why it was not (the session is then solved as for a bundle).
std::unique_ptr<DaylightRelighting> openDaylightRelighting(const Scene& scene, const ImageRGB& photo, const Camera& camera,
                                                           const SkyRadiance& photoSky, const BasisOptions& options,
                                                           Progress& progress, std::string* how = nullptr);

}  // namespace relume::daylight
