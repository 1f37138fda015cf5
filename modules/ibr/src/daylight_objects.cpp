// Image-based objects lit by daylight: the window samples and the sun of Grosch et al.'s
// interactive method as lamps of the tables (Dinh et al.'s, one per lamp), the irradiance volume
// as the indirect table, the shadows on the room taken off the irradiance the daylight render
// showed.
#include <algorithm>
#include <cmath>
#include <memory>
#include <glm/geometric.hpp>
#include <numbers>

#include "relume/daylight/basis.h"
#include "relume/daylight/relight.h"
#include "relume/daylight/sky.h"
#include "relume/daylight/volume.h"
#include "relume/geometry/error.h"
#include "relume/geometry/polygon.h"
#include "relume/ibr/relit_objects.h"
#include "relume/radiosity/hierarchy.h"
#include "relume/raytrace/ray_scene.h"

namespace relume::ibr {

namespace {

// A square of `area` centred on p across the unit normal n, its corners counter-clockwise about n.
std::vector<glm::dvec3> squareAcross(const glm::dvec3& p, const glm::dvec3& n, double area) {
  const glm::dvec3 a = glm::normalize(glm::cross(n, std::abs(n.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0)));
  const glm::dvec3 b = glm::cross(n, a);
  const double h = 0.5 * std::sqrt(area);
  return {p - h * a - h * b, p + h * a - h * b, p + h * a + h * b, p - h * a + h * b};
}

// The sun as a lamp: a square facing the room kSunDistance metres along its direction, as wide as
// its disc (0.53 degrees, as the daylight path takes it), its exitance such that a surface facing
// it receives the sky image's sun irradiance. Far enough that the direction to it changes by a
// tenth of a degree across a room, near enough for single-precision shadow rays.
constexpr double kSunDistance = 2000.0;
constexpr double kSunHalfAngle = 0.265 * std::numbers::pi / 180.0;

}  // namespace

ObjectLighting daylightAt(daylight::DaylightRelighting& session, const daylight::SkyRadiance& sky, const glm::dvec3& c,
                          double radius, const RayScene* occluders) {
  daylight::DaylightBasis& basis = session.basis();
  if (basis.anyLampOn())
    throw Error("", "image-based object", "under daylight image-based objects are lit by daylight only: switch the lamps off");
  const auto& h = basis.engine();
  ObjectLighting out;
  out.centre = c;
  out.occluders = occluders;
  // The room's light at the centre, the windows' own left out (the samples bring it).
  daylight::IrradianceVolume& volume = session.volume();
  volume.combine(basis, sky, c - glm::dvec3(radius), c + glm::dvec3(radius));
  out.indirect = volume.at(c);
  // And at each point of the object (within its sphere: the points combined).
  const daylight::IrradianceVolume* vol = &volume;
  out.indirectAt = [vol, c, radius](const glm::dvec3& p) {
    const glm::dvec3 d = p - c;
    const double len = glm::length(d);
    return vol->at(len > radius ? c + d * (radius / len) : p);
  };
  const glm::dvec3 ground = basis.groundRadiance(sky);
  // The interactive method's window samples (kept by the session while the sky stays).
  const std::vector<daylight::DirectSample>& samples = session.interactiveSky(sky).window;
  for (const daylight::DirectSample& ws : samples) {
    const glm::dvec3 toSample = ws.point - c;
    const double d = glm::length(toSample);
    if (!(d > 0) || glm::dot(ws.normal, toSample) >= 0) continue;  // the centre is not in front of it
    const int k = basis.regions().regionOf(toSample / d);
    ObjectLamp l;
    l.polygon = squareAcross(ws.point, ws.normal, ws.area);
    l.exitance = std::numbers::pi * (k >= 0 ? sky.region[size_t(k)] : ground);
    if (glm::dot(l.exitance, l.exitance) <= 0) continue;
    l.position = ws.point;
    l.visible = blockedBetween(h.rayScene(), occluders, c, ws.point, 1e-5f) ? 0.0 : 1.0;
    l.intensity = l.intensityTowards(c);
    out.lamps.push_back(std::move(l));
  }
  if (sky.sun.found && sky.sun.direction.z > 0 && glm::dot(sky.sun.irradiance, sky.sun.irradiance) > 0) {
    const glm::dvec3 s = glm::normalize(sky.sun.direction);
    const double solidAngle = 2 * std::numbers::pi * (1 - std::cos(kSunHalfAngle));
    const double area = solidAngle * kSunDistance * kSunDistance;
    ObjectLamp l;
    l.position = c + kSunDistance * s;
    l.polygon = squareAcross(l.position, -s, area);
    // E = exitance / pi x (the square's form factor, area / (pi D^2) = solid angle / pi) x pi.
    l.exitance = std::numbers::pi * sky.sun.irradiance / solidAngle;
    // Seen past the room per point of the object: the sunlit patch's edge often crosses one.
    l.perPoint = true;
    l.visible = 1.0;
    l.intensity = l.intensityTowards(c);
    // Towards the disc's centre and four points at about 0.7 of its radius (for the penumbra;
    // the square's corners lie at 1.25 radii).
    std::vector<glm::dvec3> towards{s};
    for (const auto& q : l.polygon) towards.push_back(glm::normalize(l.position + 0.55 * (q - l.position) - c));
    out.lamps.push_back(std::move(l));
    const size_t sunLamp = out.lamps.size() - 1;
    // As the daylight path lets the sun in: out through a window, the room not in the way there
    // (a gap in a model that is not closed lets no sun in).
    const radiosity::HierarchicalRadiosity* engine = &h;
    const std::vector<int>* windows = &basis.windows();
    out.roomLets = [engine, windows, towards, sunLamp, occluders](size_t lamp, const glm::dvec3& p) {
      if (lamp != sunLamp) return 1.0;
      double v = 0;
      for (const auto& d : towards) {
        const double t = daylight::throughWindow(*engine, *windows, p, d);
        if (t > 0 && !blockedBetween(engine->rayScene(), occluders, p, p + t * d, float(1e-4 / t))) v += 1.0 / double(towards.size());
      }
      return v;
    };
  }
  return out;
}

DisplayDaylight daylightForDisplay(daylight::DaylightRelighting& session, const daylight::SkyRadiance& sky,
                                   const ImageObject& object, const glm::dvec3& eye, size_t most, const RayScene* occluders) {
  const ImageFan& fan = *object.fan;
  DisplayDaylight out;
  out.light = daylightAt(session, sky, object.place.toWorld(fan, fan.centre), fan.radius * object.place.scale, occluders);
  keepDisplayLamps(out.light, fan, object.place, most);
  out.tables = drawnTables(fan, object.place, out.light, eye);
  out.light.indirectAt = nullptr;
  out.light.roomLets = nullptr;
  out.light.occluders = nullptr;
  return out;
}

std::vector<DrawStats> drawImageObjectsInDaylight(daylight::DaylightRelighting& session, const daylight::SkyRadiance& sky,
                                                  const std::vector<ImageObject>& objects, ImageRGB& image,
                                                  std::vector<uint8_t>* mask, Progress& progress,
                                                  const std::vector<Polygon>& polygonal) {
  if (objects.empty()) return std::vector<DrawStats>();
  // The render's boxes and meshes, as occluders beside the room.
  std::vector<std::vector<glm::dvec3>> faces;
  for (const Polygon& p : polygonal)
    if (p.vertices.size() >= 3) faces.push_back(p.vertices);
  const std::unique_ptr<RayScene> occluders = faces.empty() ? nullptr : std::make_unique<RayScene>(faces);
  {
    Progress built(progress, 0.0, 0.9);
    session.volume(built);  // (made once; Cancel leaves none)
  }
  session.interactiveSky(sky, progress);  // the window samples and the room under this sky, made once per sky
  const Camera& camera = session.camera();
  const ImageRGB& shown = session.lastIrradiance();
  if (image.width != camera.width || image.height != camera.height || shown.width != camera.width ||
      shown.height != camera.height)
    throw Error("", "image-based objects", "the image is not the daylight session's render through its camera");
  std::vector<ObjectLighting> lights;
  for (const auto& o : objects)
    lights.push_back(daylightAt(session, sky, o.place.toWorld(*o.fan, o.fan->centre), o.fan->radius * o.place.scale, occluders.get()));
  // The irradiance the render showed at a room point: its pixel's (the shadows ask only about
  // points their pixels see).
  const IrradianceAt irradiance = [&](int, const glm::dvec3& p) {
    glm::dvec2 px;
    if (!camera.project(p, px)) return glm::dvec3(0.0);
    const int x = std::clamp(int(std::floor(px.x)), 0, camera.width - 1), y = std::clamp(int(std::floor(px.y)), 0, camera.height - 1);
    return glm::dvec3(shown.at(x, y));
  };
  // The sun the render showed per pixel (over the pixel's footprint and the sun's disc): the most
  // an object's sun shadow takes off there.
  const daylight::InteractiveSky& room = session.interactiveSky(sky, progress);  // (valid until its next call: none below)
  if (!occluders)
    return drawImageObjects(session.basis().engine(), objects, lights, camera, irradiance, image, mask, &room.sunLight);
  // With boxes or meshes in the render, the sun it showed at a pixel is the room's less what they
  // took off there (the irradiance the room alone would have, room / gain, less the render's):
  // where their own shadow already took the sun, an object's shadow takes no more. (Taken from
  // the render rather than from the shadow lines, whose edge of a box's shadow need not fall on
  // the render's pixel for pixel: the lines alone left a dotted seam there. What the boxes took
  // off counts their sky as well, so next to a box, out of its sun shadow, an object's sun shadow
  // comes out lighter by about the sky the box hides there.)
  ImageRGB sunShown = room.sunLight;
  for (size_t i = 0; i < sunShown.pixels.size(); ++i) {
    const float g = room.gain.pixels[i];
    if (!(g > 0)) continue;
    const float lost = std::max(0.f, room.room.pixels[i] / g - shown.pixels[i]);
    sunShown.pixels[i] = std::max(0.f, sunShown.pixels[i] - lost);
  }
  return drawImageObjects(session.basis().engine(), objects, lights, camera, irradiance, image, mask, &sunShown, occluders.get());
}

}  // namespace relume::ibr
