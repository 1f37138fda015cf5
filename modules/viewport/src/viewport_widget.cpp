#include "relume/viewport/viewport_widget.h"

#include <QCoreApplication>
#include <QHBoxLayout>
#include <QMouseEvent>
#include <QOpenGLContext>
#include <QOpenGLFramebufferObject>
#include <QOpenGLFunctions>
#include <QOpenGLPaintDevice>
#include <QOpenGLWindow>
#include <QPainter>
#include <QPainterPath>
#include <QSurfaceFormat>
#include <QWheelEvent>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <glm/geometric.hpp>

#include "relume/geometry/error.h"
#include "relume/geometry/scene.h"
#include "relume/ibr/relit_objects.h"
#include "relume/raytrace/ray_scene.h"
#include "relume/relight/relighter.h"

namespace relume {

namespace {

// The false-colour scale: luminance per colour, three labelled decades (the shader's ramp).
void paintColourBar(QPainter& p, const QRect& area, double lo, double hi) {
  p.save();
  p.translate(area.topLeft());
  const int width = area.width(), height = area.height();
  p.fillRect(QRect(0, 0, width, height), QColor(20, 20, 22, 170));
  const QRect bar(8, 24, 16, height - 36);
  QLinearGradient g(bar.bottomLeft(), bar.topLeft());
  const QColor stops[5] = {QColor::fromRgbF(0.05f, 0.1f, 0.6f), QColor::fromRgbF(0.1f, 0.7f, 0.9f),
                           QColor::fromRgbF(0.15f, 0.8f, 0.2f), QColor::fromRgbF(0.95f, 0.9f, 0.1f),
                           QColor::fromRgbF(0.9f, 0.1f, 0.1f)};
  for (int k = 0; k < 5; ++k) g.setColorAt(k / 4.0, stops[k]);
  p.fillRect(bar, g);
  p.setPen(Qt::white);
  p.drawText(QRect(4, 2, width - 8, 20), Qt::AlignLeft | Qt::AlignVCenter, ViewportWidget::tr("luminance"));
  const int steps = 4;
  for (int k = 0; k <= steps; ++k) {
    const double v = std::pow(10.0, lo + (hi - lo) * k / steps);
    const int y = bar.bottom() - k * bar.height() / steps;
    p.drawLine(bar.right() + 1, y, bar.right() + 5, y);
    p.drawText(bar.right() + 8, y + 4, QString::number(v, 'g', 2));
  }
  p.restore();
}

}  // namespace

struct ViewportWidget::ImageObjects {
  std::vector<ibr::ImageObject> objects;
  std::vector<ibr::ObjectLighting> lights;
};

// The native GL window the viewport shows its frames in (inside a window container): frames are
// drawn straight into the window's own framebuffer and swapped, which on Mesa's llvmpipe under X
// costs less than QOpenGLWidget's render-to-texture and composition (relume-workbench --bench
// measures both). Mouse events go to the ViewportWidget's handlers.
class ViewportWindow : public QOpenGLWindow {
 public:
  explicit ViewportWindow(ViewportWidget* owner) : owner_(owner) {}

 protected:
  void initializeGL() override { owner_->initializeGL(); }
  void paintGL() override { owner_->paintFrame(defaultFramebufferObject(), this); }
  void mousePressEvent(QMouseEvent* e) override {
    owner_->setFocus(Qt::MouseFocusReason);
    owner_->mousePressEvent(e);
  }
  void mouseMoveEvent(QMouseEvent* e) override { owner_->mouseMoveEvent(e); }
  void mouseReleaseEvent(QMouseEvent* e) override { owner_->mouseReleaseEvent(e); }
  void wheelEvent(QWheelEvent* e) override { owner_->wheelEvent(e); }

