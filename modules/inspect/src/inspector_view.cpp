// VTK hosted in a Qt6 QOpenGLWidget (Debian's VTK Qt support is built for Qt5): a
// vtkGenericOpenGLRenderWindow that uses the widget's context and renders into its framebuffer.
#include "relume/inspect/inspector_view.h"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellPicker.h>
#include <vtkCoordinate.h>
#include <vtkDoubleArray.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkLookupTable.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkSmartPointer.h>
#include <vtkStaticCellLocator.h>
#include <vtkStringArray.h>
#include <vtkTextProperty.h>
#include <vtkVariant.h>

#include <QElapsedTimer>
#include <QMouseEvent>
#include <QWheelEvent>
#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>

#include "relume/inspect/inspection.h"

namespace relume::inspect {

template <class T>
using Ptr = vtkSmartPointer<T>;

struct InspectorView::Vtk {
  Ptr<vtkGenericOpenGLRenderWindow> window = Ptr<vtkGenericOpenGLRenderWindow>::New();
  Ptr<vtkRenderer> renderer = Ptr<vtkRenderer>::New();
  Ptr<vtkPolyData> elements = Ptr<vtkPolyData>::New();
  Ptr<vtkPolyDataMapper> elementMapper = Ptr<vtkPolyDataMapper>::New();
  Ptr<vtkActor> elementActor = Ptr<vtkActor>::New();
  Ptr<vtkLookupTable> lut = Ptr<vtkLookupTable>::New();
  Ptr<vtkScalarBarActor> bar = Ptr<vtkScalarBarActor>::New();
  Ptr<vtkPolyData> selection = Ptr<vtkPolyData>::New();
  Ptr<vtkActor> selectionActor = Ptr<vtkActor>::New();
  Ptr<vtkPolyData> links = Ptr<vtkPolyData>::New();
  Ptr<vtkPolyDataMapper> linkMapper = Ptr<vtkPolyDataMapper>::New();
  Ptr<vtkActor> linkActor = Ptr<vtkActor>::New();
  Ptr<vtkLookupTable> linkLut = Ptr<vtkLookupTable>::New();
  Ptr<vtkCellPicker> picker = Ptr<vtkCellPicker>::New();
  Ptr<vtkStaticCellLocator> locator;  // picks in a few microseconds instead of testing every cell
  std::vector<std::vector<glm::dvec3>> outlines;
  bool initialized = false;
};

InspectorView::InspectorView(QWidget* parent) : QOpenGLWidget(parent), vtk_(std::make_unique<Vtk>()) {
  auto& v = *vtk_;
  v.window->AddRenderer(v.renderer);
  v.window->SetMultiSamples(0);
  v.renderer->SetBackground(0.16, 0.17, 0.19);
  v.renderer->SetBackground2(0.30, 0.32, 0.36);
  v.renderer->GradientBackgroundOn();
  v.elementMapper->SetInputData(v.elements);
  v.elementMapper->SetScalarModeToUseCellData();
  v.elementMapper->SetLookupTable(v.lut);
  v.elementMapper->SetColorModeToMapScalars();
  v.elementActor->SetMapper(v.elementMapper);
  v.elementActor->GetProperty()->EdgeVisibilityOn();
  v.elementActor->GetProperty()->SetEdgeColor(0.08, 0.08, 0.08);
  v.elementActor->GetProperty()->SetLineWidth(1.0);
  v.elementActor->GetProperty()->SetAmbient(0.45);
  v.elementActor->GetProperty()->SetDiffuse(0.55);
  // Elements face into the room: from outside, the near walls turn their backs and are culled
  // (the room opens like a doll's house).
  v.elementActor->GetProperty()->BackfaceCullingOn();
  v.renderer->AddActor(v.elementActor);

  auto* selMapper = vtkPolyDataMapper::New();
  selMapper->SetInputData(v.selection);
  v.selectionActor->SetMapper(selMapper);
  selMapper->Delete();
  v.selectionActor->GetProperty()->SetColor(1.0, 0.2, 0.9);
  v.selectionActor->GetProperty()->SetLineWidth(4.0);
  v.selectionActor->GetProperty()->LightingOff();
  v.selectionActor->PickableOff();
  v.renderer->AddActor(v.selectionActor);

  v.linkMapper->SetInputData(v.links);
  v.linkMapper->SetScalarModeToUseCellData();
  v.linkMapper->SetLookupTable(v.linkLut);
  v.linkActor->SetMapper(v.linkMapper);
  v.linkActor->GetProperty()->SetLineWidth(1.5);
  v.linkActor->GetProperty()->LightingOff();
  v.linkActor->PickableOff();
  v.linkLut->SetHueRange(0.66, 0.0);  // weak links blue, strong red
  v.linkLut->SetScaleToLog10();
  v.linkLut->Build();
  v.renderer->AddActor(v.linkActor);

  v.bar->SetLookupTable(v.lut);
  v.bar->SetNumberOfLabels(5);
  v.bar->SetMaximumWidthInPixels(90);
  v.bar->SetPosition(0.88, 0.1);
  v.bar->SetWidth(0.1);
  v.bar->SetHeight(0.8);
  v.bar->GetTitleTextProperty()->SetFontSize(12);
  v.bar->GetLabelTextProperty()->SetFontSize(11);
  v.renderer->AddViewProp(v.bar);

  v.picker->SetTolerance(0.0);
  v.picker->PickFromListOn();
  v.picker->AddPickList(v.elementActor);
  setMinimumSize(240, 180);
  setMouseTracking(false);
}

InspectorView::~InspectorView() {
  makeCurrent();
  vtk_->window->Finalize();
  doneCurrent();
}

void InspectorView::initializeGL() {
  auto& w = *vtk_->window;
  w.SetOwnContext(false);
  w.OpenGLInitContext();
  vtk_->initialized = true;
}

void InspectorView::resizeGL(int w, int h) {
  const double r = devicePixelRatioF();
  vtk_->window->SetSize(int(w * r), int(h * r));
}

void InspectorView::paintGL() {
  QElapsedTimer t;
  t.start();
  auto& w = *vtk_->window;
  const double r = devicePixelRatioF();
  w.SetSize(int(width() * r), int(height() * r));
  w.SetIsCurrent(true);
  w.SetReadyForRendering(true);
  w.SetFrameBlitModeToBlitToCurrent();
  w.Render();
  w.SetReadyForRendering(false);
  lastFrameMs_ = double(t.nsecsElapsed()) * 1e-6;
  emit frameDrawn(lastFrameMs_);
}

void InspectorView::setElements(const ElementMesh& mesh) {
  auto& v = *vtk_;
  auto points = Ptr<vtkPoints>::New();
  auto polys = Ptr<vtkCellArray>::New();
  for (const auto& poly : mesh.outline) {
    polys->InsertNextCell(vtkIdType(poly.size()));
    for (const auto& p : poly) polys->InsertCellPoint(points->InsertNextPoint(p.x, p.y, p.z));
  }
  v.elements->Initialize();
  v.elements->SetPoints(points);
  v.elements->SetPolys(polys);
  v.outlines = mesh.outline;
  v.elements->Modified();
  v.picker->RemoveAllLocators();
  v.locator = Ptr<vtkStaticCellLocator>::New();
  if (!mesh.outline.empty()) {
    v.locator->SetDataSet(v.elements);
    v.locator->BuildLocator();
    v.picker->AddLocator(v.locator);
  }
  setSelected(-1);
  if (!fitted_ && !mesh.outline.empty()) resetCamera();
  update();
}

namespace {
Ptr<vtkDoubleArray> cellValues(const std::vector<double>& values) {
  auto a = Ptr<vtkDoubleArray>::New();
  a->SetName("value");
  a->SetNumberOfTuples(vtkIdType(values.size()));
  for (size_t i = 0; i < values.size(); ++i) a->SetValue(vtkIdType(i), values[i]);
  return a;
}
}  // namespace

void InspectorView::setValues(const std::vector<double>& values, const QString& title) {
  auto& v = *vtk_;
  double lo = 1e300, hi = -1e300;
  for (double x : values)
    if (std::isfinite(x)) {
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
  if (lo > hi) lo = 0, hi = 1;
  if (hi <= lo) hi = lo + 1e-6 * std::max(1.0, std::abs(lo));
  v.lut->ResetAnnotations();
  v.lut->IndexedLookupOff();
  v.lut->SetNumberOfTableValues(256);
  v.lut->SetHueRange(0.67, 0.13);  // blue (low) to yellow (high)
  v.lut->SetSaturationRange(0.85, 0.85);
  v.lut->SetValueRange(0.55, 1.0);
  v.lut->SetTableRange(lo, hi);
  v.lut->SetNanColor(0.45, 0.45, 0.45, 1.0);
  v.lut->ForceBuild();
  v.elements->GetCellData()->SetScalars(cellValues(values));
  v.elementMapper->SetScalarRange(lo, hi);
  v.elementMapper->UseLookupTableScalarRangeOff();
  v.bar->SetTitle(title.toUtf8().constData());
  v.bar->DrawAnnotationsOff();
  v.bar->SetNumberOfLabels(5);
  v.elements->Modified();
  update();
}

void InspectorView::setClasses(const std::vector<double>& values, const QString& title, const std::vector<QString>& labels,
                               const std::vector<glm::dvec3>& colours) {
  auto& v = *vtk_;
  v.lut->ResetAnnotations();
  v.lut->IndexedLookupOn();
  v.lut->SetNumberOfTableValues(vtkIdType(labels.size()));
  for (size_t i = 0; i < labels.size(); ++i) {
    v.lut->SetTableValue(vtkIdType(i), colours[i].x, colours[i].y, colours[i].z, 1.0);
    v.lut->SetAnnotation(vtkVariant(double(i)), labels[i].toUtf8().constData());
  }
  v.lut->SetNanColor(0.45, 0.45, 0.45, 1.0);
  v.elements->GetCellData()->SetScalars(cellValues(values));
  v.elementMapper->UseLookupTableScalarRangeOn();
  v.bar->SetTitle(title.toUtf8().constData());
  v.bar->DrawAnnotationsOn();
  v.bar->SetNumberOfLabels(0);
  v.elements->Modified();
  update();
}

void InspectorView::setSelected(int element) {
  auto& v = *vtk_;
  selected_ = element >= 0 && size_t(element) < v.outlines.size() ? element : -1;
  auto points = Ptr<vtkPoints>::New();
  auto lines = Ptr<vtkCellArray>::New();
  if (selected_ >= 0) {
    const auto& o = v.outlines[size_t(selected_)];
    lines->InsertNextCell(vtkIdType(o.size() + 1));
    for (const auto& p : o) lines->InsertCellPoint(points->InsertNextPoint(p.x, p.y, p.z));
    lines->InsertCellPoint(0);
  }
  v.selection->Initialize();
  v.selection->SetPoints(points);
  v.selection->SetLines(lines);
  v.selection->Modified();
  update();
}

void InspectorView::setLinks(const std::vector<std::pair<glm::dvec3, glm::dvec3>>& segments, const std::vector<double>& weights) {
  auto& v = *vtk_;
  auto points = Ptr<vtkPoints>::New();
  auto lines = Ptr<vtkCellArray>::New();
  double lo = 1e300, hi = 0;
  for (size_t i = 0; i < segments.size(); ++i) {
    lines->InsertNextCell(2);
    lines->InsertCellPoint(points->InsertNextPoint(segments[i].first.x, segments[i].first.y, segments[i].first.z));
    lines->InsertCellPoint(points->InsertNextPoint(segments[i].second.x, segments[i].second.y, segments[i].second.z));
    if (weights[i] > 0) {
      lo = std::min(lo, weights[i]);
      hi = std::max(hi, weights[i]);
    }
  }
  if (lo > hi) lo = 1e-6, hi = 1;
  if (hi <= lo) hi = lo * 10;
  std::vector<double> w(weights.size());
  for (size_t i = 0; i < w.size(); ++i) w[i] = std::max(weights[i], lo);
  v.links->Initialize();
  v.links->SetPoints(points);
  v.links->SetLines(lines);
  v.links->GetCellData()->SetScalars(cellValues(w));
  v.linkLut->SetTableRange(lo, hi);
  v.linkLut->Build();
  v.linkMapper->SetScalarRange(lo, hi);
  v.links->Modified();
  update();
}

void InspectorView::resetCamera() {
  auto& v = *vtk_;
  double b[6];
  v.elements->GetBounds(b);
  auto* cam = v.renderer->GetActiveCamera();
  const glm::dvec3 centre(0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5]));
  const double size = std::max({b[1] - b[0], b[3] - b[2], b[5] - b[4], 1e-3});
  cam->SetFocalPoint(centre.x, centre.y, centre.z);
  // A view from a high corner, +z up: the room opened like a doll's house.
  cam->SetPosition(centre.x - 0.9 * size, centre.y - 1.3 * size, centre.z + 1.1 * size);
  cam->SetViewUp(0, 0, 1);
  v.renderer->ResetCameraClippingRange();
  fitted_ = true;
  update();
}

