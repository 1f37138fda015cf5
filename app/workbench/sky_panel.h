#pragma once
// The Sky panel: a daylight room (one whose scene lists measured skies) relit under any sky
// (Grosch, Eble, Mueller 2007, and beyond the paper the real room itself). Opening the room
// estimates its reflectances from the main photo under the photos' sky and solves the basis
// radiosity solutions (a job: progress, Cancel); then the user picks one of the room's measured
// skies, an HDR fisheye file or a folder of them (a time-varying sky, played back frame by
// frame), the method (near-field, the interactive irradiance volume, or the distant baseline)
// the virtual objects (a variant's, or a JSON file's) and the room's lamps switched on beside the
// daylight, and sees the photo relit — each
// render a job calling the library's DaylightRelighting::render, as `relume relight --sky` does.
#include <QImage>
#include <QString>
#include <QWidget>
#include <memory>
#include <vector>

class QCheckBox;
class QComboBox;
class QLabel;
class QListWidget;
class QPushButton;
class QToolButton;

namespace relume {

class ClickPhotoView;
class JobRunner;
class Progress;
struct Scene;
struct ImageRGB;
struct FisheyeLens;
// A daylight room made ready off the UI thread (reflectances, basis solutions): see prepare().
struct PreparedDaylight;

class SkyPanel : public QWidget {
  Q_OBJECT
 public:
  SkyPanel(JobRunner* jobs, QWidget* parent = nullptr);
  ~SkyPanel() override;

  // Does the work of opening a daylight room (any thread; cancellable through `progress`):
  // reads its main photo, estimates the reflectances, solves the basis solutions.
  static std::shared_ptr<PreparedDaylight> prepare(const Scene& scene, Progress& progress);
  // Shows a prepared room (UI thread) and renders it under the photos' sky.
  void adopt(std::shared_ptr<PreparedDaylight> room, const QString& path);
  // prepare() as a job, then adopt(). False when a job runs already.
  bool openRoom(const Scene& scene, const QString& path);
  bool isOpen() const;
  void close();
  // The open room as a Relume project at `folder`, as a job: the project written atomically with
  // the daylight session kept in it (daylight/solution.bin: the estimates and every basis
  // solution), so that opening the project estimates and solves nothing. False when no room is
  // open or a job runs; when the job ends, path() is the project and opened() is emitted.
  bool saveProject(const QString& folder);
  QString path() const;
  // A fisheye HDR file, or a folder of them (frames, in name order): added to the sky list (a
  // folder's frames as one entry, played back). False (and a message) when nothing was added.
  bool addSkyFile(const QString& file);
  bool addSkyFolder(const QString& folder);
  // The lens the fisheye files and folders added from now on are read through: a calibrated lens
  // (the JSON of `relume calibrate --fisheye`), or with an empty name the ideal one (equidistant,
  // 180 degrees, the circle filling the image). The user's camera, not the room's: it stays when
  // another room opens. False (and a message naming the file) when the file is no lens; the lens
  // chosen before stays. The room's own skies keep the lens their room gives them.
  bool setSkyLens(const QString& file);
  QString skyLens() const { return lensFile_; }
  QToolButton* lensButton() const { return lens_; }
  void setPlaying(bool on);
  bool playing() const;
  // Virtual objects and lamps from a JSON file (virtual_objects and/or virtual_lights, as
  // `relume relight --virtual-object` / `--virtual-lamp`); the lamps shine with the near-field method.
  bool addObjectsFile(const QString& file);

  // The chosen entry's virtual objects are moved by dragging their crosses in the view (each at
  // the middle of its base): the object slides over the plane it stands on to where the cursor
  // points, and is refused (a message; it stays) where it would leave the room or cut a polygon
  // (relume::checkVirtualObject). On the interactive path every move renders; otherwise the
  // release does. Save keeps the moves: a variant's entry in its variant, a file's entry (its
  // objects and lamps) as one more variant of the project, under the name the file gives it (else
  // the file's name). A moved variant keeps no truth images (they show the objects unmoved).
  std::vector<QString> objectHandles() const;

  QComboBox* skyBox() const { return sky_; }
  QComboBox* methodBox() const { return method_; }
  QComboBox* objectsBox() const { return objects_; }
  // The room's lamps, one checkable row each: checked, the lamp shines beside the daylight at the
  // radiance the room gives it (each lamp one more term of the same combination). Not for the
  // distant method (the sky alone), nor with virtual objects on the interactive path: the list is
  // then disabled, says why, and the lamps are left out.
  QListWidget* lampList() const { return lamps_; }
  QCheckBox* photoToggle() const { return showPhoto_; }
  // The interactive method drawn by OpenGL (GlDaylightRenderer: the paper's shadow maps, one per
  // window sample and per sun direction) rather than by the CPU path; checked by default, and
  // disabled (the CPU path then) when no OpenGL 3.3 context can be made. The light is the same.
  QCheckBox* gpuToggle() const { return gpu_; }
  // What the last GPU frame cost: its shadow maps and the whole draw (milliseconds; 0 before one).
  double lastGpuMapMilliseconds() const;
  double lastGpuDrawMilliseconds() const;
  ClickPhotoView* view() const { return view_; }
  // The last relit image (linear) and what the view shows (display-encoded).
  const QImage& shown() const;
  QString shownName() const;  // the sky (or frame) the shown image was rendered under
  int framesShown() const { return framesShown_; }
  int frameCount() const;

 signals:
  void message(const QString& text);
  void opened(const QString& path);

 private:
  struct State;
  void rebuild();
  // Whether the checked lamps are rendered: near-field always; the interactive path without
  // virtual objects (it lights them by daylight only); never the distant baseline (the sky alone).
  bool lampsApply() const;
  void updateLamps();  // the lamp list enabled, and its label, as lampsApply() says
  void requestRender();
  void startRender();
  void renderDone();
  void show();
  // The GPU frame of the interactive method from the library's light (UI thread); false, with
  // a message, when OpenGL cannot draw it (the CPU path is used from then on).
  struct GpuFrame;
  bool drawOnGpu(const GpuFrame& frame, ImageRGB& out);
  void updateHandles();
  void moveObject(const QString& name, QPointF pixel, bool released);
  JobRunner* jobs_;
  std::unique_ptr<State> s_;
  QLabel* summary_;
  QComboBox *sky_, *method_, *objects_;
  QListWidget* lamps_;
  QLabel* lampsLabel_;
  QPushButton *skyFile_, *skyFolder_, *objectsFile_, *play_;
  QToolButton* lens_;
  QString lensFile_;  // empty: the ideal lens
  QString withLens(const QString& why) const;  // a sky file's refusal, naming the lens it was read through
  std::unique_ptr<FisheyeLens> lensModel_;
  QCheckBox* showPhoto_;
  QCheckBox* gpu_;
  QLabel* frame_;
  ClickPhotoView* view_;
  int framesShown_ = 0;
  QString lampsNote_;    // the last word on virtual lamps left out (said once per choice, not per render)
  int generation_ = 0;  // counts rooms opened and closed: a render for an earlier one is dropped
  struct Gpu;  // the OpenGL context and renderer of the GPU path (made on first use)
  std::unique_ptr<Gpu> gpuState_;
};

}  // namespace relume
