#include "lights_panel.h"

#include <QCheckBox>
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
  layout->addStretch(1);
  connect(doc_, &Document::opened, this, &LightsPanel::rebuild);
  connect(doc_, &Document::closed, this, &LightsPanel::rebuild);
  connect(doc_, &Document::lightingChanged, this, &LightsPanel::refresh);
  rebuild();
}

QSlider* LightsPanel::slider(int lamp) const { return lamps_.at(size_t(lamp)).slider; }
QCheckBox* LightsPanel::toggle(int lamp) const { return lamps_.at(size_t(lamp)).on; }

void LightsPanel::rebuild() {
  while (QLayoutItem* item = rows_->takeAt(0)) {
    delete item->widget();
    delete item;
  }
  lamps_.clear();
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
      if (e.photographed != glm::dvec3(0.0) && e.used == e.photographed) how = tr("measured in the HDR photo");
      else if (e.leastSquares != glm::dvec3(0.0) && e.used == e.leastSquares) how = tr("least-squares fit");
      else if (e.used == e.equal) how = tr("Eq. 2, all lamps equal");
      r.estimate->setText(tr("Estimate: %1, %2, %3 W/m² (%4)")
                              .arg(u.x, 0, 'g', 3)
                              .arg(u.y, 0, 'g', 3)
                              .arg(u.z, 0, 'g', 3)
                              .arg(how));
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
      double i;
      QColor c;
      split(doc_->lampScale(lamp), i, c);
      commit(lamp, on ? 1.0 : 0.0, c, 0);
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

void LightsPanel::refresh() {
  if (!doc_->isOpen()) return;
  updating_ = true;
  for (size_t l = 0; l < lamps_.size(); ++l) {
    double i;
    QColor c;
    split(doc_->lampScale(int(l)), i, c);
    auto& r = lamps_[l];
    r.on->setChecked(i > 0);
    if (!r.slider->isSliderDown()) r.slider->setValue(positionOf(i));
    r.value->setText(QString("%1 %").arg(std::lround(100 * i)));
    r.colour->setStyleSheet(swatchStyle(c));
  }
  updating_ = false;
}

}  // namespace relume
