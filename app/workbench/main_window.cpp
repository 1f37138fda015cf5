#include "main_window.h"

#include <QAction>
#include <QActionGroup>
#include <QApplication>
#include <QCloseEvent>
#include <QDockWidget>
#include <QFileDialog>
#include <QFileInfo>
#include <QJsonArray>
#include <QJsonObject>
#include <QLabel>
#include <QMenuBar>
#include <QMessageBox>
#include <QProgressBar>
#include <QPushButton>
#include <QScrollArea>
#include <QSettings>
#include <QSignalBlocker>
#include <QDateTime>
#include <QDir>
#include <QLocale>
#include <QLockFile>
#include <QStandardPaths>
#include <QTime>
#include <QTimer>
#include <QStatusBar>
#include <QUndoGroup>
#include <QUndoStack>
#include <cmath>
#include <numbers>

#include "document.h"
#include "i18n.h"
#include "job_runner.h"
#include "relume/geometry/progress.h"
#include "edit_tool.h"
#include "lights_panel.h"
#include "objects_panel.h"
#include "clicks_panel.h"
#include "inspector_panel.h"
#include "photos_panel.h"
#include "sky_panel.h"
#include "relume/project/room_io.h"
#include "reconstruction_panel.h"
#include "references_panel.h"
#include "relume/viewport/viewport_widget.h"

