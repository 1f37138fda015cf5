#pragma once
// A photo to click corners on (Loscos 2000 §3, TotalCalib-style): zoom about the cursor (wheel),
// pan (middle or right button drag), fit or 1:1; clicked points drawn as crosses with their
// names, the match proposals as numbered rings, the epipolar curve of the point clicked in the
// other photo, and the polygons' outlines. Image coordinates follow COLMAP: the centre of the
// top-left pixel is (0.5, 0.5).
#include <QImage>
#include <QPointF>
#include <QPolygonF>
#include <QString>
#include <QWidget>
#include <vector>

namespace relume {

class ClickPhotoView : public QWidget {
  Q_OBJECT
 public:
  struct Marker {
    QString name;
    QPointF pixel;
    bool current = false;   // the point being clicked
    bool selected = false;  // picked for a polygon
    bool weak = false;      // its depth is weak or its error large
  };

  explicit ClickPhotoView(QWidget* parent = nullptr);

  void setImage(const QImage& image, const QString& name);  // keeps the view when the size is the same
  QString photoName() const { return name_; }
  const QImage& image() const { return image_; }
  void setMarkers(std::vector<Marker> markers);
  void setProposals(std::vector<QPointF> proposals);  // best first
  void setEpipolar(QPolygonF curve);                  // empty: none
  void setOutlines(std::vector<QPolygonF> outlines, std::vector<bool> lamps);
  const std::vector<Marker>& markers() const { return markers_; }
  const std::vector<QPointF>& proposals() const { return proposals_; }
  const QPolygonF& epipolar() const { return epipolar_; }

  // The view: zoom (widget pixels per image pixel) and where the image's origin lies.
  double zoom() const { return zoom_; }
  void fit();
  void setZoom(double zoom, QPointF aboutWidget);  // keeps the image point under `aboutWidget`
  void oneToOne();                                  // zoom 1 about the centre
  void centerOn(QPointF pixel);                     // that image point at the widget's centre
  // Widget position of an image point and back (a click at widget pixel p means its centre).
  QPointF widgetPosition(QPointF pixel) const;
  QPointF imagePixel(QPointF widgetPos) const;

 signals:
  void clicked(QPointF pixel, Qt::KeyboardModifiers modifiers);
  void markerClicked(const QString& name, Qt::KeyboardModifiers modifiers);
  void markerDragged(const QString& name, QPointF pixel);  // at the end of a drag
  void markerMoved(const QString& name, QPointF pixel);    // while it is dragged, at every move
  void proposalActivated(int index);                        // a proposal's ring clicked
  void viewChanged();

 protected:
  void paintEvent(QPaintEvent*) override;
  void wheelEvent(QWheelEvent* e) override;
  void mousePressEvent(QMouseEvent* e) override;
  void mouseMoveEvent(QMouseEvent* e) override;
  void mouseReleaseEvent(QMouseEvent* e) override;
  void resizeEvent(QResizeEvent* e) override;

 private:
  int markerAt(QPointF widgetPos) const;
  int proposalAt(QPointF widgetPos) const;
  void roundOffset();

  QImage image_;
  QString name_;
  std::vector<Marker> markers_;
  std::vector<QPointF> proposals_;
  QPolygonF epipolar_;
  std::vector<QPolygonF> outlines_;
  std::vector<bool> lampOutlines_;
  double zoom_ = 1;
  QPointF offset_;  // widget position of image point (0, 0)
  bool fitted_ = true;  // follows the widget's size until the user zooms or pans
  // Gestures.
  QPointF panFrom_;
  bool panning_ = false;
  int dragging_ = -1;
  bool dragMoved_ = false;  // the drag has passed 2 pixels from its press
  QPointF dragPixel_, pressPos_;
};

}  // namespace relume
