#include "relume/inspect/sparse_view.h"

#include <vtkActor.h>
#include <vtkCellArray.h>
#include <vtkPointData.h>
#include <vtkPointPicker.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <glm/geometric.hpp>

namespace relume::inspect {

template <class T>
using Ptr = vtkSmartPointer<T>;

struct SparseView::Vtk {
  Ptr<vtkPolyData> points = Ptr<vtkPolyData>::New(), frusta = Ptr<vtkPolyData>::New(), marked = Ptr<vtkPolyData>::New();
  Ptr<vtkActor> pointActor = Ptr<vtkActor>::New(), frustumActor = Ptr<vtkActor>::New(), markedActor = Ptr<vtkActor>::New();
  // Polygons: [0] surfaces, [1] lamps; faces and outlines each.
  Ptr<vtkPolyData> polys[2] = {Ptr<vtkPolyData>::New(), Ptr<vtkPolyData>::New()},
                   outlines[2] = {Ptr<vtkPolyData>::New(), Ptr<vtkPolyData>::New()};
  Ptr<vtkActor> polyActor[2] = {Ptr<vtkActor>::New(), Ptr<vtkActor>::New()},
                outlineActor[2] = {Ptr<vtkActor>::New(), Ptr<vtkActor>::New()};
  Ptr<vtkPointPicker> picker = Ptr<vtkPointPicker>::New();
  std::vector<glm::dvec3> xyz;
  size_t polygonCount = 0;
};

namespace {
void attach(vtkRenderer* r, vtkPolyData* data, vtkActor* actor) {
  auto mapper = Ptr<vtkPolyDataMapper>::New();
  mapper->SetInputData(data);
  actor->SetMapper(mapper);
  actor->GetProperty()->LightingOff();
  r->AddActor(actor);
}
}  // namespace

SparseView::SparseView(QWidget* parent) : VtkView(parent), vtk_(std::make_unique<Vtk>()) {
  auto& v = *vtk_;
  attach(renderer(), v.points, v.pointActor);
  v.pointActor->GetProperty()->SetPointSize(4.0);
  attach(renderer(), v.frusta, v.frustumActor);
  v.frustumActor->GetProperty()->SetColor(1.0, 0.55, 0.1);
  v.frustumActor->GetProperty()->SetLineWidth(1.5);
  v.frustumActor->PickableOff();
  attach(renderer(), v.marked, v.markedActor);
  v.markedActor->GetProperty()->SetColor(1.0, 0.95, 0.2);
  v.markedActor->GetProperty()->SetPointSize(11.0);
  v.markedActor->PickableOff();
  for (int k = 0; k < 2; ++k) {
    const double r = k ? 1.0 : 0.31, g = k ? 0.78 : 0.86, b = k ? 0.16 : 0.47;  // surfaces green, lamps yellow
    attach(renderer(), v.polys[k], v.polyActor[k]);
    v.polyActor[k]->GetProperty()->SetColor(r, g, b);
    v.polyActor[k]->GetProperty()->SetOpacity(k ? 0.8 : 0.3);
    v.polyActor[k]->PickableOff();
    attach(renderer(), v.outlines[k], v.outlineActor[k]);
    v.outlineActor[k]->GetProperty()->SetColor(r, g, b);
    v.outlineActor[k]->GetProperty()->SetLineWidth(2.0);
    v.outlineActor[k]->PickableOff();
  }
  // Translucent faces over one another: depth peeling (the default order-independent pass
  // draws overlapping layers in false colours on Mesa).
  renderer()->SetUseDepthPeeling(1);
  renderer()->SetMaximumNumberOfPeels(6);
  renderer()->SetOcclusionRatio(0.0);
  v.picker->SetTolerance(0.008);
  v.picker->PickFromListOn();
  v.picker->AddPickList(v.pointActor);
}

SparseView::~SparseView() = default;

size_t SparseView::pointCount() const { return vtk_->xyz.size(); }

void SparseView::setModel(const std::vector<glm::dvec3>& xyz, const std::vector<std::array<uint8_t, 3>>& colours,
                          const std::vector<Camera>& cameras, bool fit) {
  auto& v = *vtk_;
  v.xyz = xyz;
  auto pts = Ptr<vtkPoints>::New();
  auto verts = Ptr<vtkCellArray>::New();
  auto rgb = Ptr<vtkUnsignedCharArray>::New();
  rgb->SetNumberOfComponents(3);
  rgb->SetName("rgb");
  glm::dvec3 lo(1e300), hi(-1e300);
  for (size_t i = 0; i < xyz.size(); ++i) {
    verts->InsertNextCell(1);
    verts->InsertCellPoint(pts->InsertNextPoint(xyz[i].x, xyz[i].y, xyz[i].z));
    const auto c = i < colours.size() ? colours[i] : std::array<uint8_t, 3>{200, 200, 200};
    rgb->InsertNextTuple3(c[0], c[1], c[2]);
    lo = glm::min(lo, xyz[i]);
    hi = glm::max(hi, xyz[i]);
  }
  v.points->Initialize();
  v.points->SetPoints(pts);
  v.points->SetVerts(verts);
  v.points->GetPointData()->SetScalars(rgb);
  v.points->Modified();
  // The view frames the bulk of the points (2nd to 98th percentile per axis: a stray match far
  // off does not shrink the room to a dot) and every camera.
  if (xyz.size() >= 20) {
    for (int a = 0; a < 3; ++a) {
      std::vector<double> v;
      for (const auto& p : xyz) v.push_back(p[a]);
      std::sort(v.begin(), v.end());
      lo[a] = v[v.size() * 2 / 100];
      hi[a] = v[v.size() * 98 / 100];
    }
  }
  // Frusta: from each centre to the image corners at a tenth of the scene's size.
  for (const auto& c : cameras) {
    lo = glm::min(lo, c.center());
    hi = glm::max(hi, c.center());
  }
  const double depth = 0.1 * std::max(glm::length(hi - lo), 1e-3);
  auto fpts = Ptr<vtkPoints>::New();
  auto lines = Ptr<vtkCellArray>::New();
  for (const auto& c : cameras) {
    const glm::dvec3 o = c.center();
    const vtkIdType oi = fpts->InsertNextPoint(o.x, o.y, o.z);
    vtkIdType corner[4];
    const double xs[4] = {0, double(c.width), double(c.width), 0}, ys[4] = {0, 0, double(c.height), double(c.height)};
    for (int k = 0; k < 4; ++k) {
      const glm::dvec3 p = o + depth * glm::normalize(c.rayDirection(xs[k], ys[k]));
      corner[k] = fpts->InsertNextPoint(p.x, p.y, p.z);
      lines->InsertNextCell(2);
      lines->InsertCellPoint(oi);
      lines->InsertCellPoint(corner[k]);
    }
    lines->InsertNextCell(5);
    for (int k = 0; k < 5; ++k) lines->InsertCellPoint(corner[k % 4]);
  }
  v.frusta->Initialize();
  v.frusta->SetPoints(fpts);
  v.frusta->SetLines(lines);
  v.frusta->Modified();
  setMarked({});
  if (fit && (!xyz.empty() || !cameras.empty())) fitCamera(lo, hi);
  update();
}

void SparseView::setMarked(const std::vector<int>& marked) {
  auto& v = *vtk_;
  auto pts = Ptr<vtkPoints>::New();
  auto verts = Ptr<vtkCellArray>::New();
  for (int i : marked)
    if (i >= 0 && size_t(i) < v.xyz.size()) {
      verts->InsertNextCell(1);
      verts->InsertCellPoint(pts->InsertNextPoint(v.xyz[size_t(i)].x, v.xyz[size_t(i)].y, v.xyz[size_t(i)].z));
    }
  v.marked->Initialize();
  v.marked->SetPoints(pts);
  v.marked->SetVerts(verts);
  v.marked->Modified();
  update();
}

size_t SparseView::polygonCount() const { return vtk_->polygonCount; }

void SparseView::setPolygons(const std::vector<std::vector<glm::dvec3>>& polygons, const std::vector<bool>& lamps) {
  auto& v = *vtk_;
  v.polygonCount = 0;
  for (int k = 0; k < 2; ++k) {
    auto pts = Ptr<vtkPoints>::New();
    auto faces = Ptr<vtkCellArray>::New(), lines = Ptr<vtkCellArray>::New();
    for (size_t i = 0; i < polygons.size(); ++i) {
      const auto& poly = polygons[i];
      if (poly.size() < 3 || (i < lamps.size() && lamps[i]) != bool(k)) continue;
      ++v.polygonCount;
      std::vector<vtkIdType> ids;
      for (const auto& p : poly) ids.push_back(pts->InsertNextPoint(p.x, p.y, p.z));
      faces->InsertNextCell(vtkIdType(ids.size()), ids.data());
      lines->InsertNextCell(vtkIdType(ids.size() + 1));
      for (size_t j = 0; j <= ids.size(); ++j) lines->InsertCellPoint(ids[j % ids.size()]);
    }
    v.polys[k]->Initialize();
    v.polys[k]->SetPoints(pts);
    v.polys[k]->SetPolys(faces);
    v.polys[k]->Modified();
    v.outlines[k]->Initialize();
    v.outlines[k]->SetPoints(pts);
    v.outlines[k]->SetLines(lines);
    v.outlines[k]->Modified();
  }
  update();
}

int SparseView::pointAt(QPointF pos) {
  auto& v = *vtk_;
  if (v.xyz.empty()) return -1;
  syncSize();
  const double r = devicePixelRatioF();
  if (!v.picker->Pick(pos.x() * r, (height() - pos.y()) * r, 0.0, renderer())) return -1;
  const vtkIdType id = v.picker->GetPointId();
  return id >= 0 && size_t(id) < v.xyz.size() ? int(id) : -1;
}

void SparseView::clicked(QPointF pos) {
  const int p = pointAt(pos);
  if (p >= 0) emit pointPicked(p);
}

}  // namespace relume::inspect
