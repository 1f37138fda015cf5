#pragma once
// Image-based objects in a relit room (Dinh, Metoyer, Turk §3-4, beyond the paper's one
// directional light): the fan image nearest the viewer's direction on a billboard facing the
// camera, depth-tested against the room; its pixels shaded by tables of the 225 normal codes, one
// per lamp (each pixel weighted by that lamp's distance falloff from its own 3-D point, known from
// the fan's depth) and one for the room's indirect light at the object (spherical harmonics of the
// radiosity solution's incident light); shadows from the fan image seen from each lamp's
// direction, cast onto any real surface and darkening it by that lamp's share of its light.
#include <array>
#include <functional>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <memory>
#include <vector>

#include "relume/geometry/camera.h"
#include "relume/geometry/photometry.h"
#include "relume/ibr/fan.h"
#include "relume/ibr/normal_code.h"
#include "relume/image/image.h"
#include "relume/radiosity/form_factor.h"
#include "relume/radiosity/sh.h"

namespace relume {
class RayScene;
}
namespace relume::radiosity {
class HierarchicalRadiosity;
}

namespace relume::ibr {

using LightTable = std::array<glm::vec3, kNormalCodes>;

// Where an image-based object stands: the bottom centre of its mesh's bounding box at `position`
// (world, metres), scaled, turned by `yaw` radians about +Z.
struct Placement {
  glm::dvec3 position{0.0};
  double scale = 1.0;
  double yaw = 0.0;
  glm::dvec3 toWorld(const ImageFan& fan, const glm::dvec3& objectPoint) const;
  glm::dvec3 toObject(const ImageFan& fan, const glm::dvec3& worldPoint) const;
  glm::dvec3 toWorldDirection(const glm::dvec3& d) const;
  glm::dvec3 toObjectDirection(const glm::dvec3& d) const;
};

// A lamp as the object sees it: its polygon and exitance (for the exact direct light at shadow
// receivers) and, towards the object's centre, a point at its polygon's centre.
struct ObjectLamp {
  int surface = -1;  // the engine's surface
  std::vector<glm::dvec3> polygon;
  glm::dvec3 exitance{0.0};
  bool twoSided = false;
  std::shared_ptr<const PhotometricDistribution> photometry;
  glm::dvec3 position{0.0};
  double visible = 1.0;  // the fraction of the lamp's area the object's centre sees past the room
  // Seen past the room per drawn point of the object instead (visible is then 1, the tables hold
  // the lamp's whole light, and ObjectLighting::roomLets is asked at each point): for a lamp whose
  // light the room cuts sharply across an object (the sun's patch through a window).
  bool perPoint = false;
  // Intensity towards the object's centre (W/sr, RGB), times `visible`.
  glm::dvec3 intensity{0.0};
  // Its intensity towards a point (times `visible`).
  glm::dvec3 intensityTowards(const glm::dvec3& p) const;
};

struct ObjectLighting {
  std::vector<ObjectLamp> lamps;
  radiosity::SH9 indirect;  // radiance arriving at the centre, the lamps' own emission left out
  glm::dvec3 centre{0.0};   // world
  // For the lamps with perPoint: the share of lamp `lamp` (in `lamps`) that the room lets reach
  // world point p of the object.
  std::function<double(size_t lamp, const glm::dvec3& p)> roomLets;
  // The indirect light at a world point, where a display can ask it there (an irradiance volume):
  // drawObject then takes it at each table cell's surface point, as the lamps' tables are aimed,
  // instead of `indirect` at the centre — next to a sunlit patch it changes across the object.
  std::function<radiosity::SH9(const glm::dvec3& p)> indirectAt;
  // Occluders beside the room (a daylight render's boxes and meshes, which are not in the room's
  // rays): they hide lamps from the object and from the room points its shadows fall on, as the
  // room does. Not owned; null: none.
  const RayScene* occluders = nullptr;
};

// The lights of a radiosity solution at a world point: every surface with an exitance is a lamp.
ObjectLighting lightingAt(const radiosity::HierarchicalRadiosity& h, const glm::dvec3& worldCentre, int shRays = 2048);

// Eq. 1 per lamp. The paper's one table per (distant) light, T[k] = I max(0, n_k . l), assumes
// one direction l over the whole object; a room's lamp a couple of metres away sees a 60 cm object
// under up to +-9 degrees, which costs about 10 dB (measured). So each fan image is cut into
// cells x cells cells and each cell gets the lamp's table for the direction and intensity from its
// surface (its covered pixels' mean depth); a pixel blends the four nearest cells' entries
// bilinearly and divides by its own squared distance to the lamp. cells = 1 is the paper's.
struct LampTables {
  int cells = 1;
  std::vector<LightTable> table;  // cells x cells, row-major from the image's top left
};
LampTables lampTables(const ImageFan& fan, int view, const Placement& place, const ObjectLamp& lamp,
                      int cells = kTableCells);
// The indirect irradiance for each code's normal.
LightTable indirectTable(const ImageFan& fan, int view, const Placement& place, const radiosity::SH9& sh);
// The same per table cell (kTableCells^2, row-major), the light taken at each cell's surface point.
std::vector<LightTable> indirectTables(const ImageFan& fan, int view, const Placement& place,
                                       const std::function<radiosity::SH9(const glm::dvec3&)>& indirectAt);

// The fan images a viewer at `eye` sees the object in, in the order they are asked: the one
// nearest its direction, the next nearest, and the nearest on another ring (it sees under a lip
// or over a rim the two of one ring hide); -1 for those a fan lacks, all -1 when the eye is inside
// the object's sphere.
inline constexpr int kDrawnViews = 3;
std::array<int, kDrawnViews> viewsToward(const ImageFan& fan, const Placement& place, const glm::dvec3& eye);
// The fan image nearest a lamp's direction: the object's own shadow map for that lamp.
int lampView(const ImageFan& fan, const Placement& place, const glm::dvec3& lampPosition);

// Everything that lights one drawn fan image, as the tables a display looks up: first the
// indirect light's indirectRows(light) rows (one table, or with ObjectLighting::indirectAt one per
// table cell, row-major cells, as drawObject takes it), then for each lamp of `light` in order its
// kTableCells^2 cell tables (row-major cells); each row kNormalCodes RGB entries. (What drawObject
// computes per frame; a GPU display uploads it as a texture.)
std::vector<glm::vec3> viewTables(const ImageFan& fan, int view, const Placement& place, const ObjectLighting& light);
inline int indirectRows(const ObjectLighting& light) { return light.indirectAt ? kTableCells * kTableCells : 1; }

// The lamps a display that takes at most `most` per object keeps of `light`: those whose light
// reaches the object's centre, the strongest there first (beyond `most` the weakest are left out),
// then ordered by the fan image each one's own shadow is read from (lampView), so that lamps
// sharing one follow each other.
void keepDisplayLamps(ObjectLighting& light, const ImageFan& fan, const Placement& place, size_t most);

// The tables of the fan images a viewer at `eye` is drawn from (viewsToward), made while `light`
// can still be asked (ObjectLighting::indirectAt may look up a volume that changes later): a
// display whose viewer stays where it is needs no other.
struct DrawnTables {
  std::array<int, kDrawnViews> views{-1, -1, -1};
  int rowsPerView = 0;
  int indirectRows = 1;
  std::vector<glm::vec3> rows;  // the views' viewTables, one after the other
};
DrawnTables drawnTables(const ImageFan& fan, const Placement& place, const ObjectLighting& light, const glm::dvec3& eye);

// One lamp's silhouette of the object, what its shadows on the room are made from: the fan image
// nearest the lamp's direction, its axes in the world, and points spread over the lamp.
struct ShadowCaster {
  size_t lamp = 0;  // in ObjectLighting::lamps
  int view = -1;
  glm::dvec3 right{0.0}, up{0.0}, toCamera{0.0};          // the view's image axes and direction, world
  std::vector<std::pair<glm::dvec3, double>> samples;      // points on the lamp, weights summing to 1
  double lampRadius = 0;                                   // its farthest vertex from its centre
  // A point can be shadowed only inside the cone from the lamp's centre around the object's
  // sphere widened by lampRadius, beyond its near side (cone false: the lamp is too close to tell).
  bool cone = false;
  glm::dvec3 apex{0.0}, axis{0.0};
  double cos2 = 0, nearSide = 0;
};
// The casters of the lamps that shine (exitance > 0) from outside the object's sphere.
std::vector<ShadowCaster> shadowCasters(const ImageFan& fan, const Placement& place, const ObjectLighting& light);

// The room as a camera sees it: per pixel the distance to the first surface along the pixel's
// (unit) ray, that point, and its surface (-1: nothing, or a back face).
struct RoomView {
  int width = 0, height = 0;
  std::vector<float> depth;
  std::vector<glm::vec3> point, normal;
  std::vector<int> surface;
  // Per tile of kRoomTile x kRoomTile pixels (row-major, tilesX() across): the sphere around the
  // points its pixels see (xyz the centre, w the radius; w < 0: it sees no surface). Shadows ask
  // per tile first whether an object's shadow can reach it.
  static constexpr int kRoomTile = 8;
  int tilesX() const { return (width + kRoomTile - 1) / kRoomTile; }
  int tilesY() const { return (height + kRoomTile - 1) / kRoomTile; }
  std::vector<glm::dvec4> tiles;
};
// With `occluders` (not in the room's rays), a pixel that sees one of them nearer than the room
// takes its depth and point and no surface: an object behind it is hidden there, and no shadow
// falls on it.
RoomView roomView(const radiosity::HierarchicalRadiosity& h, const Camera& camera, const RayScene* occluders = nullptr);

// Whether the room's rays or the occluders beside them (ObjectLighting::occluders; null: none)
// block the segment from a to b (its ends' margin `endEpsilon`, as RayScene::occluded takes it).
bool blockedBetween(const RayScene& room, const RayScene* occluders, const glm::dvec3& a, const glm::dvec3& b,
                    float endEpsilon);

struct DrawStats {
  int view = -1;  // the fan view drawn
  size_t objectPixels = 0, shadowPixels = 0;
};

// Draws the object into `image` (linear radiance): albedo / pi x (sum over lamps of V_l T_l[code]
// / |x_l - p|^2 + T_indirect[code]), p the pixel's 3-D point, met by the pixel's ray in the depth
// of the nearest fan image (or of the next of viewsToward's where the one before saw the ray pass
// behind a surface); V_l the object's own shadow (beyond the paper: the fan image nearest the
// lamp's direction as a shadow map, 3 x 3 percentage-closer). Blended by its alpha, hidden where the room is nearer. `mask`
// (optional, width x height) gets the alpha drawn (0..255).
DrawStats drawObject(const ImageFan& fan, const Placement& place, const ObjectLighting& light, const Camera& camera,
                     const RoomView& room, ImageRGB& image, std::vector<uint8_t>* mask = nullptr);

// The irradiance the display shows at a surface's point (what a pixel there is proportional to).
using IrradianceAt = std::function<glm::dvec3(int surface, const glm::dvec3& point)>;

// What an object's silhouettes take off the light at points of the room (§4, onto any surface,
// beyond the paper): for each lamp, lines from the point to points spread over the lamp are met
// with the fan image nearest the lamp's direction (the silhouette, its surface between the point
// and the lamp); the share blocked times that lamp's direct irradiance there, where the room lets
// the lamp through, is taken off. A lamp switched off or dimmed takes off as much less.
class ObjectShadows {
 public:
  // (Keeps references to `fan` and `light`: both must outlive it.) `cull` false: every lamp is
  // tried at every point, its lines to all the lamp's points (what culling must not change).
  ObjectShadows(const ImageFan& fan, const Placement& place, const ObjectLighting& light, bool cull = true);
  bool empty() const { return casters_.empty(); }
  // The casters (bit i: the i-th lamp that casts; the 64th on share bit 63) that may shadow some
  // point within `radius` of `centre` (0: none can).
  using Casters = uint64_t;
  static constexpr Casters kAllCasters = ~Casters(0);
  Casters castersNear(const glm::dvec3& centre, double radius) const;
  bool mayShadow(const glm::dvec3& centre, double radius) const { return castersNear(centre, radius) != 0; }
  // The irradiance (W/m^2, RGB) taken off point X (normal n) of engine surface `surface`, by the
  // casters in `casters` (from castersNear around X: the others take nothing there).
  // With `perPoint` given, the lamps seen past the room per point (ObjectLamp::perPoint) are left
  // out of the result and the share of their area the object hides from X is added there instead
  // (a display that knows what it showed of them takes that share of it).
  glm::dvec3 taken(const radiosity::HierarchicalRadiosity& h, int surface, const glm::dvec3& X, const glm::dvec3& n,
                   Casters casters = kAllCasters, glm::dvec3* perPoint = nullptr) const;