 private:
  ViewportWidget* owner_;
};

QSurfaceFormat viewportSurfaceFormat() {
  QSurfaceFormat f = QSurfaceFormat::defaultFormat();
  f.setVersion(3, 3);
  f.setProfile(QSurfaceFormat::CoreProfile);
  f.setDepthBufferSize(24);
  f.setStencilBufferSize(8);  // QPainter fills non-convex overlays with the stencil
  return f;
}

ViewportWidget::ViewportWidget(QWidget* parent) : QWidget(parent), renderer_(std::make_unique<GlRelightRenderer>()) {
  window_ = new ViewportWindow(this);
  window_->setFormat(viewportSurfaceFormat());
  // Keys stay with the widget (and the main window's shortcuts) when the GL window is clicked.
  window_->setFlag(Qt::WindowDoesNotAcceptFocus);
  container_ = QWidget::createWindowContainer(window_, this);
  container_->setFocusPolicy(Qt::NoFocus);
  auto* layout = new QHBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(container_);
  setMinimumSize(320, 240);
  setFocusPolicy(Qt::StrongFocus);
  setMouseTracking(true);
}

ViewportWidget::~ViewportWidget() {
  if (window_->isValid()) {
    window_->makeCurrent();
    renderer_.reset();
    window_->doneCurrent();
  }
}

void ViewportWidget::requestFrame() { window_->update(); }

QWindow* ViewportWidget::glWindow() const { return window_; }

void ViewportWidget::renderNow() {
  window_->update();
  QEvent request(QEvent::UpdateRequest);
  QCoreApplication::sendEvent(window_, &request);
}

void ViewportWidget::setRoom(const Scene* scene, const RelightData* data, const RelightSession* session) {
  scene_ = scene;
  data_ = data;
  session_ = session;
  photo_.clear();
  if (glReady_) glError_.clear();  // a new room gets a new chance (an unusable context stays unusable)
  roomDirty_ = meshDirty_ = lightingDirty_ = true;
  if (imageObjects_) *imageObjects_ = ImageObjects{};  // the new room's come with it
  objectsDirty_ = true;
  resetOrbit();
  requestFrame();
}

void ViewportWidget::meshChanged() {
  meshDirty_ = true;
  requestFrame();
}

void ViewportWidget::lightingChanged() {
  lightingDirty_ = true;
  requestFrame();
}

void ViewportWidget::setViewMode(ViewMode mode) {
  mode_ = mode;
  requestFrame();
}

void ViewportWidget::setExposureEV(double ev) {
  ev_ = ev;
  requestFrame();
}

void ViewportWidget::setFalseColour(bool on) {
  falseColour_ = on;
  requestFrame();
}

void ViewportWidget::lockToPhoto(const std::string& photo) {
  photo_ = photo;
  orbit_ = false;
  emit viewChanged();
  requestFrame();
}

void ViewportWidget::setOrbit(bool free) {
  orbit_ = free;
  emit viewChanged();
  requestFrame();
}

void ViewportWidget::resetOrbit() {
  orbitState_ = Orbit{};
  if (!scene_ || scene_->polygons.empty()) return;
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const auto& p : scene_->polygons)
    for (const auto& v : p.vertices) {
      lo = glm::min(lo, v);
      hi = glm::max(hi, v);
    }
  const glm::dvec3 c = 0.5 * (lo + hi);
  for (int k = 0; k < 3; ++k) orbitState_.target[k] = c[k];
  // Start from the photo's camera position when there is one, else from a corner of the room.
  glm::dvec3 eye = c + glm::dvec3(0.4, -0.45, 0.1) * glm::length(hi - lo);
  if (data_)
    if (const Photo* ph = scene_->findPhoto(data_->photo)) eye = ph->camera.center();
  const glm::dvec3 d = eye - c;
  orbitState_.distance = std::max(0.5, glm::length(d));
  orbitState_.yaw = std::atan2(d.y, d.x);
  orbitState_.pitch = std::asin(std::clamp(d.z / orbitState_.distance, -1.0, 1.0));
}

void ViewportWidget::setOrbitState(const Orbit& o) {
  orbitState_ = o;
  requestFrame();
}

