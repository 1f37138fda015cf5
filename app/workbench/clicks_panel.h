#pragma once
// The Model panel (Loscos 2000 §3, TotalCalib-style): corners clicked in two photos side by
// side, with the library's match proposals along the epipolar line; each point shows its
// reprojection error and whether its depth is weak; polygons made from points picked in order
// (rectangle and shared-plane constraints, lamps); typed positions for corners no photo shows.
// Every edit is undoable and saved at once (atomically) as clicks.json in the workspace.
// "Build model" takes the same path as `relume triangulate` (cameras from the workspace's model,
// else solved from the clicks), writes the project with its clicks, and opens it (preprocess).
#include <QImage>
#include <QPointF>
#include <QString>
#include <QUndoStack>
#include <QWidget>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "relume/reconstruct/clicks.h"
#include "relume/reconstruct/colmap_model.h"

class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QLineEdit;
class QPushButton;
class QTabWidget;
class QThreadPool;
class QTreeWidget;

namespace relume {
namespace recon {
struct MatchImage;
}
namespace inspect {
class SparseView;
}

class ClickPhotoView;
class JobRunner;
class PhotosPanel;

class ClicksPanel : public QWidget {
  Q_OBJECT
 public:
  ClicksPanel(JobRunner* jobs, PhotosPanel* photos, QWidget* parent = nullptr);
  ~ClicksPanel() override;

  // Opens a workspace (a `relume reconstruct` workspace, a COLMAP model folder, or a new folder)
  // and its photos (empty: from the workspace); reads its clicks.json when there is one. False
  // with the reason shown when it cannot.
  bool load(const QString& workspace, const QString& photos = QString());
  bool isLoaded() const { return !photoNames_.empty(); }
  QString clicksFile() const { return clicksFile_; }
  const recon::Clicks& clicks() const { return clicks_; }
  const std::vector<std::string>& photoNames() const { return photoNames_; }
  bool hasCameras() const { return model_ != nullptr; }

  // The two photos shown side by side.
  ClickPhotoView* viewA() const { return views_[0]; }
  ClickPhotoView* viewB() const { return views_[1]; }
  void showPhotos(const QString& a, const QString& b);

  // The point being clicked ("" none) and the points picked for a polygon, in order.
  QString currentPoint() const { return QString::fromStdString(current_); }
  void setCurrentPoint(const QString& name);
  void startNewPoint();  // the next click starts a new point
  const std::vector<std::string>& picked() const { return picked_; }
  void setPicked(const std::vector<std::string>& names);

  // Edits (each one undo step).
  void clickAt(int view, QPointF pixel);  // as a click in view 0 or 1
  bool acceptProposal(int view, int index);
  void movePoint(const QString& name, const QString& photo, QPointF pixel);
  void deletePoints(const QStringList& names);
  bool mergePoints(const QString& keep, const QString& gone);
  void setTyped(const QString& name, const std::optional<glm::dvec3>& xyz);
  QString addTypedPoint(const glm::dvec3& xyz);
  QString addPolygonFromPicked(const QString& name = QString());
  void deletePolygon(const QString& name);
  // A lamp named `lampName` (empty: the polygon's name), or not a lamp.
  void setPolygonLamp(const QString& name, bool lamp, const QString& lampName = QString());
  bool renamePolygon(const QString& name, const QString& newName);
  void setPolygonGroup(const QString& name, const QString& group);
  void setPolygonRectangle(const QString& name, bool rectangle);
  void setPolygonPlane(const QString& name, const QString& plane);
  QUndoStack* undoStack() { return &undo_; }

  // Proposals wait on a worker thread; this waits for the ones under way (tests).
  void waitForProposals();
  // Per point: its triangulation (when it has cameras and two clicks), else why not.
  struct PointState {
    bool triangulated = false;
    glm::dvec3 X{0.0};
    double maxError = 0, rayAngleDeg = 0;
    QString problem;
  };
  const std::map<std::string, PointState>& pointStates() const { return states_; }

