#pragma once
// The workbench's document: a preprocessed room (scene + relighting data), the live relighting
// session on it, and every edit the user made (lamp scales, the view), with an undo stack.
// Light is computed only by the library: the document calls the session as `relume` does.
#include <QJsonObject>
#include <QObject>
#include <QString>
#include <QUndoStack>
#include <glm/vec3.hpp>
#include <functional>
#include <map>
#include <optional>
#include <memory>
#include <vector>

#include "relume/geometry/scene.h"
#include "relume/ibr/relit_objects.h"
#include "relume/relight/relighter.h"

namespace relume {

class Progress;

// What a load job hands to the UI thread.
struct LoadedRoom {
  Scene scene;
  RelightData data;
  std::unique_ptr<RelightSession> session;
  std::shared_ptr<Preprocessor> preprocessor;  // when the room was preprocessed now (for Recompute)
  QString projectPath;   // the project folder, or empty when the room came from a bundle / OBJ
  QString sourcePath;    // what the user opened
  QJsonObject state;     // the workbench's saved edits (workbench.json), empty if none
  std::vector<ReferenceRegion> regions;  // painted reference regions (the state's, else the data's)
  SessionMesh mesh = SessionMesh::Refined;  // the mesh the session was built on (the state's choice)
  std::vector<ibr::ImageObject> imageObjects;  // the state's image-based objects, their fans read
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

  // --- virtual lamps and objects, named (names stay stable across undo / redo) ---
  // An emissive square `size` wide centred at `centre`, facing along `normal`.
  static VirtualLamp lampQuad(const std::string& name, const glm::dvec3& centre, const glm::dvec3& normal,
                              double size, const glm::dvec3& radiance);
  // A radiance that gives a `size`-wide square the power of the brightest real lamp as estimated.
  glm::dvec3 defaultLampRadiance(double size) const;
  std::string newName(const QString& stem) const;  // "Lamp 1", "Box 2", ... not used yet
  int virtualLampIndex(const std::string& name) const;
  int objectIndex(const std::string& name) const;
  size_t virtualLampCount() const { return session_ ? session_->virtualLampCount() : 0; }
  size_t objectCount() const { return session_ ? session_->objectCount() : 0; }
  double objectTurn(const std::string& name) const;  // degrees, as the user turned it
  // How far a virtual lamp hangs in front of the surface it was put on (metres), and the change.
  double lampDrop(const std::string& name) const;
  bool trySetLampDrop(const std::string& name, double metres, QString* error = nullptr);
  // After a drag: the lamp goes in afresh where it now is (links refined there), not undoable (it
  // changes nothing the user sees but shadow sharpness).
  void settleVirtualLamp(const std::string& name);
  // An object drag: its steps are previews (fewer visibility rays); at the end it settles (full
  // rays on its links). Not undo steps: they change how exact the shadows are, not the scene.
  void beginObjectDrag();
  void settleObject(const std::string& name);
  // Undoable edits. The "try" ones apply at once and return false (with the library's message in
  // `error`) when the library refuses, leaving everything as it was.
  bool tryAddVirtualLamp(const VirtualLamp& lamp, QString* error = nullptr);
  void removeVirtualLamp(const std::string& name);
  bool tryMoveVirtualLamp(const std::string& name, const glm::dvec3& offset, int gesture, QString* error = nullptr);
  // Radiance and size (the square is rebuilt about its centre when the size changes).
  void editVirtualLamp(const std::string& name, const glm::dvec3& radiance, double size, int gesture = 0);
  bool tryAddObject(const VirtualObject& object, QString* error = nullptr);
  void removeObject(const std::string& name);
  bool tryMoveObject(const std::string& name, const glm::dvec3& offset, double turnDegrees, int gesture,
                     QString* error = nullptr);
  // Direct application (what the commands call).
  void applyAddVirtualLamp(const VirtualLamp& lamp);
  void applyRemoveVirtualLamp(const std::string& name);
  void applyMoveVirtualLamp(const std::string& name, const glm::dvec3& offset);
  void applyVirtualLamp(const std::string& name, const VirtualLamp& lamp);
  void applyAddObject(const VirtualObject& object, double turnDegrees);
  void applyRemoveObject(const std::string& name);
  void applyMoveObject(const std::string& name, const glm::dvec3& offset, double turnDegrees);
  void applyUnmoveObject(const std::string& name, const glm::dvec3& offset, double turnDegrees);

  // --- image-based objects (Dinh, Metoyer, Turk): drawn from their fans, lit by the session's
  // light, not part of its radiosity solution; named like the other virtual things ---
  const std::vector<ibr::ImageObject>& imageObjects() const { return imageObjects_; }
  int imageObjectIndex(const std::string& name) const;
  // Undoable. Placing checks the object against the room (ibr::checkImageObject): false with the
  // library's message in `error` when it would leave the room or cut a wall, nothing changed.
  // Consecutive placements of one object with the same nonzero `gesture` merge into one step.
  bool tryAddImageObject(const ibr::ImageObject& object, QString* error = nullptr);
  bool tryPlaceImageObject(const std::string& name, const ibr::Placement& place, int gesture = 0, QString* error = nullptr);
  void removeImageObject(const std::string& name);
  void applyImageObject(const std::string& name, const std::optional<ibr::ImageObject>& object);
  // The light at each image-based object now (the engine's radiosity made current first).
  std::vector<ibr::ObjectLighting> imageObjectLighting();

