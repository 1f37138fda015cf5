#include "document.h"

#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QJsonArray>
#include <QJsonDocument>
#include <QSaveFile>
#include <QUndoCommand>
#include <chrono>
#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>

#include "relume/geometry/error.h"
#include "relume/geometry/polygon.h"
#include "relume/geometry/progress.h"
#include "relume/project/relight_store.h"
#include "relume/project/room_io.h"
#include "relume/project/save_hooks.h"
#include "relume/radiosity/hierarchy.h"

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
  const QString file = QString::fromStdString(fileInFolder(folder.toStdString(), "workbench.json", folder.toStdString(), ""));
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

// Virtual lamps and objects: commands by name. Edits that the library may refuse are applied
// before the command is pushed; such a command skips its first redo().
class VirtualCommand : public QUndoCommand {
 public:
  VirtualCommand(Document* doc, std::string name, int gesture, bool applied)
      : doc_(doc), name_(std::move(name)), gesture_(gesture), skip_(applied) {}
  void redo() final {
    if (skip_) {
      skip_ = false;
      return;
    }
    guarded([this] { doRedo(); });
  }
  void undo() final { guarded([this] { doUndo(); }); }

 protected:
  virtual void doRedo() = 0;
  virtual void doUndo() = 0;
  // The library may refuse (an object that would now cut the room): the step is dropped and the
  // user told, never an exception through the event loop.
  template <class F>
  void guarded(F&& f) {
    try {
      f();
    } catch (const std::exception& e) {
      setObsolete(true);
      emit doc_->editFailed(QString::fromStdString(e.what()));
    }
  }
  bool sameGesture(const VirtualCommand* o) const { return gesture_ != 0 && o->gesture_ == gesture_ && o->name_ == name_; }
  Document* doc_;
  std::string name_;
  int gesture_;
  bool skip_;
};

class AddLampCommand : public VirtualCommand {
 public:
  AddLampCommand(Document* doc, VirtualLamp lamp, bool adding)
      : VirtualCommand(doc, lamp.name, 0, adding), lamp_(std::move(lamp)), adding_(adding) {
    setText((adding ? Document::tr("add %1") : Document::tr("remove %1")).arg(QString::fromStdString(name_)));
  }

 protected:
  void doRedo() override { adding_ ? doc_->applyAddVirtualLamp(lamp_) : doc_->applyRemoveVirtualLamp(name_); }
  void doUndo() override { adding_ ? doc_->applyRemoveVirtualLamp(name_) : doc_->applyAddVirtualLamp(lamp_); }

 private:
  VirtualLamp lamp_;
  bool adding_;
};

class MoveLampCommand : public VirtualCommand {
 public:
  MoveLampCommand(Document* doc, const std::string& name, glm::dvec3 offset, int gesture)
      : VirtualCommand(doc, name, gesture, true), offset_(offset) {
    setText(Document::tr("move %1").arg(QString::fromStdString(name)));
  }
  int id() const override { return 2; }
  bool mergeWith(const QUndoCommand* other) override {
    const auto* o = static_cast<const MoveLampCommand*>(other);
    if (!sameGesture(o)) return false;
    offset_ += o->offset_;
    return true;
  }

 protected:
  void doRedo() override { doc_->applyMoveVirtualLamp(name_, offset_); }
  void doUndo() override { doc_->applyMoveVirtualLamp(name_, -offset_); }

 private:
  glm::dvec3 offset_;
};

class EditLampCommand : public VirtualCommand {
 public:
  EditLampCommand(Document* doc, VirtualLamp before, VirtualLamp after, int gesture, bool applied = false)
      : VirtualCommand(doc, before.name, gesture, applied), before_(std::move(before)), after_(std::move(after)) {
    setText(Document::tr("change %1").arg(QString::fromStdString(name_)));
  }
  int id() const override { return 3; }
  bool mergeWith(const QUndoCommand* other) override {
    const auto* o = static_cast<const EditLampCommand*>(other);
    if (!sameGesture(o)) return false;
    after_ = o->after_;
    return true;
  }

 protected:
  void doRedo() override { doc_->applyVirtualLamp(name_, after_); }
  void doUndo() override { doc_->applyVirtualLamp(name_, before_); }

 private:
  VirtualLamp before_, after_;
};

class AddObjectCommand : public VirtualCommand {
 public:
  AddObjectCommand(Document* doc, VirtualObject object, double turn, bool adding)
      : VirtualCommand(doc, object.name, 0, true), object_(std::move(object)), turn_(turn), adding_(adding) {
    setText((adding ? Document::tr("add %1") : Document::tr("remove %1")).arg(QString::fromStdString(name_)));
  }

 protected:
  void doRedo() override { adding_ ? doc_->applyAddObject(object_, turn_) : doc_->applyRemoveObject(name_); }
  void doUndo() override { adding_ ? doc_->applyRemoveObject(name_) : doc_->applyAddObject(object_, turn_); }

 private:
  VirtualObject object_;
  double turn_;
  bool adding_;
};

