#include "relume/inspect/vtk_view.h"

#include <vtkCamera.h>
#include <vtkCoordinate.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkOpenGLState.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>

#include <QElapsedTimer>
#include <QOpenGLContext>
#include <QMouseEvent>
#include <QWheelEvent>
#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>

namespace relume::inspect {

struct VtkView::Vtk {
  vtkSmartPointer<vtkGenericOpenGLRenderWindow> window = vtkSmartPointer<vtkGenericOpenGLRenderWindow>::New();
  vtkSmartPointer<vtkRenderer> renderer = vtkSmartPointer<vtkRenderer>::New();
};

VtkView::VtkView(QWidget* parent) : QOpenGLWidget(parent), vtk_(std::make_unique<Vtk>()) {
  vtk_->window->AddRenderer(vtk_->renderer);
  vtk_->window->SetMultiSamples(0);  // on llvmpipe multisampling costs more than the frame
  vtk_->renderer->SetBackground(0.16, 0.17, 0.19);
  vtk_->renderer->SetBackground2(0.30, 0.32, 0.36);
  vtk_->renderer->GradientBackgroundOn();
  setMinimumSize(240, 180);
}

VtkView::~VtkView() {
  // The context outlives this widget's VTK objects only for a moment: no callback may reach them.
  QObject::disconnect(contextGone_);
  makeCurrent();
  vtk_->window->Finalize();
  doneCurrent();
}

vtkRenderer* VtkView::renderer() const { return vtk_->renderer; }

void VtkView::syncSize() {
  const double r = devicePixelRatioF();
  vtk_->window->SetSize(int(width() * r), int(height() * r));
  vtk_->renderer->ResetCameraClippingRange();
}

void VtkView::initializeGL() {
  vtk_->window->SetOwnContext(false);
  vtk_->window->OpenGLInitContext();
  // A QOpenGLWidget gets a new context when it moves to another top-level window (a dock floated
  // or docked again): VTK's buffers and shaders of the old one are released with it.
  // (Qt refuses Qt::UniqueConnection for a lambda, so the one connection is kept and replaced.)
  QObject::disconnect(contextGone_);
  contextGone_ = connect(context(), &QOpenGLContext::aboutToBeDestroyed, this, [this] {
    if (!vtk_) return;
    makeCurrent();
    vtk_->window->ReleaseGraphicsResources(vtk_->window);
    doneCurrent();
  });
}

void VtkView::resizeGL(int w, int h) {
  const double r = devicePixelRatioF();
  vtk_->window->SetSize(int(w * r), int(h * r));
}

void VtkView::paintGL() {
  QElapsedTimer t;
  t.start();
  auto& w = *vtk_->window;
  syncSize();
  w.SetIsCurrent(true);
  w.SetReadyForRendering(true);
  w.SetFrameBlitModeToBlitToCurrent();
  // Qt binds its own framebuffer and viewport before paintGL: VTK's cached GL state must not
  // assume its previous values.
  vtkOpenGLState* state = w.GetState();
  state->Reset();
  state->Push();
  w.Render();
  state->Pop();
  w.SetReadyForRendering(false);
  lastFrameMs_ = double(t.nsecsElapsed()) * 1e-6;
  emit frameDrawn(lastFrameMs_);
}

void VtkView::fitCamera(const glm::dvec3& lo, const glm::dvec3& hi) {
  auto* cam = vtk_->renderer->GetActiveCamera();
  const glm::dvec3 centre = 0.5 * (lo + hi);
  const double size = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-3});
  cam->SetFocalPoint(centre.x, centre.y, centre.z);
  cam->SetPosition(centre.x - 0.9 * size, centre.y - 1.3 * size, centre.z + 1.1 * size);
  cam->SetViewUp(0, 0, 1);
  vtk_->renderer->ResetCameraClippingRange();
  update();
}