namespace relume {

namespace {
constexpr int kRecentMax = 10;

struct ModeName {
  ViewMode mode;
  const char* key;
};
constexpr ModeName kModes[] = {{ViewMode::Relit, "relit"},           {ViewMode::RatioOnly, "ratio-only"},
                               {ViewMode::Photo, "photo"},           {ViewMode::Unoccluded, "unoccluded"},
                               {ViewMode::Radiosity, "radiosity"},   {ViewMode::DisplayFactor, "display-factor"},
                               {ViewMode::Leaves, "leaves"},         {ViewMode::References, "references"}};
}  // namespace

MainWindow::MainWindow(QWidget* parent) : QMainWindow(parent) {
  setObjectName("MainWindow");
  doc_ = new Document(this);
  jobs_ = new JobRunner(this);
  viewport_ = new ViewportWidget(this);
  setCentralWidget(viewport_);

  tool_ = new EditTool(doc_, this);
  viewport_->setGestures(tool_);
  lights_ = new LightsPanel(doc_, this);
  lights_->setEditTool(tool_);
  auto* lightsDock = new QDockWidget(tr("Lights"), this);
  lightsDock->setObjectName("LightsDock");
  auto* lightsScroll = new QScrollArea(lightsDock);
  lightsScroll->setWidgetResizable(true);
  lightsScroll->setWidget(lights_);
  lightsDock->setWidget(lightsScroll);
  addDockWidget(Qt::RightDockWidgetArea, lightsDock);
  objects_ = new ObjectsPanel(doc_, tool_, jobs_, this);
  auto* objectsDock = new QDockWidget(tr("Objects"), this);
  objectsDock->setObjectName("ObjectsDock");
  objectsDock->setWidget(objects_);
  addDockWidget(Qt::RightDockWidgetArea, objectsDock);
  tabifyDockWidget(lightsDock, objectsDock);
  references_ = new ReferencesPanel(doc_, tool_, jobs_, this);
  auto* referencesDock = referencesDock_ = new QDockWidget(tr("Reference patches"), this);
  referencesDock->setObjectName("ReferencesDock");
  referencesDock->setWidget(references_);
  addDockWidget(Qt::RightDockWidgetArea, referencesDock);
  tabifyDockWidget(objectsDock, referencesDock);
  // From photographs to a model: the photos of a capture, on the left.
  photos_ = new PhotosPanel(jobs_, this);
  auto* photosDock = new QDockWidget(tr("Photos"), this);
  photosDock->setObjectName("PhotosDock");
  photosDock->setWidget(photos_);
  addDockWidget(Qt::LeftDockWidgetArea, photosDock);
  photosDock->hide();
  connect(photos_, &PhotosPanel::message, this, [this](const QString& m) { statusBar()->showMessage(m, 8000); });
  reconstruction_ = new ReconstructionPanel(jobs_, photos_, this);
  auto* reconstructionDock = new QDockWidget(tr("Reconstruction"), this);
  reconstructionDock->setObjectName("ReconstructionDock");
  reconstructionDock->setWidget(reconstruction_);
  addDockWidget(Qt::LeftDockWidgetArea, reconstructionDock);
  tabifyDockWidget(photosDock, reconstructionDock);
  reconstructionDock->hide();
  connect(reconstruction_, &ReconstructionPanel::message, this, [this](const QString& m) { statusBar()->showMessage(m, 8000); });
  // The inspector, below the viewport (hidden until asked for: View > Inspector).
  inspector_ = new InspectorPanel(doc_, jobs_, this);
  inspectorDock_ = new QDockWidget(tr("Inspector"), this);
  inspectorDock_->setObjectName("InspectorDock");
  inspectorDock_->setWidget(inspector_);
  addDockWidget(Qt::BottomDockWidgetArea, inspectorDock_);
  inspectorDock_->hide();
  inspectorDock_->toggleViewAction()->setShortcut(QKeySequence(Qt::CTRL | Qt::Key_I));
  // Clicking corners into a model (TotalCalib-style), below the viewport beside the inspector.
  clicks_ = new ClicksPanel(jobs_, photos_, this);
  clicksDock_ = new QDockWidget(tr("Model from clicks"), this);
  clicksDock_->setObjectName("ClicksDock");
  clicksDock_->setWidget(clicks_);
  addDockWidget(Qt::BottomDockWidgetArea, clicksDock_);
  tabifyDockWidget(inspectorDock_, clicksDock_);
  clicksDock_->hide();
  clicksDock_->toggleViewAction()->setShortcut(QKeySequence(Qt::CTRL | Qt::Key_M));
  connect(clicks_, &ClicksPanel::message, this, [this](const QString& m) { statusBar()->showMessage(m, 8000); });
  // Built: the project opens (and is preprocessed) once the build job has ended.
  connect(clicks_, &ClicksPanel::modelBuilt, this, [this](const QString& project) { openPath(project); }, Qt::QueuedConnection);
  connect(clicksDock_, &QDockWidget::visibilityChanged, this, [this](bool on) {
    if (on && !clicksDock_->isFloating() && clicksDock_->height() < height() / 2)
      resizeDocks({clicksDock_}, {int(height() * 0.6)}, Qt::Vertical);
  });
  // Daylight rooms (measured skies, windows): relit under another sky in their own panel, on the
  // left, shown when one opens.
  sky_ = new SkyPanel(jobs_, this);
  skyDock_ = new QDockWidget(tr("Sky"), this);
  skyDock_->setObjectName("SkyDock");
  skyDock_->setWidget(sky_);
  addDockWidget(Qt::LeftDockWidgetArea, skyDock_);
  skyDock_->hide();
  connect(sky_, &SkyPanel::message, this, [this](const QString& m) { statusBar()->showMessage(m, 8000); });
  connect(sky_, &SkyPanel::opened, this, [this](const QString& path) { addRecent(path); });
  // Edit > Undo acts on the clicks while they have the focus, else on the document.
  undoGroup_ = new QUndoGroup(this);
  undoGroup_->addStack(doc_->undoStack());
  undoGroup_->addStack(clicks_->undoStack());
  undoGroup_->setActiveStack(doc_->undoStack());
  connect(qApp, &QApplication::focusChanged, this, [this](QWidget*, QWidget* now) {
    // While a job runs Undo stays off (setEditing); a floating Model dock is a window of its own.
    if (!now || jobs_->busy()) return;
    if (clicks_->isAncestorOf(now)) undoGroup_->setActiveStack(clicks_->undoStack());
    else if (now->window() == this) undoGroup_->setActiveStack(doc_->undoStack());
  });
  connect(inspector_, &InspectorPanel::pickedChanged, this, &MainWindow::updateOverlays);
  connect(inspectorDock_, &QDockWidget::visibilityChanged, this, &MainWindow::updateOverlays);
  connect(inspectorDock_, &QDockWidget::visibilityChanged, this, [this](bool on) {
    // Shown for the first time (no saved layout gave it a size): 45 % of the window's height.
    if (on && !inspectorDock_->isFloating() && inspectorDock_->height() < height() / 3)
      resizeDocks({inspectorDock_}, {int(height() * 0.45)}, Qt::Vertical);
  });
  connect(tool_, &EditTool::surfaceClicked, this, [this](int surface, const glm::dvec3& point) {
    if (inspectorDock_->isVisible()) inspector_->pickAt(surface, point);
  });
  connect(references_, &ReferencesPanel::showElements, this, [this](bool on) {
    for (QAction* a : modes_->actions())
      if (a->data().toString() == (on ? "references" : "relit")) a->trigger();
  });
  connect(referencesDock, &QDockWidget::visibilityChanged, this, &MainWindow::updateOverlays);
  connect(tool_, &EditTool::strokeChanged, this, &MainWindow::updateOverlays);
  connect(doc_, &Document::referencesChanged, this, &MainWindow::updateOverlays);
  connect(doc_, &Document::opened, this, &MainWindow::updateOverlays);
  connect(doc_, &Document::closed, this, &MainWindow::updateOverlays);
  lightsDock->raise();
  connect(tool_, &EditTool::message, this, [this](const QString& m) { statusBar()->showMessage(m, 8000); });
  connect(lights_, &LightsPanel::message, this, [this](const QString& m) { statusBar()->showMessage(m, 8000); });
  connect(objects_, &ObjectsPanel::message, this, [this](const QString& m) { statusBar()->showMessage(m, 8000); });
  connect(tool_, &EditTool::selected, this, [this](const QString& n) { selected_ = n; });
  connect(doc_, &Document::editFailed, this, [this](const QString& m) { showError(tr("Relume"), m); });

  // Status bar: what the viewport shows; the running job with its progress and Cancel.
  statusView_ = new QLabel(this);
  jobLabel_ = new QLabel(this);
  jobProgress_ = new QProgressBar(this);
  jobProgress_->setRange(0, 1000);
  jobProgress_->setMaximumWidth(220);
  jobCancel_ = new QPushButton(tr("Cancel"), this);
  statusBar()->addWidget(statusView_, 1);
  statusBar()->addPermanentWidget(jobLabel_);
  statusBar()->addPermanentWidget(jobProgress_);
  statusBar()->addPermanentWidget(jobCancel_);
  jobLabel_->hide();
  jobProgress_->hide();
  jobCancel_->hide();
  connect(jobCancel_, &QPushButton::clicked, jobs_, &JobRunner::cancel);
  jobShowTimer_ = new QTimer(this);
  jobShowTimer_->setSingleShot(true);
  jobShowTimer_->setInterval(250);
  connect(jobShowTimer_, &QTimer::timeout, this, [this] {
    if (!jobs_->busy()) return;
    jobLabel_->show();
    jobProgress_->show();
    jobCancel_->show();
  });
  connect(jobs_, &JobRunner::started, this, [this](const QString& title) {
    jobLabel_->setText(title);
    jobProgress_->setValue(0);
    jobShowTimer_->start();
    setEditing(false);
  });
  connect(jobs_, &JobRunner::progressed, this, [this](double f, const QString& text) {
    jobProgress_->setValue(int(1000 * f));
    jobProgress_->setToolTip(text);
    jobLabel_->setText(text.left(60));
  });
  connect(jobs_, &JobRunner::finished, this, [this](bool ok, bool cancelled, const QString& message) {
    jobShowTimer_->stop();
    jobLabel_->hide();
    jobProgress_->hide();
    jobCancel_->hide();
    setEditing(true);
    if (ok) return;
    if (cancelled) statusBar()->showMessage(message, 5000);
    else showError(tr("Relume"), message);
  });

  connect(doc_, &Document::opened, this, [this] {
    if (interactiveMesh_) {
      const QSignalBlocker block(interactiveMesh_);
      interactiveMesh_->setChecked(doc_->mesh() == SessionMesh::Interactive);
    }
    if (!lingering_.isEmpty() || QSettings().contains(autosaveKey() + "/folder")) discardAutosave();
    viewport_->setRoom(&doc_->scene(), &doc_->data(), doc_->session());
    restoreView();
    updateTitle();
    updateStatus();
  });
  connect(doc_, &Document::closed, this, [this] {
    viewport_->setRoom(nullptr, nullptr, nullptr);
    updateTitle();
  });
  connect(doc_, &Document::lightingChanged, viewport_, &ViewportWidget::lightingChanged);
  connect(doc_, &Document::meshChanged, viewport_, &ViewportWidget::meshChanged);
  // Image-based objects follow their document and its light (once per turn of the event loop).
  for (auto signal : {&Document::opened, &Document::relightingReplaced, &Document::imageObjectsChanged,
                      &Document::lightingChanged, &Document::meshChanged})
    connect(doc_, signal, this, [this] {
      if (imagesPending_) return;
      imagesPending_ = true;
      QTimer::singleShot(0, this, [this] {
        imagesPending_ = false;
        if (doc_->isOpen()) viewport_->setImageObjects(doc_->imageObjects(), doc_->imageObjectLighting());
      });
    });
  connect(doc_, &Document::virtualsChanged, this, [this] { updateStatus(); });
  connect(doc_, &Document::relightingReplaced, this, [this] {
    const QSignalBlocker block(interactiveMesh_);
    interactiveMesh_->setChecked(doc_->mesh() == SessionMesh::Interactive);
    viewport_->setRoom(&doc_->scene(), &doc_->data(), doc_->session());
    restoreView();
    updateStatus();
  });
  connect(doc_, &Document::dirtyChanged, this, [this](bool) { updateTitle(); });
  // The status bar's frame time follows the frames at most four times a second, and once after
  // the last: repainting the window's status bar after every frame cost up to a third of a
  // frame on llvmpipe while the viewport played (relume-workbench --bench).
  statusTimer_ = new QTimer(this);
  statusTimer_->setSingleShot(true);
  statusTimer_->setInterval(250);
  connect(statusTimer_, &QTimer::timeout, this, [this] { updateStatus(); });
  connect(viewport_, &ViewportWidget::frameDrawn, this, [this](double) {
    if (!statusTimer_->isActive()) statusTimer_->start();
  });

  // Autosave on its own runner: it never blocks the panels or the user's jobs. The lock says
  // "this Relume is alive" to another one looking for autosaves to recover.
  QDir().mkpath(QFileInfo(autosaveFolder()).absolutePath());
  autosaveLock_ = std::make_unique<QLockFile>(autosaveFolder() + ".lock");
  autosaveLock_->tryLock(0);  // a second window of the same process shares the first one's lock
  autosaveJobs_ = new JobRunner(this);
  autosaveTimer_ = new QTimer(this);
  connect(autosaveTimer_, &QTimer::timeout, this, [this] { autosaveNow(); });
  autosaveTimer_->start(120000);
  connect(autosaveJobs_, &JobRunner::finished, this, [this](bool ok, bool, const QString& message) {
    if (!ok) statusBar()->showMessage(tr("Autosave failed: %1").arg(message), 8000);
  });
  connect(doc_, &Document::closed, this, [this] { discardAutosave(); });

  buildMenus();
  QSettings settings;
  restoreGeometry(settings.value("window/geometry").toByteArray());
  restoreState(settings.value("window/state").toByteArray());
  if (!settings.contains("window/geometry")) resize(1280, 800);
  updateTitle();
}

// While a job runs, nothing edits the document (its result replaces or saves what it was given).
void MainWindow::setEditing(bool on) {
  for (QWidget* w : {static_cast<QWidget*>(lights_), static_cast<QWidget*>(objects_), static_cast<QWidget*>(references_),
                     static_cast<QWidget*>(photos_), static_cast<QWidget*>(reconstruction_), static_cast<QWidget*>(clicks_)})
    w->setEnabled(on);
  tool_->setEnabled(on);
  if (!on) tool_->setMode(EditTool::Mode::Select);
  undoAction_->setEnabled(on && undoGroup_->canUndo());
  redoAction_->setEnabled(on && undoGroup_->canRedo());
  for (QAction* a : lightingMenu_->actions()) a->setEnabled(on);
}

MainWindow::~MainWindow() {
  jobs_->cancel();
  autosaveJobs_->waitForIdle();
}

void MainWindow::setAutosaveInterval(int ms) { autosaveTimer_->start(ms); }

QString MainWindow::autosaveKey() { return "autosaves/" + QString::number(QCoreApplication::applicationPid()); }

QString MainWindow::autosaveFolder() {
  return QStandardPaths::writableLocation(QStandardPaths::AppLocalDataLocation) + "/autosave/" +
         QString::number(QCoreApplication::applicationPid()) + ".relume";
}

bool MainWindow::autosaveRunning() const { return autosaveJobs_->busy(); }

bool MainWindow::autosaveNow() {
  if (!doc_->isOpen() || !doc_->isDirty() || jobs_->busy() || autosaveJobs_->busy()) return false;
  if (doc_->changeCount() == autosavedChanges_) return false;
  storeView();
  const QString folder = autosaveFolder();
  QDir().mkpath(QFileInfo(folder).absolutePath());
  auto work = doc_->saveWork(folder);
  const quint64 index = doc_->changeCount();
  const QString source = doc_->projectPath().isEmpty() ? doc_->sourcePath() : doc_->projectPath();
  return autosaveJobs_->start(tr("Autosaving"), [this, work, folder, index, source](Progress& progress) {
    work(progress);
    return JobRunner::Continuation([this, folder, index, source] {
      autosavedChanges_ = index;
      QSettings settings;
      settings.setValue(autosaveKey() + "/folder", folder);
      settings.setValue(autosaveKey() + "/source", source);
      settings.setValue(autosaveKey() + "/time", QDateTime::currentDateTime());
      statusBar()->showMessage(tr("Autosaved at %1").arg(QTime::currentTime().toString("HH:mm")), 4000);
    });
  });
}

void MainWindow::discardAutosave() {
  autosaveJobs_->waitForIdle();
  autosavedChanges_ = ~quint64(0);
  QSettings settings;
  const QString own = autosaveFolder();
  settings.remove(autosaveKey());
  // A recovered document reads its photos from its autosave folder: that stays until the
  // document is replaced or Relume exits.
  const bool inUse = doc_->isOpen() && QDir::cleanPath(QString::fromStdString(doc_->scene().baseDir)).startsWith(QDir::cleanPath(own));
  if (!lingering_.isEmpty() && lingering_ != own) QDir(lingering_).removeRecursively();
  lingering_.clear();
  if (inUse) lingering_ = own;
  else QDir(own).removeRecursively();
}

void MainWindow::closeEvent_discard() {
  autosaveJobs_->waitForIdle();
  QSettings settings;
  settings.remove(autosaveKey());
  QDir(autosaveFolder()).removeRecursively();
}

bool MainWindow::recoverAutosave(bool acceptWhenQuiet) {
  // Autosaves of processes that are gone (their lock is free or stale); the newest first. A
  // Relume still running keeps its lock, so its autosave is never taken from it.
  QSettings settings;
  settings.beginGroup("autosaves");
  const QStringList owners = settings.childGroups();
  settings.endGroup();
  QString key;
  QDateTime newest;
  for (const QString& owner : owners) {
    const QString k = "autosaves/" + owner;
    if (k == autosaveKey()) continue;
    const QString f = settings.value(k + "/folder").toString();
    if (f.isEmpty() || !QFileInfo::exists(f + "/project.json")) {
      settings.remove(k);
      continue;
    }
    QLockFile lock(f + ".lock");
    if (!lock.tryLock(0)) continue;  // its Relume is still running
    lock.unlock();
    const QDateTime t = settings.value(k + "/time").toDateTime();
    if (key.isEmpty() || t > newest) {
      key = k;
      newest = t;
    }
  }
  if (key.isEmpty()) return false;
  const QString folder = settings.value(key + "/folder").toString();
  const QString source = settings.value(key + "/source").toString();
  const QDateTime when = newest;
  bool accept = acceptWhenQuiet;
  if (interactive_)
    accept = QMessageBox::question(this, tr("Recover unsaved edits"),
                                   tr("Relume did not close properly. Recover the edits to %1 autosaved at %2?")
                                       .arg(source, QLocale().toString(when, QLocale::ShortFormat)),
                                   QMessageBox::Yes | QMessageBox::No, QMessageBox::Yes) == QMessageBox::Yes;
  if (!accept) {
    settings.remove(key);
    QDir(folder).removeRecursively();
    return false;
  }
  // It becomes this process's autosave (the document will read its photos from there), so that a
  // second crash before a save still finds it; the entry is kept until the recovery succeeded.
  const QString own = autosaveFolder();
  QDir(own).removeRecursively();
  QDir().mkpath(QFileInfo(own).absolutePath());
  if (!QDir().rename(folder, own)) {
    showError(tr("Relume"), tr("Cannot move the autosave %1 to %2").arg(folder, own));
    return false;
  }
  settings.remove(key);
  settings.setValue(autosaveKey() + "/folder", own);
  settings.setValue(autosaveKey() + "/source", source);
  settings.setValue(autosaveKey() + "/time", when);
  return jobs_->start(tr("Recovering %1").arg(QFileInfo(source).fileName()), [this, own, source](Progress& progress) {
    std::shared_ptr<LoadedRoom> room = loadRoomForWorkbench(own, progress);
    return JobRunner::Continuation([this, room, own, source]() mutable {
      doc_->adopt(std::make_unique<LoadedRoom>(std::move(*room)));
      // Unsaved again, pointing back at the user's project (never at the side folder).
      doc_->markRecovered(QFileInfo(source + "/project.json").exists() ? source : QString(), source);
      lingering_ = own;
      QSettings settings;  // still recoverable until it is saved
      settings.setValue(autosaveKey() + "/folder", own);
      settings.setValue(autosaveKey() + "/source", source);
      settings.setValue(autosaveKey() + "/time", QDateTime::currentDateTime());
      statusBar()->showMessage(tr("Recovered the autosaved edits of %1: save them to keep them.").arg(source), 10000);
    });
  });
}

void MainWindow::buildMenus() {
  QMenu* file = menuBar()->addMenu(tr("&File"));
  QAction* open = file->addAction(tr("&Open..."), this, [this] {
    const QString dir = QFileDialog::getExistingDirectory(this, tr("Open a room or a Relume project"));
    if (!dir.isEmpty()) openPath(dir);
  });
  open->setShortcut(QKeySequence::Open);
  file->addAction(tr("Open &OBJ + JSON..."), this, [this] {
    const QString f = QFileDialog::getOpenFileName(this, tr("Open a room"), {}, tr("Room geometry (*.obj)"));
    if (!f.isEmpty()) openPath(f);
  });
  recentMenu_ = file->addMenu(tr("Open &Recent"));
  file->addSeparator();
  // A daylight room (the Sky panel) is saved as a project that keeps its daylight session; one
  // opened from a project is saved back to it.
  auto daylightProject = [this] {
    const QString p = sky_->path();
    if (QFileInfo(p).fileName() == "project.json") return QFileInfo(p).absolutePath();
    return QFileInfo(p + "/project.json").exists() ? p : QString();
  };
  auto saveDaylight = [this](const QString& current) {
    const QString f = !current.isEmpty() ? current
                      : QFileDialog::getSaveFileName(this, tr("Save the daylight room as a project"),
                                                     QFileInfo(sky_->path()).completeBaseName() + ".relume");
    if (!f.isEmpty()) saveTo(f);
  };
  QAction* save = file->addAction(tr("&Save"), this, [this, daylightProject, saveDaylight] {
    if (!doc_->isOpen() && sky_->isOpen()) return saveDaylight(daylightProject());
    if (!doc_->isOpen()) return;
    if (doc_->projectPath().isEmpty()) {
      const QString f = QFileDialog::getSaveFileName(this, tr("Save the project as"), doc_->displayName() + ".relume");
      if (!f.isEmpty()) saveTo(f);
    } else {
      saveTo(doc_->projectPath());
    }
  });
  save->setShortcut(QKeySequence::Save);
  QAction* saveAs = file->addAction(tr("Save &As..."), this, [this, saveDaylight] {
    if (!doc_->isOpen() && sky_->isOpen()) return saveDaylight({});
    if (!doc_->isOpen()) return;
    const QString f = QFileDialog::getSaveFileName(this, tr("Save the project as"), doc_->displayName() + ".relume");
    if (!f.isEmpty()) saveTo(f);
  });
  saveAs->setShortcut(QKeySequence::SaveAs);
  file->addSeparator();
  QAction* quit = file->addAction(tr("&Quit"), this, &QWidget::close);
  quit->setShortcut(QKeySequence::Quit);

  QMenu* edit = menuBar()->addMenu(tr("&Edit"));
  QAction* undo = undoAction_ = undoGroup_->createUndoAction(this, tr("&Undo"));
  undo->setShortcut(QKeySequence::Undo);
  QAction* redo = redoAction_ = undoGroup_->createRedoAction(this, tr("&Redo"));
  redo->setShortcuts({QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_Z), QKeySequence::Redo});
  edit->addAction(undo);
  edit->addAction(redo);