  // "Build model" as a job: the project goes to `project` (the field's value when empty).
  bool build(const QString& project = QString());
  QLineEdit* workspaceEdit() const { return workspace_; }
  QLineEdit* projectEdit() const { return project_; }
  QDoubleSpinBox* focalEdit() const { return focal_; }
  QTreeWidget* pointsList() const { return points_; }
  QTreeWidget* polygonsList() const { return polygons_; }
  QLabel* summary() const { return summary_; }
  QLineEdit* polygonNameEdit() const { return polygonName_; }
  QTabWidget* tabs() const { return tabs_; }
  inspect::SparseView* view3d() const { return view3d_; }
  QPushButton* buildButton() const { return build_; }
  QPushButton* measuredButton() const { return measured_; }
  QPushButton* polygonButton() const { return makePolygon_; }
  QPushButton* undoButton() const { return undoButton_; }
  QPushButton* redoButton() const { return redoButton_; }
  QPushButton* newPointButton() const { return newPoint_; }
  QDoubleSpinBox* measuredEdit(int axis) const { return axis == 0 ? x_ : axis == 1 ? y_ : z_; }

  // Applies a snapshot (what the undo commands call).
  void applyClicks(const recon::Clicks& clicks);

 signals:
  void message(const QString& text);
  void modelBuilt(const QString& project);

 protected:
  void showEvent(QShowEvent* e) override;
  void keyPressEvent(QKeyEvent* e) override;

 private:
  void edit(const QString& text, const std::function<void(recon::Clicks&)>& change);
  std::string newPointName() const;
  void retriangulate();
  void refreshLists();
  void refreshViews();
  void refreshHint();
  void refresh3d();
  void requestProposals();
  QImage displayImage(const std::string& photo);
  bool cameraOf(const std::string& photo, recon::ColmapCamera& cc, glm::dmat3& R, glm::dvec3& t) const;
  QPolygonF epipolarCurve(const std::string& from, QPointF pixel, const std::string& to) const;
  bool projectPoint(const glm::dvec3& X, const std::string& photo, QPointF& pixel) const;

  JobRunner* jobs_;
  PhotosPanel* photosPanel_;
  QLineEdit *workspace_, *photos_, *project_, *polygonName_, *scaleA_, *scaleB_, *floor_;
  QDoubleSpinBox* scaleMetres_;
  QPushButton *load_, *build_, *measured_, *makePolygon_, *undoButton_, *redoButton_, *newPoint_;
  QComboBox* photoBox_[2];
  ClickPhotoView* views_[2];
  QTreeWidget *points_, *polygons_;
  QTabWidget* tabs_;
  inspect::SparseView* view3d_;
  size_t fittedCameras_ = size_t(-1);
  bool fittedEmpty_ = true;
  QDoubleSpinBox *x_, *y_, *z_, *focal_;
  QLabel *summary_, *hint_, *counts_;
  QUndoStack undo_;
  QThreadPool* pool_;
  QObject* results_;     // receives the workers' results (flushed alone by waitForProposals)
  QString autoProject_;  // the project path the panel proposed (replaced when another workspace opens)

  QString workspaceDir_, photosDir_, clicksFile_;
  bool metricModel_ = false;
  std::vector<std::string> photoNames_;
  std::map<std::string, QString> photoFiles_;
  std::unique_ptr<recon::ColmapModel> model_;
  recon::Clicks clicks_;
  std::string current_;
  std::vector<std::string> picked_;
  std::map<std::string, PointState> states_;
  std::map<std::string, QImage> display_;
  std::map<std::string, std::shared_ptr<const recon::MatchImage>> match_;  // prepared for proposals
  // Proposals per view, for the current point's click in the other view.
  std::vector<QPointF> proposals_[2];
  QString proposalKey_[2];
  unsigned proposalGeneration_ = 0, shownGeneration_[2] = {0, 0};
  int proposalsRunning_ = 0;
  bool refreshing_ = false;
};

}  // namespace relume