Camera ViewportWidget::currentCamera() const {
  if (!scene_ || !data_) return Camera{};
  if (!orbit_) {
    const Photo* ph = scene_->findPhoto(photo_.empty() ? data_->photo : photo_);
    if (!ph) ph = scene_->findPhoto(data_->photo);
    return ph ? ph->camera : Camera{};
  }
  const auto& o = orbitState_;
  const glm::dvec3 target(o.target[0], o.target[1], o.target[2]);
  const glm::dvec3 dir(std::cos(o.pitch) * std::cos(o.yaw), std::cos(o.pitch) * std::sin(o.yaw), std::sin(o.pitch));
  const int w = std::max(1, int(width() * devicePixelRatio())), h = std::max(1, int(height() * devicePixelRatio()));
  const double f = 0.5 * h / std::tan(0.5 * 55.0 * 3.14159265358979 / 180.0);  // 55 degrees vertical
  return Camera::lookAt(target + o.distance * dir, target, w, h, f);
}

ViewRect ViewportWidget::photoRect() const {
  const int W = std::max(1, int(width() * devicePixelRatio())), H = std::max(1, int(height() * devicePixelRatio()));
  const Camera cam = currentCamera();
  if (orbit_ || cam.width <= 0) return {0, 0, W, H};
  // The photo fitted into the widget, aspect kept, centred.
  const double s = std::min(double(W) / cam.width, double(H) / cam.height);
  const int w = std::max(1, int(std::lround(cam.width * s))), h = std::max(1, int(std::lround(cam.height * s)));
  return {(W - w) / 2, (H - h) / 2, w, h};
}

void ViewportWidget::initializeGL() {
  try {
    renderer_->initialize();
    glReady_ = true;
  } catch (const std::exception& e) {
    glError_ = QString::fromStdString(e.what());
  }
}


void ViewportWidget::setImageObjects(std::vector<ibr::ImageObject> objects, std::vector<ibr::ObjectLighting> lights) {
  if (!imageObjects_) imageObjects_ = std::make_unique<ImageObjects>();
  imageObjects_->objects = std::move(objects);
  imageObjects_->lights = std::move(lights);
  objectsDirty_ = true;
  requestFrame();
}

void ViewportWidget::upload() {
  if (!glReady_) return;
  if (!scene_ || !data_ || !session_) return;
  try {
    if (roomDirty_) renderer_->setRoom(*scene_, *data_);
    if (roomDirty_ || meshDirty_) renderer_->setMesh(*session_);
    else if (lightingDirty_) renderer_->setLighting(*session_);
    roomDirty_ = meshDirty_ = lightingDirty_ = false;
    if (objectsDirty_ && imageObjects_) {
      objectsDirty_ = false;
      renderer_->setImageObjects(imageObjects_->objects, imageObjects_->lights, session_->engine());
    }
    objectsDirty_ = false;
  } catch (const std::exception& e) {
    glError_ = QString::fromStdString(e.what());
  }
}

size_t ViewportWidget::leafCount() const { return renderer_->leafCount(); }

void ViewportWidget::paintFrame(unsigned framebuffer, QPaintDevice* device) {
  upload();
  QString message = glError_;
  const bool drawing = glError_.isEmpty() && session_ && renderer_->ready();
  const int W = std::max(1, int(width() * devicePixelRatio())), H = std::max(1, int(height() * devicePixelRatio()));
  if (!drawing) {  // (the renderer clears what it draws into)
    auto* f = QOpenGLContext::currentContext()->functions();
    f->glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    f->glViewport(0, 0, W, H);
    f->glClearColor(0.16f, 0.16f, 0.17f, 1.f);
    f->glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  }
  DisplaySettings d;
  if (drawing) {
    d.output = falseColour_ ? DisplayOutput::FalseColour : DisplayOutput::Exposed;
    d.exposure = (data_ ? data_->photoExposure : 1.0) * std::pow(2.0, ev_);
    // False colour: from 1 % to 200 % of the luminance that the display shows as white.
    d.falseMin = std::log10(0.01 / d.exposure);
    d.falseMax = std::log10(2.0 / d.exposure);
    try {
      renderer_->draw(currentCamera(), mode_, d, framebuffer, photoRect());
      frameMs_ = renderer_->lastDrawMilliseconds();
    } catch (const std::exception& e) {
      message = QString::fromStdString(e.what());
    }
    emit frameDrawn(frameMs_);
  } else if (message.isEmpty()) {
    message = tr("Open a room or a project (File > Open) to relight it.");
  }
  const bool showing = drawing && message.isEmpty();
  if (showing && overlays_.empty() && !falseColour_) return;
  // What is drawn over the frame: overlays, the colour bar, or the message.
  QOpenGLContext::currentContext()->functions()->glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  QPainter p(device);
  if (showing) {
    paintOverlays(p);
    if (falseColour_) paintColourBar(p, QRect(width() - 110, 16, 100, std::max(120, height() - 32)), d.falseMin, d.falseMax);
  } else {
    p.setPen(QColor(0xdd, 0xdd, 0xdd));
    p.drawText(rect().adjusted(16, 16, -16, -16), Qt::AlignCenter | Qt::TextWordWrap, message);
  }
}