class MoveObjectCommand : public VirtualCommand {
 public:
  MoveObjectCommand(Document* doc, const std::string& name, glm::dvec3 offset, double turn, int gesture)
      : VirtualCommand(doc, name, gesture, true), offset_(offset), turn_(turn) {
    setText(Document::tr("move %1").arg(QString::fromStdString(name)));
  }
  int id() const override { return 4; }
  bool mergeWith(const QUndoCommand* other) override {
    const auto* o = static_cast<const MoveObjectCommand*>(other);
    if (!sameGesture(o)) return false;
    offset_ += o->offset_;
    turn_ += o->turn_;
    return true;
  }

 protected:
  void doRedo() override { doc_->applyMoveObject(name_, offset_, turn_); }
  // The pivot has moved by offset_: turning back about it, then moving back, is the exact inverse.
  void doUndo() override { doc_->applyUnmoveObject(name_, offset_, turn_); }

 private:
  glm::dvec3 offset_;
  double turn_;
};

// An image-based object added (no before), removed (no after) or placed anew; applied before it
// is pushed (its first redo is skipped).
class ImageObjectCommand : public QUndoCommand {
 public:
  ImageObjectCommand(Document* doc, std::string name, std::optional<ibr::ImageObject> before,
                     std::optional<ibr::ImageObject> after, int gesture)
      : doc_(doc), name_(std::move(name)), before_(std::move(before)), after_(std::move(after)), gesture_(gesture) {
    const QString n = QString::fromStdString(name_);
    setText(!before_ ? Document::tr("add %1").arg(n) : !after_ ? Document::tr("remove %1").arg(n) : Document::tr("move %1").arg(n));
  }
  int id() const override { return 5; }
  bool mergeWith(const QUndoCommand* other) override {
    const auto* o = static_cast<const ImageObjectCommand*>(other);
    if (gesture_ == 0 || o->gesture_ != gesture_ || o->name_ != name_ || !before_ || !after_ || !o->after_) return false;
    after_ = o->after_;
    return true;
  }
  void redo() override {
    if (skip_) {
      skip_ = false;
      return;
    }
    doc_->applyImageObject(name_, after_);
  }
  void undo() override { doc_->applyImageObject(name_, before_); }

 private:
  Document* doc_;
  std::string name_;
  std::optional<ibr::ImageObject> before_, after_;
  int gesture_;
  bool skip_ = true;
};

class ReferenceCommand : public QUndoCommand {
 public:
  ReferenceCommand(Document* doc, std::string polygon, std::optional<glm::dvec2> before, std::optional<glm::dvec2> after)
      : doc_(doc), polygon_(std::move(polygon)), before_(before), after_(after) {
    setText((after ? Document::tr("reference patch of %1") : Document::tr("automatic reference of %1"))
                .arg(QString::fromStdString(polygon_)));
  }
  void redo() override { doc_->applyReferenceOverride(polygon_, after_); }
  void undo() override { doc_->applyReferenceOverride(polygon_, before_); }

 private:
  Document* doc_;
  std::string polygon_;
  std::optional<glm::dvec2> before_, after_;
};

class RegionsCommand : public QUndoCommand {
 public:
  RegionsCommand(Document* doc, const QString& text, std::vector<ReferenceRegion> before, std::vector<ReferenceRegion> after)
      : doc_(doc), before_(std::move(before)), after_(std::move(after)) {
    setText(text);
  }
  void redo() override { doc_->applyReferenceRegions(after_); }
  void undo() override { doc_->applyReferenceRegions(before_); }

 private:
  Document* doc_;
  std::vector<ReferenceRegion> before_, after_;
};

QJsonArray point(const glm::dvec3& v) { return QJsonArray{v.x, v.y, v.z}; }

QJsonArray polygonJson(const std::vector<glm::dvec3>& poly) {
  QJsonArray a;
  for (const auto& v : poly) a.append(point(v));
  return a;
}

