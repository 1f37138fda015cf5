#include "clicks_panel.h"

#include <QCheckBox>
#include <QComboBox>
#include <QApplication>
#include <QCoreApplication>
#include <QStyledItemDelegate>
#include <QDir>
#include <QDoubleSpinBox>
#include <QFileDialog>
#include <QFileInfo>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QJsonDocument>
#include <QJsonObject>
#include <QKeyEvent>
#include <QLabel>
#include <QLineEdit>
#include <QPointer>
#include <QPushButton>
#include <QSplitter>
#include <QTabWidget>
#include <QTemporaryDir>
#include <QThreadPool>
#include <QTreeWidget>
#include <QUndoCommand>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "click_photo_view.h"
#include "job_runner.h"
#include "photos_panel.h"
#include "relume/geometry/error.h"
#include "relume/image/image.h"
#include "relume/inspect/sparse_view.h"
#include "relume/reconstruct/click_build.h"
#include "relume/reconstruct/colmap_driver.h"
#include "relume/reconstruct/matching.h"
#include "relume/reconstruct/photos.h"

namespace relume {

namespace {
// One edit of the clicks: the whole before and after (a few kilobytes), so that undo restores
// exactly what was there, names included.
class ClicksCommand : public QUndoCommand {
 public:
  ClicksCommand(ClicksPanel* panel, recon::Clicks before, recon::Clicks after, const QString& text)
      : QUndoCommand(text), panel_(panel), before_(std::move(before)), after_(std::move(after)) {}
  void undo() override { panel_->applyClicks(before_); }
  void redo() override { panel_->applyClicks(after_); }

