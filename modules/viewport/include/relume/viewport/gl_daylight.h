#pragma once
// The daylight viewport's renderer (OpenGL 3.3 core): Grosch, Eble, Mueller 2007 §7 on the GPU.
// Virtual objects in the photographed room under a measured sky, as the library's interactive
// method (daylight::DaylightRelighting::render with DaylightMethod::Volume) draws them on the CPU:
// the room as relit under the sky (the library's image), minus what the objects newly block of
// each window sample's and the sun's light (only new shadows: where the room itself lets that
// light through), and the objects' own pixels as albedo / pi x (indirect + direct) — the indirect
// light per vertex from the irradiance volume, the direct light from the same samples.
//
// What the objects block is found by shadow maps, as in the paper: per window sample a
// perspective map from the sample around the objects' bounding sphere, per direction of the
// sun's disc (four) an orthographic one, each holding the nearest room surface and the nearest
// object surface along every line (two channels, so that a shadow the room already casts is not
// cast again). The maps are made again when the objects change; a frame only reads them. The
// light itself (the samples, their sky radiance, the room's image, the per-vertex indirect light,
// which tiles a shadow may reach) is the library's.
//
// The view is the photo's camera (differential rendering is defined per photo pixel), drawn at
// any size. Needs a current OpenGL 3.3 context for every call except the constructor.
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

#include "relume/geometry/camera.h"
#include "relume/image/image.h"
#include "relume/viewport/gl_renderer.h"

namespace relume {

struct Polygon;
namespace ibr {
struct ImageObject;
struct ObjectLighting;
struct DrawnTables;
}  // namespace ibr
namespace daylight {
struct InteractiveSky;
struct ShadowReach;
struct ObjectIndirect;
}  // namespace daylight

class GlDaylightRenderer {
 public:
  GlDaylightRenderer();
  ~GlDaylightRenderer();
  // Compiles the shaders. Throws relume::Error when the context cannot run them.
  void initialize();
  // The room's polygons that block light (DaylightRelighting::roomPolygons) and its photo's camera.
  void setRoom(const std::vector<std::vector<glm::dvec3>>& polygons, const Camera& photoCamera);
  // The sky's light (DaylightRelighting::interactiveSky). Throws relume::Error when the context
  // cannot hold a map per window sample.
  void setSky(const daylight::InteractiveSky& sky);
  // The virtual objects (faces with their albedos), their indirect light
  // (DaylightRelighting::objectIndirect) and the tiles their shadows may reach
  // (DaylightRelighting::shadowReach for their bounding sphere): the shadow maps are made again.
  // `reach` is for the sphere around the boxes and the image-based objects both.
  void setObjects(const std::vector<Polygon>& objects, const daylight::ObjectIndirect& indirect,
                  const daylight::ShadowReach& reach);
  // Image-based objects (Dinh, Metoyer, Turk) lit by daylight: each with its light
  // (ibr::daylightAt) and the tables of the views the photo's camera draws it from, made with it
  // (ibr::drawnTables, after ibr::keepDisplayLamps(light, fan, place, imageLamps())), as the CPU
  // path (ibr::drawImageObjectsInDaylight) draws them; their silhouettes go into the shadow maps
  // (made again at the next draw), so their shadows fall on the room as the boxes' do.
  void setImageObjects(const std::vector<ibr::ImageObject>& objects, const std::vector<ibr::ObjectLighting>& lights,
                       std::vector<ibr::DrawnTables> tables);
  static int imageLamps();
  // The window samples' shadow maps, size x size texels (default 128: their shadows are soft, each
  // one of many), and the sun's (default 256: its shadow is sharp); made again at the next draw.
  void setMapSize(int size);
  int mapSize() const;
  void setSunMapSize(int size);
  int sunMapSize() const;
  int mapCount() const;  // window samples + the sun's four (when the sky has a sun)
  bool ready() const;    // room and sky set
  // Clears `target` and draws the photo camera's view into it at `rect` (the objects' maps made
  // first when they are out of date).
  void draw(const DisplaySettings& display, unsigned target, const ViewRect& rect);
  // The view at the photo camera's resolution, linear radiance, top row first (as the library's
  // render() gives it).
  ImageRGB renderLinear();
  // Milliseconds of the last draw (glFinish before and after), and of its shadow-map part.
  double lastDrawMilliseconds() const;
  double lastMapMilliseconds() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace relume
