#pragma once
// Image-based objects in a relighting session: placed, checked against the room, lit by the
// session's lamps (real at their current scales, virtual) and indirect light, drawn with their
// shadows into the session's relit image. What `relume relight` and the workbench call.
#include <memory>
#include <string>
#include <vector>

#include "relume/ibr/ibr_object.h"

namespace relume {
class RelightSession;
struct Scene;
}  // namespace relume

namespace relume::ibr {

struct ImageObject {
  std::string name;
  std::shared_ptr<const ImageFan> fan;
  Placement place;
  std::string fanFile;  // for messages
};

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