std::vector<glm::dvec3> readPolygon(const QJsonValue& v, const std::string& file, const std::string& what) {
  std::vector<glm::dvec3> out;
  for (const auto& p : v.toArray()) {
    const QJsonArray a = p.toArray();
    if (a.size() != 3 || !a[0].isDouble() || !a[1].isDouble() || !a[2].isDouble())
      throw Error(file, what, "expected a list of [x, y, z] points");
    out.emplace_back(a[0].toDouble(), a[1].toDouble(), a[2].toDouble());
  }
  if (out.size() < 3) throw Error(file, what, "a polygon needs 3 or more points");
  return out;
}

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
    room->preprocessor = std::make_shared<Preprocessor>(room->scene, RelightOptions{}, scope);
    room->data = room->preprocessor->data();
  }
  // Saved virtual lamps and objects go into the session as it is built.
  const std::string stateFile = (room->projectPath + "/workbench.json").toStdString();
  if (room->state.contains("reference_regions") && !room->state["reference_regions"].isArray())
    throw Error(stateFile, "reference_regions", "must be a list");
  room->regions = room->state.contains("reference_regions")
                      ? referenceRegionsFromJson(room->state["reference_regions"].toArray(), stateFile)
                      : room->data.referenceRegions;
  for (const auto& r : room->regions) {
    const int s = room->scene.findPolygon(r.polygon);
    if (s < 0 || room->scene.polygons[size_t(s)].kind != PolygonKind::Real)
      throw Error(stateFile, "reference_regions", "names '" + r.polygon + "', which is not a photographed polygon of the room");
  }
  std::vector<VirtualLamp> vlamps;
  std::vector<VirtualObject> objects;
  for (const auto& v : room->state["virtual_lights"].toArray()) {
    const QJsonObject o = v.toObject();
    VirtualLamp l;
    l.name = o["name"].toString().toStdString();
    if (l.name.empty()) throw Error(stateFile, "virtual_lights", "a virtual lamp has no name");
    l.polygon = readPolygon(o["polygon"], stateFile, "virtual lamp '" + l.name + "' polygon");
    l.radiance = readRgb(o["radiance_rgb"], stateFile, "virtual lamp '" + l.name + "' radiance_rgb");
    vlamps.push_back(l);
  }
  for (const auto& v : room->state["virtual_objects"].toArray()) {
    const QJsonObject o = v.toObject();
    VirtualObject ob;
    ob.name = o["name"].toString().toStdString();
    if (ob.name.empty()) throw Error(stateFile, "virtual_objects", "a virtual object has no name");
    for (const auto& p : o["polygons"].toArray())
      ob.polygons.push_back(readPolygon(p, stateFile, "virtual object '" + ob.name + "' polygons"));
    ob.albedo = readRgb(o["albedo"], stateFile, "virtual object '" + ob.name + "' albedo");
    objects.push_back(ob);
  }
  if (room->state.contains("image_objects") && !room->state["image_objects"].isArray())
    throw Error(stateFile, "image_objects", "must be a list");
  for (const auto& v : room->state["image_objects"].toArray()) {
    const QJsonObject o = v.toObject();
    ibr::ImageObject io;
    io.name = o["name"].toString().toStdString();
    if (io.name.empty()) throw Error(stateFile, "image_objects", "an image-based object has no name");
    const std::string where = "image-based object '" + io.name + "'";
    const QJsonArray pos = o["position"].toArray();
    if (pos.size() != 3 || !pos[0].isDouble() || !pos[1].isDouble() || !pos[2].isDouble())
      throw Error(stateFile, where, "position must be [x, y, z] in metres");
    io.place.position = glm::dvec3(pos[0].toDouble(), pos[1].toDouble(), pos[2].toDouble());
    io.place.scale = o["scale"].toDouble(1.0);
    if (!(io.place.scale > 0) || !std::isfinite(io.place.scale)) throw Error(stateFile, where, "scale must be a number > 0");
    const double degrees = o["rotation_degrees"].toDouble(0.0);
    if (!std::isfinite(degrees) || std::abs(degrees) > 1e6) throw Error(stateFile, where, "rotation_degrees must be a number");
    io.place.yaw = degrees * std::numbers::pi / 180.0;
    for (const auto& other : room->imageObjects)
      if (other.name == io.name) throw Error(stateFile, where, "the name is given to two image-based objects");
    io.fanFile = fileInFolder(room->projectPath.toStdString(), o["fan"].toString().toStdString(), stateFile, where + " fan");
    io.fan = ibr::readFan(io.fanFile);
    ibr::checkImageObject(room->scene, io);
    room->imageObjects.push_back(std::move(io));
  }
  if (room->state.contains("mesh") && !room->state["mesh"].isString()) throw Error(stateFile, "mesh", "must be a string");
  const QString meshName = room->state["mesh"].toString("refined");
  if (meshName != "refined" && meshName != "interactive")
    throw Error(stateFile, "mesh", "must be \"refined\" or \"interactive\", not \"" + meshName.toStdString() + "\"");
  room->mesh = meshName == "interactive" ? SessionMesh::Interactive : SessionMesh::Refined;
  {
    ProgressScope scope(progress, preprocessed ? 0.0 : 0.8, 1.0);
    room->session = std::make_unique<RelightSession>(room->scene, room->data, vlamps, objects, scope, room->mesh);
  }
  // Saved lamp scales (by lamp name) go on the session before the UI sees it.
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
  for (auto signal : {&Document::lightingChanged, &Document::meshChanged, &Document::relightingReplaced, &Document::opened})
    connect(this, signal, this, [this] { ++lightEpoch_; });
  for (auto signal : {&Document::lightingChanged, &Document::meshChanged, &Document::virtualsChanged,
                      &Document::referencesChanged, &Document::relightingReplaced, &Document::opened,
                      &Document::imageObjectsChanged})
    connect(this, signal, this, [this] { ++changes_; });
}

Document::~Document() = default;

