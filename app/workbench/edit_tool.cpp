#include "edit_tool.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "document.h"
#include "relume/geometry/polygon.h"
#include "relume/ibr/relit_objects.h"

namespace relume {

namespace {
// Where the ray meets the plane; false when it runs parallel to it or away from it.
bool rayPlane(const ViewportPick& pick, const glm::dvec3& p, const glm::dvec3& n, glm::dvec3& out) {
  const double d = glm::dot(pick.direction, n);
  if (std::abs(d) < 1e-9) return false;
  const double t = glm::dot(p - pick.origin, n) / d;
  if (t <= 0) return false;
  out = pick.origin + t * pick.direction;
  return true;
}
}  // namespace

EditTool::EditTool(Document* doc, QObject* parent) : QObject(parent), doc_(doc) {}

void EditTool::setMode(Mode m) {
  if (m == mode_) return;
  if (mode_ == Mode::PaintRegion && !stroke_.discs.empty()) {
    stroke_.discs.clear();
    emit strokeChanged();
  }
  painting_ = strokeDone_ = false;
  mode_ = m;
  emit modeChanged(m);
  if (m == Mode::PlaceLamp) emit message(tr("Click a surface to put a virtual lamp 2 cm in front of it."));
  if (m == Mode::PlaceBox) emit message(tr("Click a floor or a table top to stand the box on it."));
  if (m == Mode::PlaceMesh || m == Mode::PlaceImage)
    emit message(tr("Click a floor or a table top to stand %1 on it.").arg(meshStem_));
}

void EditTool::pickReferenceOn(const std::string& polygon) {
  referencePolygon_ = polygon;
  mode_ = Mode::Select;  // so that setMode announces the change
  setMode(Mode::PickReference);
  emit message(tr("Click a texel of %1 whose colour its shadowed parts should take.").arg(QString::fromStdString(polygon)));
}

void EditTool::paintRegionOn(const std::string& polygon, double radius) {
  mode_ = Mode::Select;
  setMode(Mode::PaintRegion);
  stroke_ = ReferenceRegion{polygon, {}, glm::dvec2(0.0)};
  brush_ = radius;
  emit strokeChanged();
  emit message(tr("Paint over the shadowed part of %1 (drag); then click the texel it should take its colour from.")
                   .arg(QString::fromStdString(polygon)));
}

void EditTool::placeMesh(const QString& stem, const VirtualObject& mesh) {
  meshStem_ = stem;
  mesh_ = mesh;
  mode_ = Mode::Select;
  setMode(Mode::PlaceMesh);
}

void EditTool::placeImageObject(const QString& stem, std::shared_ptr<const ibr::ImageFan> fan, const std::string& fanFile,
                                double scale) {
  meshStem_ = stem;
  imageFan_ = std::move(fan);
  imageFanFile_ = fanFile;
  imageScale_ = scale;
  mode_ = Mode::Select;
  setMode(Mode::PlaceImage);
}

void EditTool::setBoxTemplate(const glm::dvec3& size, const glm::dvec3& albedo) {
  boxSize_ = size;
  boxAlbedo_ = albedo;
}

std::string EditTool::virtualLampAt(const ViewportPick& pick) const {
  if (!pick.hit() || !doc_->session()) return {};
  for (size_t i = 0; i < doc_->virtualLampCount(); ++i)
    if (doc_->session()->virtualLampSurface(int(i)) == pick.surface) return doc_->session()->virtualLamp(int(i)).name;
  return {};
}

std::string EditTool::objectAt(const ViewportPick& pick) const {
  if (!pick.hit() || !doc_->session()) return {};
  for (size_t i = 0; i < doc_->objectCount(); ++i) {
    const auto& ids = doc_->session()->objectSurfaces(int(i));
    if (std::find(ids.begin(), ids.end(), pick.surface) != ids.end()) return doc_->session()->object(int(i)).name;
  }
  return {};
}

std::string EditTool::imageObjectAt(const ViewportPick& pick) const {
  std::string best;
  double bestT = pick.hit() ? glm::length(pick.point - pick.origin) / std::max(glm::length(pick.direction), 1e-12) : 1e300;
  for (const auto& o : doc_->imageObjects()) {
    // The ray in the object's frame (o + t d there is origin + t direction in the world).
    const glm::dvec3 org = o.place.toObject(*o.fan, pick.origin);
    const glm::dvec3 dir = o.place.toObjectDirection(pick.direction) / o.place.scale;
    double t0 = 0, t1 = 1e300;
    for (int a = 0; a < 3; ++a) {
      if (std::abs(dir[a]) < 1e-15) {
        if (org[a] < o.fan->boundsMin[a] || org[a] > o.fan->boundsMax[a]) t0 = 1e301;
        continue;
      }
      double ta = (o.fan->boundsMin[a] - org[a]) / dir[a], tb = (o.fan->boundsMax[a] - org[a]) / dir[a];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    }
    if (t0 <= t1 && t0 < bestT) {
      bestT = t0;
      best = o.name;
    }
  }
  return best;
}

Qt::CursorShape EditTool::hoverCursor(const ViewportPick& pick) const {
  if (!enabled_) return Qt::BusyCursor;
  if (mode_ != Mode::Select) return pick.hit() ? Qt::CrossCursor : Qt::ForbiddenCursor;
  if (!virtualLampAt(pick).empty() || !objectAt(pick).empty() || !imageObjectAt(pick).empty()) return Qt::OpenHandCursor;
  return Qt::ArrowCursor;
}

bool EditTool::press(const ViewportPick& pick, Qt::KeyboardModifiers) {
  dragLamp_.clear();
  dragObject_.clear();
  dragImage_.clear();
  if (!doc_->isOpen() || !enabled_) return false;
  if (mode_ == Mode::PlaceLamp) {
    if (!pick.hit()) {
      emit message(tr("No surface there: click on the room."));
      return true;
    }
    const std::string name = doc_->newName(tr("Lamp"));
    const VirtualLamp lamp = Document::lampQuad(name, pick.point + kLampOffset * pick.normal, pick.normal, kLampSize,
                                                doc_->defaultLampRadiance(kLampSize));
    QString error;
    if (doc_->tryAddVirtualLamp(lamp, &error)) {
      emit message(tr("Added %1 (%2 ms).").arg(QString::fromStdString(name)).arg(doc_->lastUpdateMilliseconds(), 0, 'f', 0));
      emit selected(QString::fromStdString(name));
    } else {
      emit message(error);
    }
    setMode(Mode::Select);
    return true;
  }
  if (mode_ == Mode::PickReference) {
    const int s = doc_->scene().findPolygon(referencePolygon_);
    if (!pick.hit() || pick.surface != s) {
      emit message(tr("That is not %1: click on it, or press Esc.").arg(QString::fromStdString(referencePolygon_)));
      return true;
    }
    doc_->setReferenceOverride(referencePolygon_, doc_->session()->engine().toUV(s, pick.point));
    emit message(tr("Reference patch of %1 set: recompute to see it.").arg(QString::fromStdString(referencePolygon_)));
    setMode(Mode::Select);
    return true;
  }
  if (mode_ == Mode::PaintRegion) {
    const int s = doc_->scene().findPolygon(stroke_.polygon);
    if (!pick.hit() || pick.surface != s) {
      emit message(tr("That is not %1: click on it, or press Esc.").arg(QString::fromStdString(stroke_.polygon)));
      return true;
    }
    const glm::dvec2 uv = doc_->session()->engine().toUV(s, pick.point);
    if (!strokeDone_) {  // painting starts
      painting_ = true;
      stroke_.discs.emplace_back(uv, brush_);
      emit strokeChanged();
      return true;
    }
    stroke_.reference = uv;  // the reference: the region is done
    const ReferenceRegion region = stroke_;
    setMode(Mode::Select);  // drops the stroke
    doc_->addReferenceRegion(region);
    emit message(tr("Reference region painted on %1: recompute to see it.").arg(QString::fromStdString(region.polygon)));
    return true;
  }
  if (mode_ == Mode::PlaceImage) {
    if (!pick.hit() || pick.normal.z < 0.7) {
      emit message(tr("Objects stand on floors and tables: click a horizontal surface."));
      return true;
    }
    ibr::ImageObject o;
    o.name = doc_->newName(meshStem_);
    o.fan = imageFan_;
    o.fanFile = imageFanFile_;
    o.place.position = pick.point + glm::dvec3(0, 0, 0.002);  // 2 mm above what it stands on
    o.place.scale = imageScale_;
    QString error;
    if (doc_->tryAddImageObject(o, &error)) {
      emit message(tr("Added %1.").arg(QString::fromStdString(o.name)));
      emit selected(QString::fromStdString(o.name));
    } else {
      emit message(tr("%1 cannot stand there: %2").arg(QString::fromStdString(o.name), error));
    }
    setMode(Mode::Select);
    return true;
  }
  if (mode_ == Mode::PlaceBox || mode_ == Mode::PlaceMesh) {
    if (!pick.hit() || pick.normal.z < 0.7) {
      emit message(tr("Objects stand on floors and tables: click a horizontal surface."));
      return true;
    }
    const glm::dvec3 base = pick.point + glm::dvec3(0, 0, 0.002);  // 2 mm above what it stands on
    std::string name;
    VirtualObject box;
    if (mode_ == Mode::PlaceBox) {
      name = doc_->newName(tr("Box"));
      const glm::dvec3 half(0.5 * boxSize_.x, 0.5 * boxSize_.y, 0.0);
      box = boxObject(name, base - half, base + half + glm::dvec3(0, 0, boxSize_.z), boxAlbedo_);
    } else {  // the mesh's footprint centre on the point, its lowest point on the surface
      name = doc_->newName(meshStem_);
      box = mesh_;
      box.name = name;
      glm::dvec3 lo(1e300), hi(-1e300);
      for (const auto& p : box.polygons)
        for (const auto& v : p) {
          lo = glm::min(lo, v);
          hi = glm::max(hi, v);
        }
      const glm::dvec3 shift = base - glm::dvec3(0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), lo.z);
      for (auto& p : box.polygons)
        for (auto& v : p) v += shift;
    }
    QString error;
    if (doc_->tryAddObject(box, &error)) {
      emit message(tr("Added %1 (%2 ms).").arg(QString::fromStdString(name)).arg(doc_->lastUpdateMilliseconds(), 0, 'f', 0));
      emit selected(QString::fromStdString(name));
    } else {
      emit message(tr("%1 cannot stand there: %2").arg(QString::fromStdString(name), error));
    }
    setMode(Mode::Select);
    return true;
  }
  // Select: grab an image-based object, a virtual lamp or an object under the cursor.
  dragImage_ = imageObjectAt(pick);
  if (!dragImage_.empty()) {  // slides on the horizontal plane it stands on
    const auto& o = doc_->imageObjects()[size_t(doc_->imageObjectIndex(dragImage_))];
    planePoint_ = o.place.position;
    planeNormal_ = glm::dvec3(0, 0, 1);
    if (!rayPlane(pick, planePoint_, planeNormal_, anchor_)) {
      dragImage_.clear();
      return false;
    }
    imageStart_ = o.place;
    moved_ = glm::dvec3(0.0);
    refused_ = false;
    ++gesture_;
    emit selected(QString::fromStdString(dragImage_));
    return true;
  }
  dragLamp_ = virtualLampAt(pick);
  dragObject_ = dragLamp_.empty() ? objectAt(pick) : std::string();
  if (dragLamp_.empty() && dragObject_.empty()) {
    if (pick.hit()) emit surfaceClicked(pick.surface, pick.point);
    return false;
  }
  if (!dragLamp_.empty()) {  // slides in its own plane, parallel to the surface it sits on
    const VirtualLamp& l = doc_->session()->virtualLamp(doc_->virtualLampIndex(dragLamp_));
    planePoint_ = glm::dvec3(0.0);
    for (const auto& v : l.polygon) planePoint_ += v;
    planePoint_ /= double(l.polygon.size());
    planeNormal_ = polygonNormal(l.polygon);
  } else {  // slides on the horizontal plane it stands on
    const VirtualObject& o = doc_->session()->object(doc_->objectIndex(dragObject_));
    double zmin = 1e300;
    for (const auto& p : o.polygons)
      for (const auto& v : p) zmin = std::min(zmin, v.z);
    planePoint_ = glm::dvec3(0, 0, zmin);
    planeNormal_ = glm::dvec3(0, 0, 1);
  }
  if (!rayPlane(pick, planePoint_, planeNormal_, anchor_)) {
    dragLamp_.clear();
    dragObject_.clear();
    return false;
  }
  moved_ = glm::dvec3(0.0);
  refused_ = false;
  ++gesture_;
  if (!dragObject_.empty()) doc_->beginObjectDrag();
  emit selected(QString::fromStdString(dragLamp_.empty() ? dragObject_ : dragLamp_));
  return true;
}