void ViewportWidget::setOverlays(std::vector<ViewportOverlay> overlays) {
  overlays_ = std::move(overlays);
  requestFrame();
}

void ViewportWidget::paintOverlays(QPainter& p) {
  p.setRenderHint(QPainter::Antialiasing);
  const Camera cam = currentCamera();
  const ViewRect rect = photoRect();
  for (const auto& o : overlays_) {
    const QColor c((o.rgb >> 16) & 255, (o.rgb >> 8) & 255, o.rgb & 255);
    QPainterPath path;
    path.setFillRule(Qt::WindingFill);  // overlapping loops fill once: their union
    for (const auto& loop : o.areas) {
      QPolygonF poly;
      QPointF q;
      for (const auto& v : loop)
        if (widgetPosition(cam, rect, v, q)) poly << q;
      if (poly.size() == int(loop.size()) && poly.size() >= 3) path.addPolygon(poly);
    }
    if (!path.isEmpty()) {
      QColor fill = c;
      fill.setAlpha(70);
      p.fillPath(path, fill);
      p.strokePath(path.simplified(), QPen(c, 1.5));
    }
    p.setPen(QPen(c, 2));
    for (const auto& m : o.markers) {
      QPointF q;
      if (!widgetPosition(cam, rect, m, q)) continue;
      p.drawEllipse(q, 6, 6);
      p.drawLine(q - QPointF(10, 0), q + QPointF(10, 0));
      p.drawLine(q - QPointF(0, 10), q + QPointF(0, 10));
    }
  }
}

QImage ViewportWidget::grabFramebuffer() {
  if (!window_->isValid()) return QImage();
  window_->makeCurrent();
  const QSize s(std::max(1, int(width() * devicePixelRatio())), std::max(1, int(height() * devicePixelRatio())));
  QOpenGLFramebufferObjectFormat format;
  format.setAttachment(QOpenGLFramebufferObject::CombinedDepthStencil);
  QImage img;
  {
    QOpenGLFramebufferObject fbo(s, format);
    QOpenGLPaintDevice device(s);
    device.setDevicePixelRatio(devicePixelRatio());
    paintFrame(fbo.handle(), &device);
    img = fbo.toImage();
    img.setDevicePixelRatio(devicePixelRatio());
  }
  window_->doneCurrent();
  return img;
}

ImageRGB ViewportWidget::renderLinear(const Camera& camera, ViewMode mode) {
  if (!window_->isValid()) throw Error("", "viewport", "the viewport is not on screen yet");
  window_->makeCurrent();
  struct Done {
    QOpenGLWindow* w;
    ~Done() { w->doneCurrent(); }
  } done{window_};
  upload();
  if (!glReady_ || !glError_.isEmpty() || !renderer_->ready())
    throw Error("", "viewport", glError_.isEmpty() ? "nothing to render" : glError_.toStdString());
  return renderer_->renderLinear(camera, mode);
}