  // --- reference patches (Loscos 2000 §4.3): the user's choice per polygon, plane uv ---
  const std::map<std::string, glm::dvec2>& referenceOverrides() const { return overrides_; }
  // Undoable; `uv` empty clears the override (back to the automatic choice). Takes effect on
  // the image after recomputeReferencesWork() has run.
  void setReferenceOverride(const std::string& polygon, const std::optional<glm::dvec2>& uv);
  void applyReferenceOverride(const std::string& polygon, const std::optional<glm::dvec2>& uv);
  // Painted regions (§4.3): their occluded elements take the reflectance of one chosen element.
  // Undoable; take effect after recomputeReferencesWork() like the overrides.
  const std::vector<ReferenceRegion>& referenceRegions() const { return regions_; }
  void addReferenceRegion(const ReferenceRegion& region);
  void clearReferenceRegions(const std::string& polygon);
  void applyReferenceRegions(const std::vector<ReferenceRegion>& regions);
  bool referencesPending() const { return overrides_ != data_.referenceOverride || regions_ != data_.referenceRegions; }
  // Work for a job: §4.3's step 2 again for the polygons whose reference choices changed, on the
  // preprocess state kept since the room was preprocessed (the whole preprocess first when there
  // is none, as after opening a saved project). Its continuation gives the live session the new
  // reflectance maps (lamps, virtual lamps and objects stay) and the document the new data.
  std::function<std::function<void()>(Progress&)> recomputeReferencesWork();
  // Work for a job: the session on another mesh (§4.4's coarser interactive mesh: faster edits
  // and drags, coarser shadows; or the refined one), with everything the user did.
  std::function<std::function<void()>(Progress&)> switchMeshWork(SessionMesh mesh);
  SessionMesh mesh() const { return mesh_; }
  // Work for a job: a second session on the other mesh with the same lamps, virtual lamps and
  // objects, for the inspector (the document keeps its own).
  std::function<std::unique_ptr<RelightSession>(Progress&)> otherMeshSessionWork() const;
  // The engine's own radiosity made current (the inspector reads it).
  void syncEngine();

  // The view, kept in the project.
  QJsonObject viewState() const { return view_; }
  void setViewState(const QJsonObject& v) { view_ = v; }

  // What a save writes beside the project: the edits as JSON (workbench.json).
  QJsonObject editsJson() const;
  // Saves off the caller's thread: a function that writes the project at `folder` from copies
  // taken now (runs on a worker thread), and what to run on the UI thread once it succeeded.
  std::function<void(Progress&)> saveWork(const QString& folder) const;
  void markSaved(const QString& folder);
  // After opening an autosave: the document belongs to `project` (empty: never saved) and came
  // from `source`; it has unsaved edits.
  void markRecovered(const QString& project, const QString& source);

  double lastUpdateMilliseconds() const { return lastUpdateMs_; }
  size_t lastLinksUpdated() const { return lastLinks_; }  // by the last object or lamp move
  // Counts every change to what the document holds (for autosave: "anything new since?").
  quint64 changeCount() const { return changes_; }

 signals:
  void opened();
  void closed();
  void lightingChanged();
  void meshChanged();
  void virtualsChanged();  // virtual lamps or objects added, removed, edited
  void imageObjectsChanged();  // image-based objects added, removed, placed
  void referencesChanged();  // an override set or cleared, or recomputed
  void relightingReplaced();  // new relighting data and session (textures changed)
  void dirtyChanged(bool dirty);
  void editFailed(const QString& message);  // an undo / redo the library refused (the step is dropped)

 private:
  Scene scene_;
  RelightData data_;
  std::unique_ptr<RelightSession> session_;
  std::shared_ptr<Preprocessor> preprocessor_;  // the preprocess state for redoing step 2, if kept
  QString projectPath_, sourcePath_;
  std::vector<glm::dvec3> lampScale_;
  QJsonObject view_;
  std::map<std::string, double> objectTurn_;
  std::vector<ibr::ImageObject> imageObjects_;
  // The light at each image-based object, kept until the room's light or mesh changes (a drag
  // computes only the moved object's): per object centre, the lighting and the epoch it was for.
  struct ObjectLight {
    glm::dvec3 centre{0.0};
    quint64 epoch = 0;
    std::shared_ptr<const ibr::ObjectLighting> light;
  };
  std::map<std::string, ObjectLight> objectLights_;
  quint64 lightEpoch_ = 1;
  std::map<std::string, glm::dvec2> overrides_;
  std::vector<ReferenceRegion> regions_;
  SessionMesh mesh_ = SessionMesh::Refined;
  std::function<std::function<void()>(const RelightData&, Progress&)> rebuildWork(SessionMesh mesh);
  std::function<std::unique_ptr<RelightSession>(const RelightData&, Progress&)> sessionWork(SessionMesh mesh) const;
  struct Mount {
    glm::dvec3 point{0.0}, normal{0.0};
  };
  std::map<std::string, Mount> lampMount_;  // the plane of the surface each lamp was put on
  Mount mountOf(const VirtualLamp& lamp) const;
  QUndoStack undo_;
  bool unsavedNew_ = false;
  double lastUpdateMs_ = 0;
  size_t lastLinks_ = 0;
  quint64 changes_ = 0;
  std::map<std::string, glm::dvec3> objectPivot_;  // what each object turns about (follows its moves)
 public:
  glm::dvec3 objectPivot(const std::string& name) const;
 private:
  void timed(const std::function<void()>& f);
};

inline constexpr int kWorkbenchStateVersion = 3;  // 2: virtual lamps and objects; 3: image-based objects

}  // namespace relume
