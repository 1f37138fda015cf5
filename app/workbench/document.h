#pragma once
// The workbench's document: a preprocessed room (scene + relighting data), the live relighting
// session on it, and every edit the user made (lamp scales, the view), with an undo stack.
// Light is computed only by the library: the document calls the session as `relume` does.
#include <QJsonObject>
#include <QObject>
#include <QString>
#include <QUndoStack>
#include <glm/vec3.hpp>
#include <memory>
#include <vector>

#include "relume/geometry/scene.h"
#include "relume/relight/relighter.h"

namespace relume {

class Progress;

// What a load job hands to the UI thread.
struct LoadedRoom {
  Scene scene;
  RelightData data;
  std::unique_ptr<RelightSession> session;
  QString projectPath;   // the project folder, or empty when the room came from a bundle / OBJ
  QString sourcePath;    // what the user opened
  QJsonObject state;     // the workbench's saved edits (workbench.json), empty if none
};

// Reads a room or project; preprocesses it when it holds no relighting data; builds the session
// and applies the saved edits. Runs on a worker thread; throws relume::Error / Cancelled.
std::unique_ptr<LoadedRoom> loadRoomForWorkbench(const QString& path, Progress& progress);

class Document : public QObject {
  Q_OBJECT
 public:
  explicit Document(QObject* parent = nullptr);
  ~Document() override;

  bool isOpen() const { return session_ != nullptr; }
  void adopt(std::unique_ptr<LoadedRoom> room);  // replaces the document (UI thread)
  void close();

  const Scene& scene() const { return scene_; }
  const RelightData& data() const { return data_; }
  const RelightSession* session() const { return session_.get(); }
  QString projectPath() const { return projectPath_; }
  QString sourcePath() const { return sourcePath_; }
  QString displayName() const;
  QUndoStack* undoStack() { return &undo_; }
  bool isDirty() const { return !undo_.isClean() || unsavedNew_; }

  // Edits (applied now; wrap them in undo commands through the functions below).
  glm::dvec3 lampScale(int lamp) const { return lampScale_.at(size_t(lamp)); }
  void applyLampScale(int lamp, const glm::dvec3& scale);
  // One undoable lamp edit; consecutive edits with the same nonzero `gesture` merge into one.
  void editLampScale(int lamp, const glm::dvec3& scale, int gesture = 0);

  // The view, kept in the project.
  QJsonObject viewState() const { return view_; }
  void setViewState(const QJsonObject& v) { view_ = v; }

  // What a save writes beside the project: the edits as JSON (workbench.json).
  QJsonObject editsJson() const;
  // Saves off the caller's thread: a function that writes the project at `folder` from copies
  // taken now (runs on a worker thread), and what to run on the UI thread once it succeeded.
  std::function<void(Progress&)> saveWork(const QString& folder) const;
  void markSaved(const QString& folder);

  double lastUpdateMilliseconds() const { return lastUpdateMs_; }

 signals:
  void opened();
  void closed();
  void lightingChanged();
  void meshChanged();
  void dirtyChanged(bool dirty);

 private:
  Scene scene_;
  RelightData data_;
  std::unique_ptr<RelightSession> session_;
  QString projectPath_, sourcePath_;
  std::vector<glm::dvec3> lampScale_;
  QJsonObject view_;
  QUndoStack undo_;
  bool unsavedNew_ = false;
  double lastUpdateMs_ = 0;
};

inline constexpr int kWorkbenchStateVersion = 1;

}  // namespace relume
