#pragma once
// The Lights panel (Loscos 2000, Fig. 9 made real): per real lamp an on/off switch, an intensity
// slider (0-400 %, logarithmic), a colour, and its estimate with how the preprocess obtained it.
#include <QWidget>
#include <vector>

class QCheckBox;
class QSlider;
class QLabel;
class QPushButton;
class QVBoxLayout;

namespace relume {

class Document;

class LightsPanel : public QWidget {
  Q_OBJECT
 public:
  explicit LightsPanel(Document* doc, QWidget* parent = nullptr);
  // Slider position (0-1000) <-> intensity (0 off, 1 % .. 400 %, logarithmic).
  static double intensityOf(int position);
  static int positionOf(double intensity);
  QSlider* slider(int lamp) const;
  QCheckBox* toggle(int lamp) const;

 private:
  void rebuild();
  void refresh();
  void commit(int lamp, double intensity, const QColor& colour, int gesture);

  struct Row {
    QCheckBox* on = nullptr;
    QSlider* slider = nullptr;
    QLabel* value = nullptr;
    QPushButton* colour = nullptr;
    QLabel* estimate = nullptr;
  };
  Document* doc_;
  QVBoxLayout* rows_;
  QLabel* summary_;
  std::vector<Row> lamps_;
  int gesture_ = 1;
  bool updating_ = false;
};

}  // namespace relume