 private:
  const ImageFan* fan_;
  Placement place_;
  const ObjectLighting* light_;
  glm::dvec3 centre_{0.0};
  double radius_ = 0;
  bool cull_ = true;
  std::vector<ShadowCaster> casters_;
  std::vector<radiosity::EmitterShape> shapes_;
  std::vector<const FanView*> silhouettes_;  // each caster's view, decoded once
  // Each caster's lamp points (ShadowCaster::samples, in order) in its view's frame about the
  // object's centre (metres along right, up, toCamera): a line's crossing of the view's plane is
  // then a few products per point.
  std::vector<std::vector<glm::dvec3>> inFrame_;
  // Per caster, in the same frame: the lamp's centre, and the box on the view's plane that holds
  // every silhouette pixel (metres along right, up; empty: lo > hi). A point whose lines to the
  // lamp (its points lie within lampRadius of the centre) all cross the plane outside the box is
  // passed over before its points are tried.
  struct Reach {
    glm::dvec3 lampCentre{0.0};
    glm::dvec2 lo{1.0}, hi{-1.0};
  };
  std::vector<Reach> reach_;
};

// Per engine surface: whether it emits (a lamp keeps its glow: shadows fall on what reflects).
std::vector<char> emittingSurfaces(const radiosity::HierarchicalRadiosity& h);

// Shadows (§4, onto any surface): for each pixel and lamp, the line to the lamp is met with the
// fan image nearest the lamp's direction (the silhouette, its depth in front of the pixel); where
// it is blocked (by the coverage there), that lamp's direct irradiance at the point, over the
// irradiance shown, is taken off. A lamp switched off or dimmed casts a shadow as much lighter.
// `perPointCap` (optional, per pixel): the light the display showed there of the lamps seen per
// point (the sun over a pixel's footprint and its disc, past the room); the share of those lamps the
// object hides takes that share of it off (a ray per disc point from the pixel's centre would cut
// a sharper sunlit edge than the display drew).
DrawStats drawShadows(const ImageFan& fan, const Placement& place, const ObjectLighting& light,
                      const radiosity::HierarchicalRadiosity& h, const Camera& camera, const RoomView& room,
                      const IrradianceAt& irradiance, ImageRGB& image, const ImageRGB* perPointCap = nullptr);

}  // namespace relume::ibr
