#pragma once
// Editing the scene with the mouse in the viewport: placing a virtual lamp on the surface clicked
// (an emissive square 2 cm off it, facing away from it), placing a box standing on the floor or
// table clicked, and dragging lamps and objects (a lamp along the surface it sits on, an object
// along the surface it stands on). Each drag is one undo step; a move the library refuses (the
// object would cut a real polygon) leaves the object where it was and says why.
#include <QObject>
#include <QString>
#include <glm/vec3.hpp>
#include <string>

#include <memory>

#include "relume/ibr/ibr_object.h"
#include "relume/relight/relighter.h"
#include "relume/viewport/viewport_widget.h"

namespace relume {

class Document;

class EditTool : public QObject, public ViewportGestures {
  Q_OBJECT
 public:
  enum class Mode { Select, PlaceLamp, PlaceBox, PlaceMesh, PlaceImage, PickReference, PaintRegion };
  explicit EditTool(Document* doc, QObject* parent = nullptr);

  void setMode(Mode m);
  void setEnabled(bool on) { enabled_ = on; }  // off while a job runs
  Mode mode() const { return mode_; }
  // The box the next "place" click makes (metres; albedo in (0, 1]).
  void setBoxTemplate(const glm::dvec3& size, const glm::dvec3& albedo);
  // A mesh the next click places (Mode::PlaceMesh): standing on the point clicked, its footprint
  // centred there. `stem` names it ("chair" -> "chair 1").
  void placeMesh(const QString& stem, const VirtualObject& mesh);
  // An image-based object (its fan) the next click places (Mode::PlaceImage), standing on the
  // point clicked at `scale`; `fanFile` names it in messages.
  void placeImageObject(const QString& stem, std::shared_ptr<const ibr::ImageFan> fan, const std::string& fanFile,
                        double scale = 1.0);
  static constexpr double kLampSize = 0.3, kLampOffset = 0.02;
  // The polygon whose reference patch the next click (Mode::PickReference) chooses.
  void pickReferenceOn(const std::string& polygon);
  // Mode::PaintRegion on `polygon`: a drag paints discs of `radius` metres; after the release a
  // click on the polygon picks the element the painted occluded elements take their reflectance
  // from, and the region goes to the document (one undo step). Esc or another tool drops it.
  void paintRegionOn(const std::string& polygon, double radius);
  const ReferenceRegion& stroke() const { return stroke_; }

  bool press(const ViewportPick& pick, Qt::KeyboardModifiers mods) override;
  void drag(const ViewportPick& pick) override;
  void release(const ViewportPick& pick) override;
  Qt::CursorShape hoverCursor(const ViewportPick& pick) const override;

  // What a pick hit among the virtual things (empty when nothing virtual).
  std::string virtualLampAt(const ViewportPick& pick) const;
  std::string objectAt(const ViewportPick& pick) const;
  // The image-based object whose placed bounding box the ray meets first, if the room is not nearer.
  std::string imageObjectAt(const ViewportPick& pick) const;

 signals:
  void modeChanged(Mode m);
  void message(const QString& text);
  void selected(const QString& name);
  void strokeChanged();
  // A click in Select mode on a surface that is no virtual lamp or object (the inspector picks
  // the element there).
  void surfaceClicked(int surface, const glm::dvec3& point);  // the region being painted grew, was finished or was dropped

 private:
  Document* doc_;
  Mode mode_ = Mode::Select;
  bool enabled_ = true;
  glm::dvec3 boxSize_{0.4, 0.4, 0.4}, boxAlbedo_{0.6, 0.6, 0.6};
  std::string referencePolygon_;
  ReferenceRegion stroke_;
  double brush_ = 0.1;
  bool painting_ = false, strokeDone_ = false;
  QString meshStem_;
  VirtualObject mesh_;
  std::shared_ptr<const ibr::ImageFan> imageFan_;
  std::string imageFanFile_;
  double imageScale_ = 1.0;
  // The drag under way: what, the plane it slides on, where the cursor's ray met it at the press,
  // and how far the thing has moved since.
  std::string dragLamp_, dragObject_, dragImage_;
  glm::dvec3 planePoint_{0.0}, planeNormal_{0.0}, anchor_{0.0}, moved_{0.0};
  int gesture_ = 1000000;
  ibr::Placement imageStart_;  // where the image-based object dragged stood at the press
  bool refused_ = false;
};

}  // namespace relume
