#include "document.h"

#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QJsonArray>
#include <QJsonDocument>
#include <QSaveFile>
#include <QUndoCommand>
#include <chrono>

#include "relume/geometry/error.h"
#include "relume/geometry/progress.h"
#include "relume/project/relight_store.h"
#include "relume/project/room_io.h"

namespace relume {

namespace {

QJsonArray rgb(const glm::dvec3& v) { return QJsonArray{v.x, v.y, v.z}; }

// The project folder `path` names, or empty when it names something else.
QString projectFolderOf(const QString& path) {
  const QFileInfo fi(path);
  if (fi.isDir() && QFileInfo::exists(fi.absoluteFilePath() + "/project.json")) return fi.absoluteFilePath();
  if (fi.fileName() == "project.json") return fi.absolutePath();
  return {};
}

QJsonObject readState(const QString& folder) {
  if (folder.isEmpty()) return {};
  const QString file = folder + "/workbench.json";
  QFile f(file);
  if (!f.exists()) return {};
  if (!f.open(QIODevice::ReadOnly)) throw Error(file.toStdString(), "", "cannot be read: " + f.errorString().toStdString());
  QJsonParseError err;
  const QJsonDocument doc = QJsonDocument::fromJson(f.readAll(), &err);
  if (err.error != QJsonParseError::NoError || !doc.isObject())
    throw Error(file.toStdString(), "offset " + std::to_string(err.offset),
                "is not valid JSON: " + err.errorString().toStdString());
  const QJsonObject o = doc.object();
  if (o["format"].toString() != "relume-workbench")
    throw Error(file.toStdString(), "format", "is not a Relume workbench state");
  if (o["version"].toInt() > kWorkbenchStateVersion)
    throw Error(file.toStdString(), "version",
                "was written by a newer Relume (version " + std::to_string(o["version"].toInt()) + ", this one reads " +
                    std::to_string(kWorkbenchStateVersion) + ")");
  return o;
}

glm::dvec3 readRgb(const QJsonValue& v, const std::string& file, const std::string& what) {
  const QJsonArray a = v.toArray();
  if (a.size() != 3) throw Error(file, what, "expected [r, g, b]");
  glm::dvec3 out;
  for (int c = 0; c < 3; ++c) {
    if (!a[c].isDouble() || a[c].toDouble() < 0) throw Error(file, what, "expected three numbers >= 0");
    out[c] = a[c].toDouble();
  }
  return out;
}

class LampCommand : public QUndoCommand {
 public:
  LampCommand(Document* doc, int lamp, glm::dvec3 before, glm::dvec3 after, int gesture)
      : doc_(doc), lamp_(lamp), before_(before), after_(after), gesture_(gesture) {
    setText(Document::tr("lamp %1").arg(QString::fromStdString(doc->scene().lamps[size_t(lamp)].name)));
  }
  int id() const override { return 1; }
  bool mergeWith(const QUndoCommand* other) override {
    const auto* o = static_cast<const LampCommand*>(other);
    if (gesture_ == 0 || o->gesture_ != gesture_ || o->lamp_ != lamp_) return false;
    after_ = o->after_;
    return true;
  }
  void redo() override { doc_->applyLampScale(lamp_, after_); }
  void undo() override { doc_->applyLampScale(lamp_, before_); }

