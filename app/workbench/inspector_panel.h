#pragma once
// The Inspector: the radiosity engine as a radiosity engineer checks it. The session's leaf
// elements in 3-D coloured by a chosen quantity (B, E, D, B/D, reflectance, T_final, level, or
// the visibility class of a lamp's links), a picked element's links listed (source, receiver, F,
// V, type, the oracle's error) and drawn as lines coloured by F x V, a filter by polygon, the
// counts of elements, leaves and links per polygon as a chart, and the other mesh (refined or
// interactive) inspected as a second session built on demand. A pick here outlines the element
// in the viewport, and a click in the viewport picks the element there.
#include <QWidget>
#include <glm/vec3.hpp>
#include <memory>
#include <vector>

class QComboBox;
class QLabel;
class QPushButton;
class QTableWidget;
class QTimer;

namespace relume {

class Document;
class JobRunner;
class RelightSession;
namespace inspect {
class InspectorView;
struct ElementMesh;
}  // namespace inspect

class InspectorPanel : public QWidget {
  Q_OBJECT
 public:
  InspectorPanel(Document* doc, JobRunner* jobs, QWidget* parent = nullptr);
  ~InspectorPanel() override;

  inspect::InspectorView* view() const { return view_; }
  QComboBox* quantity() const { return quantity_; }
  QComboBox* lamp() const { return lamp_; }
  QComboBox* polygonFilter() const { return filter_; }
  QComboBox* mesh() const { return mesh_; }
  QTableWidget* linksTable() const { return links_; }
  QWidget* chart() const { return chart_; }
  // The inspected session (the document's, or the other mesh's once built) and its elements.
  const RelightSession* session() const;
  const inspect::ElementMesh& elements() const;
  // Picks the element holding engine node `node` (-1: none), as a click in the view does.
  void pickNode(int node);
  int pickedNode() const;
  // The picked element's outline (world), for the viewport; empty when none.
  std::vector<glm::dvec3> pickedOutline() const;
  // Picks the leaf of `surface` at a world point (a click in the viewport).
  void pickAt(int surface, const glm::dvec3& point);
  // Brings the view up to date now (otherwise done when shown and after changes).
  void refresh();

 signals:
  void pickedChanged();  // the picked element changed (the viewport outlines it)

 protected:
  void showEvent(QShowEvent* e) override;

 private:
  void rebuildMesh();
  void recolour();
  void showLinks();
  void rebuildChart();
  void fillLamps();
  void otherMeshChosen();
  void markStale(bool geometry);

  Document* doc_;
  JobRunner* jobs_;
  inspect::InspectorView* view_;
  QComboBox *quantity_, *lamp_, *filter_, *mesh_;
  QLabel* summary_;
  QTableWidget* links_;
  QWidget* chart_;
  QTimer* refreshTimer_;
  std::unique_ptr<inspect::ElementMesh> all_, shown_;  // every element; those the filter shows
  std::vector<int> shownIndex_;                        // shown element -> index in all_
  std::unique_ptr<RelightSession> other_;              // the other mesh's session, when built
  int pickedNode_ = -1;
  bool geometryStale_ = true, valuesStale_ = true;
};

}  // namespace relume
