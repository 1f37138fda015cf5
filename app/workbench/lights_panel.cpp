#include "lights_panel.h"

#include <QCheckBox>
#include <QDoubleSpinBox>
#include <QSignalBlocker>
#include <QColorDialog>
#include <QGridLayout>
#include <QGroupBox>
#include <QLabel>
#include <QPushButton>
#include <QSlider>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>

#include "document.h"
#include "edit_tool.h"
#include <glm/geometric.hpp>

namespace relume {

namespace {
constexpr double kMaxIntensity = 4.0, kMinIntensity = 0.01;

// The lamp's colour (its RGB scale normalised to its largest channel) and its intensity.
void split(const glm::dvec3& s, double& intensity, QColor& colour) {
  const double m = std::max({s.x, s.y, s.z});
  intensity = m;
  colour = m > 0 ? QColor::fromRgbF(float(s.x / m), float(s.y / m), float(s.z / m)) : QColor(Qt::white);
}

QString swatchStyle(const QColor& c) {
  return QString("background-color: %1; border: 1px solid #555; min-width: 28px;").arg(c.name());
}
}  // namespace

double LightsPanel::intensityOf(int position) {
  if (position <= 0) return 0.0;
  return kMinIntensity * std::pow(kMaxIntensity / kMinIntensity, position / 1000.0);
}

int LightsPanel::positionOf(double intensity) {
  if (intensity <= 0) return 0;
  const double p = 1000.0 * std::log(intensity / kMinIntensity) / std::log(kMaxIntensity / kMinIntensity);
  return std::clamp(int(std::lround(p)), 1, 1000);
}

LightsPanel::LightsPanel(Document* doc, QWidget* parent) : QWidget(parent), doc_(doc) {
  auto* layout = new QVBoxLayout(this);
  summary_ = new QLabel(this);
  summary_->setWordWrap(true);
  layout->addWidget(summary_);
  rows_ = new QVBoxLayout;
  layout->addLayout(rows_);
  auto* vbox = new QGroupBox(tr("Virtual lamps"), this);
  auto* vlayout = new QVBoxLayout(vbox);
  addLamp_ = new QPushButton(tr("Add a lamp (click a surface)"), vbox);
  addLamp_->setCheckable(true);
  addLamp_->setToolTip(tr("Then click a surface in the viewport: a 30 cm lamp appears 2 cm in front of it, "
                          "facing away from it. Drag it to move it along that surface."));
  vlayout->addWidget(addLamp_);
  virtualRows_ = new QVBoxLayout;
  vlayout->addLayout(virtualRows_);
  layout->addWidget(vbox);
  layout->addStretch(1);
  connect(doc_, &Document::virtualsChanged, this, &LightsPanel::syncVirtuals);
  connect(doc_, &Document::opened, this, &LightsPanel::rebuild);
  connect(doc_, &Document::closed, this, &LightsPanel::rebuild);
  connect(doc_, &Document::relightingReplaced, this, &LightsPanel::rebuild);
  connect(doc_, &Document::lightingChanged, this, &LightsPanel::refresh);
  rebuild();
}

QSlider* LightsPanel::slider(int lamp) const { return lamps_.at(size_t(lamp)).slider; }
QCheckBox* LightsPanel::toggle(int lamp) const { return lamps_.at(size_t(lamp)).on; }

void LightsPanel::rebuild() {
  while (QLayoutItem* item = rows_->takeAt(0)) {
    if (QWidget* w = item->widget()) {  // a button of it may be emitting right now
      w->hide();
      w->deleteLater();
    }
    delete item;
  }
  lamps_.clear();
  lastOn_.assign(doc_->isOpen() ? doc_->scene().lamps.size() : 0, glm::dvec3(1.0));
  rebuildVirtuals();
  if (!doc_->isOpen()) {
    summary_->setText(tr("No room open."));
    return;
  }
  const auto& est = doc_->data().estimates;
  summary_->setText(tr("Lamp strengths estimated by the preprocess (%1). Drag a slider to dim or boost a lamp; "
                       "untick to switch it off.")
                        .arg(QString::fromStdString(est.lampModel)));
  summary_->setToolTip(QString::fromStdString(est.lampModelReason));
  const auto& lamps = doc_->scene().lamps;
  for (size_t l = 0; l < lamps.size(); ++l) {
    auto* box = new QGroupBox(tr("Lamp %1").arg(QString::fromStdString(lamps[l].name)), this);
    auto* grid = new QGridLayout(box);
    Row r;
    r.on = new QCheckBox(tr("On"), box);
    r.slider = new QSlider(Qt::Horizontal, box);
    r.slider->setRange(0, 1000);
    r.slider->setPageStep(50);
    r.slider->setToolTip(tr("Intensity, 0-400 % of the photographed lamp"));
    r.value = new QLabel(box);
    r.value->setMinimumWidth(48);
    r.value->setAlignment(Qt::AlignRight | Qt::AlignVCenter);
    r.colour = new QPushButton(box);
    r.colour->setToolTip(tr("Colour of the lamp"));
    r.colour->setFixedWidth(36);
    r.estimate = new QLabel(box);
    r.estimate->setWordWrap(true);
    r.estimate->setStyleSheet("color: #666; font-size: small;");
    if (l < est.lamps.size()) {
      const auto& e = est.lamps[l];
      const glm::dvec3 u = e.used;
      QString how = QString::fromStdString(est.lampModel);
      const Lamp& lamp = doc_->scene().lamps[l];
      const bool fromFile = lamp.photometry && doc_->data().options.calibratedPhotos;
      if (fromFile && e.photographed != glm::dvec3(0.0) && e.used == e.photographed) how = tr("its photometric file's flux");
      else if (e.photographed != glm::dvec3(0.0) && e.used == e.photographed) how = tr("measured in the HDR photo");
      else if (e.leastSquares != glm::dvec3(0.0) && e.used == e.leastSquares) how = tr("least-squares fit");
      else if (e.used == e.equal) how = tr("Eq. 2, all lamps equal");
      r.estimate->setText(tr("Estimate: %1, %2, %3 W/m² (%4)")
                              .arg(u.x, 0, 'g', 3)
                              .arg(u.y, 0, 'g', 3)
                              .arg(u.z, 0, 'g', 3)
                              .arg(how));
      if (lamp.photometry)
        r.estimate->setText(r.estimate->text() + "\n" +
                            tr("Emits as %1 says (%2, %3 lm)")
                                .arg(QString::fromStdString(lamp.photometryFile), QString::fromStdString(lamp.photometry->format))
                                .arg(lamp.photometry->flux(), 0, 'f', 0));
    }
    grid->addWidget(r.on, 0, 0);
    grid->addWidget(r.slider, 0, 1);
    grid->addWidget(r.value, 0, 2);
    grid->addWidget(r.colour, 0, 3);
    grid->addWidget(r.estimate, 1, 0, 1, 4);
    grid->setColumnStretch(1, 1);
    rows_->addWidget(box);
    const int lamp = int(l);
    connect(r.slider, &QSlider::sliderPressed, this, [this] { ++gesture_; });
    connect(r.slider, &QSlider::valueChanged, this, [this, lamp](int pos) {
      if (updating_) return;
      double i;
      QColor c;
      split(doc_->lampScale(lamp), i, c);
      // A drag is one undo step; a key or click on the groove is one step each.
      const int g = lamps_[size_t(lamp)].slider->isSliderDown() ? gesture_ : 0;
      commit(lamp, intensityOf(pos), c, g);
    });
    connect(r.on, &QCheckBox::toggled, this, [this, lamp](bool on) {
      if (updating_) return;
      // Back on as it was before it went off (intensity and colour), not white at 100 %.
      double i;
      QColor c;
      split(lastOn_.at(size_t(lamp)), i, c);
      commit(lamp, on ? i : 0.0, c, 0);
    });
    connect(r.colour, &QPushButton::clicked, this, [this, lamp] {
      double i;
      QColor c;
      split(doc_->lampScale(lamp), i, c);
      const QColor chosen = QColorDialog::getColor(c, this, tr("Colour of the lamp"));
      if (chosen.isValid()) commit(lamp, i > 0 ? i : 1.0, chosen, 0);
    });
    lamps_.push_back(r);
  }
  refresh();
}

void LightsPanel::commit(int lamp, double intensity, const QColor& colour, int gesture) {
  const glm::dvec3 c(colour.redF(), colour.greenF(), colour.blueF());
  doc_->editLampScale(lamp, intensity * c, gesture);
}

void LightsPanel::setEditTool(EditTool* tool) {
  tool_ = tool;
  connect(addLamp_, &QPushButton::toggled, this, [this](bool on) {
    if (on) tool_->setMode(EditTool::Mode::PlaceLamp);
    else if (tool_->mode() == EditTool::Mode::PlaceLamp) tool_->setMode(EditTool::Mode::Select);
  });
  connect(tool_, &EditTool::modeChanged, this, [this](EditTool::Mode m) {
    const QSignalBlocker block(addLamp_);
    addLamp_->setChecked(m == EditTool::Mode::PlaceLamp);
  });
}

void LightsPanel::syncVirtuals() {
  bool same = virtuals_.size() == doc_->virtualLampCount();
  for (size_t i = 0; same && i < virtuals_.size(); ++i) same = virtuals_[i].name == doc_->session()->virtualLamp(int(i)).name;
  if (!same) rebuildVirtuals();
  else refresh();
}

namespace {
double lampSize(const VirtualLamp& l) { return glm::length(l.polygon[1] - l.polygon[0]); }
}  // namespace

void LightsPanel::rebuildVirtuals() {
  while (QLayoutItem* item = virtualRows_->takeAt(0)) {
    if (QWidget* w = item->widget()) {  // its Delete button may be emitting right now
      w->hide();
      w->deleteLater();
    }
    delete item;
  }
  virtuals_.clear();
  for (size_t i = 0; i < doc_->virtualLampCount(); ++i) {
    const VirtualLamp& l = doc_->session()->virtualLamp(int(i));
    auto* row = new QWidget(this);
    auto* grid = new QGridLayout(row);
    grid->setContentsMargins(0, 4, 0, 4);
    VirtualRow r;
    r.name = l.name;
    auto* name = new QLabel(QString::fromStdString(l.name), row);
    name->setStyleSheet("font-weight: bold;");
    r.slider = new QSlider(Qt::Horizontal, row);
    r.slider->setRange(0, 1000);
    r.slider->setPageStep(50);
    r.slider->setToolTip(tr("Power, 0-400 % of the brightest real lamp"));
    r.value = new QLabel(row);
    r.value->setMinimumWidth(48);
    r.value->setAlignment(Qt::AlignRight | Qt::AlignVCenter);
    r.colour = new QPushButton(row);
    r.colour->setFixedWidth(36);
    r.colour->setToolTip(tr("Colour of the lamp"));
    r.size = new QDoubleSpinBox(row);
    r.size->setRange(0.05, 2.0);
    r.size->setSingleStep(0.05);
    r.size->setDecimals(2);
    r.size->setSuffix(tr(" m"));
    r.size->setToolTip(tr("Width of the square lamp"));
    r.drop = new QDoubleSpinBox(row);
    r.drop->setRange(0.0, 5.0);
    r.drop->setSingleStep(0.05);
    r.drop->setDecimals(2);
    r.drop->setSuffix(tr(" m"));
    r.drop->setPrefix(tr("drop "));
    r.drop->setToolTip(tr("Distance from the surface it was put on (a pendant's suspension)"));
    r.remove = new QPushButton(tr("Delete"), row);
    grid->addWidget(r.drop, 2, 0, 1, 2);
    grid->addWidget(name, 0, 0);
    grid->addWidget(r.size, 0, 1);
    grid->addWidget(r.remove, 0, 2, 1, 2);
    grid->addWidget(r.slider, 1, 0, 1, 2);
    grid->addWidget(r.value, 1, 2);
    grid->addWidget(r.colour, 1, 3);
    grid->setColumnStretch(0, 1);
    virtualRows_->addWidget(row);
    const std::string n = l.name;
    auto current = [this, n](double& intensity, QColor& colour, double& size) {
      const int k = doc_->virtualLampIndex(n);
      if (k < 0) return false;
      const VirtualLamp& v = doc_->session()->virtualLamp(k);
      size = lampSize(v);
      const glm::dvec3 ref = doc_->defaultLampRadiance(size);
      split(v.radiance / std::max({ref.x, ref.y, ref.z, 1e-12}), intensity, colour);
      return true;
    };
    connect(r.slider, &QSlider::sliderPressed, this, [this] { ++gesture_; });
    connect(r.slider, &QSlider::valueChanged, this, [this, n, current, i](int pos) {
      double in, size;
      QColor c;
      if (updating_ || !current(in, c, size)) return;
      const int g = virtuals_[i].slider->isSliderDown() ? gesture_ : 0;
      commitVirtual(n, intensityOf(pos), c, size, g);
    });
    connect(r.colour, &QPushButton::clicked, this, [this, n, current] {
      double in, size;
      QColor c;
      if (!current(in, c, size)) return;
      const QColor chosen = QColorDialog::getColor(c, this, tr("Colour of the lamp"));
      if (chosen.isValid()) commitVirtual(n, in > 0 ? in : 1.0, chosen, size, 0);
    });
    connect(r.size, &QDoubleSpinBox::editingFinished, this, [this, n, current, i] {
      double in, size;
      QColor c;
      if (updating_ || !current(in, c, size) || std::abs(virtuals_[i].size->value() - size) < 1e-6) return;
      commitVirtual(n, in, c, virtuals_[i].size->value(), 0);
    });
    connect(r.drop, &QDoubleSpinBox::editingFinished, this, [this, n, i] {
      if (updating_ || std::abs(virtuals_[i].drop->value() - doc_->lampDrop(n)) < 1e-6) return;
      QString error;
      if (!doc_->trySetLampDrop(n, virtuals_[i].drop->value(), &error)) {
        emit message(tr("Not moved: %1").arg(error));
        refresh();
      }
    });
    connect(r.remove, &QPushButton::clicked, this, [this, n] { doc_->removeVirtualLamp(n); });
    virtuals_.push_back(r);
  }
  refresh();
}

void LightsPanel::commitVirtual(const std::string& name, double intensity, const QColor& colour, double size, int gesture) {
  // Power kept when the size changes: the reference radiance is that of the new size.
  const glm::dvec3 ref = doc_->defaultLampRadiance(size);
  const double m = std::max({ref.x, ref.y, ref.z});
  doc_->editVirtualLamp(name, intensity * m * glm::dvec3(colour.redF(), colour.greenF(), colour.blueF()), size, gesture);
}

void LightsPanel::refresh() {
  if (!doc_->isOpen()) return;
  updating_ = true;
  for (size_t i = 0; i < virtuals_.size() && i < doc_->virtualLampCount(); ++i) {
    const VirtualLamp& v = doc_->session()->virtualLamp(int(i));
    const double size = lampSize(v);
    const glm::dvec3 ref = doc_->defaultLampRadiance(size);
    double in;
    QColor c;
    split(v.radiance / std::max({ref.x, ref.y, ref.z, 1e-12}), in, c);
    auto& r = virtuals_[i];
    if (!r.slider->isSliderDown()) r.slider->setValue(positionOf(in));
    r.value->setText(QString("%1 %").arg(std::lround(100 * in)));
    r.colour->setStyleSheet(swatchStyle(c));
    if (!r.size->hasFocus()) r.size->setValue(size);
    if (!r.drop->hasFocus()) r.drop->setValue(doc_->lampDrop(v.name));
  }
  for (size_t l = 0; l < lamps_.size(); ++l) {
    double i;
    QColor c;
    split(doc_->lampScale(int(l)), i, c);
    auto& r = lamps_[l];
    r.on->setChecked(i > 0);
    if (i > 0) lastOn_[l] = doc_->lampScale(int(l));
    if (!r.slider->isSliderDown()) r.slider->setValue(positionOf(i));
    r.value->setText(QString("%1 %").arg(std::lround(100 * i)));
    r.colour->setStyleSheet(swatchStyle(c));
  }
  updating_ = false;
}

}  // namespace relume
