#pragma once
// The Reconstruction panel: COLMAP on the capture's photos as a job (the library's driver:
// attempts, progress from its output, Cancel kills it and writes nothing), then which photos
// registered and which did not, the mean reprojection error, and the sparse points with the
// cameras' frusta in 3-D; the metric frame set by picking two points and typing their distance
// and picking three floor points. The workspace (sparse/ and workspace.json) is what `relume
// reconstruct` writes and `relume triangulate` reads.
#include <QString>
#include <QWidget>
#include <memory>
#include <vector>

#include "relume/reconstruct/multiview.h"

class QDoubleSpinBox;
class QLabel;
class QLineEdit;
class QPushButton;
class QTreeWidget;

namespace relume {

class JobRunner;
class PhotosPanel;
namespace recon {
struct ColmapRun;
}
namespace inspect {
class SparseView;
}

class ReconstructionPanel : public QWidget {
  Q_OBJECT
 public:
  enum class Picking { None, Scale, Floor };

  ReconstructionPanel(JobRunner* jobs, PhotosPanel* photos, QWidget* parent = nullptr);
  ~ReconstructionPanel() override;

  QLineEdit* photosFolder() const { return photosFolder_; }
  QLineEdit* workspace() const { return workspace_; }
  QPushButton* runButton() const { return run_; }
  QTreeWidget* photosList() const { return list_; }
  QLabel* summary() const { return summary_; }
  inspect::SparseView* view() const { return view_; }
  QDoubleSpinBox* distance() const { return distance_; }
  // Starts COLMAP as a job (false when a job runs or the folders are missing).
  bool run();
  const recon::ColmapRun* result() const { return run_result_.get(); }
  // The model's point ids of the points picked for the scale and the floor.
  const std::vector<long long>& scalePoints() const { return scale_; }
  const std::vector<long long>& floorPoints() const { return floor_; }
  void setPicking(Picking mode);
  // Puts the model in the metric frame from the picked points and the typed distance, and
  // rewrites the workspace (atomically); false with the reason shown when they are not enough.
  bool applyMetricFrame();
  // Puts the model in the frame of known cameras (a room, project or reconstruction whose photos
  // have the same names), rewriting the workspace as a whole; false with the reason shown.
  bool alignToKnownCameras(const QString& reference);
  // The camera-centre fit of the last alignment (errors in metres).
  const recon::CenterAlignment& lastAlignment() const { return lastAlignment_; }

 signals:
  void message(const QString& text);

 protected:
  void showEvent(QShowEvent* e) override;

 private:
  void showResult();
  void pointPicked(int point);
  void refreshPicks();
  void moveModel(const recon::Similarity& S);  // applied and written (model folder, workspace.json)

  JobRunner* jobs_;
  PhotosPanel* photos_;
  QLineEdit *photosFolder_, *workspace_;
  QPushButton *run_, *pickScale_, *pickFloor_, *apply_, *align_;
  recon::CenterAlignment lastAlignment_;
  QTreeWidget* list_;
  QLabel *summary_, *picks_;
  QDoubleSpinBox* distance_;
  inspect::SparseView* view_;
  std::unique_ptr<recon::ColmapRun> run_result_;
  QString runWorkspace_, runPhotos_;  // the run's folders, absolute
  std::vector<long long> pointIds_;  // view point index -> model point id
  std::vector<long long> scale_, floor_;
  Picking picking_ = Picking::None;
};

}  // namespace relume