  edit->addSeparator();
  QMenu* language = edit->addMenu(tr("&Language"));
  auto* languages = new QActionGroup(this);
  const QString current = chosenLanguage();
  for (const auto& [code, name] : {std::pair<QString, QString>{"", tr("System language")}, {"en", "English"},
                                   {"fr", "Français"}, {"de", "Deutsch"}}) {
    QAction* a = language->addAction(name);
    a->setCheckable(true);
    a->setChecked(code == current);
    languages->addAction(a);
    const QString c = code;
    connect(a, &QAction::triggered, this, [this, c] {
      chooseLanguage(c);
      statusBar()->showMessage(tr("The language changes when Relume starts again."), 8000);
    });
  }

  QMenu* view = menuBar()->addMenu(tr("&View"));
  modes_ = new QActionGroup(this);
  const QString labels[] = {tr("&Relit (texture × B / D)"), tr("Relit, r&atio only (texture × B / B_orig)"),
                            tr("Original &photo"),           tr("&Unoccluded textures (shadows removed)"),
                            tr("Radiosity &B"),              tr("Display factor &D"),
                            tr("&Leaf outlines"),
                            tr("Occluded and &frontier elements (§4.3)")};
  int k = 0;
  for (const auto& m : kModes) {
    QAction* a = view->addAction(labels[k]);
    a->setCheckable(true);
    a->setData(QString(m.key));
    a->setShortcut(QKeySequence(QString("Ctrl+%1").arg(k + 1)));
    a->setChecked(m.mode == ViewMode::Relit);
    modes_->addAction(a);
    const ViewMode mode = m.mode;
    connect(a, &QAction::triggered, this, [this, mode] {
      viewport_->setViewMode(mode);
      const QSignalBlocker block(references_->showButton());
      references_->showButton()->setChecked(mode == ViewMode::References);
      storeView();
      updateStatus();
    });
    ++k;
  }
  view->addSeparator();
  QAction* falseColour = view->addAction(tr("&False colour luminance"));
  falseColour->setCheckable(true);
  falseColour->setShortcut(QKeySequence(Qt::Key_F));
  connect(falseColour, &QAction::toggled, this, [this](bool on) {
    viewport_->setFalseColour(on);
    storeView();
  });
  QAction* brighter = view->addAction(tr("Exposure +½ EV"), this, [this] {
    viewport_->setExposureEV(viewport_->exposureEV() + 0.5);
    storeView();
    updateStatus();
  });
  brighter->setShortcut(QKeySequence(Qt::Key_Plus));
  QAction* darker = view->addAction(tr("Exposure −½ EV"), this, [this] {
    viewport_->setExposureEV(viewport_->exposureEV() - 0.5);
    storeView();
    updateStatus();
  });
  darker->setShortcut(QKeySequence(Qt::Key_Minus));
  view->addAction(tr("Exposure of the &photo"), this, [this] {
    viewport_->setExposureEV(0);
    storeView();
    updateStatus();
  });
  view->addSeparator();
  QAction* locked = view->addAction(tr("&Through the photo's camera"), this, [this] {
    viewport_->lockToPhoto();
    storeView();
    updateStatus();
  });
  locked->setShortcut(QKeySequence(Qt::Key_Home));
  view->addAction(tr("Free &orbit"), this, [this] {
    viewport_->setOrbit(true);
    storeView();
    updateStatus();
  });
  view->addSeparator();
  interactiveMesh_ = view->addAction(tr("&Interactive mesh (faster edits, coarser shadows)"));
  interactiveMesh_->setCheckable(true);
  connect(interactiveMesh_, &QAction::triggered, this, [this](bool on) { switchMesh(on); });
  view->addSeparator();
  for (QDockWidget* d : findChildren<QDockWidget*>()) view->addAction(d->toggleViewAction());