void Document::adopt(std::unique_ptr<LoadedRoom> room) {
  undo_.clear();
  scene_ = std::move(room->scene);
  data_ = std::move(room->data);
  session_ = std::move(room->session);
  preprocessor_ = room->preprocessor;
  projectPath_ = room->projectPath;
  sourcePath_ = room->sourcePath;
  view_ = room->state["view"].toObject();
  objectTurn_.clear();
  objectPivot_.clear();
  imageObjects_ = std::move(room->imageObjects);
  mesh_ = room->mesh;
  overrides_ = data_.referenceOverride;
  if (room->state.contains("reference_overrides")) {
    overrides_.clear();
    const QJsonObject ro = room->state["reference_overrides"].toObject();
    for (auto it = ro.begin(); it != ro.end(); ++it) {
      const QJsonArray a = it.value().toArray();
      if (a.size() == 2) overrides_[it.key().toStdString()] = glm::dvec2(a[0].toDouble(), a[1].toDouble());
    }
  }
  regions_ = room->regions;
  lampMount_.clear();
  for (const auto& v : room->state["virtual_lights"].toArray()) {
    const QJsonArray m = v.toObject()["mount"].toArray();
    if (m.size() == 6)
      lampMount_[v.toObject()["name"].toString().toStdString()] =
          Mount{glm::dvec3(m[0].toDouble(), m[1].toDouble(), m[2].toDouble()), glm::dvec3(m[3].toDouble(), m[4].toDouble(), m[5].toDouble())};
  }
  for (const auto& v : room->state["virtual_objects"].toArray())
    objectTurn_[v.toObject()["name"].toString().toStdString()] = v.toObject()["turn_degrees"].toDouble(0);
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
  preprocessor_.reset();
  scene_ = Scene{};
  data_ = RelightData{};
  projectPath_.clear();
  sourcePath_.clear();
  lampScale_.clear();
  objectTurn_.clear();
  objectPivot_.clear();
  imageObjects_.clear();
  overrides_.clear();
  regions_.clear();
  lampMount_.clear();
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
  QJsonArray vlamps, objects;
  for (size_t i = 0; i < virtualLampCount(); ++i) {
    const VirtualLamp& l = session_->virtualLamp(int(i));
    const Mount m = mountOf(l);
    vlamps.append(QJsonObject{{"name", QString::fromStdString(l.name)},
                              {"polygon", polygonJson(l.polygon)},
                              {"radiance_rgb", rgb(l.radiance)},
                              {"mount", QJsonArray{m.point.x, m.point.y, m.point.z, m.normal.x, m.normal.y, m.normal.z}}});
  }
  for (size_t i = 0; i < objectCount(); ++i) {
    const VirtualObject& o = session_->object(int(i));
    QJsonArray polys;
    for (const auto& p : o.polygons) polys.append(polygonJson(p));
    objects.append(QJsonObject{{"name", QString::fromStdString(o.name)}, {"albedo", rgb(o.albedo)}, {"polygons", polys},
                               {"turn_degrees", objectTurn(o.name)}});
  }
  QJsonArray images;
  for (size_t i = 0; i < imageObjects_.size(); ++i) {
    const auto& o = imageObjects_[i];
    const glm::dvec3& p = o.place.position;
    images.append(QJsonObject{{"name", QString::fromStdString(o.name)},
                              {"fan", QString("objects/image_%1.fan").arg(i + 1)},
                              {"position", QJsonArray{p.x, p.y, p.z}},
                              {"scale", o.place.scale},
                              {"rotation_degrees", o.place.yaw * 180.0 / std::numbers::pi}});
  }
  QJsonObject refs;
  for (const auto& [name, uv] : overrides_) refs[QString::fromStdString(name)] = QJsonArray{uv.x, uv.y};
  // Version 3 only when it holds image-based objects (older workbenches read the rest).
  return QJsonObject{{"format", "relume-workbench"}, {"version", images.isEmpty() ? 2 : kWorkbenchStateVersion},
                     {"image_objects", images}, {"lamps", lamps},
                     {"virtual_lights", vlamps}, {"virtual_objects", objects}, {"reference_overrides", refs},
                     {"reference_regions", referenceRegionsJson(regions_)},
                     {"mesh", mesh_ == SessionMesh::Interactive ? "interactive" : "refined"}, {"view", view_}};
}

// --- virtual lamps and objects -------------------------------------------------------------------

