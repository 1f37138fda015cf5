#pragma once
// A 3-D view rendered by VTK into a Qt6 QOpenGLWidget (Debian's VTK Qt support is built for Qt5):
// a vtkGenericOpenGLRenderWindow on the widget's own context. The mouse orbits (left drag, +z
// stays up), pans (right or middle drag) and zooms (wheel); a click without a drag goes to
// clicked(). VTK's headers stay in the .cpp files.
#include <QOpenGLWidget>
#include <QPointF>
#include <glm/vec3.hpp>
#include <memory>

class vtkRenderer;

namespace relume::inspect {

class VtkView : public QOpenGLWidget {
  Q_OBJECT
 public:
  explicit VtkView(QWidget* parent = nullptr);
  ~VtkView() override;

  // Looks at the box [lo, hi] from a high corner (+z up), all of it in view.
  void fitCamera(const glm::dvec3& lo, const glm::dvec3& hi);
  // Turns the camera about its focal point (degrees), as a left drag does.
  void orbit(double azimuthDegrees, double elevationDegrees);
  // Where a world point shows in the widget (false: outside it).
  bool widgetPosition(const glm::dvec3& world, QPointF& pos);
  // The ray through a widget position: from the near plane, unit direction.
  void viewRay(QPointF pos, glm::dvec3& origin, glm::dvec3& direction);
  double lastFrameMilliseconds() const { return lastFrameMs_; }

 signals:
  void frameDrawn(double milliseconds);

 protected:
  vtkRenderer* renderer() const;
  // The renderer sized to the widget (for picking between frames).
  void syncSize();
  virtual void clicked(QPointF pos) { (void)pos; }

  void initializeGL() override;
  void paintGL() override;
  void resizeGL(int w, int h) override;
  void mousePressEvent(QMouseEvent* e) override;
  void mouseMoveEvent(QMouseEvent* e) override;
  void mouseReleaseEvent(QMouseEvent* e) override;
  void wheelEvent(QWheelEvent* e) override;

 private:
  struct Vtk;
  std::unique_ptr<Vtk> vtk_;
  QMetaObject::Connection contextGone_;  // the current context's aboutToBeDestroyed
  QPointF pressPos_, lastPos_;
  bool dragged_ = false;
  double lastFrameMs_ = 0;
};

}  // namespace relume::inspect
