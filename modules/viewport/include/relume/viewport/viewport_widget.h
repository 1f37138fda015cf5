#pragma once
// The relighting viewport of the workbench: a widget holding a native OpenGL window (the faster
// presentation path on Mesa, see relume-workbench --bench) that shows a RelightSession through
// a photo's camera (the default: the image lies exactly on the photo) or from a free orbit
// around the model, in one of the view modes, exposed like the photo.
#include <QImage>
#include <QSurfaceFormat>
#include <QWidget>
#include <glm/vec3.hpp>
#include <memory>
#include <vector>

#include "relume/geometry/camera.h"
#include "relume/image/image.h"
#include "relume/viewport/gl_renderer.h"

class QPainter;
class QWindow;
class QPaintDevice;

namespace relume {

struct Scene;
struct RelightData;
class RelightSession;
namespace ibr {
struct ImageObject;
struct ObjectLighting;
}  // namespace ibr

// What lies under a point of the viewport: the engine surface hit (real polygon, virtual lamp or
// object face), the point, and the surface normal turned towards the viewer.
struct ViewportPick {
  int surface = -1;
  glm::dvec3 point{0.0}, normal{0.0};
  glm::dvec3 origin{0.0}, direction{0.0};  // the ray through the cursor
  bool hit() const { return surface >= 0; }
};

// Who edits the scene with the mouse: the viewport offers each left-button gesture to it first;
// when press() returns false the gesture navigates the view as usual.
class ViewportGestures {
 public:
  virtual ~ViewportGestures() = default;
  virtual bool press(const ViewportPick& pick, Qt::KeyboardModifiers mods) = 0;
  virtual void drag(const ViewportPick& pick) = 0;
  virtual void release(const ViewportPick& pick) = 0;
  virtual Qt::CursorShape hoverCursor(const ViewportPick& pick) const = 0;
};

// Marks drawn over the image, not part of its light: translucent areas (closed loops of world
// points, filled as their union and outlined) and point markers, in one colour (0xRRGGBB).
struct ViewportOverlay {
  std::vector<std::vector<glm::dvec3>> areas;
  std::vector<glm::dvec3> markers;
  unsigned rgb = 0xff8c1a;
};

class ViewportWindow;

// What the viewport's renderer needs of an OpenGL surface: 3.3 core, a depth buffer, and a
// stencil for QPainter's overlays. Set it as the default before the first window exists.
QSurfaceFormat viewportSurfaceFormat();

class ViewportWidget : public QWidget {
  Q_OBJECT
 public:
  explicit ViewportWidget(QWidget* parent = nullptr);
  ~ViewportWidget() override;

  // The room shown (all three must outlive the widget's use of them, or be cleared by nullptrs).
  void setRoom(const Scene* scene, const RelightData* data, const RelightSession* session);
  // Call after the session's mesh changed (objects moved, lamps added) / after any lighting edit.
  void meshChanged();
  void lightingChanged();
  // Image-based objects with their light (ibr::lightingAt on the session's engine), drawn from the
  // next frame on (see GlRelightRenderer::setImageObjects).
  void setImageObjects(std::vector<ibr::ImageObject> objects, std::vector<ibr::ObjectLighting> lights);

  void setViewMode(ViewMode mode);
  ViewMode viewMode() const { return mode_; }
  void setExposureEV(double ev);  // relative to the photo's exposure
  double exposureEV() const { return ev_; }
  void setFalseColour(bool on);
  bool falseColour() const { return falseColour_; }
  // Locks the view to a photo's camera (by name; empty = the textures' photo) or frees it.
  void lockToPhoto(const std::string& photo = {});
  void setOrbit(bool free);
  bool orbiting() const { return orbit_; }
  void resetOrbit();
  // The camera the viewport shows now, at the widget's size (orbit) or the photo's own camera.
  Camera currentCamera() const;

  // The ray through a widget position (logical pixels) and what it meets in the session's scene.
  ViewportPick pickAt(const QPointF& pos) const;
  // The widget position (logical pixels) where a world point appears; false when behind the camera.
  bool widgetPosition(const glm::dvec3& world, QPointF& pos) const;
  void setGestures(ViewportGestures* g) { gestures_ = g; }
  void setOverlays(std::vector<ViewportOverlay> overlays);

  // Renders `camera`'s view at its own resolution into a float buffer: linear radiance.
  ImageRGB renderLinear(const Camera& camera, ViewMode mode);
  double lastFrameMilliseconds() const { return frameMs_; }
  // The frame as shown (overlays included), drawn afresh into an image of the widget's size.
  QImage grabFramebuffer();
  // Draws a frame now (not at the next turn of the event loop), or at the next turn.
  void renderNow();
  void requestFrame();
  QWindow* glWindow() const;  // the native window the frames are shown in (it takes the mouse)
  size_t leafCount() const;

  // Orbit state, for projects that keep the view.
  struct Orbit {
    double yaw = 0, pitch = 0, distance = 0;
    double target[3] = {0, 0, 0};
  };
  Orbit orbitState() const { return orbitState_; }
  void setOrbitState(const Orbit& o);

 signals:
  void frameDrawn(double milliseconds);
  void viewChanged();

 protected:
  void mousePressEvent(QMouseEvent* e) override;
  void mouseMoveEvent(QMouseEvent* e) override;
  void mouseReleaseEvent(QMouseEvent* e) override;
  void wheelEvent(QWheelEvent* e) override;

 private:
  ViewRect photoRect() const;
  void upload();
  void paintOverlays(QPainter& p);
  bool widgetPosition(const Camera& cam, const ViewRect& rect, const glm::dvec3& world, QPointF& pos) const;
  friend class ViewportWindow;
  void initializeGL();
  void paintFrame(unsigned framebuffer, QPaintDevice* device);
  ViewportWindow* window_ = nullptr;
  QWidget* container_ = nullptr;

  std::unique_ptr<GlRelightRenderer> renderer_;
  const Scene* scene_ = nullptr;
  const RelightData* data_ = nullptr;
  const RelightSession* session_ = nullptr;
  bool roomDirty_ = false, meshDirty_ = false, lightingDirty_ = false, objectsDirty_ = false, glReady_ = false;
  struct ImageObjects;
  std::unique_ptr<ImageObjects> imageObjects_;
  QString glError_;
  ViewMode mode_ = ViewMode::Relit;
  double ev_ = 0;
  bool falseColour_ = false;
  std::string photo_;
  bool orbit_ = false;
  Orbit orbitState_;
  QPoint lastMouse_;
  ViewportGestures* gestures_ = nullptr;
  std::vector<ViewportOverlay> overlays_;
  bool gestureActive_ = false;
  double frameMs_ = 0;
};

}  // namespace relume
