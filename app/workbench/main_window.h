#pragma once
// The workbench's main window: the relighting viewport in the centre, dock panels around it,
// menus, a status bar with what the viewport shows and the running job (progress, Cancel).
#include <QMainWindow>

class QLabel;
class QProgressBar;
class QPushButton;
class QMenu;
class QActionGroup;

namespace relume {

class Document;
class JobRunner;
class LightsPanel;
class ObjectsPanel;
class EditTool;
class ViewportWidget;

class MainWindow : public QMainWindow {
  Q_OBJECT
 public:
  explicit MainWindow(QWidget* parent = nullptr);
  ~MainWindow() override;

  // Opens a bundle folder, a project, or an OBJ with its JSON (a job: preprocesses when needed).
  // Asks first when the open document has unsaved edits. Returns false when nothing started.
  bool openPath(const QString& path);
  // Saves to `folder` (a job). Returns false when nothing started.
  bool saveTo(const QString& folder);

  Document* document() const { return doc_; }
  JobRunner* jobs() const { return jobs_; }
  ViewportWidget* viewport() const { return viewport_; }
  LightsPanel* lightsPanel() const { return lights_; }
  ObjectsPanel* objectsPanel() const { return objects_; }
  EditTool* editTool() const { return tool_; }
  QString lastError() const { return lastError_; }
  // When false (tests), questions and errors are not shown as dialogs (errors still go to the
  // status bar and lastError()).
  void setInteractive(bool on) { interactive_ = on; }

 protected:
  void closeEvent(QCloseEvent* e) override;

 private:
  void buildMenus();
  void updateTitle();
  void updateStatus();
  void updateRecent();
  void addRecent(const QString& path);
  bool maybeSave();
  void showError(const QString& title, const QString& message);
  void storeView();
  void restoreView();

  Document* doc_;
  JobRunner* jobs_;
  ViewportWidget* viewport_;
  LightsPanel* lights_;
  ObjectsPanel* objects_;
  EditTool* tool_;
  QString selected_;
  QLabel* statusView_;
  QLabel* jobLabel_;
  QProgressBar* jobProgress_;
  QPushButton* jobCancel_;
  QMenu* recentMenu_;
  QActionGroup* modes_;
  QString lastError_;
  bool interactive_ = true;
};

}  // namespace relume
