#pragma once
// The Lights panel (Loscos 2000, Fig. 9 made real): per real lamp an on/off switch, an intensity
// slider (0-400 %, logarithmic), a colour, and its estimate with how the preprocess obtained it.
#include <QWidget>
#include <string>
#include <vector>
#include <glm/vec3.hpp>

class QCheckBox;
class QSlider;
class QLabel;
class QPushButton;
class QVBoxLayout;
class QDoubleSpinBox;

namespace relume {

class Document;
class EditTool;

class LightsPanel : public QWidget {
  Q_OBJECT
 public:
  explicit LightsPanel(Document* doc, QWidget* parent = nullptr);
  // Slider position (0-1000) <-> intensity (0 off, 1 % .. 400 %, logarithmic).
  static double intensityOf(int position);
  static int positionOf(double intensity);
  QSlider* slider(int lamp) const;
  QCheckBox* toggle(int lamp) const;
  // Virtual lamps: the button that arms "click a surface to add a lamp", and per lamp its row.
  void setEditTool(EditTool* tool);
  QPushButton* addLampButton() const { return addLamp_; }
  QSlider* virtualSlider(int lamp) const { return virtuals_.at(size_t(lamp)).slider; }
  QPushButton* virtualDelete(int lamp) const { return virtuals_.at(size_t(lamp)).remove; }
  QDoubleSpinBox* virtualDrop(int lamp) const { return virtuals_.at(size_t(lamp)).drop; }

 signals:
  void message(const QString& text);

 private:
  void rebuild();
  void refresh();
  void commit(int lamp, double intensity, const QColor& colour, int gesture);
  void syncVirtuals();
  void rebuildVirtuals();
  void commitVirtual(const std::string& name, double intensity, const QColor& colour, double size, int gesture);

  struct Row {
    QCheckBox* on = nullptr;
    QSlider* slider = nullptr;
    QLabel* value = nullptr;
    QPushButton* colour = nullptr;
    QLabel* estimate = nullptr;
  };
  struct VirtualRow {
    std::string name;
    QSlider* slider = nullptr;
    QLabel* value = nullptr;
    QPushButton* colour = nullptr;
    QDoubleSpinBox* size = nullptr;
    QDoubleSpinBox* drop = nullptr;
    QPushButton* remove = nullptr;
  };
  Document* doc_;
  EditTool* tool_ = nullptr;
  QPushButton* addLamp_;
  QVBoxLayout* virtualRows_;
  std::vector<VirtualRow> virtuals_;
  QVBoxLayout* rows_;
  QLabel* summary_;
  std::vector<Row> lamps_;
  std::vector<glm::dvec3> lastOn_;  // per lamp its last scale while on
  int gesture_ = 1;
  bool updating_ = false;
};

}  // namespace relume