ViewportPick ViewportWidget::pickAt(const QPointF& pos) const {
  ViewportPick pick;
  if (!session_) return pick;
  const Camera cam = currentCamera();
  const ViewRect r = photoRect();
  if (cam.width <= 0 || r.width <= 0 || r.height <= 0) return pick;
  // Widget (logical, y down) -> framebuffer pixels -> the camera's pixels.
  const double dpr = devicePixelRatio();
  const double fbY = pos.y() * dpr, fbX = pos.x() * dpr;
  const double H = std::max(1, int(height() * dpr));
  // photoRect is in GL coordinates (y up from the bottom).
  const double x = (fbX - r.x) * cam.width / r.width, y = (fbY - (H - r.y - r.height)) * cam.height / r.height;
  pick.origin = cam.center();
  pick.direction = glm::normalize(cam.rayDirection(x, y));
  if (x < 0 || y < 0 || x > cam.width || y > cam.height) return pick;
  const RayHit hit = session_->engine().rayScene().intersect(Ray{glm::vec3(pick.origin), glm::vec3(pick.direction), 1e-4f, 1e30f});
  if (hit.polygon < 0) return pick;
  pick.surface = hit.polygon;
  pick.point = glm::dvec3(hit.point);
  glm::dvec3 n = glm::normalize(glm::dvec3(hit.geometricNormal));
  if (glm::dot(n, pick.direction) > 0) n = -n;
  pick.normal = n;
  return pick;
}

bool ViewportWidget::widgetPosition(const glm::dvec3& world, QPointF& pos) const {
  return widgetPosition(currentCamera(), photoRect(), world, pos);
}

bool ViewportWidget::widgetPosition(const Camera& cam, const ViewRect& r, const glm::dvec3& world, QPointF& pos) const {
  glm::dvec2 px;
  if (cam.width <= 0 || !cam.project(world, px)) return false;
  const double dpr = devicePixelRatio();
  const double H = std::max(1, int(height() * dpr));
  pos = QPointF((r.x + px.x * r.width / cam.width) / dpr, ((H - r.y - r.height) + px.y * r.height / cam.height) / dpr);
  return true;
}

void ViewportWidget::mousePressEvent(QMouseEvent* e) {
  lastMouse_ = e->position().toPoint();
  gestureActive_ = false;
  if (gestures_ && e->button() == Qt::LeftButton && session_)
    gestureActive_ = gestures_->press(pickAt(e->position()), e->modifiers());
  QWidget::mousePressEvent(e);
}

void ViewportWidget::mouseReleaseEvent(QMouseEvent* e) {
  if (gestureActive_ && e->button() == Qt::LeftButton) {
    gestureActive_ = false;
    gestures_->release(pickAt(e->position()));
  }
  QWidget::mouseReleaseEvent(e);
}

void ViewportWidget::mouseMoveEvent(QMouseEvent* e) {
  const QPoint p = e->position().toPoint();
  const QPoint d = p - lastMouse_;
  lastMouse_ = p;
  if (gestureActive_) {
    gestures_->drag(pickAt(e->position()));
    return;
  }
  if (gestures_ && session_ && e->buttons() == Qt::NoButton) {
    const Qt::CursorShape shape = gestures_->hoverCursor(pickAt(e->position()));
    setCursor(shape);
    window_->setCursor(shape);
  }
  if (!orbit_) return;
  if (e->buttons() & Qt::LeftButton) {  // orbit about the target
    orbitState_.yaw -= 0.008 * d.x();
    orbitState_.pitch = std::clamp(orbitState_.pitch + 0.008 * d.y(), -1.5, 1.5);
  } else if (e->buttons() & (Qt::MiddleButton | Qt::RightButton)) {  // pan in the view plane
    const Camera c = currentCamera();
    const double s = orbitState_.distance / c.fy();
    const glm::dvec3 right = glm::transpose(c.R) * glm::dvec3(1, 0, 0), down = glm::transpose(c.R) * glm::dvec3(0, 1, 0);
    const glm::dvec3 m = -s * (double(d.x()) * right + double(d.y()) * down);
    for (int k = 0; k < 3; ++k) orbitState_.target[k] += m[k];
  } else {
    return;
  }
  emit viewChanged();
  requestFrame();
}

void ViewportWidget::wheelEvent(QWheelEvent* e) {
  if (!orbit_) return;
  orbitState_.distance = std::clamp(orbitState_.distance * std::pow(0.9, e->angleDelta().y() / 120.0), 0.2, 100.0);
  emit viewChanged();
  requestFrame();
}

}  // namespace relume
