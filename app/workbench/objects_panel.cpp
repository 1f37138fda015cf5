#include "objects_panel.h"

#include <QColorDialog>
#include <QFileDialog>
#include <QFileInfo>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QGridLayout>
#include <QGroupBox>
#include <QLabel>
#include <QPushButton>
#include <QSignalBlocker>
#include <QSpinBox>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "document.h"
#include "edit_tool.h"
#include "job_runner.h"
#include "relume/geometry/progress.h"
#include "relume/ibr/fan.h"
#include "relume/ibr/mesh.h"
#include "relume/project/room_io.h"

namespace relume {

namespace {
QString swatch(const QColor& c) { return QString("background-color: %1; border: 1px solid #555; min-width: 28px;").arg(c.name()); }
}  // namespace

ObjectsPanel::ObjectsPanel(Document* doc, EditTool* tool, JobRunner* jobs, QWidget* parent)
    : QWidget(parent), doc_(doc), tool_(tool), jobs_(jobs) {
  auto* layout = new QVBoxLayout(this);
  auto* box = new QGroupBox(tr("New box"), this);
  auto* form = new QFormLayout(box);
  auto spin = [&](double v) {
    auto* s = new QDoubleSpinBox(box);
    s->setRange(0.05, 3.0);
    s->setSingleStep(0.05);
    s->setDecimals(2);
    s->setSuffix(tr(" m"));
    s->setValue(v);
    connect(s, &QDoubleSpinBox::valueChanged, this, &ObjectsPanel::pushTemplate);
    return s;
  };
  width_ = spin(0.4);
  depth_ = spin(0.4);
  height_ = spin(0.4);
  albedo_ = new QPushButton(box);
  albedo_->setToolTip(tr("Albedo (diffuse reflectance) of the box"));
  albedo_->setStyleSheet(swatch(colour_));
  form->addRow(tr("Width"), width_);
  form->addRow(tr("Depth"), depth_);
  form->addRow(tr("Height"), height_);
  form->addRow(tr("Albedo"), albedo_);
  place_ = new QPushButton(tr("Place a box (click a floor)"), box);
  place_->setCheckable(true);
  place_->setToolTip(tr("Then click a floor or a table top in the viewport. Drag a box to move it along what it "
                        "stands on."));
  form->addRow(place_);
  layout->addWidget(box);
  placeObj_ = new QPushButton(tr("Place an OBJ mesh..."), this);
  placeObj_->setToolTip(tr("A mesh in metres, +Z up, with the albedo above; it stands where you click."));
  layout->addWidget(placeObj_);
  connect(placeObj_, &QPushButton::clicked, this, [this] {
    const QString f = QFileDialog::getOpenFileName(this, tr("Place an OBJ mesh"), {}, tr("Wavefront OBJ (*.obj)"));
    if (!f.isEmpty()) placeObj(f);
  });
  auto* image = new QGroupBox(tr("Image-based object"), this);
  auto* imageForm = new QFormLayout(image);
  imageScaleTemplate_ = new QDoubleSpinBox(image);
  imageScaleTemplate_->setRange(0.05, 20.0);
  imageScaleTemplate_->setSingleStep(0.1);
  imageScaleTemplate_->setDecimals(2);
  imageScaleTemplate_->setValue(1.0);
  imageScaleTemplate_->setPrefix(tr("x "));
  imageScaleTemplate_->setToolTip(tr("The mesh's units times this are metres"));
  imageForm->addRow(tr("Scale"), imageScaleTemplate_);
  placeImage_ = new QPushButton(tr("Place an image-based object..."), image);
  placeImage_->setToolTip(tr("An image fan (relume ibr-fan writes them) or a mesh of any size (OBJ, PLY, glTF), drawn "
                             "from images relit by the room's lamps; it stands where you click."));
  imageForm->addRow(placeImage_);
  layout->addWidget(image);
  connect(placeImage_, &QPushButton::clicked, this, [this] {
    const QString f = QFileDialog::getOpenFileName(this, tr("Place an image-based object"), {},
                                                   tr("Image fans and meshes (*.fan *.obj *.ply *.gltf *.glb)"));
    if (!f.isEmpty()) placeImageFile(f);
  });
  auto* placed = new QGroupBox(tr("Objects in the room"), this);
  list_ = new QVBoxLayout(placed);
  empty_ = new QLabel(tr("None yet."), placed);
  list_->addWidget(empty_);
  layout->addWidget(placed);
  auto* images = new QGroupBox(tr("Image-based objects in the room"), this);
  imageList_ = new QVBoxLayout(images);
  imageEmpty_ = new QLabel(tr("None yet."), images);
  imageList_->addWidget(imageEmpty_);
  layout->addWidget(images);
  layout->addStretch(1);

  connect(albedo_, &QPushButton::clicked, this, [this] {
    const QColor c = QColorDialog::getColor(colour_, this, tr("Albedo of the box"));
    if (!c.isValid()) return;
    colour_ = c;
    albedo_->setStyleSheet(swatch(c));
    pushTemplate();
  });
  connect(place_, &QPushButton::toggled, this, [this](bool on) {
    if (on) tool_->setMode(EditTool::Mode::PlaceBox);
    else if (tool_->mode() == EditTool::Mode::PlaceBox) tool_->setMode(EditTool::Mode::Select);
  });
  connect(tool_, &EditTool::modeChanged, this, [this](EditTool::Mode m) {
    const QSignalBlocker block(place_);
    place_->setChecked(m == EditTool::Mode::PlaceBox);
  });
  connect(doc_, &Document::virtualsChanged, this, &ObjectsPanel::sync);
  connect(doc_, &Document::opened, this, &ObjectsPanel::rebuild);
  connect(doc_, &Document::closed, this, &ObjectsPanel::rebuild);
  connect(doc_, &Document::relightingReplaced, this, &ObjectsPanel::rebuild);
  connect(doc_, &Document::imageObjectsChanged, this, [this] {
    bool same = imageRows_.size() == doc_->imageObjects().size();
    for (size_t i = 0; same && i < imageRows_.size(); ++i) same = imageRows_[i].name == doc_->imageObjects()[i].name;
    same ? refreshImages() : rebuildImages();
  });
  connect(doc_, &Document::opened, this, &ObjectsPanel::rebuildImages);
  connect(doc_, &Document::closed, this, &ObjectsPanel::rebuildImages);
  pushTemplate();
  rebuild();
  rebuildImages();
}

bool ObjectsPanel::placeImageFile(const QString& path) {
  const QString stem = QFileInfo(path).completeBaseName();
  const double scale = imageScaleTemplate_->value();
  if (QFileInfo(path).suffix().compare("fan", Qt::CaseInsensitive) == 0) {
    try {
      std::shared_ptr<const ibr::ImageFan> fan = ibr::readFan(path.toStdString());
      tool_->placeImageObject(stem, fan, path.toStdString(), scale);
      return true;
    } catch (const std::exception& e) {
      emit message(QString::fromStdString(e.what()));
      return false;
    }
  }
  // A mesh: its fan rendered off the UI thread (the defaults of relume ibr-fan), then placed.
  const std::string file = path.toStdString();
  const bool started = jobs_->start(tr("Rendering the image fan of %1").arg(QFileInfo(path).fileName()),
                                    [this, file, stem, scale](Progress& progress) {
                                      const ibr::Mesh mesh = ibr::readMesh(file);
                                      std::shared_ptr<ibr::ImageFan> fan = ibr::buildFan(mesh, ibr::FanOptions{}, progress);
                                      fan->source = file;
                                      return JobRunner::Continuation([this, fan, file, stem, scale] {
                                        tool_->placeImageObject(stem, fan, file, scale);
                                      });
                                    });
  if (!started) emit message(tr("Another job is running: wait for it, or cancel it."));
  return started;
}

void ObjectsPanel::rebuildImages() {
  for (auto& r : imageRows_) {
    r.turn->parentWidget()->hide();
    r.turn->parentWidget()->deleteLater();
  }
  imageRows_.clear();
  for (const auto& o : doc_->imageObjects()) {
    auto* row = new QWidget(this);
    auto* grid = new QGridLayout(row);
    grid->setContentsMargins(0, 2, 0, 2);
    ImageRow r;
    r.name = o.name;
    auto* name = new QLabel(QString::fromStdString(o.name), row);
    name->setToolTip(QString::fromStdString(o.fanFile));
    r.turn = turnSpin(row);
    r.scale = new QDoubleSpinBox(row);
    r.scale->setRange(0.05, 20.0);
    r.scale->setSingleStep(0.1);
    r.scale->setDecimals(2);
    r.scale->setPrefix(tr("x "));
    r.scale->setKeyboardTracking(false);
    r.scale->setToolTip(tr("Scale (it keeps standing where it stands)"));
    r.remove = new QPushButton(tr("Delete"), row);
    grid->addWidget(name, 0, 0);
    grid->addWidget(r.turn, 0, 1);
    grid->addWidget(r.scale, 0, 2);
    grid->addWidget(r.remove, 0, 3);
    grid->setColumnStretch(0, 1);
    imageList_->addWidget(row);
    const std::string n = o.name;
    auto place = [this, n](double turnDegrees, double scale) {
      if (updating_) return;
      const int i = doc_->imageObjectIndex(n);
      if (i < 0) return;
      ibr::Placement p = doc_->imageObjects()[size_t(i)].place;
      p.yaw = turnDegrees * std::numbers::pi / 180.0;
      p.scale = scale;
      QString error;
      if (!doc_->tryPlaceImageObject(n, p, 0, &error)) {
        emit message(tr("Not changed: %1").arg(error));
        refreshImages();
      }
    };
    connect(r.turn, &QSpinBox::valueChanged, this, [this, n, place](int deg) {
      const int i = doc_->imageObjectIndex(n);
      if (i >= 0) place(deg, doc_->imageObjects()[size_t(i)].place.scale);
    });
    connect(r.scale, &QDoubleSpinBox::valueChanged, this, [this, n, place](double s) {
      const int i = doc_->imageObjectIndex(n);
      if (i >= 0) place(doc_->imageObjects()[size_t(i)].place.yaw * 180.0 / std::numbers::pi, s);
    });
    connect(r.remove, &QPushButton::clicked, this, [this, n] { doc_->removeImageObject(n); });
    imageRows_.push_back(r);
  }
  imageEmpty_->setVisible(imageRows_.empty());
  refreshImages();
}

void ObjectsPanel::refreshImages() {
  updating_ = true;
  for (auto& r : imageRows_) {
    const int i = doc_->imageObjectIndex(r.name);
    if (i < 0) continue;
    const ibr::Placement& p = doc_->imageObjects()[size_t(i)].place;
    r.turn->setValue(int(std::lround(std::remainder(p.yaw * 180.0 / std::numbers::pi, 360.0))));
    r.scale->setValue(p.scale);
  }
  updating_ = false;
}

bool ObjectsPanel::placeObj(const QString& path) {
  // Each face becomes a radiosity surface linked to the whole room: past a few thousand faces the
  // engine is the wrong tool (image-based objects are meant for those).
  constexpr size_t kMaxFaces = 3000;
  try {
    auto a = [](double v) { return std::clamp(v, 0.02, 0.95); };
    const VirtualObject mesh = meshObject(QFileInfo(path).completeBaseName().toStdString(), readObjFaces(path.toStdString()),
                                          glm::dvec3(a(colour_.redF()), a(colour_.greenF()), a(colour_.blueF())));
    if (mesh.polygons.size() > kMaxFaces) {
      emit message(tr("%1: %2 triangles; the radiosity engine takes meshes of up to %3.").arg(path).arg(mesh.polygons.size()).arg(kMaxFaces));
      return false;
    }
    tool_->placeMesh(QFileInfo(path).completeBaseName(), mesh);
    return true;
  } catch (const std::exception& e) {
    emit message(QString::fromStdString(e.what()));
    return false;
  }
}

QSpinBox* ObjectsPanel::turnSpin(QWidget* row) {
  auto* turn = new QSpinBox(row);
  turn->setRange(-180, 180);
  turn->setSingleStep(15);
  turn->setWrapping(true);
  turn->setKeyboardTracking(false);  // a typed angle turns once, when it is complete
  turn->setSuffix(tr("°"));
  turn->setToolTip(tr("Turn about the vertical"));
  return turn;
}

void ObjectsPanel::pushTemplate() {
  // Albedo in (0, 1): a physical surface never reflects everything.
  auto a = [](double v) { return std::clamp(v, 0.02, 0.95); };
  tool_->setBoxTemplate(glm::dvec3(width_->value(), depth_->value(), height_->value()),
                        glm::dvec3(a(colour_.redF()), a(colour_.greenF()), a(colour_.blueF())));
}

void ObjectsPanel::sync() {
  bool same = rows_.size() == doc_->objectCount();
  for (size_t i = 0; same && i < rows_.size(); ++i) same = rows_[i].name == doc_->session()->object(int(i)).name;
  if (same) refresh();
  else rebuild();
}

void ObjectsPanel::rebuild() {
  for (auto& r : rows_) {  // its Delete button may be emitting right now
    r.turn->parentWidget()->hide();
    r.turn->parentWidget()->deleteLater();
  }
  rows_.clear();
  for (size_t i = 0; i < doc_->objectCount(); ++i) {
    const VirtualObject& o = doc_->session()->object(int(i));
    auto* row = new QWidget(this);
    auto* grid = new QGridLayout(row);
    grid->setContentsMargins(0, 2, 0, 2);
    auto* name = new QLabel(QString::fromStdString(o.name), row);
    auto* colour = new QLabel(row);
    colour->setFixedSize(18, 18);
    colour->setStyleSheet(swatch(QColor::fromRgbF(float(o.albedo.x), float(o.albedo.y), float(o.albedo.z))));
    Row r;
    r.name = o.name;
    r.turn = turnSpin(row);
    r.remove = new QPushButton(tr("Delete"), row);
    grid->addWidget(colour, 0, 0);
    grid->addWidget(name, 0, 1);
    grid->addWidget(r.turn, 0, 2);
    grid->addWidget(r.remove, 0, 3);
    grid->setColumnStretch(1, 1);
    list_->addWidget(row);
    const std::string n = o.name;
    connect(r.turn, &QSpinBox::valueChanged, this, [this, n](int deg) {
      if (updating_) return;
      const double now = doc_->objectTurn(n);
      double delta = std::remainder(double(deg) - now, 360.0);
      QString error;
      if (std::abs(delta) > 1e-9 && !doc_->tryMoveObject(n, glm::dvec3(0.0), delta, 0, &error)) {
        emit message(tr("Not turned: %1").arg(error));
        refresh();  // back to where it is
      }
    });
    connect(r.remove, &QPushButton::clicked, this, [this, n] { doc_->removeObject(n); });
    rows_.push_back(r);
  }
  empty_->setVisible(rows_.empty());
  refresh();
}

void ObjectsPanel::refresh() {
  updating_ = true;
  for (auto& r : rows_) r.turn->setValue(int(std::lround(std::remainder(doc_->objectTurn(r.name), 360.0))));
  updating_ = false;
}

}  // namespace relume