  QMenu* lighting = lightingMenu_ = menuBar()->addMenu(tr("&Lighting"));
  lighting->addAction(tr("&All lamps as photographed"), this, [this] {
    if (!doc_->isOpen()) return;
    doc_->undoStack()->beginMacro(tr("all lamps as photographed"));
    for (size_t l = 0; l < doc_->scene().lamps.size(); ++l) doc_->editLampScale(int(l), glm::dvec3(1.0));
    doc_->undoStack()->endMacro();
  });
  lighting->addAction(tr("All lamps &off"), this, [this] {
    if (!doc_->isOpen()) return;
    doc_->undoStack()->beginMacro(tr("all lamps off"));
    for (size_t l = 0; l < doc_->scene().lamps.size(); ++l) doc_->editLampScale(int(l), glm::dvec3(0.0));
    doc_->undoStack()->endMacro();
  });

  lighting->addSeparator();
  QAction* addLamp = lighting->addAction(tr("Add a &virtual lamp (click a surface)"), this,
                                         [this] { tool_->setMode(EditTool::Mode::PlaceLamp); });
  addLamp->setShortcut(QKeySequence(Qt::Key_L));
  QAction* addBox = lighting->addAction(tr("Add a &box (click a floor)"), this, [this] { tool_->setMode(EditTool::Mode::PlaceBox); });
  addBox->setShortcut(QKeySequence(Qt::Key_B));
  QAction* del = lighting->addAction(tr("&Delete the selected lamp or object"), this, [this] {
    const std::string n = selected_.toStdString();
    if (doc_->virtualLampIndex(n) >= 0) doc_->removeVirtualLamp(n);
    else if (doc_->objectIndex(n) >= 0) doc_->removeObject(n);
    selected_.clear();
  });
  del->setShortcut(QKeySequence::Delete);
  QAction* esc = new QAction(this);
  esc->setShortcut(QKeySequence(Qt::Key_Escape));
  connect(esc, &QAction::triggered, this, [this] { tool_->setMode(EditTool::Mode::Select); });
  addAction(esc);
  QMenu* help = menuBar()->addMenu(tr("&Help"));
  help->addAction(tr("&About Relume"), this, [this] {
    QMessageBox::about(this, tr("About Relume"),
                       tr("<b>Relume</b> relights photographed rooms: switch real lamps off, dim or tint them, "
                          "add virtual lamps and objects, and see the photograph respond.<br><br>"
                          "Method: Loscos, Drettakis, Robert 2000, <i>Interactive virtual relighting of real "
                          "scenes</i> — hierarchical radiosity with clustering, real shadows removed from the "
                          "photo textures, display of texture × B / D."));
  });
  updateRecent();
}

