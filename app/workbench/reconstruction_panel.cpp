#include "reconstruction_panel.h"

#include <QDir>
#include <QDoubleSpinBox>
#include <QFileDialog>
#include <QFileInfo>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>
#include <QSplitter>
#include <QTreeWidget>
#include <QVBoxLayout>
#include <algorithm>

#include "job_runner.h"
#include "photos_panel.h"
#include "relume/geometry/error.h"
#include "relume/inspect/sparse_view.h"
#include "relume/reconstruct/click_build.h"
#include "relume/reconstruct/colmap_driver.h"
#include "relume/reconstruct/multiview.h"

namespace relume {

ReconstructionPanel::ReconstructionPanel(JobRunner* jobs, PhotosPanel* photos, QWidget* parent)
    : QWidget(parent), jobs_(jobs), photos_(photos) {
  auto* layout = new QVBoxLayout(this);
  auto folderRow = [&](const QString& label, QLineEdit*& edit, const QString& tip, bool mustExist) {
    auto* row = new QHBoxLayout;
    row->addWidget(new QLabel(label, this));
    edit = new QLineEdit(this);
    edit->setToolTip(tip);
    row->addWidget(edit, 1);
    auto* choose = new QPushButton(tr("Choose..."), this);
    row->addWidget(choose);
    QLineEdit* target = edit;
    connect(choose, &QPushButton::clicked, this, [this, target, mustExist] {
      const QString d = QFileDialog::getExistingDirectory(this, tr("Choose a folder"), target->text(),
                                                          mustExist ? QFileDialog::ShowDirsOnly : QFileDialog::Options());
      if (!d.isEmpty()) target->setText(d);
    });
    layout->addLayout(row);
  };
  folderRow(tr("Photos"), photosFolder_, tr("One photo per viewpoint (8-bit; the merged photos of the Photos panel)"), true);
  folderRow(tr("Workspace"), workspace_, tr("Where COLMAP's database and the model go (sparse/, workspace.json)"), false);
  run_ = new QPushButton(tr("Run COLMAP"), this);
  run_->setToolTip(tr("Features, matching and mapping on the CPU, as a job (Cancel stops COLMAP and writes nothing)"));
  layout->addWidget(run_);
  summary_ = new QLabel(tr("No reconstruction yet."), this);
  summary_->setWordWrap(true);
  layout->addWidget(summary_);

  auto* split = new QSplitter(Qt::Vertical, this);
  view_ = new inspect::SparseView(split);
  split->addWidget(view_);
  list_ = new QTreeWidget(split);
  list_->setColumnCount(2);
  list_->setHeaderLabels({tr("Photo"), tr("Registered")});
  list_->setRootIsDecorated(false);
  list_->header()->setSectionResizeMode(QHeaderView::ResizeToContents);
  split->addWidget(list_);
  split->setStretchFactor(0, 3);
  split->setStretchFactor(1, 1);
  layout->addWidget(split, 1);

  auto* metric = new QHBoxLayout;
  pickScale_ = new QPushButton(tr("Pick 2 points"), this);
  pickScale_->setCheckable(true);
  pickScale_->setToolTip(tr("Click two points of the reconstruction whose distance you measured in the room"));
  distance_ = new QDoubleSpinBox(this);
  distance_->setRange(0.001, 1000);
  distance_->setDecimals(3);
  distance_->setValue(1.0);
  distance_->setSuffix(tr(" m"));
  distance_->setToolTip(tr("Their distance in the room"));
  pickFloor_ = new QPushButton(tr("Pick 3 floor points"), this);
  pickFloor_->setCheckable(true);
  pickFloor_->setToolTip(tr("Click three points on the floor: it becomes z = 0, +z up"));
  apply_ = new QPushButton(tr("Apply metric frame"), this);
  align_ = new QPushButton(tr("Align to known cameras..."), this);
  align_->setToolTip(tr("Put the model in the frame of known cameras: a room, a project, or another reconstruction "
                        "whose photos have the same names (their camera centres are matched)"));
  metric->addWidget(pickScale_);
  metric->addWidget(distance_);
  metric->addWidget(pickFloor_);
  metric->addWidget(apply_);
  metric->addWidget(align_);
  layout->addLayout(metric);
  picks_ = new QLabel(this);
  picks_->setWordWrap(true);
  layout->addWidget(picks_);

  connect(run_, &QPushButton::clicked, this, [this] { run(); });
  connect(pickScale_, &QPushButton::toggled, this, [this](bool on) { setPicking(on ? Picking::Scale : Picking::None); });
  connect(pickFloor_, &QPushButton::toggled, this, [this](bool on) { setPicking(on ? Picking::Floor : Picking::None); });
  connect(apply_, &QPushButton::clicked, this, [this] { applyMetricFrame(); });
  connect(align_, &QPushButton::clicked, this, [this] {
    const QString d = QFileDialog::getExistingDirectory(this, tr("The room, project or reconstruction with the known cameras"));
    if (!d.isEmpty()) alignToKnownCameras(d);
  });
  connect(view_, &inspect::SparseView::pointPicked, this, [this](int p) { pointPicked(p); });
  refreshPicks();
}

ReconstructionPanel::~ReconstructionPanel() = default;

void ReconstructionPanel::showEvent(QShowEvent* e) {
  QWidget::showEvent(e);
  // Defaults from the Photos panel's capture: its merged photos (else the originals).
  const QString capture = photos_ ? photos_->captureFolder() : QString();
  if (capture.isEmpty()) return;
  if (photosFolder_->text().isEmpty())
    photosFolder_->setText(QDir(capture + "/photos").exists() ? capture + "/photos" : capture + "/originals");
  if (workspace_->text().isEmpty()) workspace_->setText(capture + "/reconstruction");
}

bool ReconstructionPanel::run() {
  if (jobs_->busy()) return false;
  const QString photos = QFileInfo(photosFolder_->text()).absoluteFilePath(),
                ws = workspace_->text().isEmpty() ? QString() : QFileInfo(workspace_->text()).absoluteFilePath();
  if (photosFolder_->text().isEmpty() || !QDir(photos).exists()) {
    emit message(tr("Choose the folder of photos first."));
    return false;
  }
  if (ws.isEmpty()) {
    emit message(tr("Choose a workspace folder first."));
    return false;
  }
  return jobs_->start(tr("Reconstructing with COLMAP"), [this, photos, ws](Progress& progress) -> JobRunner::Continuation {
    auto r = std::make_shared<recon::ColmapRun>(recon::runColmap(photos.toStdString(), ws.toStdString(), recon::ColmapOptions{}, progress));
    // The model is in sparse/ now: a workspace.json that cannot be written costs the photos
    // folder's default only, so it is said, not made a failure of the whole run.
    QString warning;
    try {
      recon::writeWorkspaceInfo(ws.toStdString(), photos.toStdString(), *r, false);
    } catch (const Error& e) {
      warning = QString::fromStdString(e.what());
    }
    return [this, r, ws, photos, warning]() {
      run_result_ = std::make_unique<recon::ColmapRun>(std::move(*r));
      runWorkspace_ = ws;
      runPhotos_ = photos;
      if (!warning.isEmpty()) emit message(warning);
      scale_.clear();
      floor_.clear();
      showResult();
    };
  });
}

void ReconstructionPanel::showResult() {
  list_->clear();
  if (!run_result_) return;
  const auto& r = *run_result_;
  for (const auto& n : r.registered) {
    auto* item = new QTreeWidgetItem(list_, {QString::fromStdString(n), tr("yes")});
    item->setForeground(1, QColor(30, 140, 50));
  }
  for (const auto& n : r.leftOut) {
    auto* item = new QTreeWidgetItem(list_, {QString::fromStdString(n), tr("no: no pose found")});
    item->setForeground(1, QColor(200, 40, 40));
  }
  std::vector<glm::dvec3> xyz;
  std::vector<std::array<uint8_t, 3>> rgb;
  pointIds_.clear();
  for (const auto& [id, p] : r.model.points) {
    xyz.push_back(p.xyz);
    rgb.push_back(p.rgb);
    pointIds_.push_back(id);
  }
  std::vector<Camera> cams;
  for (const auto& [id, im] : r.model.images) cams.push_back(r.model.camera(im));
  view_->setModel(xyz, rgb, cams);
  summary_->setText(tr("%1 of %2 photos registered; %3 points; mean reprojection error %4 px. Model: %5")
                        .arg(r.registered.size())
                        .arg(r.registered.size() + r.leftOut.size())
                        .arg(r.model.points.size())
                        .arg(recon::meanReprojectionError(r.model), 0, 'f', 2)
                        .arg(QDir::toNativeSeparators(QString::fromStdString(r.modelFolder))));
  refreshPicks();
}

void ReconstructionPanel::setPicking(Picking mode) {
  picking_ = mode;
  {
    const QSignalBlocker a(pickScale_), b(pickFloor_);
    pickScale_->setChecked(mode == Picking::Scale);
    pickFloor_->setChecked(mode == Picking::Floor);
  }
  if (mode == Picking::Scale) scale_.clear();
  if (mode == Picking::Floor) floor_.clear();
  refreshPicks();
}

void ReconstructionPanel::pointPicked(int point) {
  if (point < 0 || size_t(point) >= pointIds_.size() || picking_ == Picking::None) return;
  auto& picks = picking_ == Picking::Scale ? scale_ : floor_;
  const size_t want = picking_ == Picking::Scale ? 2 : 3;
  if (std::find(picks.begin(), picks.end(), pointIds_[size_t(point)]) == picks.end()) picks.push_back(pointIds_[size_t(point)]);
  if (picks.size() >= want) setPicking(Picking::None);
  refreshPicks();
}

void ReconstructionPanel::refreshPicks() {
  auto ids = [](const std::vector<long long>& v) {
    QStringList s;
    for (long long i : v) s << QString::number(i);
    return s.isEmpty() ? QStringLiteral("-") : s.join(", ");
  };
  picks_->setText(tr("Scale points: %1; floor points: %2%3")
                      .arg(ids(scale_), ids(floor_))
                      .arg(picking_ == Picking::None ? QString() : tr(" (click points in the view)")));
  std::vector<int> marked;
  for (size_t i = 0; i < pointIds_.size(); ++i)
    if (std::find(scale_.begin(), scale_.end(), pointIds_[i]) != scale_.end() ||
        std::find(floor_.begin(), floor_.end(), pointIds_[i]) != floor_.end())
      marked.push_back(int(i));
  view_->setMarked(marked);
  const bool have = run_result_ != nullptr;
  pickScale_->setEnabled(have);
  pickFloor_->setEnabled(have);
  align_->setEnabled(have);
  apply_->setEnabled(have && scale_.size() == 2 && floor_.size() == 3);
}

void ReconstructionPanel::moveModel(const recon::Similarity& S) {
  auto& r = *run_result_;
  recon::ColmapRun moved = r;
  recon::transformModel(moved.model, S);
  recon::replaceColmapText(moved.model, r.modelFolder);
  try {
    recon::writeWorkspaceInfo(runWorkspace_.toStdString(), runPhotos_.toStdString(), moved, true);
  } catch (const Error&) {
    recon::replaceColmapText(r.model, r.modelFolder);
    throw;
  }
  r = std::move(moved);
}

bool ReconstructionPanel::alignToKnownCameras(const QString& reference) {
  if (!run_result_ || jobs_->busy()) return false;
  recon::KnownCameraAlignment k;
  try {
    k = recon::alignToKnownCameras(run_result_->model, reference.toStdString());
    moveModel(k.fit.S);
  } catch (const Error& e) {
    emit message(QString::fromStdString(e.what()));
    return false;
  }
  lastAlignment_ = k.fit;
  scale_.clear();
  floor_.clear();
  showResult();
  emit message(tr("Aligned to the %1 known cameras: camera centres %2 m apart (median), %3 m at most.")
                   .arg(k.photos.size())
                   .arg(k.fit.median, 0, 'f', 4)
                   .arg(k.fit.max, 0, 'f', 4));
  return true;
}

bool ReconstructionPanel::applyMetricFrame() {
  if (!run_result_ || scale_.size() != 2 || floor_.size() != 3 || jobs_->busy()) {
    emit message(tr("Pick two points and their distance, and three floor points, first."));
    return false;
  }
  auto& r = *run_result_;
  // The run's own workspace and photos (the fields may have been edited since), written as a
  // whole: the model folder is swapped in, then workspace.json; a failure puts the old model back.
  try {
    auto at = [&](long long id) { return r.model.points.at(id).xyz; };
    const recon::Similarity S =
        recon::metricFrame(at(scale_[0]), at(scale_[1]), distance_->value(), {at(floor_[0]), at(floor_[1]), at(floor_[2])},
                           recon::meanCameraCentre(r.model));
    moveModel(S);
  } catch (const Error& e) {
    emit message(QString::fromStdString(e.what()));
    return false;
  }
  const auto keepScale = scale_, keepFloor = floor_;
  showResult();
  scale_ = keepScale;
  floor_ = keepFloor;
  refreshPicks();
  emit message(tr("The model is in metres now, the floor at z = 0."));
  return true;
}

}  // namespace relume