void VtkView::orbit(double azimuthDegrees, double elevationDegrees) {
  auto* cam = vtk_->renderer->GetActiveCamera();
  cam->Azimuth(azimuthDegrees);
  // Not over the poles: the elevation stops 5 degrees short of straight up or down.
  double fp[3], pos[3];
  cam->GetFocalPoint(fp);
  cam->GetPosition(pos);
  const glm::dvec3 d = glm::normalize(glm::dvec3(pos[0] - fp[0], pos[1] - fp[1], pos[2] - fp[2]));
  const double now = std::asin(std::clamp(d.z, -1.0, 1.0)) * 180.0 / std::numbers::pi;
  cam->Elevation(std::clamp(now + elevationDegrees, -85.0, 85.0) - now);
  cam->SetViewUp(0, 0, 1);
  cam->OrthogonalizeViewUp();
  vtk_->renderer->ResetCameraClippingRange();
  update();
}

bool VtkView::widgetPosition(const glm::dvec3& world, QPointF& pos) {
  syncSize();
  auto c = vtkSmartPointer<vtkCoordinate>::New();
  c->SetCoordinateSystemToWorld();
  c->SetValue(world.x, world.y, world.z);
  const double* d = c->GetComputedDoubleDisplayValue(vtk_->renderer);
  const double r = devicePixelRatioF();
  pos = QPointF(d[0] / r, height() - d[1] / r);
  return pos.x() >= 0 && pos.y() >= 0 && pos.x() < width() && pos.y() < height();
}

void VtkView::viewRay(QPointF pos, glm::dvec3& origin, glm::dvec3& direction) {
  syncSize();
  const double r = devicePixelRatioF();
  double p[2][4];
  for (int k = 0; k < 2; ++k) {
    vtk_->renderer->SetDisplayPoint(pos.x() * r, (height() - pos.y()) * r, double(k));
    vtk_->renderer->DisplayToWorld();
    vtk_->renderer->GetWorldPoint(p[k]);
    for (int c = 0; c < 3; ++c) p[k][c] /= (p[k][3] != 0 ? p[k][3] : 1.0);
  }
  origin = {p[0][0], p[0][1], p[0][2]};
  direction = glm::normalize(glm::dvec3(p[1][0], p[1][1], p[1][2]) - origin);
}

void VtkView::mousePressEvent(QMouseEvent* e) {
  pressPos_ = lastPos_ = e->position();
  dragged_ = false;
}

void VtkView::mouseMoveEvent(QMouseEvent* e) {
  const QPointF d = e->position() - lastPos_;
  lastPos_ = e->position();
  if ((e->position() - pressPos_).manhattanLength() > 3) dragged_ = true;
  if (!dragged_) return;
  auto* cam = vtk_->renderer->GetActiveCamera();
  if (e->buttons() & Qt::LeftButton) {
    orbit(-0.4 * d.x(), 0.4 * d.y());
    return;
  }
  if (e->buttons() & (Qt::RightButton | Qt::MiddleButton)) {
    double fp[3], pos[3], up[3];
    cam->GetFocalPoint(fp);
    cam->GetPosition(pos);
    cam->GetViewUp(up);
    const glm::dvec3 f(fp[0], fp[1], fp[2]), p(pos[0], pos[1], pos[2]), u(up[0], up[1], up[2]);
    const glm::dvec3 dir = glm::normalize(f - p), right = glm::normalize(glm::cross(dir, u)), upv = glm::cross(right, dir);
    const double scale = 2.0 * glm::length(f - p) * std::tan(cam->GetViewAngle() * std::numbers::pi / 360.0) / std::max(height(), 1);
    const glm::dvec3 shift = (-d.x() * right + d.y() * upv) * scale;
    cam->SetFocalPoint(f.x + shift.x, f.y + shift.y, f.z + shift.z);
    cam->SetPosition(p.x + shift.x, p.y + shift.y, p.z + shift.z);
    vtk_->renderer->ResetCameraClippingRange();
    update();
  }
}

void VtkView::mouseReleaseEvent(QMouseEvent* e) {
  if (!dragged_ && e->button() == Qt::LeftButton) clicked(e->position());
  dragged_ = false;
}

void VtkView::wheelEvent(QWheelEvent* e) {
  vtk_->renderer->GetActiveCamera()->Dolly(std::pow(1.1, e->angleDelta().y() / 120.0));
  vtk_->renderer->ResetCameraClippingRange();
  update();
}

}  // namespace relume::inspect
