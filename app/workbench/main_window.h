#pragma once
// The workbench's main window: the relighting viewport in the centre, dock panels around it,
// menus, a status bar with what the viewport shows and the running job (progress, Cancel).
#include <QMainWindow>
#include <QLockFile>
#include <memory>
#include <vector>

class QLabel;
class QProgressBar;
class QPushButton;
class QMenu;
class QActionGroup;
class QUndoGroup;

namespace relume {

class Document;
class JobRunner;
class LightsPanel;
class ObjectsPanel;
class ReferencesPanel;
class InspectorPanel;
class PhotosPanel;
class ReconstructionPanel;
class ClicksPanel;
class SkyPanel;
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
  // Rebuilds the session on §4.4's interactive mesh or back on the refined one (a job).
  bool switchMesh(bool interactive);

  Document* document() const { return doc_; }
  JobRunner* jobs() const { return jobs_; }
  ViewportWidget* viewport() const { return viewport_; }
  LightsPanel* lightsPanel() const { return lights_; }
  ObjectsPanel* objectsPanel() const { return objects_; }
  ReferencesPanel* referencesPanel() const { return references_; }
  InspectorPanel* inspectorPanel() const { return inspector_; }
  PhotosPanel* photosPanel() const { return photos_; }
  ReconstructionPanel* reconstructionPanel() const { return reconstruction_; }
  ClicksPanel* clicksPanel() const { return clicks_; }
  SkyPanel* skyPanel() const { return sky_; }
  QDockWidget* skyDock() const { return skyDock_; }
  QDockWidget* clicksDock() const { return clicksDock_; }
  QDockWidget* inspectorDock() const { return inspectorDock_; }
  EditTool* editTool() const { return tool_; }
  QString lastError() const { return lastError_; }
  // When false (tests), questions and errors are not shown as dialogs (errors still go to the
  // status bar and lastError()).
  void setInteractive(bool on) { interactive_ = on; }

  // Autosave: every `ms` (2 minutes by default) a document with edits not yet autosaved is written
  // to a side folder (never over the user's project), off the UI thread. A clean exit, a save or
  // closing the document removes it; one still there at the next start means Relume did not end
  // cleanly, and recoverAutosave() offers it.
  void setAutosaveInterval(int ms);
  static QString autosaveFolder();
  static QString autosaveKey();  // this process's QSettings group for its autosave
  bool autosaveNow();  // returns false when there was nothing to save or a save runs already
  bool autosaveRunning() const;
  // At start: when an autosave is left over, asks (or, not interactive, does `acceptWhenQuiet`)
  // and opens it as an unsaved document. Returns true when a recovery started.
  bool recoverAutosave(bool acceptWhenQuiet = true);

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
  void updateOverlays();  // painted reference regions (while their panel shows) and the stroke under way
  void restoreView();
  void discardAutosave();
  void closeEvent_discard();

  Document* doc_;
  JobRunner* jobs_;
  ViewportWidget* viewport_;
  LightsPanel* lights_;
  ObjectsPanel* objects_;
  ReferencesPanel* references_;
  QDockWidget* referencesDock_ = nullptr;
  InspectorPanel* inspector_ = nullptr;
  PhotosPanel* photos_ = nullptr;
  ReconstructionPanel* reconstruction_ = nullptr;
  QDockWidget* inspectorDock_ = nullptr;
  ClicksPanel* clicks_ = nullptr;
  QDockWidget* clicksDock_ = nullptr;
  SkyPanel* sky_ = nullptr;
  QDockWidget* skyDock_ = nullptr;
  std::vector<QDockWidget*> hiddenForDaylight_;  // lamp-room docks hidden while a daylight room is open
  QUndoGroup* undoGroup_ = nullptr;
  EditTool* tool_;
  QString selected_;
  QLabel* statusView_;
  class QTimer* statusTimer_ = nullptr;  // paces the status bar's updates from frames
  QLabel* jobLabel_;
  QProgressBar* jobProgress_;
  QPushButton* jobCancel_;
  // Shows the three above once a job has run for a quarter of a second: a drag's renders (a few
  // milliseconds each) would otherwise make the status bar flash and lay out twice per move.
  class QTimer* jobShowTimer_;
  QMenu* recentMenu_;
  QActionGroup* modes_;
  QString lastError_;
  bool interactive_ = true;
  class QTimer* autosaveTimer_;
  std::unique_ptr<class QLockFile> autosaveLock_;
  JobRunner* autosaveJobs_;
  quint64 autosavedChanges_ = ~quint64(0);  // the document's change count at the last autosave
  QString lingering_;  // an autosave folder the open document still reads its photos from
  QMenu* lightingMenu_ = nullptr;
  QAction* interactiveMesh_ = nullptr;
  QAction *undoAction_ = nullptr, *redoAction_ = nullptr;
  void setEditing(bool on);
  bool imagesPending_ = false;  // the viewport's image-based objects are to be brought up to date
};

}  // namespace relume