bool MainWindow::openPath(const QString& path) {
  if (jobs_->busy()) {
    showError(tr("Relume"), tr("Another job is running; wait for it or cancel it first."));
    return false;
  }
  if (!maybeSave()) return false;
  const QString abs = QFileInfo(path).absoluteFilePath();
  return jobs_->start(tr("Opening %1").arg(QFileInfo(abs).fileName()), [this, abs](Progress& progress) {
    // A daylight room (its scene lists measured skies) goes to the Sky panel: reflectances from
    // its photo under its own sky, the basis solutions; the lamp room's document is closed.
    if (const Scene scene = loadRoom(abs.toStdString()); !scene.skies.empty()) {
      std::shared_ptr<PreparedDaylight> daylight = SkyPanel::prepare(scene, progress);
      return JobRunner::Continuation([this, daylight, abs] {
        doc_->close();
        sky_->adopt(daylight, abs);
        // The lamp room's viewport and panels have nothing to show: the Sky panel takes their place
        // (they come back with the next lamp room).
        viewport_->hide();
        for (const char* name : {"LightsDock", "ObjectsDock", "ReferencesDock"})
          if (auto* d = findChild<QDockWidget*>(name); d && d->isVisible()) {
            d->hide();
            hiddenForDaylight_.push_back(d);
          }
        skyDock_->show();
        skyDock_->raise();
        addRecent(abs);
        statusBar()->showMessage(tr("Opened %1 (daylight: see the Sky panel)").arg(abs), 5000);
      });
    }
    std::shared_ptr<LoadedRoom> room = loadRoomForWorkbench(abs, progress);
    return JobRunner::Continuation([this, room, abs]() mutable {
      sky_->close();
      skyDock_->hide();
      viewport_->show();
      for (QDockWidget* d : hiddenForDaylight_) d->show();
      hiddenForDaylight_.clear();
      const std::vector<std::string> notes = room->scene.notes;
      doc_->adopt(std::make_unique<LoadedRoom>(std::move(*room)));
      addRecent(abs);
      statusBar()->showMessage(tr("Opened %1").arg(abs), 5000);
      if (!notes.empty()) {
        QStringList lines;
        for (const auto& n : notes) lines << QString::fromStdString(n);
        auto* box = new QMessageBox(QMessageBox::Information, tr("Relume"), lines.join("\n\n"), QMessageBox::Ok, this);
        box->setAttribute(Qt::WA_DeleteOnClose);
        box->open();  // not modal to the event loop: the room is open behind it
      }
    });
  });
}