void EditTool::drag(const ViewportPick& pick) {
  if (painting_) {  // a disc wherever the brush has moved a third of its radius on the polygon
    const int s = doc_->scene().findPolygon(stroke_.polygon);
    if (!pick.hit() || pick.surface != s) return;
    const glm::dvec2 uv = doc_->session()->engine().toUV(s, pick.point);
    if (!stroke_.discs.empty() && glm::length(uv - glm::dvec2(stroke_.discs.back())) < brush_ / 3) return;
    stroke_.discs.emplace_back(uv, brush_);
    emit strokeChanged();
    return;
  }
  if (!dragImage_.empty()) {
    if (doc_->imageObjectIndex(dragImage_) < 0) {  // gone while dragged (undone): the drag ends
      dragImage_.clear();
      return;
    }
    glm::dvec3 q;
    if (!rayPlane(pick, planePoint_, planeNormal_, q)) return;
    ibr::Placement place = imageStart_;
    place.position += q - anchor_;
    if (glm::length((q - anchor_) - moved_) < 1e-4) return;
    QString error;
    if (doc_->tryPlaceImageObject(dragImage_, place, gesture_, &error)) {
      moved_ = q - anchor_;
      refused_ = false;
    } else if (!refused_) {
      refused_ = true;
      emit message(tr("Not moved: %1").arg(error));
    }
    return;
  }
  if (dragLamp_.empty() && dragObject_.empty()) return;
  glm::dvec3 q;
  if (!rayPlane(pick, planePoint_, planeNormal_, q)) return;
  const glm::dvec3 step = (q - anchor_) - moved_;
  if (glm::length(step) < 1e-4) return;
  QString error;
  const bool ok = dragLamp_.empty() ? doc_->tryMoveObject(dragObject_, step, 0.0, gesture_, &error)
                                    : doc_->tryMoveVirtualLamp(dragLamp_, step, gesture_, &error);
  if (ok) {
    moved_ += step;
    refused_ = false;
  } else if (!refused_) {  // stays at its last good place
    refused_ = true;
    emit message(tr("Not moved: %1").arg(error));
  }
}

void EditTool::release(const ViewportPick& pick) {
  if (painting_) {
    drag(pick);
    painting_ = false;
    strokeDone_ = true;
    emit message(tr("Now click the texel of %1 whose colour the painted shadow should take.")
                     .arg(QString::fromStdString(stroke_.polygon)));
    return;
  }
  drag(pick);
  if (!dragLamp_.empty() && glm::length(moved_) > 0) doc_->settleVirtualLamp(dragLamp_);
  if (!dragObject_.empty()) doc_->settleObject(dragObject_);
  dragLamp_.clear();
  dragObject_.clear();
  dragImage_.clear();
}

}  // namespace relume
