#pragma once
// The Reference patches panel (Loscos 2000 §4.3, step 2): occluded elements that find no
// similar-coloured unoccluded neighbour take their reflectance from their polygon's reference
// patch. Per polygon: the automatic choice and the user's; the user picks a texel in the
// viewport or clears the choice, or paints a region of a shadow and picks the texel its occluded
// elements take their reflectance from; then recomputes the shadow-free textures (a job).
#include <QWidget>
#include <string>

class QDoubleSpinBox;
class QLabel;
class QPushButton;
class QTreeWidget;

namespace relume {

class Document;
class EditTool;
class JobRunner;

class ReferencesPanel : public QWidget {
  Q_OBJECT
 public:
  ReferencesPanel(Document* doc, EditTool* tool, JobRunner* jobs, QWidget* parent = nullptr);
  QTreeWidget* list() const { return list_; }
  QPushButton* pickButton() const { return pick_; }
  QPushButton* clearButton() const { return clear_; }
  QPushButton* recomputeButton() const { return recompute_; }
  QPushButton* paintButton() const { return paint_; }
  QPushButton* clearRegionsButton() const { return clearRegions_; }
  QDoubleSpinBox* brush() const { return brush_; }
  QPushButton* showButton() const { return show_; }
  // Starts the recompute job; false when nothing is pending or a job runs.
  bool recompute();

 signals:
  void showElements(bool on);  // the view shows occluded (blue) and frontier (yellow) elements

 private:
  void rebuild();
  void refresh();
  std::string selectedPolygon() const;

  Document* doc_;
  EditTool* tool_;
  JobRunner* jobs_;
  QLabel* summary_;
  QTreeWidget* list_;
  QPushButton *pick_, *clear_, *recompute_, *show_, *paint_, *clearRegions_;
  QDoubleSpinBox* brush_;
};

}  // namespace relume