int InspectorView::elementAt(QPointF pos) {
  auto& v = *vtk_;
  if (v.outlines.empty()) return -1;
  const double r = devicePixelRatioF();
  int size[2] = {int(width() * r), int(height() * r)};
  v.window->SetSize(size);
  v.renderer->ResetCameraClippingRange();
  if (!v.picker->Pick(pos.x() * r, (height() - pos.y()) * r, 0.0, v.renderer)) return -1;
  const vtkIdType cell = v.picker->GetCellId();
  return cell >= 0 && size_t(cell) < v.outlines.size() ? int(cell) : -1;
}

bool InspectorView::widgetPosition(const glm::dvec3& world, QPointF& pos) {
  auto& v = *vtk_;
  const double r = devicePixelRatioF();
  v.window->SetSize(int(width() * r), int(height() * r));
  auto c = Ptr<vtkCoordinate>::New();
  c->SetCoordinateSystemToWorld();
  c->SetValue(world.x, world.y, world.z);
  const double* d = c->GetComputedDoubleDisplayValue(v.renderer);
  pos = QPointF(d[0] / r, height() - d[1] / r);
  return pos.x() >= 0 && pos.y() >= 0 && pos.x() < width() && pos.y() < height();
}

void InspectorView::mousePressEvent(QMouseEvent* e) {
  pressPos_ = lastPos_ = e->position();
  dragged_ = false;
}

