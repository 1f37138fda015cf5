#include "click_photo_view.h"

#include <QFontMetricsF>
#include <QMouseEvent>
#include <QPainter>
#include <QPainterPath>
#include <QWheelEvent>
#include <algorithm>
#include <cmath>

namespace relume {

namespace {
constexpr double kHit = 7;  // widget pixels: how near a marker or ring a click must be
}

ClickPhotoView::ClickPhotoView(QWidget* parent) : QWidget(parent) {
  setMouseTracking(false);
  setFocusPolicy(Qt::ClickFocus);
  setMinimumSize(240, 180);
  setSizePolicy(QSizePolicy::Expanding, QSizePolicy::Expanding);
}

void ClickPhotoView::setImage(const QImage& image, const QString& name) {
  const bool same = image.size() == image_.size();
  image_ = image;
  name_ = name;
  if (!same || fitted_) fit();
  update();
}

void ClickPhotoView::setMarkers(std::vector<Marker> markers) {
  if (dragging_ >= 0) {
    // A drag goes on only while its marker stays (same place in the list, same name), where the
    // cursor has it.
    const size_t d = size_t(dragging_);
    if (d < markers_.size() && d < markers.size() && markers[d].name == markers_[d].name)
      markers[d].pixel = markers_[d].pixel;
    else
      dragging_ = -1;
  }
  markers_ = std::move(markers);
  update();
}
void ClickPhotoView::setProposals(std::vector<QPointF> proposals) {
  proposals_ = std::move(proposals);
  update();
}
void ClickPhotoView::setEpipolar(QPolygonF curve) {
  epipolar_ = std::move(curve);
  update();
}
void ClickPhotoView::setOutlines(std::vector<QPolygonF> outlines, std::vector<bool> lamps) {
  outlines_ = std::move(outlines);
  lampOutlines_ = std::move(lamps);
  update();
}

void ClickPhotoView::roundOffset() {
  // Whole widget pixels: at 1:1 a click then lands on a pixel centre exactly.
  offset_ = QPointF(std::round(offset_.x()), std::round(offset_.y()));
}

void ClickPhotoView::fit() {
  fitted_ = true;
  if (image_.isNull() || width() < 2 || height() < 2) return;
  zoom_ = std::min(double(width()) / image_.width(), double(height()) / image_.height());
  offset_ = QPointF((width() - zoom_ * image_.width()) / 2, (height() - zoom_ * image_.height()) / 2);
  roundOffset();
  update();
  emit viewChanged();
}

void ClickPhotoView::setZoom(double zoom, QPointF about) {
  zoom = std::clamp(zoom, 0.02, 64.0);
  const QPointF pixel = (about - offset_) / zoom_;
  zoom_ = zoom;
  offset_ = about - pixel * zoom_;
  roundOffset();
  fitted_ = false;
  update();
  emit viewChanged();
}

void ClickPhotoView::oneToOne() { setZoom(1, QPointF(width() / 2.0, height() / 2.0)); }

void ClickPhotoView::centerOn(QPointF pixel) {
  offset_ = QPointF(width() / 2.0, height() / 2.0) - pixel * zoom_;
  roundOffset();
  fitted_ = false;
  update();
  emit viewChanged();
}

QPointF ClickPhotoView::widgetPosition(QPointF pixel) const { return offset_ + pixel * zoom_ - QPointF(0.5, 0.5); }
QPointF ClickPhotoView::imagePixel(QPointF pos) const { return (pos + QPointF(0.5, 0.5) - offset_) / zoom_; }

void ClickPhotoView::resizeEvent(QResizeEvent* e) {
  QWidget::resizeEvent(e);
  if (fitted_) fit();
}

void ClickPhotoView::paintEvent(QPaintEvent*) {
  QPainter p(this);
  p.fillRect(rect(), QColor(40, 40, 44));
  if (image_.isNull()) {
    p.setPen(QColor(180, 180, 180));
    p.drawText(rect(), Qt::AlignCenter, tr("No photo"));
    return;
  }
  // Image point x lies at offset + x * zoom: the image's rectangle spans [0, w] x [0, h].
  const QRectF target(offset_, QSizeF(image_.width() * zoom_, image_.height() * zoom_));
  p.setRenderHint(QPainter::SmoothPixmapTransform, zoom_ < 2);  // pixels stay square when zoomed in
  p.drawImage(target, image_);
  p.setRenderHint(QPainter::Antialiasing, true);
  auto W = [&](QPointF px) { return offset_ + px * zoom_; };
  for (size_t i = 0; i < outlines_.size(); ++i) {
    QPolygonF poly;
    for (const QPointF& q : outlines_[i]) poly << W(q);
    const bool lamp = i < lampOutlines_.size() && lampOutlines_[i];
    p.setPen(QPen(lamp ? QColor(255, 200, 40) : QColor(80, 220, 120), 1.5));
    p.setBrush(lamp ? QColor(255, 200, 40, 50) : QColor(80, 220, 120, 28));
    p.drawPolygon(poly);
  }
  p.setBrush(Qt::NoBrush);
  if (epipolar_.size() >= 2) {
    QPolygonF line;
    for (const QPointF& q : epipolar_) line << W(q);
    p.setPen(QPen(QColor(255, 90, 200), 1.2, Qt::DashLine));
    p.drawPolyline(line);
  }
  for (size_t i = 0; i < proposals_.size(); ++i) {
    const QPointF c = W(proposals_[i]);
    p.setPen(QPen(i == 0 ? QColor(255, 120, 30) : QColor(255, 180, 120), i == 0 ? 2.0 : 1.2));
    p.drawEllipse(c, kHit, kHit);
    p.drawText(c + QPointF(kHit + 2, -kHit), QString::number(i + 1));
  }
  // The current and picked points first, so that their labels win where labels would overlap
  // (a crowded corner keeps its crosses; the names that do not fit are left out).
  std::vector<const Marker*> order;
  for (const Marker& m : markers_)
    if (m.current || m.selected) order.push_back(&m);
  for (const Marker& m : markers_)
    if (!m.current && !m.selected) order.push_back(&m);
  std::vector<QRectF> labels;
  const QFontMetricsF fm(font());
  for (const Marker* mp : order) {
    const Marker& m = *mp;
    const QPointF c = W(m.pixel);
    const QColor col = m.current ? QColor(255, 235, 60) : m.selected ? QColor(90, 170, 255) : QColor(60, 230, 230);
    const double r = m.current ? 7 : 5;
    p.setPen(QPen(QColor(0, 0, 0, 160), 3));
    p.drawLine(c - QPointF(r, 0), c + QPointF(r, 0));
    p.drawLine(c - QPointF(0, r), c + QPointF(0, r));
    p.setPen(QPen(col, 1.4));
    p.drawLine(c - QPointF(r, 0), c + QPointF(r, 0));
    p.drawLine(c - QPointF(0, r), c + QPointF(0, r));
    if (m.selected) p.drawEllipse(c, r + 2, r + 2);
    const QString text = m.name + (m.weak ? QStringLiteral(" !") : QString());
    const QPointF at = c + QPointF(r + 2, r + 11);
    const QRectF box = fm.boundingRect(text).translated(at);
    if (std::any_of(labels.begin(), labels.end(), [&](const QRectF& b) { return b.intersects(box); })) continue;
    labels.push_back(box);
    p.setPen(m.weak ? QColor(255, 110, 90) : col);
    p.drawText(at, text);
  }
  // The scale and the photo's name, top left.
  p.setPen(QColor(230, 230, 230));
  p.fillRect(QRectF(4, 4, 180, 18), QColor(0, 0, 0, 140));
  p.drawText(QRectF(8, 4, 176, 18), Qt::AlignVCenter | Qt::AlignLeft,
             QStringLiteral("%1  %2 %").arg(name_).arg(std::round(zoom_ * 100)));
}

int ClickPhotoView::markerAt(QPointF pos) const {
  int best = -1;
  double bestD = kHit;
  for (size_t i = 0; i < markers_.size(); ++i) {
    const double d = std::hypot(pos.x() + 0.5 - (offset_.x() + markers_[i].pixel.x() * zoom_),
                                pos.y() + 0.5 - (offset_.y() + markers_[i].pixel.y() * zoom_));
    if (d <= bestD) best = int(i), bestD = d;
  }
  return best;
}

int ClickPhotoView::proposalAt(QPointF pos) const {
  for (size_t i = 0; i < proposals_.size(); ++i)
    if (std::hypot(pos.x() + 0.5 - (offset_.x() + proposals_[i].x() * zoom_),
                   pos.y() + 0.5 - (offset_.y() + proposals_[i].y() * zoom_)) <= kHit + 2)
      return int(i);
  return -1;
}

void ClickPhotoView::wheelEvent(QWheelEvent* e) {
  const double steps = e->angleDelta().y() / 120.0;
  if (steps != 0) setZoom(zoom_ * std::pow(1.25, steps), e->position());
  e->accept();
}

void ClickPhotoView::mousePressEvent(QMouseEvent* e) {
  if (e->button() == Qt::MiddleButton || e->button() == Qt::RightButton) {
    panning_ = true;
    panFrom_ = e->position();
    return;
  }
  if (e->button() != Qt::LeftButton || image_.isNull()) return;
  // A click on a proposal's ring accepts it (Shift: exactly where clicked, rings or not).
  if (!(e->modifiers() & Qt::ShiftModifier)) {
    const int k = proposalAt(e->position());
    if (k >= 0) {
      emit proposalActivated(k);
      return;
    }
  }
  const int m = markerAt(e->position());
  dragging_ = m;
  dragMoved_ = false;
  if (m >= 0) {
    dragPixel_ = markers_[size_t(m)].pixel;
    pressPos_ = e->position();
    emit markerClicked(markers_[size_t(m)].name, e->modifiers());
    return;
  }
  emit clicked(imagePixel(e->position()), e->modifiers());
}

void ClickPhotoView::mouseMoveEvent(QMouseEvent* e) {
  if (panning_) {
    offset_ += e->position() - panFrom_;
    panFrom_ = e->position();
    roundOffset();
    fitted_ = false;
    update();
    emit viewChanged();
    return;
  }
  if (dragging_ >= 0 && size_t(dragging_) < markers_.size()) {
    // A hand's jitter on a click is not a move: the drag starts 2 pixels from the press.
    if (!dragMoved_ && std::hypot(e->position().x() - pressPos_.x(), e->position().y() - pressPos_.y()) < 2) return;
    dragMoved_ = true;
    markers_[size_t(dragging_)].pixel = imagePixel(e->position());
    update();
    emit markerMoved(markers_[size_t(dragging_)].name, markers_[size_t(dragging_)].pixel);
  }
}

void ClickPhotoView::mouseReleaseEvent(QMouseEvent* e) {
  if (panning_) {
    panning_ = false;
    return;
  }
  const int d = dragging_;
  dragging_ = -1;
  if (d >= 0 && size_t(d) < markers_.size()) {
    const Marker m = markers_[size_t(d)];
    const QPointF px = imagePixel(e->position());
    // A press and release on the same spot is a click on the marker, not a move (unless the
    // marker was moved away and brought back: its listeners have seen it move).
    if (dragMoved_ || std::hypot(px.x() - dragPixel_.x(), px.y() - dragPixel_.y()) * zoom_ >= 2) {
      emit markerDragged(m.name, px);
    } else {
      markers_[size_t(d)].pixel = dragPixel_;
      update();
    }
  }
  dragMoved_ = false;
}

}  // namespace relume
