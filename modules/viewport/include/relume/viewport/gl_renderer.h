#pragma once
// The relighting renderer of the workbench (OpenGL 3.3 core): draws a RelightSession's display
// mesh as texture x B / D (or another view mode) and applies the display transform (linear, the
// photo's exposure and sRGB, or false colour) in the same pass, into the target framebuffer.
// It computes no light: B, D and the textures are the session's. Needs a current OpenGL 3.3
// context for every call except the constructor.
#include <memory>
#include <vector>

#include "relume/geometry/camera.h"
#include "relume/image/image.h"

namespace relume {

struct Scene;
struct RelightData;
class RelightSession;
namespace radiosity {
class HierarchicalRadiosity;
}
namespace ibr {
struct ImageObject;
struct ObjectLighting;
}  // namespace ibr

enum class ViewMode { Relit = 0, RatioOnly, Photo, Unoccluded, Radiosity, DisplayFactor, Leaves, References };
enum class DisplayOutput { Linear = 0, Exposed = 1, FalseColour = 2 };

struct DisplaySettings {
  DisplayOutput output = DisplayOutput::Exposed;
  double exposure = 1.0;  // linear gain before sRGB (the photo's exposure x 2^EV)
  double falseMin = -3, falseMax = 1;  // log10 luminance at the ends of the false-colour scale
};

// A rectangle of the target framebuffer in GL's convention (origin bottom-left), pixels.
struct ViewRect {
  int x = 0, y = 0, width = 0, height = 0;
};

class GlRelightRenderer {
 public:
  GlRelightRenderer();
  ~GlRelightRenderer();
  // Compiles the shaders (from the binary's resources). Throws relume::Error when the context
  // cannot run them.
  void initialize();
  // Textures and the glow layer of a preprocessed room; then the session's mesh and lighting.
  void setRoom(const Scene& scene, const RelightData& data);
  void setMesh(const RelightSession& session);      // after the session's mesh changed
  void setLighting(const RelightSession& session);  // after any lighting change
  // Image-based objects (Dinh, Metoyer, Turk) drawn into the relit and ratio-only views, with
  // their shadows on the room: each with its light (ibr::lightingAt on `engine`, the session's).
  // The light is the library's (its tables and lamps); the shaders look it up, as the CPU
  // renderer (ibr::drawObject, ibr::drawShadows) does per pixel. Call after setMesh; again after
  // any change of the objects or of the light.
  void setImageObjects(const std::vector<ibr::ImageObject>& objects, const std::vector<ibr::ObjectLighting>& lights,
                       const radiosity::HierarchicalRadiosity& engine);
  size_t imageObjectCount() const;
  bool ready() const;
  // Clears `target` (a framebuffer object id; 0 the default; black for linear output, grey
  // otherwise) and draws `camera`'s view into it at `rect`.
  // The glow layer is added when `camera` is the photo's camera (its image, scaled to rect).
  void draw(const Camera& camera, ViewMode mode, const DisplaySettings& display, unsigned target, const ViewRect& rect);
  // Renders `camera`'s view at the camera's own resolution into a float framebuffer and reads it
  // back: linear radiance, top row first (as RelightSession::render gives it).
  ImageRGB renderLinear(const Camera& camera, ViewMode mode);
  // GPU time of the last draw (glFinish before and after), milliseconds.
  double lastDrawMilliseconds() const;
  size_t leafCount() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace relume