void InspectorView::mouseMoveEvent(QMouseEvent* e) {
  const QPointF d = e->position() - lastPos_;
  lastPos_ = e->position();
  if ((e->position() - pressPos_).manhattanLength() > 3) dragged_ = true;
  if (!dragged_) return;
  auto* cam = vtk_->renderer->GetActiveCamera();
  if (e->buttons() & Qt::LeftButton) {
    orbit(-0.4 * d.x(), 0.4 * d.y());
    return;
  } else if (e->buttons() & (Qt::RightButton | Qt::MiddleButton)) {
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
  }
  vtk_->renderer->ResetCameraClippingRange();
  update();
}

void InspectorView::orbit(double azimuthDegrees, double elevationDegrees) {
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

void InspectorView::mouseReleaseEvent(QMouseEvent* e) {
  if (!dragged_ && e->button() == Qt::LeftButton) {
    const int element = elementAt(e->position());
    setSelected(element);
    emit elementPicked(element);
  }
  dragged_ = false;
}

void InspectorView::wheelEvent(QWheelEvent* e) {
  auto* cam = vtk_->renderer->GetActiveCamera();
  cam->Dolly(std::pow(1.1, e->angleDelta().y() / 120.0));
  vtk_->renderer->ResetCameraClippingRange();
  update();
}

}  // namespace relume::inspect
