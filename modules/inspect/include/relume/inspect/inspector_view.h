#pragma once
// The inspector's 3-D view: the engine's leaf elements as polygons coloured by one value each
// (with a colour bar), a picked element outlined, and its links drawn as lines coloured by F x V.
// A click without a drag picks an element (the rest of the mouse: VtkView).
#include <QPointF>
#include <QString>
#include <glm/vec3.hpp>
#include <memory>
#include <utility>
#include <vector>

#include "relume/inspect/vtk_view.h"

namespace relume::inspect {

struct ElementMesh;

class InspectorView : public VtkView {
  Q_OBJECT
 public:
  explicit InspectorView(QWidget* parent = nullptr);
  ~InspectorView() override;

  // The elements (a new mesh resets the selection; the camera is fitted the first time).
  void setElements(const ElementMesh& mesh);
  // One value per element, mapped from [lo, hi] to a blue-to-yellow scale; NaN shows grey.
  void setValues(const std::vector<double>& values, const QString& title);
  // Values that name a class (0, 1, 2, ...), each with its label and colour (RGB in [0, 1]).
  void setClasses(const std::vector<double>& values, const QString& title, const std::vector<QString>& labels,
                  const std::vector<glm::dvec3>& colours);
  // The picked element (-1: none), outlined.
  void setSelected(int element);
  int selected() const { return selected_; }
  // Line segments (a link from its source's centre to its receiver's) coloured by weight (F x V),
  // log scale from the smallest to the largest.
  void setLinks(const std::vector<std::pair<glm::dvec3, glm::dvec3>>& segments, const std::vector<double>& weights);
  void resetCamera();

  // The element under a widget position (-1: none).
  int elementAt(QPointF pos);

 signals:
  void elementPicked(int element);

 protected:
  void clicked(QPointF pos) override;

 private:
  struct Vtk;
  std::unique_ptr<Vtk> vtk_;
  int selected_ = -1;
  bool fitted_ = false;
};

}  // namespace relume::inspect