bool MainWindow::switchMesh(bool interactive) {
  const SessionMesh mesh = interactive ? SessionMesh::Interactive : SessionMesh::Refined;
  if (!doc_->isOpen() || jobs_->busy() || doc_->mesh() == mesh) {
    const QSignalBlocker block(interactiveMesh_);
    interactiveMesh_->setChecked(doc_->isOpen() && doc_->mesh() == SessionMesh::Interactive);
    return false;
  }
  auto work = doc_->switchMeshWork(mesh);
  return jobs_->start(interactive ? tr("Building the interactive mesh") : tr("Building the refined mesh"),
                      [work](Progress& progress) { return work(progress); });
}

bool MainWindow::saveTo(const QString& folder) {
  if (!doc_->isOpen() && sky_->isOpen()) {  // a daylight room: the project keeps its session
    // (listed under Open Recent once written: SkyPanel::opened)
    if (sky_->saveProject(QFileInfo(folder).absoluteFilePath())) return true;
    statusBar()->showMessage(tr("A job is running: wait for it or cancel it, then save."), 5000);
    return false;
  }
  if (!doc_->isOpen() || jobs_->busy()) return false;
  storeView();
  auto work = doc_->saveWork(folder);
  const QString abs = QFileInfo(folder).absoluteFilePath();
  return jobs_->start(tr("Saving %1").arg(QFileInfo(abs).fileName()), [this, work, abs](Progress& progress) {
    work(progress);
    return JobRunner::Continuation([this, abs] {
      doc_->markSaved(abs);
      discardAutosave();
      addRecent(abs);
      statusBar()->showMessage(tr("Saved %1").arg(abs), 5000);
    });
  });
}

