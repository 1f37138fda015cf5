#pragma once
// A reconstruction in 3-D: sparse points in their colours, the cameras as frusta, and points the
// user marked (for the metric frame) drawn large. A click picks the point nearest the cursor.
#include <array>
#include <cstdint>
#include <vector>

#include "relume/geometry/camera.h"
#include "relume/inspect/vtk_view.h"

namespace relume::inspect {

class SparseView : public VtkView {
  Q_OBJECT
 public:
  explicit SparseView(QWidget* parent = nullptr);
  ~SparseView() override;
  // The points (with colours) and the cameras (frusta scaled to the scene); fits the view unless
  // `fit` is false (the model grows while the user works on it).
  void setModel(const std::vector<glm::dvec3>& points, const std::vector<std::array<uint8_t, 3>>& colours,
                const std::vector<Camera>& cameras, bool fit = true);
  // Points drawn large in yellow (indices into setModel's points).
  void setMarked(const std::vector<int>& points);
  // Polygons drawn translucent with their outlines (lamps in yellow, others in green); the view
  // is not moved (setModel fits it).
  void setPolygons(const std::vector<std::vector<glm::dvec3>>& polygons, const std::vector<bool>& lamps);
  size_t polygonCount() const;
  // The point nearest a widget position, within a few pixels (-1: none).
  int pointAt(QPointF pos);
  size_t pointCount() const;

 signals:
  void pointPicked(int point);

 protected:
  void clicked(QPointF pos) override;

 private:
  struct Vtk;
  std::unique_ptr<Vtk> vtk_;
};

}  // namespace relume::inspect