VirtualLamp Document::lampQuad(const std::string& name, const glm::dvec3& centre, const glm::dvec3& normal, double size,
                               const glm::dvec3& radiance) {
  const glm::dvec3 n = glm::normalize(normal);
  const glm::dvec3 a = std::abs(n.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
  const glm::dvec3 t1 = glm::normalize(glm::cross(a, n)), t2 = glm::cross(n, t1);  // t1 x t2 = n: CCW about n
  const double h = 0.5 * size;
  VirtualLamp l;
  l.name = name;
  l.radiance = radiance;
  l.polygon = {centre - h * t1 - h * t2, centre + h * t1 - h * t2, centre + h * t1 + h * t2, centre - h * t1 + h * t2};
  return l;
}

glm::dvec3 Document::defaultLampRadiance(double size) const {
  // Power of the brightest real lamp (exitance x area), spread over the square: radiance = M / pi.
  double best = 0;
  glm::dvec3 power(0.0);
  for (size_t l = 0; l < scene_.lamps.size() && l < data_.lampExitance.size(); ++l) {
    const glm::dvec3 p = data_.lampExitance[l] * polygonArea(scene_.polygons[size_t(scene_.lamps[l].polygon)].vertices);
    if (p.x + p.y + p.z > best) {
      best = p.x + p.y + p.z;
      power = p;
    }
  }
  if (best <= 0) power = glm::dvec3(50.0);
  return power / (std::numbers::pi * size * size);
}

std::string Document::newName(const QString& stem) const {
  for (int k = 1;; ++k) {
    const std::string n = QString("%1 %2").arg(stem).arg(k).toStdString();
    if (virtualLampIndex(n) < 0 && objectIndex(n) < 0 && imageObjectIndex(n) < 0) return n;
  }
}

int Document::virtualLampIndex(const std::string& name) const {
  for (size_t i = 0; i < virtualLampCount(); ++i)
    if (session_->virtualLamp(int(i)).name == name) return int(i);
  return -1;
}

int Document::objectIndex(const std::string& name) const {
  for (size_t i = 0; i < objectCount(); ++i)
    if (session_->object(int(i)).name == name) return int(i);
  return -1;
}

namespace {
template <class F>
bool attempt(F&& f, QString* error) {
  try {
    f();
    return true;
  } catch (const std::exception& e) {
    if (error) *error = QString::fromStdString(e.what());
    return false;
  }
}
}  // namespace

Document::Mount Document::mountOf(const VirtualLamp& lamp) const {
  const auto it = lampMount_.find(lamp.name);
  if (it != lampMount_.end()) return it->second;
  glm::dvec3 c(0.0);
  for (const auto& v : lamp.polygon) c += v;
  c /= double(lamp.polygon.size());
  const glm::dvec3 n = polygonNormal(lamp.polygon);
  return Mount{c - 0.02 * n, n};  // as the lamp tool puts them
}

double Document::lampDrop(const std::string& name) const {
  const int i = virtualLampIndex(name);
  if (i < 0) return 0;
  const VirtualLamp& l = session_->virtualLamp(i);
  const Mount m = mountOf(l);
  glm::dvec3 c(0.0);
  for (const auto& v : l.polygon) c += v;
  return glm::dot(c / double(l.polygon.size()) - m.point, m.normal);
}

bool Document::trySetLampDrop(const std::string& name, double metres, QString* error) {
  const int i = virtualLampIndex(name);
  if (i < 0) return false;
  const VirtualLamp before = session_->virtualLamp(i);  // a copy: the replacement reuses its slot
  const Mount m = mountOf(before);
  lampMount_[name] = m;
  // A new place, not a drag: the lamp goes in afresh, so its links are refined where it now is.
  VirtualLamp after = before;
  for (auto& v : after.polygon) v += (metres - lampDrop(name)) * m.normal;
  if (!attempt([&] { applyVirtualLamp(name, after); }, error)) return false;
  undo_.push(new EditLampCommand(this, before, after, 0, true));
  return true;
}

void Document::beginObjectDrag() {
  if (session_) session_->setDragPreview(true);
}

void Document::settleObject(const std::string& name) {
  if (!session_) return;
  const int i = objectIndex(name);
  if (i < 0) {
    session_->setDragPreview(false);
    return;
  }
  timed([&] { session_->settleObject(i); });
  emit meshChanged();
}

void Document::settleVirtualLamp(const std::string& name) {
  const int i = virtualLampIndex(name);
  if (i < 0) return;
  const VirtualLamp lamp = session_->virtualLamp(i);
  timed([&] { session_->replaceVirtualLamp(i, lamp); });
  emit meshChanged();
  emit virtualsChanged();
}

double Document::objectTurn(const std::string& name) const {
  const auto it = objectTurn_.find(name);
  return it == objectTurn_.end() ? 0.0 : it->second;
}

void Document::timed(const std::function<void()>& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  lastUpdateMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

bool Document::tryAddVirtualLamp(const VirtualLamp& lamp, QString* error) {
  if (!session_) return false;
  if (!attempt([&] { applyAddVirtualLamp(lamp); }, error)) return false;
  lampMount_.erase(lamp.name);  // a deleted lamp's name may come back: not its mount
  lampMount_[lamp.name] = mountOf(lamp);
  undo_.push(new AddLampCommand(this, lamp, true));
  return true;
}

void Document::removeVirtualLamp(const std::string& name) {
  const int i = virtualLampIndex(name);
  if (i < 0) return;
  undo_.push(new AddLampCommand(this, session_->virtualLamp(i), false));
}

bool Document::tryMoveVirtualLamp(const std::string& name, const glm::dvec3& offset, int gesture, QString* error) {
  if (virtualLampIndex(name) < 0) return false;
  if (!attempt([&] { applyMoveVirtualLamp(name, offset); }, error)) return false;
  undo_.push(new MoveLampCommand(this, name, offset, gesture));
  return true;
}

void Document::editVirtualLamp(const std::string& name, const glm::dvec3& radiance, double size, int gesture) {
  const int i = virtualLampIndex(name);
  if (i < 0) return;
  const VirtualLamp before = session_->virtualLamp(i);
  const double oldSize = glm::length(before.polygon[1] - before.polygon[0]);
  VirtualLamp after = before;
  after.radiance = radiance;
  if (std::abs(size - oldSize) > 1e-6) {
    glm::dvec3 c(0.0);
    for (const auto& v : before.polygon) c += v;
    c /= double(before.polygon.size());
    after = lampQuad(name, c, polygonNormal(before.polygon), size, radiance);
  }
  undo_.push(new EditLampCommand(this, before, after, gesture));
}

bool Document::tryAddObject(const VirtualObject& object, QString* error) {
  if (!session_) return false;
  if (!attempt([&] { applyAddObject(object, 0.0); }, error)) return false;
  undo_.push(new AddObjectCommand(this, object, 0.0, true));
  return true;
}

void Document::removeObject(const std::string& name) {
  const int i = objectIndex(name);
  if (i < 0) return;
  undo_.push(new AddObjectCommand(this, session_->object(i), objectTurn(name), false));
  // AddObjectCommand skips its first redo: do the removal now.
  applyRemoveObject(name);
}

bool Document::tryMoveObject(const std::string& name, const glm::dvec3& offset, double turnDegrees, int gesture,
                             QString* error) {
  if (objectIndex(name) < 0) return false;
  if (!attempt([&] { applyMoveObject(name, offset, turnDegrees); }, error)) return false;
  undo_.push(new MoveObjectCommand(this, name, offset, turnDegrees, gesture));
  return true;
}

int Document::imageObjectIndex(const std::string& name) const {
  for (size_t i = 0; i < imageObjects_.size(); ++i)
    if (imageObjects_[i].name == name) return int(i);
  return -1;
}

bool Document::tryAddImageObject(const ibr::ImageObject& object, QString* error) {
  if (!session_ || !object.fan) return false;
  if (!attempt([&] { ibr::checkImageObject(scene_, object); }, error)) return false;
  applyImageObject(object.name, object);
  undo_.push(new ImageObjectCommand(this, object.name, std::nullopt, object, 0));
  return true;
}

bool Document::tryPlaceImageObject(const std::string& name, const ibr::Placement& place, int gesture, QString* error) {
  const int i = imageObjectIndex(name);
  if (i < 0) return false;
  ibr::ImageObject moved = imageObjects_[size_t(i)];
  moved.place = place;
  if (!attempt([&] { ibr::checkImageObject(scene_, moved); }, error)) return false;
  const ibr::ImageObject before = imageObjects_[size_t(i)];
  applyImageObject(name, moved);
  undo_.push(new ImageObjectCommand(this, name, before, moved, gesture));
  return true;
}

void Document::removeImageObject(const std::string& name) {
  const int i = imageObjectIndex(name);
  if (i < 0) return;
  const ibr::ImageObject before = imageObjects_[size_t(i)];
  applyImageObject(name, std::nullopt);
  undo_.push(new ImageObjectCommand(this, name, before, std::nullopt, 0));
}

void Document::applyImageObject(const std::string& name, const std::optional<ibr::ImageObject>& object) {
  const int i = imageObjectIndex(name);
  if (object && i >= 0) imageObjects_[size_t(i)] = *object;
  else if (object) imageObjects_.push_back(*object);
  else if (i >= 0) imageObjects_.erase(imageObjects_.begin() + i);
  emit imageObjectsChanged();
}

std::vector<ibr::ObjectLighting> Document::imageObjectLighting() {
  std::vector<ibr::ObjectLighting> out;
  if (!session_ || imageObjects_.empty()) return out;
  bool synced = false;
  for (const auto& o : imageObjects_) {
    const glm::dvec3 c = o.place.toWorld(*o.fan, o.fan->centre);
    ObjectLight& cached = objectLights_[o.name];
    if (!cached.light || cached.epoch != lightEpoch_ || glm::length(cached.centre - c) > 1e-9) {
      if (!synced) session_->syncEngine();
      synced = true;
      cached = ObjectLight{c, lightEpoch_, std::make_shared<const ibr::ObjectLighting>(ibr::lightingAt(session_->engine(), c))};
    }
    out.push_back(*cached.light);
  }
  return out;
}

void Document::applyAddVirtualLamp(const VirtualLamp& lamp) {
  timed([&] { session_->addVirtualLamp(lamp); });
  emit meshChanged();
  emit virtualsChanged();
}

void Document::applyRemoveVirtualLamp(const std::string& name) {
  const int i = virtualLampIndex(name);
  if (i < 0) return;
  timed([&] { session_->removeVirtualLamp(i); });
  emit meshChanged();
  emit virtualsChanged();
}

void Document::applyMoveVirtualLamp(const std::string& name, const glm::dvec3& offset) {
  const int i = virtualLampIndex(name);
  if (i < 0) return;
  timed([&] { lastLinks_ = session_->moveVirtualLamp(i, offset); });
  emit meshChanged();
  emit virtualsChanged();
}

void Document::applyVirtualLamp(const std::string& name, const VirtualLamp& lamp) {
  const int i = virtualLampIndex(name);
  if (i < 0) return;
  const VirtualLamp& now = session_->virtualLamp(i);
  if (now.polygon == lamp.polygon) {  // radiance only: per-lamp solutions, no radiosity steps
    timed([&] {
      session_->setVirtualLampRadiance(i, lamp.radiance);
      session_->update();
    });
    emit lightingChanged();
  } else {  // a new square: put in afresh (its links refined where it now is)
    timed([&] { session_->replaceVirtualLamp(i, lamp); });
    emit meshChanged();
  }
  emit virtualsChanged();
}

void Document::applyAddObject(const VirtualObject& object, double turnDegrees) {
  timed([&] { session_->addObject(object); });
  objectTurn_[object.name] = turnDegrees;
  objectPivot_[object.name] = objectCentre(object);
  emit meshChanged();
  emit virtualsChanged();
}

void Document::applyUnmoveObject(const std::string& name, const glm::dvec3& offset, double turnDegrees) {
  const int i = objectIndex(name);
  if (i < 0) return;
  const glm::dvec3 pivot = objectPivot(name);  // = the pivot before the move + offset
  timed([&] { lastLinks_ = session_->moveObjectAbout(i, -offset, -turnDegrees * std::numbers::pi / 180.0, pivot); });
  objectPivot_[name] = pivot - offset;
  objectTurn_[name] = objectTurn(name) - turnDegrees;
  emit meshChanged();
  emit virtualsChanged();
}

void Document::applyRemoveObject(const std::string& name) {
  const int i = objectIndex(name);
  if (i < 0) return;
  timed([&] { session_->removeObject(i); });
  objectTurn_.erase(name);
  objectPivot_.erase(name);
  emit meshChanged();
  emit virtualsChanged();
}

glm::dvec3 Document::objectPivot(const std::string& name) const {
  const auto it = objectPivot_.find(name);
  if (it != objectPivot_.end()) return it->second;
  const int i = objectIndex(name);
  return i < 0 ? glm::dvec3(0.0) : objectCentre(session_->object(i));
}

void Document::applyMoveObject(const std::string& name, const glm::dvec3& offset, double turnDegrees) {
  const int i = objectIndex(name);
  if (i < 0) return;
  // Turned about its pivot, then moved; the pivot follows. Undo (-offset, -turn) about the moved
  // pivot gives back exactly the place before, whatever the shape.
  const glm::dvec3 pivot = objectPivot(name);
  timed([&] { lastLinks_ = session_->moveObjectAbout(i, offset, turnDegrees * std::numbers::pi / 180.0, pivot); });
  objectPivot_[name] = pivot + offset;
  objectTurn_[name] = objectTurn(name) + turnDegrees;
  emit meshChanged();
  emit virtualsChanged();
}

std::function<void(Progress&)> Document::saveWork(const QString& folder) const {
  auto scene = std::make_shared<Scene>(scene_);
  auto data = std::make_shared<RelightData>(data_);
  const QByteArray edits = QJsonDocument(editsJson()).toJson();
  std::vector<std::shared_ptr<const ibr::ImageFan>> fans;  // objects/image_N.fan, as editsJson names them
  for (const auto& o : imageObjects_) fans.push_back(o.fan);
  return [scene, data, edits, folder, fans](Progress& progress) {
    saveRelightProject(*scene, *data, folder.toStdString(), progress, [&](const std::string& staging) {
      if (!fans.empty() && !QDir().mkpath(QString::fromStdString(staging) + "/objects"))
        throw Error(folder.toStdString(), "objects", "cannot create the folder for the image fans");
      for (size_t i = 0; i < fans.size(); ++i) {
        ibr::writeFan(*fans[i], staging + "/objects/image_" + std::to_string(i + 1) + ".fan");
        detail::saveStep("image fan written");
      }
      QSaveFile f(QString::fromStdString(staging) + "/workbench.json");
      if (!f.open(QIODevice::WriteOnly) || f.write(edits) < 0 || !f.commit())
        throw Error(folder.toStdString(), "workbench.json", "cannot write: " + f.errorString().toStdString());
      detail::saveStep("workbench.json written");
    });
  };
}

void Document::setReferenceOverride(const std::string& polygon, const std::optional<glm::dvec2>& uv) {
  std::optional<glm::dvec2> before;
  if (auto it = overrides_.find(polygon); it != overrides_.end()) before = it->second;
  if (before == uv) return;
  undo_.push(new ReferenceCommand(this, polygon, before, uv));
}

void Document::applyReferenceOverride(const std::string& polygon, const std::optional<glm::dvec2>& uv) {
  if (uv) overrides_[polygon] = *uv;
  else overrides_.erase(polygon);
  emit referencesChanged();
}

void Document::addReferenceRegion(const ReferenceRegion& region) {
  auto after = regions_;
  after.push_back(region);
  undo_.push(new RegionsCommand(this, Document::tr("reference region on %1").arg(QString::fromStdString(region.polygon)),
                                regions_, after));
}

void Document::clearReferenceRegions(const std::string& polygon) {
  auto after = regions_;
  std::erase_if(after, [&](const ReferenceRegion& r) { return r.polygon == polygon; });
  if (after.size() == regions_.size()) return;
  undo_.push(new RegionsCommand(this, Document::tr("no reference regions on %1").arg(QString::fromStdString(polygon)),
                                regions_, after));
}

void Document::applyReferenceRegions(const std::vector<ReferenceRegion>& regions) {
  regions_ = regions;
  emit referencesChanged();
}

std::function<std::function<void()>(Progress&)> Document::recomputeReferencesWork() {
  auto scene = std::make_shared<Scene>(scene_);
  auto pre = preprocessor_;
  const auto overrides = overrides_;
  const auto regions = regions_;
  RelightOptions options = data_.options;
  options.referenceOverride = overrides;
  options.referenceRegions = regions;
  const std::vector<glm::dvec3> exitance = data_.lampExitance;
  auto rebuild = rebuildWork(mesh_);
  return [this, scene, pre, overrides, regions, options, exitance, rebuild](Progress& progress) mutable -> std::function<void()> {
    {
      ProgressScope scope(progress, 0.0, 0.8);
      if (!pre) pre = std::make_shared<Preprocessor>(*scene, options, scope);  // the first time: all of it
      else pre->redoReferences(overrides, regions, scope);                      // then step 2 where it changed
    }
    auto data = std::make_shared<RelightData>(pre->data());
    std::function<void()> swapSession;
    // A preprocess by another version may have estimated other lamps: then a new session.
    if (data->lampExitance != exitance) {
      ProgressScope scope(progress, 0.8, 1.0);
      swapSession = rebuild(*data, scope);
    }
    return [this, pre, data, swapSession]() {
      if (!swapSession) timed([&] { session_->setReflectanceMaps(data->textures); });
      data_ = std::move(*data);
      preprocessor_ = pre;
      unsavedNew_ = true;  // the recomputed textures are not on disk yet
      if (swapSession) swapSession();
      else emit relightingReplaced();
      emit referencesChanged();
      emit dirtyChanged(isDirty());
    };
  };
}

std::function<std::function<void()>(Progress&)> Document::switchMeshWork(SessionMesh mesh) {
  auto data = std::make_shared<RelightData>(data_);
  auto rebuild = rebuildWork(mesh);
  return [data, rebuild](Progress& progress) { return rebuild(*data, progress); };
}

// A session on `data` (on the mesh given) with the lamps, virtual lamps and objects as they are
// now (copied here, built by the returned function on a worker thread).
std::function<std::unique_ptr<RelightSession>(const RelightData&, Progress&)> Document::sessionWork(SessionMesh mesh) const {
  auto scene = std::make_shared<Scene>(scene_);
  std::vector<VirtualLamp> vlamps;
  std::vector<VirtualObject> objects;
  for (size_t i = 0; i < virtualLampCount(); ++i) vlamps.push_back(session_->virtualLamp(int(i)));
  for (size_t i = 0; i < objectCount(); ++i) objects.push_back(session_->object(int(i)));
  const std::vector<glm::dvec3> scales = lampScale_;
  return [scene, vlamps, objects, scales, mesh](const RelightData& data, Progress& progress) {
    auto session = std::make_unique<RelightSession>(*scene, data, vlamps, objects, progress, mesh);
    for (size_t l = 0; l < scales.size(); ++l) session->setLampScale(int(l), scales[l]);
    session->update(progress);
    return session;
  };
}

// A new session on `data`, swapped in by the continuation; the undo stack stays.
std::function<std::function<void()>(const RelightData&, Progress&)> Document::rebuildWork(SessionMesh mesh) {
  auto build = sessionWork(mesh);
  return [this, build, mesh](const RelightData& data, Progress& progress) -> std::function<void()> {
    auto session = std::make_shared<std::unique_ptr<RelightSession>>(build(data, progress));
    return [this, session, mesh]() mutable {
      session_ = std::move(*session);
      if (mesh_ != mesh) unsavedNew_ = true;  // the project keeps the mesh chosen
      mesh_ = mesh;
      emit relightingReplaced();
      emit dirtyChanged(isDirty());
    };
  };
}

std::function<std::unique_ptr<RelightSession>(Progress&)> Document::otherMeshSessionWork() const {
  auto data = std::make_shared<RelightData>(data_);
  auto build = sessionWork(mesh_ == SessionMesh::Refined ? SessionMesh::Interactive : SessionMesh::Refined);
  return [data, build](Progress& progress) {
    auto session = build(*data, progress);
    session->syncEngine(progress);
    return session;
  };
}

void Document::syncEngine() {
  if (session_) session_->syncEngine();
}

void Document::markRecovered(const QString& project, const QString& source) {
  projectPath_ = project;
  sourcePath_ = source;
  unsavedNew_ = true;
  emit dirtyChanged(true);
}

void Document::markSaved(const QString& folder) {
  projectPath_ = QFileInfo(folder).absoluteFilePath();
  unsavedNew_ = false;
  undo_.setClean();
  emit dirtyChanged(false);
}

}  // namespace relume