bool MainWindow::maybeSave() {
  if (!doc_->isOpen() || !doc_->isDirty() || !interactive_) return true;
  const auto answer = QMessageBox::question(
      this, tr("Unsaved edits"), tr("%1 has unsaved edits. Save them first?").arg(doc_->displayName()),
      QMessageBox::Save | QMessageBox::Discard | QMessageBox::Cancel, QMessageBox::Save);
  if (answer == QMessageBox::Cancel) return false;
  if (answer == QMessageBox::Discard) return true;
  QString folder = doc_->projectPath();
  if (folder.isEmpty()) folder = QFileDialog::getSaveFileName(this, tr("Save the project as"), doc_->displayName() + ".relume");
  if (folder.isEmpty() || !saveTo(folder)) return false;
  jobs_->waitForIdle();
  return !doc_->isDirty();
}

void MainWindow::closeEvent(QCloseEvent* e) {
  if (jobs_->busy() || !maybeSave()) {
    if (jobs_->busy()) statusBar()->showMessage(tr("A job is running: cancel it before quitting."), 5000);
    e->ignore();
    return;
  }
  QSettings settings;
  settings.setValue("window/geometry", saveGeometry());
  // The layout as a lamp room has it: the docks a daylight room hid come back first (the next
  // start opens no daylight room to bring them back).
  if (!hiddenForDaylight_.empty() || skyDock_->isVisible()) {
    skyDock_->hide();
    viewport_->show();
    for (QDockWidget* d : hiddenForDaylight_) d->show();
    hiddenForDaylight_.clear();
  }
  settings.setValue("window/state", saveState());
  closeEvent_discard();  // a clean exit leaves nothing to recover
  e->accept();
}

void MainWindow::showError(const QString& title, const QString& message) {
  lastError_ = message;
  statusBar()->showMessage(message, 15000);
  if (interactive_) QMessageBox::warning(this, title, message);
}

void MainWindow::updateTitle() {
  setWindowTitle(doc_->isOpen() ? tr("%1[*] — Relume").arg(doc_->displayName()) : tr("Relume"));
  setWindowModified(doc_->isDirty());
}

