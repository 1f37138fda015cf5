#pragma once
// The Objects panel: a box of chosen size and albedo placed by clicking a floor or table in the
// viewport; per object its turn about the vertical and a Delete button. Objects are dragged in
// the viewport (EditTool) along the surface they stand on.
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

class ObjectsPanel : public QWidget {
  Q_OBJECT
 public:
  ObjectsPanel(Document* doc, EditTool* tool, QWidget* parent = nullptr);
  QPushButton* placeButton() const { return place_; }
  // Reads an OBJ mesh (metres) and arms the tool to place it; false (with a message) on error.
  bool placeObj(const QString& path);
  QSpinBox* turn(int object) const { return rows_.at(size_t(object)).turn; }
  QPushButton* deleteButton(int object) const { return rows_.at(size_t(object)).remove; }

 signals:
  void message(const QString& text);

 private:
  void sync();
  void rebuild();
  void refresh();
  void pushTemplate();

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
  bool updating_ = false;
};

}  // namespace relume
