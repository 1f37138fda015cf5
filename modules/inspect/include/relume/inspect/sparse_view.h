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
  // The points (with colours) and the cameras (frusta scaled to the scene); fits the view.
  void setModel(const std::vector<glm::dvec3>& points, const std::vector<std::array<uint8_t, 3>>& colours,
                const std::vector<Camera>& cameras);
  // Points drawn large in yellow (indices into setModel's points).
  void setMarked(const std::vector<int>& points);
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