void MainWindow::updateStatus() {
  if (!doc_->isOpen()) {
    statusView_->setText(tr("No room open"));
    return;
  }
  QString mode;
  for (QAction* a : modes_->actions())
    if (a->isChecked()) mode = a->text().remove('&');
  const auto totals = doc_->session()->engine().totals();
  statusView_->setText(tr("%1 · %2 · %3, %4 leaves · %5 links · frame %6 ms · EV %7%8")
                           .arg(mode)
                           .arg(viewport_->orbiting() ? tr("free orbit") : tr("photo camera"))
                           .arg(doc_->mesh() == SessionMesh::Interactive ? tr("interactive mesh") : tr("refined mesh"))
                           .arg(totals.leaves)
                           .arg(totals.links)
                           .arg(viewport_->lastFrameMilliseconds(), 0, 'f', 1)
                           .arg(viewport_->exposureEV() >= 0 ? "+" : "")
                           .arg(viewport_->exposureEV(), 0, 'f', 1));
}

void MainWindow::updateOverlays() {
  std::vector<ViewportOverlay> overlays;
  if (doc_->isOpen() && doc_->session()) {
    const auto& engine = doc_->session()->engine();
    auto add = [&](const ReferenceRegion& r, unsigned rgb, bool marker) {
      const int s = doc_->scene().findPolygon(r.polygon);
      if (s < 0) return;
      ViewportOverlay o;
      o.rgb = rgb;
      for (const auto& d : r.discs) {
        std::vector<glm::dvec3> loop;
        for (int k = 0; k < 32; ++k) {
          const double a = 2 * std::numbers::pi * k / 32;
          loop.push_back(engine.toWorld(s, glm::dvec2(d) + d.z * glm::dvec2(std::cos(a), std::sin(a))));
        }
        o.areas.push_back(std::move(loop));
      }
      if (marker) o.markers.push_back(engine.toWorld(s, r.reference));
      overlays.push_back(std::move(o));
    };
    if (referencesDock_ && referencesDock_->isVisible() && !referencesDock_->visibleRegion().isEmpty())
      for (const auto& r : doc_->referenceRegions()) add(r, 0xe040fb, true);
    if (!tool_->stroke().discs.empty()) add(tool_->stroke(), 0xff8c1a, false);
    // The element picked in the inspector (of the viewport's own session).
    if (inspectorDock_ && inspectorDock_->isVisible() && inspector_->session() == doc_->session()) {
      auto outline = inspector_->pickedOutline();
      if (!outline.empty()) {
        ViewportOverlay o;
        o.rgb = 0x00e5ff;
        o.areas.push_back(std::move(outline));
        overlays.push_back(std::move(o));
      }
    }
  }
  viewport_->setOverlays(std::move(overlays));
}

void MainWindow::storeView() {
  if (!doc_->isOpen()) return;
  QString mode = "relit";
  for (const auto& m : kModes)
    if (m.mode == viewport_->viewMode()) mode = m.key;
  const auto o = viewport_->orbitState();
  doc_->setViewState(QJsonObject{{"mode", mode},
                                 {"ev", viewport_->exposureEV()},
                                 {"false_colour", viewport_->falseColour()},
                                 {"orbit", viewport_->orbiting()},
                                 {"yaw", o.yaw},
                                 {"pitch", o.pitch},
                                 {"distance", o.distance},
                                 {"target", QJsonArray{o.target[0], o.target[1], o.target[2]}}});
}

void MainWindow::restoreView() {
  const QJsonObject v = doc_->viewState();
  ViewMode mode = ViewMode::Relit;
  for (const auto& m : kModes)
    if (v["mode"].toString() == m.key) mode = m.mode;
  viewport_->setViewMode(mode);
  for (QAction* a : modes_->actions()) a->setChecked(a->data().toString() == (v["mode"].toString().isEmpty() ? "relit" : v["mode"].toString()));
  viewport_->setExposureEV(v["ev"].toDouble(0));
  viewport_->setFalseColour(v["false_colour"].toBool(false));
  if (v.contains("distance") && v["distance"].toDouble() > 0) {
    ViewportWidget::Orbit o;
    o.yaw = v["yaw"].toDouble();
    o.pitch = v["pitch"].toDouble();
    o.distance = v["distance"].toDouble();
    const QJsonArray t = v["target"].toArray();
    for (int k = 0; k < 3 && k < t.size(); ++k) o.target[k] = t[k].toDouble();
    viewport_->setOrbitState(o);
  }
  if (v["orbit"].toBool(false)) viewport_->setOrbit(true);
  else viewport_->lockToPhoto();
}

void MainWindow::addRecent(const QString& path) {
  QSettings settings;
  QStringList recent = settings.value("recent").toStringList();
  recent.removeAll(path);
  recent.prepend(path);
  while (recent.size() > kRecentMax) recent.removeLast();
  settings.setValue("recent", recent);
  updateRecent();
}

void MainWindow::updateRecent() {
  recentMenu_->clear();
  const QStringList recent = QSettings().value("recent").toStringList();
  for (int i = 0; i < recent.size(); ++i) {
    const QString p = recent[i];
    QAction* a = recentMenu_->addAction(QString("&%1 %2").arg((i + 1) % 10).arg(p), this, [this, p] { openPath(p); });
    a->setData(p);
  }
  recentMenu_->setEnabled(!recent.isEmpty());
}

}  // namespace relume
