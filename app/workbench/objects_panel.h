#pragma once
// The Objects panel: a box of chosen size and albedo placed by clicking a floor or table in the
// viewport; per object its turn about the vertical and a Delete button. Objects are dragged in
// the viewport (EditTool) along the surface they stand on. Image-based objects (Dinh, Metoyer,
// Turk): an image fan, or a mesh whose fan is rendered first (a job, with progress and Cancel),
// placed the same way; per object its turn, its scale and a Delete button.
#include <QColor>
#include <QWidget>
#include <string>
#include <vector>

class QDoubleSpinBox;
class QPushButton;
class QSpinBox;
class QVBoxLayout;
class QLabel;

namespace relume {

class Document;
class EditTool;
class JobRunner;

class ObjectsPanel : public QWidget {
  Q_OBJECT
 public:
  ObjectsPanel(Document* doc, EditTool* tool, JobRunner* jobs, QWidget* parent = nullptr);
  QPushButton* placeButton() const { return place_; }
  // Reads an OBJ mesh (metres) and arms the tool to place it; false (with a message) on error.
  bool placeObj(const QString& path);
  QSpinBox* turn(int object) const { return rows_.at(size_t(object)).turn; }
  QPushButton* deleteButton(int object) const { return rows_.at(size_t(object)).remove; }
  // An image fan (.fan) or a mesh (OBJ, PLY, glTF: its fan rendered first, as a job); then the
  // tool is armed to place it. False (with a message) when it cannot be read or a job runs.
  bool placeImageFile(const QString& path);
  QSpinBox* imageTurn(int object) const { return imageRows_.at(size_t(object)).turn; }
  QDoubleSpinBox* imageScale(int object) const { return imageRows_.at(size_t(object)).scale; }
  QPushButton* imageDeleteButton(int object) const { return imageRows_.at(size_t(object)).remove; }

 signals:
  void message(const QString& text);

 private:
  void sync();
  void rebuild();
  void refresh();
  void pushTemplate();
  QSpinBox* turnSpin(QWidget* row);  // an object row's turn about the vertical, degrees
  void rebuildImages();
  void refreshImages();

  struct Row {
    std::string name;
    QSpinBox* turn = nullptr;
    QPushButton* remove = nullptr;
  };
  Document* doc_;
  EditTool* tool_;
  QDoubleSpinBox *width_, *depth_, *height_;
  QPushButton* albedo_;
  QColor colour_{153, 153, 153};
  QPushButton* place_;
  QPushButton* placeObj_;
  QVBoxLayout* list_;
  QLabel* empty_;
  std::vector<Row> rows_;
  struct ImageRow {
    std::string name;
    QSpinBox* turn = nullptr;
    QDoubleSpinBox* scale = nullptr;
    QPushButton* remove = nullptr;
  };
  JobRunner* jobs_;
  QPushButton* placeImage_;
  QDoubleSpinBox* imageScaleTemplate_;
  QVBoxLayout* imageList_;
  QLabel* imageEmpty_;
  std::vector<ImageRow> imageRows_;
  bool updating_ = false;
};

}  // namespace relume
