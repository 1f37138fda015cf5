#pragma once
// Image-based objects in a relighting session: placed, checked against the room, lit by the
// session's lamps (real at their current scales, virtual) and indirect light, drawn with their
// shadows into the session's relit image. What `relume relight` and the workbench call.
#include <memory>
#include <string>
#include <vector>

#include "relume/geometry/polygon.h"
#include "relume/geometry/progress.h"
#include "relume/ibr/ibr_object.h"

namespace relume {
class RelightSession;
struct Scene;
struct Variant;
}  // namespace relume
namespace relume::daylight {
class DaylightRelighting;
struct SkyRadiance;
}  // namespace relume::daylight

namespace relume::ibr {

struct ImageObject {
  std::string name;
  std::shared_ptr<const ImageFan> fan;
  Placement place;
  std::string fanFile;  // for messages
};

// The image-based objects (entries with a fan) a variant places, appended to `out` with their fans
// read: fan paths relative to `folder`, or when it is empty to the folder of `file` (the variant
// file); a room's own variants pass its Scene::baseDir, which for an OBJ + JSON room is the JSON's
// folder, not the OBJ's. An unnamed one is "image_object_<k>", k its place in `out`, and a name
// `out` or `reserved` (the names of objects drawn beside them, e.g. boxes) has already gets
// " (<k>)". Throws relume::Error naming a fan file that cannot be read.
void appendImageObjects(const Variant& v, const std::string& file, std::vector<ImageObject>& out,
                        const std::string& folder = {}, const std::vector<std::string>& reserved = {});

// Throws relume::Error naming the object and its fan file when the object (its mesh's bounding
// box, placed) leaves the room or cuts one of its polygons.
void checkImageObject(const Scene& scene, const ImageObject& object);

// Draws the objects and their shadows into `image`, the session's relit view through `camera`
// (RelightSession::render): shadows first (onto the room), then the objects, farthest first.
// Brings the engine's radiosity up to date (RelightSession::syncEngine) for the indirect light.
// `mask` (optional) gets the objects' coverage per pixel.
std::vector<DrawStats> drawImageObjects(RelightSession& session, const std::vector<ImageObject>& objects,
                                        const Camera& camera, ImageRGB& image, std::vector<uint8_t>* mask = nullptr);
// The same with each object's light given (lightingAt on the session's engine, whose radiosity
// the caller made current): what a display that keeps the lights draws.
std::vector<DrawStats> drawImageObjects(const RelightSession& session, const std::vector<ImageObject>& objects,
                                        const std::vector<ObjectLighting>& lights, const Camera& camera, ImageRGB& image,
                                        std::vector<uint8_t>* mask = nullptr);

// The same on any room `h` (whose rays the objects are depth-tested and shadowed against), the
// light shown at a real surface's point given by `irradiance` (what the shadows' share is of);
// `perPointCap` as drawShadows takes it; `occluders` (not in h's rays) as roomView takes them.
std::vector<DrawStats> drawImageObjects(const radiosity::HierarchicalRadiosity& h, const std::vector<ImageObject>& objects,
                                        const std::vector<ObjectLighting>& lights, const Camera& camera,
                                        const IrradianceAt& irradiance, ImageRGB& image, std::vector<uint8_t>* mask = nullptr,
                                        const ImageRGB* perPointCap = nullptr, const RayScene* occluders = nullptr);

// ---- Under daylight (Grosch, Eble, Mueller 2007 with the tables of Dinh et al.) ----
// The daylight at an image-based object whose centre is `centre`, under `sky`, as the tables take
// it: each window sample of the session's interactive method (the paper's set of shadow maps, here
// DaylightRelighting::interactive().directSamples points over the windows) a small lamp in the
// window's plane, of its share of the window's area, shining with the radiance of the sky region
// (or the ground) seen through it from the centre; the sun a lamp the size of its disc far along
// its direction, as bright as the sky image's sun; each seen from the centre past the room. The
// indirect light is the irradiance volume's at the centre (Eq. 4, the windows' own light left out:
// it is the samples'), at the centre and, for the tables' cells, at any point within `radius` of it
// (ObjectLighting::indirectAt); the sun is seen past the room per point of the object (perPoint),
// the window samples from the centre. Refused (relume::Error) with a room lamp switched on: under
// daylight these objects are lit by daylight only.
// What it returns looks up the session's room and irradiance volume as they are now: valid until
// the session's next render() or volume combination (another sky, objects added to the basis).
// `occluders` (boxes and meshes drawn by the render, not in the session's room): they hide the
// window samples and the sun as the room does (ObjectLighting::occluders); not owned.
ObjectLighting daylightAt(daylight::DaylightRelighting& session, const daylight::SkyRadiance& sky, const glm::dvec3& centre,
                          double radius, const RayScene* occluders = nullptr);
// An image-based object's daylight for a display that draws it apart from the session (the OpenGL
// daylight view): daylightAt at its centre, the strongest `most` lamps kept (keepDisplayLamps) and
// the tables of the views a viewer at `eye` draws it from (drawnTables), made now; the light
// returned no longer looks up the session or `occluders` (its indirectAt, roomLets and occluders
// cleared: the tables hold what they gave).
struct DisplayDaylight {
  ObjectLighting light;
  DrawnTables tables;
};
DisplayDaylight daylightForDisplay(daylight::DaylightRelighting& session, const daylight::SkyRadiance& sky,
                                   const ImageObject& object, const glm::dvec3& eye, size_t most,
                                   const RayScene* occluders = nullptr);
// Draws image-based objects lit by daylight into `image`, the session's last render() under the
// same `sky` (through the session's camera): their shadows on the room's pixels, each lamp's
// share of the irradiance that render showed there (DaylightRelighting::lastIrradiance) taken
// off, so that a shadow falls only where the room let the light through; then the objects,
// depth-tested against the room. `polygonal`: the boxes and meshes that render drew (placed as it
// drew them). They hide the image-based objects behind them, their pixels take no shadow of
// them, and they hide the window samples and the sun from them and from the room points their
// shadows fall on; an image-based object's shadow on a box or mesh is not drawn, nor its light
// reflected onto them (the render solved the room without it).
// `progress`: the first call builds the session's irradiance volume (DaylightRelighting::volume).
std::vector<DrawStats> drawImageObjectsInDaylight(daylight::DaylightRelighting& session, const daylight::SkyRadiance& sky,
                                                  const std::vector<ImageObject>& objects, ImageRGB& image,
                                                  std::vector<uint8_t>* mask = nullptr, Progress& progress = silentProgress(),
                                                  const std::vector<Polygon>& polygonal = {});

// The objects' shadows on the room's surfaces as maps in each surface's plane coordinates
// (radiosity::HierarchicalRadiosity::toUV), for a display whose camera moves: per texel the
// share of the displayed light kept, the product over the objects of 1 - taken / irradiance
// (ObjectShadows, as drawShadows does per pixel, one object after the other). Only surfaces a shadow reaches, cropped to where it does (a texel of border).
struct SurfaceShadow {
  int surface = -1;
  glm::dvec2 origin{0.0};  // plane coordinates of texel (0, 0)'s corner
  double texel = 0;        // metres
  int width = 0, height = 0;
  std::vector<glm::vec3> keep;  // row-major from origin, +u then +v
};
// `lights`: one per object (lightingAt on `h`, whose radiosity is current).
std::vector<SurfaceShadow> shadowMaps(const radiosity::HierarchicalRadiosity& h, const std::vector<ImageObject>& objects,
                                      const std::vector<ObjectLighting>& lights, double texel = 0.015);
// The product of maps made apart (shadowMaps of one object each, the same texel size): what
// shadowMaps of them all gives, so that a display recomputes only the object that moved. Per
// surface over the union of their rectangles (a surface's maps share its texel grid).
std::vector<SurfaceShadow> multiplyShadowMaps(const std::vector<const std::vector<SurfaceShadow>*>& maps);

}  // namespace relume::ibr
