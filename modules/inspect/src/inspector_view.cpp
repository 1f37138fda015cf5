// The inspector's view: elements, their values, a picked element and its links (VTK).
#include "relume/inspect/inspector_view.h"

#include <vtkActor.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkLookupTable.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkTextProperty.h>
#include <vtkVariant.h>

#include <algorithm>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <numbers>

#include "relume/inspect/inspection.h"

namespace relume::inspect {

template <class T>
using Ptr = vtkSmartPointer<T>;

struct InspectorView::Vtk {
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
  std::vector<glm::dvec3> normals;  // per element, the side it is drawn from
  std::vector<std::vector<glm::dvec3>> outlines;
};

InspectorView::InspectorView(QWidget* parent) : VtkView(parent), vtk_(std::make_unique<Vtk>()) {
  auto& v = *vtk_;
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
  renderer()->AddActor(v.elementActor);

  auto* selMapper = vtkPolyDataMapper::New();
  selMapper->SetInputData(v.selection);
  v.selectionActor->SetMapper(selMapper);
  selMapper->Delete();
  v.selectionActor->GetProperty()->SetColor(1.0, 0.2, 0.9);
  v.selectionActor->GetProperty()->SetLineWidth(4.0);
  v.selectionActor->GetProperty()->LightingOff();
  v.selectionActor->PickableOff();
  renderer()->AddActor(v.selectionActor);

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
  renderer()->AddActor(v.linkActor);

  v.bar->SetLookupTable(v.lut);
  v.bar->SetNumberOfLabels(5);
  v.bar->SetMaximumWidthInPixels(90);
  v.bar->SetPosition(0.88, 0.1);
  v.bar->SetWidth(0.1);
  v.bar->SetHeight(0.8);
  v.bar->GetTitleTextProperty()->SetFontSize(12);
  v.bar->GetLabelTextProperty()->SetFontSize(11);
  renderer()->AddViewProp(v.bar);

  setMinimumSize(240, 180);
  setMouseTracking(false);
}

InspectorView::~InspectorView() = default;

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
  v.normals.clear();
  for (const auto& o : mesh.outline) {
    glm::dvec3 n(0.0);  // Newell's normal, in the order the corners are drawn
    for (size_t k = 0; k < o.size(); ++k) n += glm::cross(o[k], o[(k + 1) % o.size()]);
    v.normals.push_back(glm::length(n) > 0 ? glm::normalize(n) : n);
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
  double b[6];
  vtk_->elements->GetBounds(b);
  fitCamera({b[0], b[2], b[4]}, {b[1], b[3], b[5]});
  fitted_ = true;
}

int InspectorView::elementAt(QPointF pos) {
  // The nearest element the ray through the cursor meets on its drawn side: the culled backs of
  // walls between the camera and the room are seen through, as they are on screen.
  auto& v = *vtk_;
  if (v.outlines.empty()) return -1;
  glm::dvec3 o, d;
  viewRay(pos, o, d);
  int best = -1;
  double bestT = 1e300;
  for (size_t i = 0; i < v.outlines.size(); ++i) {
    const glm::dvec3& n = v.normals[i];
    const double dn = glm::dot(d, n);
    if (dn >= 0) continue;  // seen from behind: culled
    const auto& poly = v.outlines[i];
    const double t = glm::dot(poly[0] - o, n) / dn;
    if (t <= 0 || t >= bestT) continue;
    const glm::dvec3 p = o + t * d;
    // Crossing-number test in the plane (the element's outline need not be convex): the axis
    // along which the normal is largest is dropped.
    const glm::dvec3 an = glm::abs(n);
    const int drop = an.x >= an.y && an.x >= an.z ? 0 : (an.y >= an.z ? 1 : 2);
    const int u = drop == 0 ? 1 : 0, w = drop == 2 ? 1 : 2;
    bool inside = false;
    for (size_t k = 0, j = poly.size() - 1; k < poly.size(); j = k++) {
      const glm::dvec3 &a = poly[k], &b = poly[j];
      if ((a[w] > p[w]) != (b[w] > p[w]) && p[u] < (b[u] - a[u]) * (p[w] - a[w]) / (b[w] - a[w]) + a[u]) inside = !inside;
    }
    if (inside) {
      best = int(i);
      bestT = t;
    }
  }
  return best;
}

void InspectorView::clicked(QPointF pos) {
  const int element = elementAt(pos);
  setSelected(element);
  emit elementPicked(element);
}

}  // namespace relume::inspect