 private:
  ClicksPanel* panel_;
  recon::Clicks before_, after_;
};

QString qs(const std::string& s) { return QString::fromStdString(s); }
std::string ss(const QString& s) { return s.toStdString(); }

const std::pair<std::string, glm::dvec2>* clickIn(const recon::ClickPoint& p, const std::string& photo) {
  for (const auto& c : p.clicks)
    if (c.first == photo) return &c;
  return nullptr;
}

// Weak: rays nearly parallel (depth from a short baseline), or the clicks disagree by pixels.
constexpr double kWeakAngleDeg = 10, kLargeErrorPx = 2;
}  // namespace

ClicksPanel::ClicksPanel(JobRunner* jobs, PhotosPanel* photos, QWidget* parent)
    : QWidget(parent), jobs_(jobs), photosPanel_(photos) {
  pool_ = new QThreadPool(this);  // proposals; its own, so that waiting for them waits for nothing else
  pool_->setMaxThreadCount(1);
  results_ = new QObject(this);  // the proposals' results are delivered to it
  auto* layout = new QVBoxLayout(this);
  {
    auto* row = new QHBoxLayout;
    row->addWidget(new QLabel(tr("Workspace"), this));
    workspace_ = new QLineEdit(this);
    workspace_->setToolTip(tr("A reconstruction workspace or COLMAP model folder (cameras), or a new folder: "
                              "the clicks are kept there as clicks.json"));
    row->addWidget(workspace_, 2);
    auto* choose = new QPushButton(tr("Choose..."), this);
    row->addWidget(choose);
    row->addWidget(new QLabel(tr("Photos"), this));
    photos_ = new QLineEdit(this);
    photos_->setPlaceholderText(tr("from the workspace"));
    row->addWidget(photos_, 1);
    load_ = new QPushButton(tr("Open"), this);
    row->addWidget(load_);
    layout->addLayout(row);
    connect(choose, &QPushButton::clicked, this, [this] {
      const QString d = QFileDialog::getExistingDirectory(this, tr("Choose the workspace"), workspace_->text());
      if (!d.isEmpty()) workspace_->setText(d);
    });
    connect(load_, &QPushButton::clicked, this, [this] { load(workspace_->text(), photos_->text()); });
  }

  auto* split = new QSplitter(Qt::Horizontal, this);
  for (int v = 0; v < 2; ++v) {
    auto* box = new QWidget(split);
    auto* bl = new QVBoxLayout(box);
    bl->setContentsMargins(0, 0, 0, 0);
    auto* top = new QHBoxLayout;
    photoBox_[v] = new QComboBox(box);
    photoBox_[v]->setToolTip(v == 0 ? tr("The photo to click corners in") : tr("A second photo: proposals for the corner appear here"));
    top->addWidget(photoBox_[v], 1);
    auto* fit = new QPushButton(tr("Fit"), box);
    auto* one = new QPushButton(tr("1:1"), box);
    fit->setToolTip(tr("The whole photo (F)"));
    one->setToolTip(tr("One photo pixel per screen pixel"));
    top->addWidget(fit);
    top->addWidget(one);
    bl->addLayout(top);
    views_[v] = new ClickPhotoView(box);
    bl->addWidget(views_[v], 1);
    split->addWidget(box);
    connect(fit, &QPushButton::clicked, views_[v], &ClickPhotoView::fit);
    connect(one, &QPushButton::clicked, views_[v], &ClickPhotoView::oneToOne);
    connect(photoBox_[v], &QComboBox::currentTextChanged, this, [this] {
      if (!refreshing_) refreshViews();
    });
    connect(views_[v], &ClickPhotoView::clicked, this, [this, v](QPointF px, Qt::KeyboardModifiers) { clickAt(v, px); });
    connect(views_[v], &ClickPhotoView::markerClicked, this, [this](const QString& n, Qt::KeyboardModifiers m) {
      if (m & Qt::ControlModifier) {  // picked for a polygon, in order
        auto p = picked_;
        const auto it = std::find(p.begin(), p.end(), ss(n));
        if (it == p.end()) p.push_back(ss(n));
        else p.erase(it);
        setPicked(p);
      } else {
        setCurrentPoint(n);
      }
    });
    connect(views_[v], &ClickPhotoView::markerDragged, this, [this, v](const QString& n, QPointF px) {
      movePoint(n, views_[v]->photoName(), px);
    });
    connect(views_[v], &ClickPhotoView::proposalActivated, this, [this, v](int k) { acceptProposal(v, k); });
  }

  tabs_ = new QTabWidget(split);
  auto* side = new QWidget(tabs_);
  tabs_->addTab(side, tr("Points and polygons"));
  view3d_ = new inspect::SparseView(tabs_);
  view3d_->setToolTip(tr("The points and polygons in 3-D with the cameras (drag to orbit, wheel to zoom)"));
  tabs_->addTab(view3d_, tr("3-D"));
  connect(tabs_, &QTabWidget::currentChanged, this, [this] { refresh3d(); });
  auto* sl = new QVBoxLayout(side);
  sl->setContentsMargins(0, 0, 0, 0);
  points_ = new QTreeWidget(side);
  points_->setColumnCount(4);
  points_->setHeaderLabels({tr("Point"), tr("Clicked in"), tr("Error"), tr("Depth")});
  points_->setRootIsDecorated(false);
  points_->setSelectionMode(QAbstractItemView::ExtendedSelection);
  points_->header()->setSectionResizeMode(QHeaderView::ResizeToContents);
  sl->addWidget(points_, 3);
  {
    auto* row = new QHBoxLayout;
    auto* add = newPoint_ = new QPushButton(tr("New point"), side);
    add->setToolTip(tr("The next click starts a new point (N)"));
    auto* del = new QPushButton(tr("Delete"), side);
    del->setToolTip(tr("Deletes the selected points (and the polygons left with fewer than 3 corners)"));
    auto* merge = new QPushButton(tr("Merge"), side);
    merge->setToolTip(tr("The second picked point's clicks go to the first; polygons follow"));
    row->addWidget(add);
    row->addWidget(del);
    row->addWidget(merge);
    sl->addLayout(row);
    connect(add, &QPushButton::clicked, this, &ClicksPanel::startNewPoint);
    connect(del, &QPushButton::clicked, this, [this] {
      QStringList names;
      for (auto* it : points_->selectedItems()) names << it->text(0);
      deletePoints(names);
    });
    connect(merge, &QPushButton::clicked, this, [this] {
      if (picked_.size() == 2) mergePoints(qs(picked_[0]), qs(picked_[1]));
      else emit message(tr("Pick two points to merge (Ctrl+click)."));
    });
  }
  {
    auto* row = new QHBoxLayout;
    auto spin = [&](QDoubleSpinBox*& s) {
      s = new QDoubleSpinBox(side);
      s->setRange(-1000, 1000);
      s->setDecimals(3);
      s->setSuffix(tr(" m"));
      row->addWidget(s);
    };
    spin(x_);
    spin(y_);
    spin(z_);
    auto* set = measured_ = new QPushButton(tr("Measured"), side);
    set->setToolTip(tr("The current point's measured position (a control point when it is clicked too); "
                       "with no point current, a new point only measured (a corner no photo shows)"));
    auto* clear = new QPushButton(tr("Clear"), side);
    clear->setToolTip(tr("Forget the current point's measured position"));
    row->addWidget(set);
    row->addWidget(clear);
    sl->addLayout(row);
    connect(set, &QPushButton::clicked, this, [this] {
      const glm::dvec3 p(x_->value(), y_->value(), z_->value());
      if (current_.empty()) addTypedPoint(p);
      else setTyped(qs(current_), p);
    });
    connect(clear, &QPushButton::clicked, this, [this] {
      if (!current_.empty()) setTyped(qs(current_), std::nullopt);
    });
  }
  polygons_ = new QTreeWidget(side);
  polygons_->setColumnCount(6);
  polygons_->setHeaderLabels({tr("Polygon"), tr("Corners"), tr("Group"), tr("Lamp"), tr("Rectangle"), tr("Plane")});
  polygons_->setToolTip(tr("Double-click a name, group, lamp name or plane key to change it. Tick Lamp for a lamp "
                           "(its name: the text, else the polygon's); polygons with the same plane key share one plane"));
  polygons_->setEditTriggers(QAbstractItemView::DoubleClicked | QAbstractItemView::EditKeyPressed);
  // Corners come from picking and Rectangle is a tick: no text editor for them.
  struct ReadOnly : QStyledItemDelegate {
    using QStyledItemDelegate::QStyledItemDelegate;
    QWidget* createEditor(QWidget*, const QStyleOptionViewItem&, const QModelIndex&) const override { return nullptr; }
  };
  polygons_->setItemDelegateForColumn(1, new ReadOnly(polygons_));
  polygons_->setItemDelegateForColumn(4, new ReadOnly(polygons_));
  polygons_->setRootIsDecorated(false);
  polygons_->header()->setSectionResizeMode(QHeaderView::ResizeToContents);
  sl->addWidget(polygons_, 2);
  {
    auto* row = new QHBoxLayout;
    polygonName_ = new QLineEdit(side);
    polygonName_->setPlaceholderText(tr("name (optional)"));
    polygonName_->setToolTip(tr("The new polygon's name"));
    auto* make = makePolygon_ = new QPushButton(tr("Polygon from picked"), side);
    make->setToolTip(tr("A polygon through the picked points, in the order picked (P)"));
    row->addWidget(polygonName_, 1);
    auto* del = new QPushButton(tr("Delete polygon"), side);
    auto* undo = undoButton_ = new QPushButton(tr("Undo"), side);
    auto* redo = redoButton_ = new QPushButton(tr("Redo"), side);
    row->addWidget(make);
    row->addWidget(del);
    row->addWidget(undo);
    row->addWidget(redo);
    sl->addLayout(row);
    connect(make, &QPushButton::clicked, this, [this] {
      if (!addPolygonFromPicked(polygonName_->text().trimmed()).isEmpty()) polygonName_->clear();
    });
    connect(del, &QPushButton::clicked, this, [this] {
      if (auto* it = polygons_->currentItem()) deletePolygon(it->text(0));
    });
    connect(undo, &QPushButton::clicked, &undo_, &QUndoStack::undo);
    connect(redo, &QPushButton::clicked, &undo_, &QUndoStack::redo);
    connect(&undo_, &QUndoStack::canUndoChanged, undo, &QPushButton::setEnabled);
    connect(&undo_, &QUndoStack::canRedoChanged, redo, &QPushButton::setEnabled);
    undo->setEnabled(false);
    redo->setEnabled(false);
  }
  split->addWidget(tabs_);
  split->setStretchFactor(0, 3);
  split->setStretchFactor(1, 3);
  split->setStretchFactor(2, 2);
  layout->addWidget(split, 1);

  hint_ = new QLabel(this);
  hint_->setWordWrap(true);
  layout->addWidget(hint_);
  counts_ = new QLabel(this);
  counts_->setWordWrap(true);
  layout->addWidget(counts_);
  {
    auto* row = new QHBoxLayout;
    row->addWidget(new QLabel(tr("Project"), this));
    project_ = new QLineEdit(this);
    project_->setToolTip(tr("The Relume project the model is written to"));
    row->addWidget(project_, 1);
    row->addWidget(new QLabel(tr("Focal length"), this));
    focal_ = new QDoubleSpinBox(this);
    focal_->setRange(0, 100000);
    focal_->setDecimals(1);
    focal_->setSuffix(tr(" px"));
    focal_->setSpecialValueText(tr("from EXIF / calibration"));
    focal_->setToolTip(tr("Without a reconstruction: the camera's focal length in pixels (the Photos panel's "
                          "calibration is used when there is one)"));
    row->addWidget(focal_);
    row->addWidget(new QLabel(tr("Scale"), this));
    scaleA_ = new QLineEdit(this);
    scaleB_ = new QLineEdit(this);
    scaleA_->setPlaceholderText(tr("point"));
    scaleB_->setPlaceholderText(tr("point"));
    scaleA_->setMaximumWidth(70);
    scaleB_->setMaximumWidth(70);
    scaleMetres_ = new QDoubleSpinBox(this);
    scaleMetres_->setRange(0, 1000);
    scaleMetres_->setDecimals(3);
    scaleMetres_->setSuffix(tr(" m"));
    floor_ = new QLineEdit(this);
    floor_->setPlaceholderText(tr("floor points"));
    floor_->setMaximumWidth(140);
    for (QWidget* w : {static_cast<QWidget*>(scaleA_), static_cast<QWidget*>(scaleB_), static_cast<QWidget*>(scaleMetres_),
                       static_cast<QWidget*>(floor_)})
      w->setToolTip(tr("Without a reconstruction and without three measured clicked points: two points, their "
                       "distance, and three or more floor points (names, comma-separated) set the metric frame"));
    row->addWidget(scaleA_);
    row->addWidget(scaleB_);
    row->addWidget(scaleMetres_);
    row->addWidget(floor_);
    build_ = new QPushButton(tr("Build model"), this);
    build_->setToolTip(tr("Triangulate the points, fit the polygons, write the project and preprocess it"));
    row->addWidget(build_);
    layout->addLayout(row);
    connect(build_, &QPushButton::clicked, this, [this] { build(); });
  }
  summary_ = new QLabel(tr("Open a workspace to click corners in its photos."), this);
  summary_->setWordWrap(true);
  layout->addWidget(summary_);

  connect(points_, &QTreeWidget::itemSelectionChanged, this, [this] {
    if (refreshing_) return;
    // The selection, in the order its points were picked.
    std::vector<std::string> sel, order;
    for (auto* it : points_->selectedItems()) sel.push_back(ss(it->text(0)));
    for (const auto& n : picked_)
      if (std::find(sel.begin(), sel.end(), n) != sel.end()) order.push_back(n);
    for (const auto& n : sel)
      if (std::find(order.begin(), order.end(), n) == order.end()) order.push_back(n);
    picked_ = order;
    if (auto* it = points_->currentItem(); it && it->isSelected()) current_ = ss(it->text(0));
    refreshViews();
  });
  connect(polygons_, &QTreeWidget::itemChanged, this, [this](QTreeWidgetItem* it, int column) {
    if (refreshing_) return;
    const QString name = it->data(0, Qt::UserRole).toString();  // as it was before this change
    // The edit runs once the view has finished with the item (the lists are rebuilt by it).
    QMetaObject::invokeMethod(this, [this, name, column, text = it->text(column), checked = it->checkState(column) == Qt::Checked] {
      switch (column) {
        case 0: renamePolygon(name, text); break;
        case 2: setPolygonGroup(name, text); break;
        case 3: setPolygonLamp(name, checked, text); break;
        case 4: setPolygonRectangle(name, checked); break;
        case 5: setPolygonPlane(name, text); break;
        default: break;
      }
    }, Qt::QueuedConnection);
  });
  refreshViews();
}

ClicksPanel::~ClicksPanel() { pool_->waitForDone(); }  // results still queued go with results_

void ClicksPanel::showEvent(QShowEvent* e) {
  QWidget::showEvent(e);
  const QString capture = photosPanel_ ? photosPanel_->captureFolder() : QString();
  if (!capture.isEmpty() && workspace_->text().isEmpty()) workspace_->setText(capture + "/reconstruction");
}

bool ClicksPanel::load(const QString& workspace, const QString& photos) {
  if (workspace.isEmpty()) {
    emit message(tr("Choose a workspace folder first."));
    return false;
  }
  const QString ws = QFileInfo(workspace).absoluteFilePath();
  if (!QDir().mkpath(ws)) {
    emit message(tr("Cannot create the folder %1.").arg(ws));
    return false;
  }
  try {
    const recon::ClickWorkspace w = recon::openClickWorkspace(ss(ws), ss(photos));
    QString pd = qs(w.photosDir);
    if (pd.isEmpty() && photosPanel_ && !photosPanel_->captureFolder().isEmpty()) {
      const QString c = photosPanel_->captureFolder();
      pd = QDir(c + "/photos").exists() ? c + "/photos" : c + "/originals";
    }
    if (pd.isEmpty() || !QDir(pd).exists()) throw Error(ss(ws), "", "its photos folder is unknown; give it");
    std::vector<std::string> names;
    std::map<std::string, QString> files;
    for (const auto& f : recon::listPhotos(ss(pd))) {
      if (isRadianceFile(f)) continue;
      const std::string stem = std::filesystem::path(f).stem().string();
      if (!files.count(stem)) names.push_back(stem), files[stem] = qs(f);
    }
    if (names.empty()) throw Error(ss(pd), "", "holds no photos (PNG, JPEG, TIFF)");
    std::unique_ptr<recon::ColmapModel> model;
    if (!w.modelFolder.empty()) model = std::make_unique<recon::ColmapModel>(recon::readColmapModel(w.modelFolder));
    bool metric = false;
    if (const auto info = recon::readWorkspaceInfo(ss(ws))) metric = info->metric;
    const QString file = ws + "/clicks.json";
    recon::Clicks c;
    if (QFileInfo::exists(file)) c = recon::readClicks(ss(file), true);
    c.file = ss(file);
    waitForProposals();
    workspaceDir_ = ws;
    photosDir_ = QFileInfo(pd).absoluteFilePath();
    clicksFile_ = file;
    photoNames_ = names;
    photoFiles_ = files;
    model_ = std::move(model);
    metricModel_ = metric;
    display_.clear();
    match_.clear();
    for (int v = 0; v < 2; ++v) {
      views_[v]->setImage(QImage(), QString());
      proposals_[v].clear();
      proposalKey_[v].clear();
    }
    clicks_ = c;
    fittedCameras_ = size_t(-1);
    current_.clear();
    picked_.clear();
    undo_.clear();
    workspace_->setText(ws);
    // The project beside the workspace, unless the user chose one for this workspace.
    if (project_->text().isEmpty() || project_->text() == autoProject_) project_->setText(autoProject_ = QDir(ws).filePath("model.relume"));
    {
      const QSignalBlocker a(photoBox_[0]), b(photoBox_[1]);
      for (int v = 0; v < 2; ++v) {
        photoBox_[v]->clear();
        for (const auto& n : names) photoBox_[v]->addItem(qs(n));
      }
      const std::string mainPhoto = !c.main.empty() && files.count(c.main) ? c.main : names.front();
      photoBox_[0]->setCurrentText(qs(mainPhoto));
      photoBox_[1]->setCurrentIndex(names.size() > 1 && names[0] == mainPhoto ? 1 : 0);
    }
    retriangulate();
    refreshLists();
    refreshViews();
    summary_->setText(tr("%1 photos from %2").arg(names.size()).arg(QDir::toNativeSeparators(photosDir_)));
    return true;
  } catch (const Error& e) {
    emit message(qs(e.what()));
    summary_->setText(qs(e.what()));
    return false;
  }
}

void ClicksPanel::showPhotos(const QString& a, const QString& b) {
  {
    const QSignalBlocker ba(photoBox_[0]), bb(photoBox_[1]);
    photoBox_[0]->setCurrentText(a);
    photoBox_[1]->setCurrentText(b);
  }
  refreshViews();
}

void ClicksPanel::setCurrentPoint(const QString& name) {
  current_ = clicks_.points.count(ss(name)) ? ss(name) : std::string();
  refreshLists();
  refreshViews();
}

void ClicksPanel::startNewPoint() { setCurrentPoint(QString()); }

void ClicksPanel::setPicked(const std::vector<std::string>& names) {
  picked_.clear();
  for (const auto& n : names)
    if (clicks_.points.count(n)) picked_.push_back(n);
  refreshLists();
  refreshViews();
}

std::string ClicksPanel::newPointName() const {
  // p<N> with N above every number in use (names of up to nine digits).
  int top = -1;
  for (const auto& [n, p] : clicks_.points)
    if (n.size() > 1 && n.size() < 10 && n[0] == 'p' && std::all_of(n.begin() + 1, n.end(), ::isdigit))
      top = std::max(top, std::stoi(n.substr(1)));
  return "p" + std::to_string(top + 1);
}

void ClicksPanel::edit(const QString& text, const std::function<void(recon::Clicks&)>& change) {
  recon::Clicks after = clicks_;
  change(after);
  if (recon::clicksJson(after) == recon::clicksJson(clicks_)) return;
  undo_.push(new ClicksCommand(this, clicks_, after, text));
}

void ClicksPanel::applyClicks(const recon::Clicks& clicks) {
  clicks_ = clicks;
  clicks_.file = ss(clicksFile_);
  if (!current_.empty() && !clicks_.points.count(current_)) current_.clear();
  picked_.erase(std::remove_if(picked_.begin(), picked_.end(), [&](const std::string& n) { return !clicks_.points.count(n); }),
                picked_.end());
  // Saved at once: the user's clicks never wait for a "Save".
  if (!clicksFile_.isEmpty()) {
    try {
      recon::writeClicks(clicks_, ss(clicksFile_));
    } catch (const Error& e) {
      emit message(qs(e.what()));
    }
  }
  retriangulate();
  refreshLists();
  refreshViews();
}

void ClicksPanel::clickAt(int view, QPointF pixel) {
  if (!isLoaded() || view < 0 || view > 1) return;
  const std::string photo = ss(views_[view]->photoName());
  const QImage& img = views_[view]->image();
  if (photo.empty() || pixel.x() < 0 || pixel.y() < 0 || pixel.x() > img.width() || pixel.y() > img.height()) return;
  const glm::dvec2 px(pixel.x(), pixel.y());
  // The current point takes the click when it has none in this photo; otherwise a new point starts.
  const auto it = clicks_.points.find(current_);
  std::string name = current_;
  if (it == clicks_.points.end() || clickIn(it->second, photo)) name = newPointName();
  const bool fresh = !clicks_.points.count(name);
  edit(fresh ? tr("New point %1").arg(qs(name)) : tr("Click %1 in %2").arg(qs(name), qs(photo)), [&](recon::Clicks& c) {
    auto& p = c.points[name];
    p.name = name;
    p.clicks.emplace_back(photo, px);
  });
  current_ = name;
  refreshLists();
  refreshViews();
}

bool ClicksPanel::acceptProposal(int view, int index) {
  if (view < 0 || view > 1 || index < 0 || size_t(index) >= proposals_[view].size() || current_.empty()) return false;
  const std::string photo = ss(views_[view]->photoName());
  const QPointF q = proposals_[view][size_t(index)];
  edit(tr("Accept the match of %1 in %2").arg(qs(current_), qs(photo)), [&](recon::Clicks& c) {
    auto& p = c.points.at(current_);
    p.clicks.erase(std::remove_if(p.clicks.begin(), p.clicks.end(), [&](const auto& k) { return k.first == photo; }), p.clicks.end());
    p.clicks.emplace_back(photo, glm::dvec2(q.x(), q.y()));
  });
  return true;
}

void ClicksPanel::movePoint(const QString& name, const QString& photo, QPointF pixel) {
  if (!clicks_.points.count(ss(name))) return;
  edit(tr("Move %1 in %2").arg(name, photo), [&](recon::Clicks& c) {
    for (auto& k : c.points.at(ss(name)).clicks)
      if (k.first == ss(photo)) k.second = glm::dvec2(pixel.x(), pixel.y());
  });
}

void ClicksPanel::deletePoints(const QStringList& names) {
  if (names.isEmpty()) return;
  edit(names.size() == 1 ? tr("Delete point %1").arg(names[0]) : tr("Delete %1 points").arg(names.size()), [&](recon::Clicks& c) {
    for (const QString& n : names) c.points.erase(ss(n));
    for (auto& poly : c.polygons)
      poly.corners.erase(std::remove_if(poly.corners.begin(), poly.corners.end(), [&](const std::string& k) { return !c.points.count(k); }),
                         poly.corners.end());
    c.polygons.erase(std::remove_if(c.polygons.begin(), c.polygons.end(), [](const auto& p) { return p.corners.size() < 3; }),
                     c.polygons.end());
  });
}

bool ClicksPanel::mergePoints(const QString& keep, const QString& gone) {
  const std::string k = ss(keep), g = ss(gone);
  if (k == g || !clicks_.points.count(k) || !clicks_.points.count(g)) return false;
  edit(tr("Merge %1 into %2").arg(gone, keep), [&](recon::Clicks& c) {
    auto& a = c.points.at(k);
    const auto& b = c.points.at(g);
    for (const auto& click : b.clicks)
      if (!clickIn(a, click.first)) a.clicks.push_back(click);
    if (!a.typed) a.typed = b.typed;
    c.points.erase(g);
    for (auto& poly : c.polygons) {
      for (auto& corner : poly.corners)
        if (corner == g) corner = k;
      // A polygon that had both keeps one.
      std::vector<std::string> once;
      for (const auto& corner : poly.corners)
        if (std::find(once.begin(), once.end(), corner) == once.end()) once.push_back(corner);
      poly.corners = once;
    }
    c.polygons.erase(std::remove_if(c.polygons.begin(), c.polygons.end(), [](const auto& p) { return p.corners.size() < 3; }),
                     c.polygons.end());
  });
  return true;
}

void ClicksPanel::setTyped(const QString& name, const std::optional<glm::dvec3>& xyz) {
  if (!clicks_.points.count(ss(name))) return;
  edit(xyz ? tr("Measure %1").arg(name) : tr("Forget the measure of %1").arg(name),
       [&](recon::Clicks& c) { c.points.at(ss(name)).typed = xyz; });
}

QString ClicksPanel::addTypedPoint(const glm::dvec3& xyz) {
  const std::string name = newPointName();
  edit(tr("New measured point %1").arg(qs(name)), [&](recon::Clicks& c) {
    auto& p = c.points[name];
    p.name = name;
    p.typed = xyz;
  });
  current_ = name;
  refreshLists();
  refreshViews();
  return qs(name);
}

QString ClicksPanel::addPolygonFromPicked(const QString& wanted) {
  if (picked_.size() < 3) {
    emit message(tr("Pick three or more corners in order first (Ctrl+click them, or select them in the list)."));
    return {};
  }
  std::string name = ss(wanted);
  if (name.empty())
    for (int k = int(clicks_.polygons.size()) + 1; name.empty(); ++k) {
      const std::string n = "polygon " + std::to_string(k);
      if (std::none_of(clicks_.polygons.begin(), clicks_.polygons.end(), [&](const auto& p) { return p.name == n; })) name = n;
    }
  if (std::any_of(clicks_.polygons.begin(), clicks_.polygons.end(), [&](const auto& p) { return p.name == name; })) {
    emit message(tr("There is a polygon called %1 already.").arg(qs(name)));
    return {};
  }
  const auto corners = picked_;
  edit(tr("New polygon %1").arg(qs(name)), [&](recon::Clicks& c) {
    recon::ClickPolygon p;
    p.name = name;
    p.group = name;
    p.corners = corners;
    c.polygons.push_back(p);
  });
  setPicked({});
  return qs(name);
}

void ClicksPanel::deletePolygon(const QString& name) {
  edit(tr("Delete polygon %1").arg(name), [&](recon::Clicks& c) {
    c.polygons.erase(std::remove_if(c.polygons.begin(), c.polygons.end(), [&](const auto& p) { return p.name == ss(name); }),
                     c.polygons.end());
  });
}

void ClicksPanel::setPolygonLamp(const QString& name, bool lamp, const QString& lampName) {
  edit(lamp ? tr("%1 is a lamp").arg(name) : tr("%1 is not a lamp").arg(name), [&](recon::Clicks& c) {
    for (auto& p : c.polygons)
      if (p.name == ss(name)) p.lamp = !lamp ? std::string() : lampName.trimmed().isEmpty() ? p.name : ss(lampName.trimmed());
  });
}

bool ClicksPanel::renamePolygon(const QString& name, const QString& wanted) {
  const std::string to = ss(wanted.trimmed());
  if (to == ss(name)) return true;
  if (to.empty() || std::any_of(clicks_.polygons.begin(), clicks_.polygons.end(), [&](const auto& p) { return p.name == to; })) {
    emit message(tr("A polygon needs a name of its own."));
    refreshLists();
    return false;
  }
  edit(tr("Rename %1 to %2").arg(name, qs(to)), [&](recon::Clicks& c) {
    for (auto& p : c.polygons)
      if (p.name == ss(name)) {
        if (p.group == p.name) p.group = to;
        if (p.lamp == p.name) p.lamp = to;
        p.name = to;
      }
  });
  return true;
}

void ClicksPanel::setPolygonGroup(const QString& name, const QString& group) {
  edit(tr("%1 in group %2").arg(name, group), [&](recon::Clicks& c) {
    for (auto& p : c.polygons)
      if (p.name == ss(name)) p.group = group.trimmed().isEmpty() ? p.name : ss(group.trimmed());
  });
}

void ClicksPanel::setPolygonRectangle(const QString& name, bool rectangle) {
  edit(rectangle ? tr("%1 is a rectangle").arg(name) : tr("%1 is not a rectangle").arg(name), [&](recon::Clicks& c) {
    for (auto& p : c.polygons)
      if (p.name == ss(name)) p.rectangle = rectangle;
  });
}

void ClicksPanel::setPolygonPlane(const QString& name, const QString& plane) {
  edit(tr("%1 shares plane %2").arg(name, plane), [&](recon::Clicks& c) {
    for (auto& p : c.polygons)
      if (p.name == ss(name)) p.plane = ss(plane.trimmed());
  });
}

bool ClicksPanel::cameraOf(const std::string& photo, recon::ColmapCamera& cc, glm::dmat3& R, glm::dvec3& t) const {
  if (!model_) return false;
  const recon::ColmapImage* im = model_->findImage(photo);
  if (!im || !model_->cameras.count(im->camera)) return false;
  cc = model_->cameras.at(im->camera);
  R = im->R();
  t = im->t;
  return true;
}

bool ClicksPanel::projectPoint(const glm::dvec3& X, const std::string& photo, QPointF& pixel) const {
  recon::ColmapCamera cc;
  glm::dmat3 R;
  glm::dvec3 t;
  if (!cameraOf(photo, cc, R, t)) return false;
  const glm::dvec3 x = R * X + t;
  if (x.z <= 1e-9) return false;
  const glm::dvec2 d = cc.distort(glm::dvec2(x.x / x.z, x.y / x.z));
  pixel = QPointF(d.x, d.y);
  return std::isfinite(d.x) && std::isfinite(d.y);
}

QPolygonF ClicksPanel::epipolarCurve(const std::string& from, QPointF pixel, const std::string& to) const {
  // The ray of the click, sampled in depth and projected (a curve when the lens distorts).
  recon::ColmapCamera ca, cb;
  glm::dmat3 Ra, Rb;
  glm::dvec3 ta, tb;
  if (!cameraOf(from, ca, Ra, ta) || !cameraOf(to, cb, Rb, tb)) return {};
  const glm::dvec2 n = ca.undistort(glm::dvec2(pixel.x(), pixel.y()));
  const glm::dmat3 Rt = glm::transpose(Ra);
  const glm::dvec3 o = -(Rt * ta), d = glm::normalize(Rt * glm::dvec3(n.x, n.y, 1.0));
  QPolygonF curve;
  const double w = cb.width, h = cb.height;
  for (double depth = 0.02; depth < 1000; depth *= 1.03) {
    QPointF q;
    if (!projectPoint(o + depth * d, to, q)) continue;
    if (q.x() < -w || q.y() < -h || q.x() > 2 * w || q.y() > 2 * h) continue;
    curve << q;
  }
  return curve;
}

void ClicksPanel::retriangulate() {
  states_.clear();
  for (const auto& [name, p] : clicks_.points) {
    PointState s;
    if (p.typed && p.clicks.size() < 2) {
      s.triangulated = true;
      s.X = *p.typed;
      states_[name] = s;
      continue;
    }
    if (p.clicks.size() < 2) {
      s.problem = tr("clicked in one photo: click it in another");
    } else if (!model_) {
      s.problem = tr("no cameras yet");
    } else {
      try {
        const recon::TriangulatedPoint tp = recon::triangulateClickedPoint(clicks_, name, *model_);
        s.triangulated = true;
        s.X = tp.X;
        s.maxError = tp.maxError();
        s.rayAngleDeg = tp.rayAngleDeg;
      } catch (const Error& e) {
        s.problem = qs(e.problem());
      }
    }
    states_[name] = s;
  }
}

void ClicksPanel::refreshLists() {
  refreshing_ = true;
  points_->clear();
  for (const auto& [name, p] : clicks_.points) {
    QStringList in;
    for (const auto& c : p.clicks) in << qs(c.first);
    auto* it = new QTreeWidgetItem(points_);
    it->setText(0, qs(name));
    it->setText(1, in.join(", ") + (p.typed ? (in.isEmpty() ? QString() : QStringLiteral("; ")) +
                                                  tr("measured (%1, %2, %3)").arg(p.typed->x).arg(p.typed->y).arg(p.typed->z)
                                            : QString()));
    const PointState& s = states_[name];
    if (!s.problem.isEmpty()) {
      it->setText(2, QStringLiteral("-"));
      it->setText(3, s.problem);
      it->setForeground(3, QColor(200, 60, 40));
    } else if (p.clicks.size() >= 2) {
      it->setText(2, tr("%1 px").arg(s.maxError, 0, 'f', 2));
      if (s.maxError > kLargeErrorPx) it->setForeground(2, QColor(200, 60, 40));
      const bool weak = s.rayAngleDeg < kWeakAngleDeg;
      it->setText(3, weak ? tr("weak (%1°)").arg(s.rayAngleDeg, 0, 'f', 1) : tr("good (%1°)").arg(s.rayAngleDeg, 0, 'f', 0));
      it->setToolTip(3, weak ? tr("Clicked in photos taken from nearly the same direction: click it in a photo further to the side")
                             : QString());
      if (weak) it->setForeground(3, QColor(200, 110, 0));
    } else {
      it->setText(3, tr("measured"));
    }
    if (std::find(picked_.begin(), picked_.end(), name) != picked_.end()) it->setSelected(true);
    if (name == current_) points_->setCurrentItem(it, 0, QItemSelectionModel::NoUpdate);
  }
  counts_->setText(tr("%1 points, %2 polygons; %3. Saved in %4")
                       .arg(clicks_.points.size())
                       .arg(clicks_.polygons.size())
                       .arg(model_ ? tr("cameras from the reconstruction") : tr("no cameras yet (solved from the clicks when building)"))
                       .arg(QDir::toNativeSeparators(clicksFile_)));
  polygons_->clear();
  for (const auto& poly : clicks_.polygons) {
    QStringList corners;
    for (const auto& c : poly.corners) corners << qs(c);
    auto* it = new QTreeWidgetItem(polygons_, {qs(poly.name), corners.join(" "), qs(poly.group), qs(poly.lamp)});
    it->setData(0, Qt::UserRole, qs(poly.name));
    it->setFlags(it->flags() | Qt::ItemIsUserCheckable | Qt::ItemIsEditable);
    it->setCheckState(3, poly.lamp.empty() ? Qt::Unchecked : Qt::Checked);
    it->setCheckState(4, poly.rectangle ? Qt::Checked : Qt::Unchecked);
    it->setText(5, qs(poly.plane));
  }
  refreshing_ = false;
}

void ClicksPanel::refreshViews() {
  if (!isLoaded()) {
    hint_->setText(tr("Open a workspace: its photos appear here side by side."));
    return;
  }
  std::string photo[2];
  for (int v = 0; v < 2; ++v) {
    photo[v] = ss(photoBox_[v]->currentText());
    if (ss(views_[v]->photoName()) != photo[v]) {
      views_[v]->setImage(displayImage(photo[v]), qs(photo[v]));
      proposals_[v].clear();
      proposalKey_[v].clear();
    }
  }
  const auto cur = clicks_.points.find(current_);
  for (int v = 0; v < 2; ++v) {
    std::vector<ClickPhotoView::Marker> markers;
    for (const auto& [name, p] : clicks_.points) {
      const auto* c = clickIn(p, photo[v]);
      if (!c) continue;
      const PointState& s = states_[name];
      const bool weak = p.clicks.size() >= 2 && s.problem.isEmpty() && (s.rayAngleDeg < kWeakAngleDeg || s.maxError > kLargeErrorPx);
      markers.push_back({qs(name), QPointF(c->second.x, c->second.y), name == current_,
                         std::find(picked_.begin(), picked_.end(), name) != picked_.end(), weak});
    }
    views_[v]->setMarkers(std::move(markers));
    // Outlines of the polygons whose corners all have a position.
    std::vector<QPolygonF> outlines;
    std::vector<bool> lamps;
    for (const auto& poly : clicks_.polygons) {
      QPolygonF q;
      for (const auto& corner : poly.corners) {
        const auto s = states_.find(corner);
        QPointF px;
        if (s == states_.end() || !s->second.triangulated || !projectPoint(s->second.X, photo[v], px)) break;
        q << px;
      }
      if (q.size() == int(poly.corners.size())) {
        outlines.push_back(q);
        lamps.push_back(!poly.lamp.empty());
      }
    }
    views_[v]->setOutlines(std::move(outlines), std::move(lamps));
    // The epipolar curve of the current point's click in the other photo, when this one has none.
    const int o = 1 - v;
    QPolygonF curve;
    if (cur != clicks_.points.end() && !clickIn(cur->second, photo[v]) && photo[v] != photo[o])
      if (const auto* c = clickIn(cur->second, photo[o])) curve = epipolarCurve(photo[o], QPointF(c->second.x, c->second.y), photo[v]);
    views_[v]->setEpipolar(curve);
  }
  requestProposals();
  refreshHint();
  refresh3d();
}

void ClicksPanel::refresh3d() {
  if (tabs_->currentWidget() != view3d_ || !isLoaded()) return;
  std::vector<glm::dvec3> xyz;
  std::vector<std::array<uint8_t, 3>> rgb;
  std::vector<int> marked;
  for (const auto& [name, st] : states_) {
    if (!st.triangulated) continue;
    if (name == current_ || std::find(picked_.begin(), picked_.end(), name) != picked_.end()) marked.push_back(int(xyz.size()));
    xyz.push_back(st.X);
    rgb.push_back({235, 235, 235});
  }
  std::vector<Camera> cams;
  if (model_)
    for (const auto& [id, im] : model_->images) cams.push_back(model_->camera(im));
  // Fitted when the cameras change (a workspace opened, cameras solved); kept while clicking.
  const bool fit = cams.size() != fittedCameras_ || xyz.empty() != fittedEmpty_;
  fittedCameras_ = cams.size();
  fittedEmpty_ = xyz.empty();
  view3d_->setModel(xyz, rgb, cams, fit);
  view3d_->setMarked(marked);
  std::vector<std::vector<glm::dvec3>> polys;
  std::vector<bool> lamps;
  for (const auto& poly : clicks_.polygons) {
    std::vector<glm::dvec3> q;
    for (const auto& c : poly.corners) {
      const auto s = states_.find(c);
      if (s == states_.end() || !s->second.triangulated) break;
      q.push_back(s->second.X);
    }
    if (q.size() == poly.corners.size()) {
      polys.push_back(q);
      lamps.push_back(!poly.lamp.empty());
    }
  }
  view3d_->setPolygons(polys, lamps);
}

void ClicksPanel::refreshHint() {
  const auto cur = clicks_.points.find(current_);
  QString hint;
  if (cur == clicks_.points.end())
    hint = tr("Click a corner in either photo to start a point. Ctrl+click points to pick polygon corners in order.");
  else if (proposals_[0].size() + proposals_[1].size() > 0)
    hint = tr("Point %1: click a ring to accept that proposal (Enter: the best; 1-3), or click the corner where it "
              "is (Shift+click: exactly there, even on a ring). N starts a new point.").arg(qs(current_));
  else
    hint = tr("Point %1: click it in the other photo; drag a cross to move it. N starts a new point.").arg(qs(current_));
  hint_->setText(hint);
}

QImage ClicksPanel::displayImage(const std::string& photo) {
  const auto it = display_.find(photo);
  if (it != display_.end()) return it->second;
  const auto f = photoFiles_.find(photo);
  QImage img;
  if (f != photoFiles_.end()) {
    try {
      const Image8 im = readImage8(ss(f->second));
      img = QImage(im.width, im.height, QImage::Format_RGB888);
      for (int y = 0; y < im.height; ++y)
        std::memcpy(img.scanLine(y), im.pixels.data() + size_t(y) * im.width * 3, size_t(im.width) * 3);
    } catch (const Error& e) {
      emit message(qs(e.what()));
    }
  }
  display_[photo] = img;
  return img;
}


void ClicksPanel::requestProposals() {
  const auto cur = clicks_.points.find(current_);
  for (int v = 0; v < 2; ++v) {
    const int o = 1 - v;
    const std::string to = ss(views_[v]->photoName()), from = ss(views_[o]->photoName());
    const recon::ClickPoint* p = cur == clicks_.points.end() ? nullptr : &cur->second;
    const auto* c = p && to != from && !clickIn(*p, to) ? clickIn(*p, from) : nullptr;
    if (!c) {
      if (!proposals_[v].empty()) views_[v]->setProposals({});
      proposals_[v].clear();
      proposalKey_[v].clear();
      continue;
    }
    const QString key = QStringLiteral("%1|%2|%3|%4|%5").arg(qs(from), qs(to)).arg(c->second.x).arg(c->second.y).arg(model_ != nullptr);
    if (key == proposalKey_[v]) {
      views_[v]->setProposals(proposals_[v]);
      continue;
    }
    proposalKey_[v] = key;
    proposals_[v].clear();
    views_[v]->setProposals({});
    // With cameras the click is looked for in every photo that has one at once (a depth must look
    // right in all of them), on the planes of the polygons built so far too; the photos are
    // resampled to the sweep's pinhole cameras (the lens distortion removed), the click taken
    // there and the proposals brought back. Each photo is prepared for matching once, on the
    // worker, and kept.
    struct Source {
      std::string name;
      std::shared_ptr<const recon::MatchImage> image;  // prepared already, else read from `file`
      QString file;
      std::shared_ptr<recon::ColmapCamera> lens;
      std::shared_ptr<Camera> camera;
    };
    auto source = [&](const std::string& name) {
      Source src{name, match_.count(name) ? match_[name] : nullptr, photoFiles_.count(name) ? photoFiles_[name] : QString(), nullptr, nullptr};
      if (model_)
        if (const auto* im = model_->findImage(name); im && model_->cameras.count(im->camera)) {
          src.camera = std::make_shared<Camera>(model_->camera(*im));
          src.lens = std::make_shared<recon::ColmapCamera>(model_->cameras.at(im->camera));
        }
      return src;
    };
    Source a = source(from);
    std::vector<Source> targets{source(to)};  // [0]: the photo shown
    const bool cameras = a.camera && targets[0].camera;
    if (cameras)
      for (const auto& name : photoNames())
        if (name != from && name != to && source(name).camera) targets.push_back(source(name));
    bool readable = a.image || !a.file.isEmpty();
    for (const auto& t : targets) readable = readable && (t.image || !t.file.isEmpty());
    if (!readable) continue;
    std::vector<recon::Plane> planes;
    if (cameras) {
      std::map<std::string, glm::dvec3> positions;
      for (const auto& [name, st] : states_)
        if (st.triangulated) positions[name] = st.X;
      planes = recon::polygonPlanes(clicks_, positions, current_);
    }
    const glm::dvec2 pa = c->second;
    // The world's up: +z in a metric frame, else as the photos' orientations tell it.
    const glm::dvec3 up = metricModel_ || !model_ ? glm::dvec3(0, 0, 1) : recon::estimateUp(*model_);
    const unsigned generation = ++proposalGeneration_;
    QPointer<ClicksPanel> self(this);
    QPointer<QObject> sink(results_);
    ++proposalsRunning_;
    pool_->start([self, sink, a, targets, cameras, planes, pa, up, v, key, generation]() mutable {
      std::vector<QPointF> found;
      std::vector<Source> prepared;
      auto prepare = [&](Source& src) {
        if (src.image) return;
        const Image8 im = readImage8(ss(src.file));
        src.image = std::make_shared<const recon::MatchImage>(src.lens ? recon::prepareForMatching(im, *src.lens)
                                                                       : recon::prepareForMatching(im));
        prepared.push_back(src);
      };
      try {
        prepare(a);
        prepare(targets[0]);
        const glm::dvec2 at = cameras ? recon::pinholePixel(*a.lens, pa) : pa;
        std::vector<recon::MatchProposal> shown;
        if (cameras) {
          std::vector<const recon::MatchImage*> images;
          std::vector<const Camera*> cams;
          for (auto& t : targets) {
            try {
              prepare(t);
            } catch (const std::exception&) {
              if (&t != &targets[0]) continue;  // an unreadable photo besides the one shown: left out
              throw;
            }
            images.push_back(t.image.get());
            cams.push_back(t.camera.get());
          }
          shown = recon::proposeMatchesInPhotos(*a.image, at, *a.camera, images, cams, 3, 7, up, planes)[0];
        } else {
          shown = recon::proposeMatches(*a.image, at, *targets[0].image, nullptr, nullptr, 3, 7, up);
        }
        for (const auto& m : shown) {
          const glm::dvec2 q = cameras ? recon::distortedPixel(*targets[0].lens, m.pixel) : m.pixel;
          found.emplace_back(q.x, q.y);
        }
      } catch (const std::exception&) {
        // No proposal then (a click at the border, a photo of another size): the user clicks it.
      }
      QMetaObject::invokeMethod(sink, [self, found, v, key, generation, prepared] {
        if (!self) return;
        --self->proposalsRunning_;
        for (const auto& p : prepared) self->match_.emplace(p.name, p.image);
        // Only the latest request of this view counts (the user may have clicked on meanwhile).
        if (self->proposalKey_[v] != key || generation < self->shownGeneration_[v]) return;
        self->shownGeneration_[v] = generation;
        self->proposals_[v] = found;
        self->views_[v]->setProposals(found);
        self->refreshHint();
      }, Qt::QueuedConnection);
    });
  }
}

void ClicksPanel::waitForProposals() {
  pool_->waitForDone();
  QCoreApplication::sendPostedEvents(results_, QEvent::MetaCall);  // their results only
}

void ClicksPanel::keyPressEvent(QKeyEvent* e) {
  // Line edits, spin boxes and lists pass keys they do not use on to here: only keys typed over
  // the photos (or the panel itself) are the panel's shortcuts; Delete in a list deletes its selection.
  QWidget* from = QApplication::focusWidget();
  if (e->key() == Qt::Key_Delete && from && (from == points_ || points_->isAncestorOf(from))) {
    QStringList names;
    for (auto* it : points_->selectedItems()) names << it->text(0);
    deletePoints(names);
    return;
  }
  if (e->key() == Qt::Key_Delete && from && (from == polygons_ || polygons_->isAncestorOf(from))) {
    if (auto* it = polygons_->currentItem()) deletePolygon(it->text(0));
    return;
  }
  if (from && from != this && !qobject_cast<ClickPhotoView*>(from)) {
    QWidget::keyPressEvent(e);
    return;
  }
  const auto cur = clicks_.points.find(current_);
  const int view = cur != clicks_.points.end() && !proposals_[1].empty() ? 1 : 0;  // where proposals show
  switch (e->key()) {
    case Qt::Key_N:
      startNewPoint();
      return;
    case Qt::Key_Return:
    case Qt::Key_Enter:
      if (acceptProposal(view, 0)) return;
      break;
    case Qt::Key_1:
    case Qt::Key_2:
    case Qt::Key_3:
      if (acceptProposal(view, e->key() - Qt::Key_1)) return;
      break;
    case Qt::Key_P:
      addPolygonFromPicked();
      return;
    case Qt::Key_F:
      views_[0]->fit();
      views_[1]->fit();
      return;
    case Qt::Key_Delete:
      if (!current_.empty()) deletePoints({qs(current_)});
      return;
    default:
      break;
  }
  QWidget::keyPressEvent(e);
}

bool ClicksPanel::build(const QString& projectPath) {
  if (!isLoaded()) {
    emit message(tr("Open a workspace and click the corners first."));
    return false;
  }
  if (jobs_->busy()) return false;
  const QString project = QFileInfo(projectPath.isEmpty() ? project_->text() : projectPath).absoluteFilePath();
  if (project.isEmpty()) {
    emit message(tr("Choose where the project goes first."));
    return false;
  }
  recon::ClickWorkspace w;
  try {
    w = recon::openClickWorkspace(ss(workspaceDir_), ss(photosDir_));
  } catch (const Error& e) {
    emit message(qs(e.what()));
    return false;
  }
  recon::ClickCameraOptions o;
  o.focal = focal_->value();
  if (o.focal == 0 && photosPanel_ && !photosPanel_->captureFolder().isEmpty() &&
      QFileInfo::exists(photosPanel_->captureFolder() + "/intrinsics.json"))
    o.intrinsicsFile = ss(photosPanel_->captureFolder() + "/intrinsics.json");
  o.scaleA = ss(scaleA_->text().trimmed());
  o.scaleB = ss(scaleB_->text().trimmed());
  o.scaleMetres = scaleMetres_->value();
  for (const QString& f : floor_->text().split(',', Qt::SkipEmptyParts)) o.floor.push_back(ss(f.trimmed()));
  const recon::Clicks clicks = clicks_;
  return jobs_->start(tr("Building the model from the clicks"), [this, clicks, w, o, project](Progress& progress) -> JobRunner::Continuation {
    QTemporaryDir tmp;
    auto b = std::make_shared<recon::ClickBuild>(recon::buildFromClicks(clicks, w, o, ss(tmp.path()) + "/undistorted", progress));
    recon::saveClickProject(*b, clicks, ss(project), progress);
    return [this, b, project]() {
      // Cameras solved from the clicks serve the clicking from now on (errors, epipolar lines).
      if (!model_) {
        model_ = std::make_unique<recon::ColmapModel>(b->model);
        match_.clear();  // prepared without cameras: again, with their distortion removed
      }
      QStringList lines;
      for (const auto& n : b->notes) lines << qs(n);
      for (const auto& n : b->warnings) lines << tr("Warning: %1").arg(qs(n));
      double worst = 0;
      for (const auto& [n, tp] : b->report.points) worst = std::max(worst, tp.maxError());
      lines << tr("%1 points (largest reprojection error %2 px), %3 polygons, %4 lamps: %5")
                   .arg(b->report.points.size())
                   .arg(worst, 0, 'f', 2)
                   .arg(b->scene.polygons.size())
                   .arg(b->scene.lamps.size())
                   .arg(QDir::toNativeSeparators(project));
      summary_->setText(lines.join("\n"));
      retriangulate();
      refreshLists();
      refreshViews();
      emit modelBuilt(project);
    };
  });
}

}  // namespace relume