 private:
  Document* doc_;
  int lamp_;
  glm::dvec3 before_, after_;
  int gesture_;
};

}  // namespace

std::unique_ptr<LoadedRoom> loadRoomForWorkbench(const QString& path, Progress& progress) {
  auto room = std::make_unique<LoadedRoom>();
  room->sourcePath = path;
  room->projectPath = projectFolderOf(path);
  progress.report(0.0, "reading " + path.toStdString());
  room->scene = loadRoom(path.toStdString());
  const bool preprocessed = !room->projectPath.isEmpty() && hasRelightData(room->projectPath.toStdString());
  if (preprocessed) {
    room->data = readRelightData(room->scene);
    room->state = readState(room->projectPath);
  } else {
    ProgressScope scope(progress, 0.0, 0.8);
    room->data = preprocessRoom(room->scene, RelightOptions{}, scope);
  }
  {
    ProgressScope scope(progress, preprocessed ? 0.0 : 0.8, 1.0);
    room->session = std::make_unique<RelightSession>(room->scene, room->data, std::vector<VirtualLamp>{},
                                                     std::vector<VirtualObject>{}, scope, SessionMesh::Refined);
  }
  // Saved lamp scales (by lamp name) go on the session before the UI sees it.
  const std::string stateFile = (room->projectPath + "/workbench.json").toStdString();
  const QJsonObject lamps = room->state["lamps"].toObject();
  for (auto it = lamps.begin(); it != lamps.end(); ++it) {
    const int l = room->scene.findLamp(it.key().toStdString());
    if (l < 0) throw Error(stateFile, "lamps", "names a lamp the room does not have: " + it.key().toStdString());
    room->session->setLampScale(l, readRgb(it.value(), stateFile, "lamps." + it.key().toStdString()));
  }
  if (!lamps.isEmpty()) room->session->update(progress);
  progress.report(1.0, "ready");
  return room;
}

Document::Document(QObject* parent) : QObject(parent) {
  connect(&undo_, &QUndoStack::cleanChanged, this, [this](bool) { emit dirtyChanged(isDirty()); });
}

Document::~Document() = default;

void Document::adopt(std::unique_ptr<LoadedRoom> room) {
  undo_.clear();
  scene_ = std::move(room->scene);
  data_ = std::move(room->data);
  session_ = std::move(room->session);
  projectPath_ = room->projectPath;
  sourcePath_ = room->sourcePath;
  view_ = room->state["view"].toObject();
  lampScale_.clear();
  for (size_t l = 0; l < scene_.lamps.size(); ++l) lampScale_.push_back(session_->lampScale(int(l)));
  unsavedNew_ = projectPath_.isEmpty();
  undo_.setClean();
  emit opened();
  emit dirtyChanged(isDirty());
}

void Document::close() {
  undo_.clear();
  session_.reset();
  scene_ = Scene{};
  data_ = RelightData{};
  projectPath_.clear();
  sourcePath_.clear();
  lampScale_.clear();
  view_ = {};
  unsavedNew_ = false;
  emit closed();
  emit dirtyChanged(false);
}

QString Document::displayName() const {
  if (!isOpen()) return {};
  const QString p = projectPath_.isEmpty() ? sourcePath_ : projectPath_;
  return QFileInfo(p).fileName().isEmpty() ? p : QFileInfo(p).fileName();
}

void Document::applyLampScale(int lamp, const glm::dvec3& scale) {
  if (!session_) return;
  const auto t0 = std::chrono::steady_clock::now();
  session_->setLampScale(lamp, scale);
  session_->update();
  lampScale_.at(size_t(lamp)) = scale;
  lastUpdateMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  emit lightingChanged();
}

void Document::editLampScale(int lamp, const glm::dvec3& scale, int gesture) {
  if (!session_ || lampScale_.at(size_t(lamp)) == scale) return;
  undo_.push(new LampCommand(this, lamp, lampScale_[size_t(lamp)], scale, gesture));
}

QJsonObject Document::editsJson() const {
  QJsonObject lamps;
  for (size_t l = 0; l < scene_.lamps.size(); ++l) lamps[QString::fromStdString(scene_.lamps[l].name)] = rgb(lampScale_[l]);
  return QJsonObject{{"format", "relume-workbench"}, {"version", kWorkbenchStateVersion}, {"lamps", lamps}, {"view", view_}};
}

std::function<void(Progress&)> Document::saveWork(const QString& folder) const {
  auto scene = std::make_shared<Scene>(scene_);
  auto data = std::make_shared<RelightData>(data_);
  const QByteArray edits = QJsonDocument(editsJson()).toJson();
  return [scene, data, edits, folder](Progress& progress) {
    saveRelightProject(*scene, *data, folder.toStdString(), progress, [&](const std::string& staging) {
      QSaveFile f(QString::fromStdString(staging) + "/workbench.json");
      if (!f.open(QIODevice::WriteOnly) || f.write(edits) < 0 || !f.commit())
        throw Error(folder.toStdString(), "workbench.json", "cannot write: " + f.errorString().toStdString());
    });
  };
}

void Document::markSaved(const QString& folder) {
  projectPath_ = QFileInfo(folder).absoluteFilePath();
  unsavedNew_ = false;
  undo_.setClean();
  emit dirtyChanged(false);
}

}  // namespace relume
