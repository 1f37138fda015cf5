#include "sky_panel.h"

#include <QApplication>
#include <QCheckBox>
#include <QComboBox>
#include <QDir>
#include <QFileDialog>
#include <QFileInfo>
#include <QHBoxLayout>
#include <QLabel>
#include <QListWidget>
#include <QMenu>
#include <QOffscreenSurface>
#include <QOpenGLContext>
#include <QSurfaceFormat>
#include <QPushButton>
#include <QToolButton>
#include <QTimer>
#include <QVBoxLayout>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <map>
#include <numbers>
#include <optional>

#include "click_photo_view.h"
#include "job_runner.h"
#include "relume/daylight/relight.h"
#include "relume/daylight/sky.h"
#include "relume/geometry/error.h"
#include "relume/geometry/progress.h"
#include "relume/geometry/scene.h"
#include "relume/ibr/relit_objects.h"
#include "relume/image/image.h"
#include "relume/project/fisheye_lens.h"
#include "relume/project/room_io.h"
#include "relume/raytrace/ray_scene.h"
#include "relume/relight/relighter.h"
#include "relume/viewport/gl_daylight.h"

namespace relume {

namespace {
// The linear image as the photo's 8-bit encoding shows radiance: sRGB(exposure x radiance).
QImage displayed(const ImageRGB& img, double exposure) {
  QImage out(img.width, img.height, QImage::Format_RGB888);
  for (int y = 0; y < img.height; ++y) {
    uchar* row = out.scanLine(y);
    for (int x = 0; x < img.width; ++x)
      for (int c = 0; c < 3; ++c)
        row[3 * x + c] = uchar(std::lround(255.0 * linearToSrgb(float(exposure) * img.pixels[3 * (size_t(y) * img.width + x) + c])));
  }
  return out;
}
}  // namespace

// One entry of the sky list: a single sky, or a folder's frames in name order.
struct SkyEntry {
  QString label;
  std::vector<daylight::SkyRadiance> frames;
  std::vector<QString> names;  // per frame (empty: the label)
};
struct ObjectsEntry {
  QString label;
  std::vector<Polygon> polygons;
  std::vector<daylight::BasisLamp> lamps;  // virtual lamps (near-field only)
  // An entry made from one of the room's variants: which (-1: a file added), each virtual
  // object's group, and how far each group has been dragged since (saved into the variant).
  int variant = -1;
  std::vector<std::string> groups;
  std::map<std::string, glm::dvec3> moved;
  // An entry from a file: the file's variant, its files named absolutely (a save makes it a
  // variant of the project, as moved, so that what the user placed and dragged is kept).
  std::optional<Variant> fromFile;
  // Its image-based objects (fan entries), lit by daylight only and drawn after the room's render
  // (ibr::drawImageObjectsInDaylight, as relume relight --sky draws them) or by the OpenGL view.
  std::vector<ibr::ImageObject> images;
};

namespace {
// A variant's objects moved as an entry's were dragged (each object by its group's move). Its
// images of the room under that lighting show the objects where they were: a moved variant
// keeps none (a stale truth would be scored against).
void applyMoves(Variant& v, const ObjectsEntry& e) {
  for (size_t k = 0; k < v.virtualObjects.size() && k < e.groups.size(); ++k) {
    const auto it = e.moved.find(e.groups[k]);
    if (it == e.moved.end() || glm::length(it->second) == 0) continue;
    v.file.clear();
    v.hdr.clear();
    VirtualBox& b = v.virtualObjects[k];
    b.boxMin += it->second;
    b.boxMax += it->second;
    b.position += it->second;
    for (auto& face : b.mesh)
      for (auto& q : face) q += it->second;
  }
}

// `v` as read from `file`, with every file it names made absolute (a project copies them in).
Variant absoluteFiles(Variant v, const QString& file) {
  const QDir dir = QFileInfo(file).absoluteDir();
  auto abs = [&](std::string& rel) {
    if (!rel.empty()) rel = QDir::cleanPath(dir.absoluteFilePath(QString::fromStdString(rel))).toStdString();
  };
  for (auto& l : v.virtualLamps) abs(l.photometryFile);
  for (auto& b : v.virtualObjects) abs(b.fan);
  abs(v.file);
  abs(v.hdr);
  return v;
}
}  // namespace

// A variant's (or file's) objects and virtual lamps as one entry. Lamps daylight cannot light (a
// photometric one) are left out beside objects, and `lampsLeftOut` says why; without objects the
// error is the entry's.
// A room's own variant (`variant` >= 0) names its fans from the room's folder (Scene::baseDir).
static ObjectsEntry objectsEntry(const Scene& room, const QString& label, const Variant& v, const std::string& file,
                                 QString& lampsLeftOut, int variant = -1) {
  ObjectsEntry entry{label, {}, {}, variant, {}, {}, {}, {}};
  // Boxes and meshes for the daylight path, image-based objects apart (drawn after the render).
  Variant polygonal = v;
  std::erase_if(polygonal.virtualObjects, [](const VirtualBox& b) { return !b.fan.empty(); });
  std::vector<std::string> polygonGroups;
  entry.polygons = daylight::variantObjects(room, polygonal, file, &polygonGroups);
  // (A fan named as a box or mesh of the entry gets its place: each object is dragged and saved
  // by its name.)
  ibr::appendImageObjects(v, file, entry.images, variant >= 0 ? room.baseDir : std::string(), polygonGroups);
  for (const auto& o : entry.images) ibr::checkImageObject(room, o);
  // Each virtual object's group, in the variant's order (what the panel drags and a save moves):
  // a box's or mesh's faces' group, a fan's name.
  size_t nextPolygonal = 0, nextImage = 0;
  for (const VirtualBox& b : v.virtualObjects) {
    if (b.fan.empty() && nextPolygonal < polygonGroups.size()) entry.groups.push_back(polygonGroups[nextPolygonal++]);
    else if (!b.fan.empty() && nextImage < entry.images.size()) entry.groups.push_back(entry.images[nextImage++].name);
  }
  try {
    entry.lamps = daylight::variantLamps(v, file);
  } catch (const std::exception& e) {
    if (entry.polygons.empty() && entry.images.empty()) throw;
    lampsLeftOut = QString::fromUtf8(e.what());
  }
  return entry;
}

// Entry o of `objects` if there is one (the combo box's current index may be -1).
static const ObjectsEntry* entryAt(const std::vector<ObjectsEntry>& objects, int o) {
  return o >= 0 && size_t(o) < objects.size() ? &objects[size_t(o)] : nullptr;
}
static bool hasImages(const ObjectsEntry* e) { return e && !e->images.empty(); }

// A daylight room made ready off the UI thread: nothing in adopt() can fail.
struct PreparedDaylight {
  Scene scene;
  std::shared_ptr<daylight::DaylightRelighting> relit;
  double exposure = 1.0;
  QImage photoShown;
  std::vector<SkyEntry> skies;
  std::vector<ObjectsEntry> objects;
  QStringList notes;  // what the user should hear (a clipped sun, a variant left out)
};

struct SkyPanel::State {
  std::unique_ptr<Scene> scene;
  QString path;
  std::shared_ptr<daylight::DaylightRelighting> relit;
  double exposure = 1.0;
  daylight::SkyRegions cells{64};
  std::vector<SkyEntry> skies;
  std::vector<ObjectsEntry> objects;
  size_t frame = 0;  // within a folder's frames
  bool pending = false, rendering = false, playing = false;
  QImage shown, photoShown;
  QString lastFrame;   // the name of what `shown` shows
  int lastIndex = 0, lastCount = 1;  // its frame and its sky's frame count
  double lastSeconds = 0;
  bool stale = false;  // the last render did not finish: `shown` is an earlier setting's
  Camera camera;       // the main photo's (the view shows its image)
  std::unique_ptr<RayScene> roomRays;  // the room's polygons, for what the cursor points at
  bool refused = false;    // a move of the drag under way was refused (said once per drag)
  bool dragMoved = false;  // the drag under way has moved its object
};

// What the GPU path draws, made by the library off the UI thread.
struct SkyPanel::GpuFrame {
  daylight::InteractiveSky light;  // when hasLight (else the renderer holds lightVersion's)
  bool hasLight = false;
  unsigned lightVersion = 0;
  std::vector<Polygon> objects;
  daylight::ObjectIndirect indirect;
  daylight::ShadowReach reach;
  std::vector<std::vector<glm::dvec3>> room;
  Camera camera;
  // Image-based objects with their daylight and their drawn views' tables (made by the library
  // while its irradiance volume holds this sky).
  std::vector<ibr::ImageObject> images;
  std::vector<ibr::ObjectLighting> imageLights;
  std::vector<ibr::DrawnTables> imageTables;
};

struct SkyPanel::Gpu {
  QOffscreenSurface surface;
  QOpenGLContext context;
  std::unique_ptr<GlDaylightRenderer> renderer;
  int generation = -1;  // the room the renderer holds
  unsigned lightVersion = ~0u;  // and the room's light (DaylightRelighting::roomVersion)
  bool failed = false;
  double mapMs = 0, drawMs = 0;
  ~Gpu() {  // the renderer's GL objects go with its own context current
    if (renderer && context.makeCurrent(&surface)) {
      renderer.reset();
      context.doneCurrent();
    }
  }
};

namespace {
// A sky's warning for the user, or nothing.
QString clippedNote(const daylight::SkyRadiance& sky, const QString& name) {
  if (!sky.sun.found || !sky.sun.clipped) return QString();
  return sky.sun.colourFromUnclipped
             ? SkyPanel::tr("%1: the sun's pixels are clipped (at 65504, half float's largest value, or saturated): its light is "
                            "understated (its colour is taken from its pixels that did not clip).")
                   .arg(name)
             : SkyPanel::tr("%1: the sun's pixels are clipped (at 65504, half float's largest value, or saturated): its light is "
                            "understated and its colour shifted.")
                   .arg(name);
}
}  // namespace

SkyPanel::SkyPanel(JobRunner* jobs, QWidget* parent) : QWidget(parent), jobs_(jobs), s_(std::make_unique<State>()) {
  auto* layout = new QVBoxLayout(this);
  summary_ = new QLabel(this);
  summary_->setWordWrap(true);
  layout->addWidget(summary_);
  auto* skyRow = new QHBoxLayout;
  skyRow->addWidget(new QLabel(tr("Sky"), this));
  sky_ = new QComboBox(this);
  sky_->setToolTip(tr("The room's measured skies, and the fisheye images or folders you added"));
  skyRow->addWidget(sky_, 1);
  skyFile_ = new QPushButton(tr("Image…"), this);
  skyFile_->setToolTip(tr("An HDR fisheye taken outside looking up (equidistant, 180°, image up = +Y)"));
  skyFolder_ = new QPushButton(tr("Folder…"), this);
  skyFolder_->setToolTip(tr("A folder of HDR fisheyes: a time-varying sky, played back in name order"));
  lens_ = new QToolButton(this);
  lens_->setPopupMode(QToolButton::InstantPopup);
  lens_->setToolTip(tr("The lens the fisheye images and folders you add are read through: the ideal one (equidistant, "
                       "180°, the circle filling the image) or your sky camera's, calibrated with `relume calibrate "
                       "--fisheye`"));
  {
    auto* menu = new QMenu(lens_);
    menu->addAction(tr("Calibrated lens…"), this, [this] {
      const QString f = QFileDialog::getOpenFileName(this, tr("Calibrated fisheye lens"), QString(), tr("JSON (*.json)"));
      if (!f.isEmpty()) setSkyLens(f);
    });
    menu->addAction(tr("Ideal lens (equidistant, 180°)"), this, [this] { setSkyLens(QString()); });
    lens_->setMenu(menu);
  }
  lensModel_ = std::make_unique<FisheyeLens>();
  setSkyLens(QString());
  skyRow->addWidget(skyFile_);
  skyRow->addWidget(skyFolder_);
  skyRow->addWidget(lens_);
  layout->addLayout(skyRow);
  auto* methodRow = new QHBoxLayout;
  methodRow->addWidget(new QLabel(tr("Method"), this));
  method_ = new QComboBox(this);
  method_->addItem(tr("Near-field (basis solutions)"));
  method_->addItem(tr("Interactive (irradiance volume)"));
  method_->addItem(tr("Distant (sky at infinity, for comparison)"));
  method_->setToolTip(tr("Near-field: the objects solved into every basis. Interactive: the paper's irradiance volume and "
                         "64 samples through the windows, nothing solved again. Distant: the baseline without windows."));
  methodRow->addWidget(method_, 1);
  layout->addLayout(methodRow);
  auto* objectsRow = new QHBoxLayout;
  objectsRow->addWidget(new QLabel(tr("Virtual objects and lamps"), this));
  objects_ = new QComboBox(this);
  objectsRow->addWidget(objects_, 1);
  objectsFile_ = new QPushButton(tr("File…"), this);
  objectsFile_->setToolTip(tr("A JSON file with virtual_objects (boxes or OBJ meshes with their albedo) and/or "
                              "virtual_lights (lamps, lit with the near-field method)"));
  objectsRow->addWidget(objectsFile_);
  layout->addLayout(objectsRow);
  lampsLabel_ = new QLabel(tr("Lamps on beside the daylight"), this);
  layout->addWidget(lampsLabel_);
  lamps_ = new QListWidget(this);
  lamps_->setToolTip(tr("Check a lamp to switch it on at the radiance the room gives it (the photos are taken with the "
                        "lamps off)"));
  lamps_->setMaximumHeight(4 * lamps_->fontMetrics().height() + 12);
  layout->addWidget(lamps_);
  auto* playRow = new QHBoxLayout;
  play_ = new QPushButton(tr("Play"), this);
  play_->setCheckable(true);
  play_->setToolTip(tr("Play a folder's skies back, one frame after another"));
  gpu_ = new QCheckBox(tr("OpenGL"), this);
  gpu_->setChecked(true);
  gpu_->setEnabled(false);
  gpu_->setToolTip(tr("Draw the interactive method with OpenGL: a shadow map per sample through the windows and per "
                      "direction of the sun's disc, as in the paper (the same light as the CPU path, drawn faster)"));
  showPhoto_ = new QCheckBox(tr("Original photo"), this);
  showPhoto_->setToolTip(tr("Show the photograph as taken, to compare"));
  frame_ = new QLabel(this);
  playRow->addWidget(play_);
  playRow->addWidget(showPhoto_);
  playRow->addWidget(gpu_);
  playRow->addWidget(frame_, 1);
  layout->addLayout(playRow);
  view_ = new ClickPhotoView(this);
  view_->setMinimumSize(320, 240);
  layout->addWidget(view_, 1);

  auto rerender = [this] {
    s_->frame = 0;
    if (frameCount() <= 1) setPlaying(false);
    requestRender();
  };
  connect(sky_, qOverload<int>(&QComboBox::currentIndexChanged), this, rerender);
  connect(method_, qOverload<int>(&QComboBox::currentIndexChanged), this, rerender);
  connect(objects_, qOverload<int>(&QComboBox::currentIndexChanged), this, rerender);
  connect(lamps_, &QListWidget::itemChanged, this, [this] { requestRender(); });
  connect(method_, qOverload<int>(&QComboBox::currentIndexChanged), this, &SkyPanel::updateLamps);
  connect(objects_, qOverload<int>(&QComboBox::currentIndexChanged), this, &SkyPanel::updateLamps);
  connect(showPhoto_, &QCheckBox::toggled, this, &SkyPanel::show);
  connect(gpu_, &QCheckBox::toggled, this, [this] { requestRender(); });
  connect(method_, qOverload<int>(&QComboBox::currentIndexChanged), this,
          [this](int m) { gpu_->setEnabled(m == 1 && !(gpuState_ && gpuState_->failed)); });
  connect(objects_, qOverload<int>(&QComboBox::currentIndexChanged), this, &SkyPanel::updateHandles);
  connect(view_, &ClickPhotoView::markerClicked, this, [this] { s_->refused = s_->dragMoved = false; });
  connect(view_, &ClickPhotoView::markerMoved, this, [this](const QString& n, QPointF px) { moveObject(n, px, false); });
  connect(view_, &ClickPhotoView::markerDragged, this, [this](const QString& n, QPointF px) { moveObject(n, px, true); });
  connect(play_, &QPushButton::toggled, this, &SkyPanel::setPlaying);
  connect(skyFile_, &QPushButton::clicked, this, [this] {
    const QString f = QFileDialog::getOpenFileName(this, tr("Sky image"), QString(), tr("HDR images (*.exr *.hdr)"));
    if (!f.isEmpty()) addSkyFile(f);
  });
  connect(skyFolder_, &QPushButton::clicked, this, [this] {
    const QString f = QFileDialog::getExistingDirectory(this, tr("Folder of sky images"));
    if (!f.isEmpty()) addSkyFolder(f);
  });
  connect(objectsFile_, &QPushButton::clicked, this, [this] {
    const QString f = QFileDialog::getOpenFileName(this, tr("Virtual objects"), QString(), tr("JSON (*.json)"));
    if (!f.isEmpty()) addObjectsFile(f);
  });
  connect(jobs_, &JobRunner::finished, this, [this](bool ok, bool, const QString& why) {
    const bool mine = s_->rendering;
    s_->rendering = false;
    if (mine && !ok) {
      // Cancelled or failed: playback stops, nothing queued starts, and the view says that its
      // image is an earlier setting's.
      s_->playing = false;
      s_->pending = false;
      s_->stale = true;
      const QSignalBlocker block(play_);
      play_->setChecked(false);
      frame_->setText(tr("Not rendered (%1): the image shows the setting before").arg(why));
    }
    // After every other listener has seen this job end (the main window hides its progress bar).
    QTimer::singleShot(0, this, &SkyPanel::renderDone);
  });
  rebuild();
}

SkyPanel::~SkyPanel() = default;

double SkyPanel::lastGpuMapMilliseconds() const { return gpuState_ ? gpuState_->mapMs : 0; }
double SkyPanel::lastGpuDrawMilliseconds() const { return gpuState_ ? gpuState_->drawMs : 0; }

bool SkyPanel::drawOnGpu(const GpuFrame& frame, ImageRGB& out) {
  if (!gpuState_) gpuState_ = std::make_unique<Gpu>();
  Gpu& g = *gpuState_;
  if (g.failed) return false;
  try {
    if (!g.renderer) {
      QSurfaceFormat f;
      f.setVersion(3, 3);
      f.setProfile(QSurfaceFormat::CoreProfile);
      g.context.setFormat(f);
      if (!g.context.create()) throw Error("", "OpenGL", "no OpenGL 3.3 core context can be made");
      g.surface.setFormat(g.context.format());
      g.surface.create();
      if (!g.context.makeCurrent(&g.surface)) throw Error("", "OpenGL", "the context cannot be made current");
      g.renderer = std::make_unique<GlDaylightRenderer>();
      g.renderer->initialize();
    } else if (!g.context.makeCurrent(&g.surface)) {
      throw Error("", "OpenGL", "the context cannot be made current");
    }
    if (g.generation != generation_) {
      if (frame.room.empty() || !frame.hasLight) throw Error("", "daylight view", "a frame came without its room");
      g.renderer->setRoom(frame.room, frame.camera);
      g.generation = generation_;
      g.lightVersion = ~0u;
    }
    if (frame.hasLight) {
      g.renderer->setSky(frame.light);
      g.lightVersion = frame.lightVersion;
    } else if (g.lightVersion != frame.lightVersion) {
      throw Error("", "daylight view", "a frame came without the sky's light");
    }
    g.renderer->setImageObjects(frame.images, frame.imageLights, frame.imageTables);
    g.renderer->setObjects(frame.objects, frame.indirect, frame.reach);
    out = g.renderer->renderLinear();
    g.mapMs = g.renderer->lastMapMilliseconds();
    g.drawMs = g.renderer->lastDrawMilliseconds();
    g.context.doneCurrent();
    return true;
  } catch (const std::exception& e) {
    g.failed = true;
    if (g.context.makeCurrent(&g.surface)) {
      g.renderer.reset();
      g.context.doneCurrent();
    } else {
      g.renderer.reset();  // (no context: its GL objects go with it)
    }
    gpu_->setChecked(false);
    gpu_->setEnabled(false);
    emit message(tr("OpenGL cannot draw the daylight view (%1): the CPU path draws it").arg(QString::fromUtf8(e.what())));
    return false;
  }
}

bool SkyPanel::isOpen() const { return s_->relit != nullptr; }
QString SkyPanel::path() const { return s_->path; }

bool SkyPanel::saveProject(const QString& folder) {
  if (!isOpen() || jobs_->busy()) return false;
  const QString abs = QFileInfo(folder).absoluteFilePath();
  // The room as it is shown: a variant's objects where they were dragged to, and each file's
  // objects and lamps as one more variant (named after the file, apart from the room's own), so
  // that the project keeps what the user placed.
  Scene shown = *s_->scene;
  for (const ObjectsEntry& e : s_->objects)
    if (e.variant >= 0 && size_t(e.variant) < shown.variants.size()) applyMoves(shown.variants[size_t(e.variant)], e);
  for (const ObjectsEntry& e : s_->objects) {
    if (!e.fromFile) continue;
    Variant v = *e.fromFile;
    applyMoves(v, e);
    auto taken = [&](const std::string& name) {
      return std::any_of(shown.variants.begin(), shown.variants.end(), [&](const Variant& o) { return o.name == name; });
    };
    const std::string base = v.name.empty() ? "objects" : v.name;
    v.name = base;
    for (int k = 2; taken(v.name); ++k) v.name = base + " " + std::to_string(k);
    // Its sky, if it names one, only when the room has it (a project names the room's skies).
    if (std::none_of(shown.skies.begin(), shown.skies.end(), [&](const SkyCapture& c) { return c.name == v.sky; })) v.sky.clear();
    // A lamp whose photometric file has gone since the file was added is left out, and said
    // (the save would fail on it every time).
    for (size_t l = v.virtualLamps.size(); l-- > 0;)
      if (!v.virtualLamps[l].photometryFile.empty() && !QFileInfo(QString::fromStdString(v.virtualLamps[l].photometryFile)).isFile()) {
        emit message(tr("Virtual lamp %1 of %2 is not saved: its photometric file %3 is gone")
                         .arg(QString::fromStdString(v.virtualLamps[l].name), e.label,
                              QString::fromStdString(v.virtualLamps[l].photometryFile)));
        v.virtualLamps.erase(v.virtualLamps.begin() + long(l));
        if (l < v.virtualLampPolygons.size()) v.virtualLampPolygons.erase(v.virtualLampPolygons.begin() + long(l));
      }
    // So is an image-based object whose fan file has gone (a project names only its own files).
    for (size_t k = v.virtualObjects.size(); k-- > 0;)
      if (!v.virtualObjects[k].fan.empty() && !QFileInfo(QString::fromStdString(v.virtualObjects[k].fan)).isFile()) {
        emit message(tr("Image-based object %1 of %2 is not saved: its fan file %3 is gone")
                         .arg(QString::fromStdString(v.virtualObjects[k].name), e.label,
                              QString::fromStdString(v.virtualObjects[k].fan)));
        v.virtualObjects.erase(v.virtualObjects.begin() + long(k));
      }
    shown.variants.push_back(std::move(v));
  }
  auto scene = std::make_shared<const Scene>(std::move(shown));
  auto relit = s_->relit;
  const int generation = generation_;
  return jobs_->start(tr("Saving %1").arg(QFileInfo(abs).fileName()), [this, scene, relit, abs, generation](Progress& progress) {
    relume::saveProject(*scene, abs.toStdString(), progress, [&](const std::string& staging) {
      if (!QDir().mkpath(QString::fromStdString(staging + "/daylight")))
        throw Error(staging + "/daylight", "", "cannot create the folder");
      try {
        relit->save(staging + "/daylight/solution.bin");
      } catch (const Error& e) {  // named as the user knows it, not by the staging folder
        throw Error(abs.toStdString() + "/daylight/solution.bin", e.element(), e.problem());
      }
    });
    return JobRunner::Continuation([this, abs, generation] {
      if (generation != generation_) return;  // another room was opened meanwhile
      s_->path = abs;
      emit message(tr("Saved %1 (its daylight session kept: it opens without solving again)").arg(abs));
      emit opened(abs);
    });
  });
}
int SkyPanel::frameCount() const {
  const int k = sky_->currentIndex();
  return k >= 0 && size_t(k) < s_->skies.size() ? int(s_->skies[size_t(k)].frames.size()) : 0;
}
const QImage& SkyPanel::shown() const { return s_->shown; }
QString SkyPanel::shownName() const { return s_->lastFrame; }
bool SkyPanel::playing() const { return s_->playing; }

void SkyPanel::close() {
  s_ = std::make_unique<State>();
  ++generation_;  // a render still running for the room before is not shown
  framesShown_ = 0;
  {
    const QSignalBlocker b1(sky_), b2(objects_), b3(method_), b4(play_), b5(showPhoto_), b6(lamps_);
    sky_->clear();
    objects_->clear();
    lamps_->clear();
    method_->setCurrentIndex(0);
    play_->setChecked(false);
    showPhoto_->setChecked(false);
  }
  view_->setImage(QImage(), QString());
  frame_->clear();
  rebuild();
  updateHandles();  // none
}

std::shared_ptr<PreparedDaylight> SkyPanel::prepare(const Scene& scene, Progress& progress) {
  auto room = std::make_shared<PreparedDaylight>();
  room->scene = scene;
  const Photo* main = scene.findPhoto(scene.mainPhoto);
  if (!main) throw Error(scene.sourceFile, "main_photo", "the room names no main photo");
  if (main->hdr.empty()) throw Error(scene.sourceFile, "photo " + main->name, "daylight relighting needs its linear (EXR) image");
  const ImageRGB photo = readImageLinear(main->hdr.front() == '/' ? main->hdr : scene.baseDir + "/" + main->hdr);
  room->exposure = photoExposure(scene, *main);
  room->photoShown = displayed(photo, room->exposure);
  const daylight::SkyRegions cells(64);
  for (const auto& c : scene.skies) {
    SkyEntry sky{QString::fromStdString(c.name), {daylight::averageSky(daylight::readRoomSky(scene, c.name), cells)}, {}};
    if (const QString note = clippedNote(sky.frames.front(), sky.label); !note.isEmpty()) room->notes << note;
    if (c.name == scene.photoSky) sky.label = tr("%1 (the photos' sky)").arg(sky.label);
    room->skies.push_back(std::move(sky));
  }
  room->objects.push_back({tr("None"), {}, {}, -1, {}, {}, {}, {}});
  for (const auto& v : scene.variants) {
    if (v.virtualObjects.empty() && v.virtualLamps.empty()) continue;
    try {
      QString lampsLeftOut;
      room->objects.push_back(objectsEntry(scene, tr("As in variant %1").arg(QString::fromStdString(v.name)), v, scene.sourceFile,
                                           lampsLeftOut, int(&v - scene.variants.data())));
      if (!lampsLeftOut.isEmpty())
        room->notes << tr("Variant %1: its virtual lamps are left out: %2").arg(QString::fromStdString(v.name), lampsLeftOut);
    } catch (const std::exception& e) {
      room->notes << tr("Variant %1 left out: %2").arg(QString::fromStdString(v.name), QString::fromUtf8(e.what()));
    }
  }
  const daylight::SkyRadiance photoSky = daylight::averageSky(daylight::readRoomSky(scene, scene.photoSky), cells);
  std::string how;
  room->relit = daylight::openDaylightRelighting(scene, photo, main->camera, photoSky, daylight::BasisOptions{}, progress, &how);
  if (!how.empty()) room->notes << QString::fromStdString(how);
  return room;
}

void SkyPanel::adopt(std::shared_ptr<PreparedDaylight> room, const QString& path) {
  close();  // nothing of an earlier room stays: lists, choices, image, playback
  s_->scene = std::make_unique<Scene>(std::move(room->scene));
  s_->path = path;
  s_->relit = room->relit;
  s_->exposure = room->exposure;
  s_->photoShown = room->photoShown;
  s_->skies = std::move(room->skies);
  s_->objects = std::move(room->objects);
  if (const Photo* main = s_->scene->findPhoto(s_->scene->mainPhoto)) s_->camera = main->camera;
  {
    std::vector<std::vector<glm::dvec3>> polygons;
    for (const auto& p : s_->scene->polygons) polygons.push_back(p.vertices);
    s_->roomRays = std::make_unique<RayScene>(polygons);
  }
  rebuild();
  {
    const QSignalBlocker block(sky_);
    for (size_t k = 0; k < s_->scene->skies.size(); ++k)
      if (s_->scene->skies[k].name == s_->scene->photoSky) sky_->setCurrentIndex(int(k));
  }
  show();
  QTimer::singleShot(100, view_, &ClickPhotoView::fit);  // once the window has laid the panel out
  for (const QString& note : room->notes) emit message(note);
  emit opened(path);
  QTimer::singleShot(0, this, &SkyPanel::requestRender);  // once the opening job has ended
}

bool SkyPanel::openRoom(const Scene& scene, const QString& path) {
  if (jobs_->busy()) return false;
  auto room = std::make_shared<Scene>(scene);
  return jobs_->start(tr("Preparing daylight for %1").arg(QFileInfo(path).fileName()), [this, room, path](Progress& progress) {
    std::shared_ptr<PreparedDaylight> prepared = prepare(*room, progress);
    return JobRunner::Continuation([this, prepared, path] { adopt(prepared, path); });
  });
}

bool SkyPanel::setSkyLens(const QString& file) {
  if (file.isEmpty()) {
    *lensModel_ = FisheyeLens{};
  } else {
    try {
      *lensModel_ = readFisheyeLens(file.toStdString());
    } catch (const std::exception& e) {
      emit message(QString::fromUtf8(e.what()));
      return false;
    }
  }
  lensFile_ = file;
  lens_->setText(file.isEmpty() ? tr("Lens: ideal") : tr("Lens: %1").arg(QFileInfo(file).fileName()));
  return true;
}

QString SkyPanel::withLens(const QString& why) const {
  return lensFile_.isEmpty() ? why : tr("%1 (read through the lens %2)").arg(why, QFileInfo(lensFile_).fileName());
}

bool SkyPanel::addSkyFile(const QString& file) {
  if (!isOpen()) return false;
  try {
    const auto sky = daylight::averageSky(daylight::readFisheyeLookingUp(file.toStdString(), *lensModel_), s_->cells);
    s_->skies.push_back({QFileInfo(file).completeBaseName(), {sky}, {QFileInfo(file).completeBaseName()}});
    if (const QString note = clippedNote(sky, QFileInfo(file).fileName()); !note.isEmpty()) emit message(note);
  } catch (const std::exception& e) {
    emit message(withLens(QString::fromUtf8(e.what())));
    return false;
  }
  rebuild();
  sky_->setCurrentIndex(sky_->count() - 1);
  return true;
}

bool SkyPanel::addSkyFolder(const QString& folder) {
  if (!isOpen()) return false;
  const QStringList names = QDir(folder).entryList({"*.exr", "*.EXR", "*.hdr", "*.HDR"}, QDir::Files, QDir::Name);
  if (names.isEmpty()) {
    emit message(tr("%1 holds no HDR sky image (.exr or .hdr)").arg(folder));
    return false;
  }
  SkyEntry entry{tr("%1 (frames: %2)").arg(QFileInfo(folder).fileName()).arg(names.size()), {}, {}};
  QStringList notes;
  QApplication::setOverrideCursor(Qt::WaitCursor);
  try {
    for (const QString& n : names) {
      const std::string file = QDir(folder).filePath(n).toStdString();
      entry.frames.push_back(daylight::averageSky(daylight::readFisheyeLookingUp(file, *lensModel_), s_->cells));
      entry.names.push_back(QFileInfo(n).completeBaseName());
      if (const QString note = clippedNote(entry.frames.back(), n); !note.isEmpty()) notes << note;
    }
  } catch (const std::exception& e) {
    QApplication::restoreOverrideCursor();
    emit message(withLens(QString::fromUtf8(e.what())));  // names the file and the problem; nothing added
    return false;
  }
  QApplication::restoreOverrideCursor();
  for (const QString& note : notes) emit message(note);
  s_->skies.push_back(std::move(entry));
  rebuild();
  sky_->setCurrentIndex(sky_->count() - 1);
  return true;
}

bool SkyPanel::addObjectsFile(const QString& file) {
  if (!isOpen()) return false;
  try {
    const Variant v = readVariantFile(file.toStdString());
    if (v.virtualObjects.empty() && v.virtualLamps.empty())
      throw Error(file.toStdString(), "virtual_objects", "lists no virtual object and no virtual lamp (virtual_lights)");
    QString lampsLeftOut;
    s_->objects.push_back(objectsEntry(*s_->scene, QFileInfo(file).fileName(), v, file.toStdString(), lampsLeftOut));
    s_->objects.back().fromFile = absoluteFiles(v, file);
    if (!lampsLeftOut.isEmpty())
      emit message(tr("The virtual lamps of %1 are left out: %2").arg(s_->objects.back().label, lampsLeftOut));
  } catch (const std::exception& e) {
    emit message(QString::fromUtf8(e.what()));
    return false;
  }
  rebuild();
  objects_->setCurrentIndex(objects_->count() - 1);
  return true;
}

void SkyPanel::setPlaying(bool on) {
  s_->playing = on && frameCount() > 1;
  const QSignalBlocker block(play_);
  play_->setChecked(s_->playing);
  if (s_->playing && !s_->rendering) requestRender();
}

void SkyPanel::rebuild() {
  const QSignalBlocker b1(sky_), b2(objects_);
  const int skyAt = sky_->currentIndex(), objectsAt = objects_->currentIndex();
  sky_->clear();
  for (const auto& s : s_->skies) sky_->addItem(s.label);
  objects_->clear();
  for (const auto& o : s_->objects) objects_->addItem(o.label);
  if (skyAt >= 0 && skyAt < sky_->count()) sky_->setCurrentIndex(skyAt);
  if (objectsAt >= 0 && objectsAt < objects_->count()) objects_->setCurrentIndex(objectsAt);
  const bool open = isOpen();
  for (QWidget* w : std::initializer_list<QWidget*>{sky_, method_, objects_, skyFile_, skyFolder_, objectsFile_, play_, showPhoto_})
    w->setEnabled(open);
  // The room's lamps (kept checked as they were while the room stays open).
  const size_t lampCount = open ? s_->scene->lamps.size() : 0;
  if (size_t(lamps_->count()) != lampCount) {
    const QSignalBlocker block(lamps_);
    lamps_->clear();
    for (size_t l = 0; l < lampCount; ++l) {
      const Lamp& lamp = s_->scene->lamps[l];
      auto* item = new QListWidgetItem(tr("Lamp %1").arg(QString::fromStdString(lamp.name)), lamps_);
      const bool known = std::max({lamp.radiance.x, lamp.radiance.y, lamp.radiance.z}) > 0;
      item->setFlags(known ? Qt::ItemIsEnabled | Qt::ItemIsUserCheckable : Qt::ItemIsUserCheckable);
      item->setCheckState(Qt::Unchecked);
      if (!known) item->setToolTip(tr("The room gives no radiance for this lamp, and a daylight photo (lamps off) cannot tell it"));
    }
  }
  lampsLabel_->setVisible(lampCount > 0);
  lamps_->setVisible(lampCount > 0);
  updateLamps();
  if (!open) {
    summary_->setText(tr("Open a daylight room (one whose scene lists measured skies and windows) to relight it under "
                         "another sky."));
    frame_->clear();
    return;
  }
  summary_->setText(tr("%1 — measured skies: %2; reflectances estimated from the main photo under %3.")
                        .arg(QFileInfo(s_->path).fileName())
                        .arg(s_->scene->skies.size())
                        .arg(QString::fromStdString(s_->scene->photoSky)));
}

void SkyPanel::updateLamps() {
  lamps_->setEnabled(isOpen() && lampsApply());
  const ObjectsEntry* chosen = isOpen() ? entryAt(s_->objects, objects_->currentIndex()) : nullptr;
  const bool images = hasImages(chosen);
  lampsLabel_->setText(method_->currentIndex() == 2 ? tr("Lamps (left out: the distant method is the sky alone)")
                       : images                    ? tr("Lamps (left out: image-based objects are lit by daylight only)")
                       : !lampsApply()             ? tr("Lamps (left out: the interactive path lights virtual objects by "
                                                        "daylight only; choose near-field)")
                                                   : tr("Lamps on beside the daylight"));
  // Virtual lamps are lit with the near-field method only, and not beside image-based objects;
  // image-based objects by the near-field and interactive methods: said when the choice leaves
  // them out.
  const bool virtualLamps = chosen && !chosen->lamps.empty();
  const QString note =
      images && method_->currentIndex() == 2
          ? tr("The image-based objects of %1 are left out: they are drawn by the near-field and interactive methods")
                .arg(chosen->label)
      : virtualLamps && images
          ? tr("The virtual lamps of %1 are left out: its image-based objects are lit by daylight only").arg(chosen->label)
      : virtualLamps && method_->currentIndex() != 0
          ? tr("The virtual lamps of %1 are left out: they are lit with the near-field method only").arg(chosen->label)
          : QString();
  if (note != lampsNote_ && !note.isEmpty()) emit message(note);
  lampsNote_ = note;
}

bool SkyPanel::lampsApply() const {
  const ObjectsEntry* e = entryAt(s_->objects, objects_->currentIndex());
  const bool objects = e && !e->polygons.empty();
  return !hasImages(e) && (method_->currentIndex() == 0 || (method_->currentIndex() == 1 && !objects));
}

void SkyPanel::requestRender() {
  if (!isOpen()) return;
  if (s_->rendering || jobs_->busy()) {
    s_->pending = true;  // once the running job ends
    return;
  }
  startRender();
}

void SkyPanel::startRender() {
  const int k = sky_->currentIndex(), o = objects_->currentIndex();
  if (k < 0 || size_t(k) >= s_->skies.size()) return;
  const SkyEntry& entry = s_->skies[size_t(k)];
  const size_t f = s_->frame % entry.frames.size();
  const daylight::SkyRadiance sky = entry.frames[f];
  const ObjectsEntry none;
  const ObjectsEntry& chosen = o >= 0 && size_t(o) < s_->objects.size() ? s_->objects[size_t(o)] : none;
  const std::vector<Polygon> objects = chosen.polygons;
  const daylight::DaylightMethod method = method_->currentIndex() == 1   ? daylight::DaylightMethod::Volume
                                          : method_->currentIndex() == 2 ? daylight::DaylightMethod::Distant
                                                                         : daylight::DaylightMethod::NearField;
  // The lamps checked, at the radiance the room gives them (none for the distant baseline).
  std::vector<glm::dvec3> lampExitance(s_->scene->lamps.size(), glm::dvec3(0.0));
  if (lampsApply())
    for (size_t l = 0; l < lampExitance.size() && int(l) < lamps_->count(); ++l)
      if (lamps_->item(int(l))->checkState() == Qt::Checked) lampExitance[l] = std::numbers::pi * s_->scene->lamps[l].radiance;
  // Virtual lamps are lit near-field only (the interactive path lights by daylight alone).
  std::vector<daylight::BasisLamp> virtualLamps;
  if (method == daylight::DaylightMethod::NearField && chosen.images.empty()) virtualLamps = chosen.lamps;
  // Image-based objects: drawn by the near-field and interactive methods (on the CPU path after
  // the room's render).
  std::vector<ibr::ImageObject> images;
  if (method != daylight::DaylightMethod::Distant) images = chosen.images;
  const QString name = entry.names.empty() ? entry.label : entry.names[f];
  const int index = int(f), count = int(entry.frames.size()), generation = generation_;
  const double exposure = s_->exposure;
  auto relit = s_->relit;
  s_->pending = false;
  gpu_->setEnabled(method == daylight::DaylightMethod::Volume && !(gpuState_ && gpuState_->failed));
  const bool gpu = gpu_->isEnabled() && gpu_->isChecked();
  const bool heldRoom = gpuState_ && gpuState_->renderer && gpuState_->generation == generation_;
  const unsigned heldLight = heldRoom ? gpuState_->lightVersion : ~0u;
  s_->rendering = jobs_->start(tr("Relighting under %1").arg(name), [=, this](Progress& p) {
    const auto t0 = std::chrono::steady_clock::now();
    for (size_t l = 0; l < lampExitance.size(); ++l) relit->setLampExitance(int(l), lampExitance[l]);
    if (gpu) {
      // The library's light for the frame here; OpenGL draws it on the UI thread (its context's).
      // The sky's light and the room go along only when the renderer does not hold them yet (a
      // drag asks for a frame at every move, under the same sky).
      auto frame = std::make_shared<GpuFrame>();
      if (!images.empty()) {
        // Their light, as the CPU path's (ibr::drawImageObjectsInDaylight) takes it: the boxes
        // and meshes hide the window samples and the sun from them.
        Progress built(p, 0.0, 0.4), windows(p, 0.4, 0.9);
        relit->volume(built);
        relit->interactiveSky(sky, windows);  // (made once per sky; daylightAt and the frame below read it)
        std::vector<std::vector<glm::dvec3>> faces;
        for (const Polygon& o : objects) faces.push_back(o.vertices);
        const std::unique_ptr<RayScene> occluders = faces.empty() ? nullptr : std::make_unique<RayScene>(faces);
        for (const auto& im : images) {
          ibr::DisplayDaylight d = ibr::daylightForDisplay(*relit, sky, im, relit->camera().center(),
                                                           size_t(GlDaylightRenderer::imageLamps()), occluders.get());
          frame->imageLights.push_back(std::move(d.light));
          frame->imageTables.push_back(std::move(d.tables));
        }
        frame->images = images;
      }
      const daylight::InteractiveSky& light = relit->interactiveSky(sky, p);
      frame->lightVersion = relit->roomVersion();
      frame->hasLight = frame->lightVersion != heldLight;
      if (frame->hasLight) frame->light = light;
      frame->objects = objects;
      if (!heldRoom) frame->room = relit->roomPolygons();
      frame->camera = relit->camera();
      if (!objects.empty() || !images.empty()) {
        glm::dvec3 lo(1e300), hi(-1e300);
        for (const auto& o : objects)
          for (const auto& v : o.vertices) lo = glm::min(lo, v), hi = glm::max(hi, v);
        for (const auto& im : images) {
          const glm::dvec3 c = im.place.toWorld(*im.fan, im.fan->centre);
          const double r = im.fan->radius * im.place.scale;
          lo = glm::min(lo, c - r), hi = glm::max(hi, c + r);
        }
        frame->indirect = relit->objectIndirect(sky, objects);
        frame->reach = relit->shadowReach(light, 0.5 * (lo + hi), 0.5 * glm::length(hi - lo));
      }
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      return JobRunner::Continuation([=, this] {
        if (generation != generation_) return;
        ImageRGB img;
        if (!drawOnGpu(*frame, img)) {
          s_->pending = true;  // drawn again by the CPU path once this job has ended
          return;
        }
        s_->shown = displayed(img, exposure);
        s_->lastFrame = name;
        s_->lastIndex = index;
        s_->lastCount = count;
        s_->lastSeconds = seconds + gpuState_->drawMs / 1000.0;
        s_->stale = false;
        ++framesShown_;
        show();
      });
    }
    Progress room(p, 0.0, images.empty() ? 1.0 : 0.7), fans(p, images.empty() ? 1.0 : 0.7, 1.0);
    ImageRGB img = relit->render(sky, objects, method, room, virtualLamps);
    ibr::drawImageObjectsInDaylight(*relit, sky, images, img, nullptr, fans, objects);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    auto shown = std::make_shared<QImage>(displayed(img, exposure));  // the display encoding off the UI thread too
    return JobRunner::Continuation([=, this] {
      if (generation != generation_) return;  // another room (or none) since
      s_->shown = *shown;
      s_->lastFrame = name;
      s_->lastIndex = index;
      s_->lastCount = count;
      s_->lastSeconds = seconds;
      s_->stale = false;
      ++framesShown_;
      show();
    });
  });
  if (!s_->rendering) s_->pending = true;
}

void SkyPanel::renderDone() {
  if (!isOpen() || jobs_->busy()) return;
  if (s_->pending) {
    startRender();
    return;
  }
  if (s_->playing && frameCount() > 1) {
    s_->frame = (s_->frame + 1) % size_t(frameCount());
    startRender();
  }
}

std::vector<QString> SkyPanel::objectHandles() const {
  std::vector<QString> names;
  const int o = objects_->currentIndex();
  if (!isOpen() || o < 0 || size_t(o) >= s_->objects.size()) return names;
  for (const auto& p : s_->objects[size_t(o)].polygons) {
    const QString g = QString::fromStdString(p.group);
    if (std::find(names.begin(), names.end(), g) == names.end()) names.push_back(g);
  }
  for (const auto& im : s_->objects[size_t(o)].images) names.push_back(QString::fromStdString(im.name));
  return names;
}

namespace {
// The bounds of the faces of object `group` among `faces`; false when it has none.
bool objectBounds(const std::vector<Polygon>& faces, const std::string& group, glm::dvec3& lo, glm::dvec3& hi) {
  lo = glm::dvec3(1e300);
  hi = glm::dvec3(-1e300);
  bool any = false;
  for (const auto& p : faces)
    if (p.group == group)
      for (const auto& v : p.vertices) {
        lo = glm::min(lo, v);
        hi = glm::max(hi, v);
        any = true;
      }
  return any;
}
// The bounds of image-based object `name` among `images` as placed (its mesh's box, turned); null
// when there is none of that name.
const ibr::ImageObject* imageBounds(const std::vector<ibr::ImageObject>& images, const std::string& name, glm::dvec3& lo,
                                    glm::dvec3& hi) {
  for (const auto& im : images) {
    if (im.name != name) continue;
    const ibr::ImageFan& f = *im.fan;
    lo = glm::dvec3(1e300);
    hi = glm::dvec3(-1e300);
    for (int i = 0; i < 8; ++i) {
      const glm::dvec3 c = im.place.toWorld(f, glm::dvec3(i & 1 ? f.boundsMax.x : f.boundsMin.x, i & 2 ? f.boundsMax.y : f.boundsMin.y,
                                                          i & 4 ? f.boundsMax.z : f.boundsMin.z));
      lo = glm::min(lo, c);
      hi = glm::max(hi, c);
    }
    return &im;
  }
  return nullptr;
}
}  // namespace

void SkyPanel::updateHandles() {
  std::vector<ClickPhotoView::Marker> markers;
  const int o = objects_->currentIndex();
  if (isOpen() && !showPhoto_->isChecked() && !s_->shown.isNull() && o >= 0 && size_t(o) < s_->objects.size())
    for (const QString& name : objectHandles()) {
      glm::dvec3 lo, hi;
      glm::dvec2 px;
      if (!objectBounds(s_->objects[size_t(o)].polygons, name.toStdString(), lo, hi) &&
          !imageBounds(s_->objects[size_t(o)].images, name.toStdString(), lo, hi))
        continue;
      if (s_->camera.project({0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), lo.z}, px)) markers.push_back({name, QPointF(px.x, px.y)});
    }
  view_->setToolTip(markers.empty() ? QString() : tr("Drag a virtual object's cross to move it over the floor"));
  view_->setMarkers(std::move(markers));
}

void SkyPanel::moveObject(const QString& name, QPointF pixel, bool released) {
  const int o = objects_->currentIndex();
  if (!isOpen() || o < 0 || size_t(o) >= s_->objects.size()) return;
  std::vector<Polygon>& faces = s_->objects[size_t(o)].polygons;
  const std::string group = name.toStdString();
  glm::dvec3 lo, hi;
  // An image-based object is dragged by its placement (its bounding box standing on the plane).
  const ibr::ImageObject* image = nullptr;
  if (!objectBounds(faces, group, lo, hi) && !(image = imageBounds(s_->objects[size_t(o)].images, group, lo, hi))) return;
  // Where the ray through the cursor meets the plane the object stands on.
  const glm::dvec3 eye = s_->camera.center(), dir = s_->camera.rayDirection(pixel.x(), pixel.y());
  const double t = std::abs(dir.z) > 1e-9 ? (lo.z - eye.z) / dir.z : -1;
  QString why;
  VirtualObject moved;
  glm::dvec3 step(0.0);
  // Only where the photo shows that plane: not past a wall, a window or the furniture in front.
  const RayHit seen = t > 0 ? s_->roomRays->intersect(Ray{glm::vec3(eye), glm::vec3(dir), 1e-4f, 1e30f}) : RayHit{};
  if (!(t > 0)) {
    why = tr("the cursor points above the plane %1 stands on").arg(name);
  } else if (seen.polygon >= 0 && double(seen.t) < t - 1e-3) {
    why = tr("the cursor points at %1, in front of the plane %2 stands on")
              .arg(QString::fromStdString(s_->scene->polygons[size_t(seen.polygon)].name), name);
  } else {
    step = eye + t * dir - glm::dvec3(0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), lo.z);
    step.z = 0;
    moved.name = group;
  }
  if (why.isEmpty() && image) {
    ibr::ImageObject there = *image;
    there.place.position += step;
    try {
      ibr::checkImageObject(*s_->scene, there);
    } catch (const std::exception& e) {
      why = QString::fromUtf8(e.what());
    }
  } else if (why.isEmpty()) {
    for (const auto& p : faces)
      if (p.group == group) {
        moved.albedo = p.albedo;
        std::vector<glm::dvec3> v = p.vertices;
        for (auto& q : v) q += step;
        moved.polygons.push_back(std::move(v));
      }
    try {
      checkVirtualObject(*s_->scene, moved);
      // Nor into another object of the entry.
      std::map<std::string, VirtualObject> others;
      for (const auto& p : faces)
        if (p.group != group) {
          VirtualObject& other = others[p.group];
          other.name = p.group;
          other.polygons.push_back(p.vertices);
        }
      std::vector<const VirtualObject*> list;
      for (const auto& [n, other] : others) list.push_back(&other);
      checkVirtualObjectsApart(*s_->scene, moved, list);
    } catch (const std::exception& e) {
      why = QString::fromUtf8(e.what());
    }
  }
  const bool interactive = method_->currentIndex() == 1;  // nothing solved again: every move renders
  if (!why.isEmpty()) {
    if (!s_->refused) emit message(tr("Not moved: %1").arg(why));
    s_->refused = true;  // said once per drag; the object stays at its last good place
  } else if (glm::length(step) > 1e-6) {
    if (image) {
      for (auto& im : s_->objects[size_t(o)].images)
        if (im.name == group) im.place.position += step;
    } else {
      size_t k = 0;  // the checked faces, in the order they were taken
      for (auto& p : faces)
        if (p.group == group) p.vertices = std::move(moved.polygons[k++]);
    }
    s_->objects[size_t(o)].moved[group] += step;
    s_->dragMoved = true;
    if (interactive) requestRender();
  }
  if (released) {
    if (s_->dragMoved && !interactive) requestRender();
    s_->dragMoved = s_->refused = false;
    updateHandles();  // the cross where the object is
  }
}

void SkyPanel::show() {
  if (!isOpen()) return;
  const bool photo = showPhoto_->isChecked() || s_->shown.isNull();
  view_->setImage(photo ? s_->photoShown : s_->shown, photo ? tr("photo") : s_->lastFrame);
  updateHandles();
  if (photo && !s_->shown.isNull())
    frame_->setText(tr("The photograph as taken"));
  else if (!s_->shown.isNull() && !s_->stale)
    frame_->setText(s_->lastCount > 1 ? tr("Frame %1 of %2: %3, %4 s").arg(s_->lastIndex + 1).arg(s_->lastCount).arg(s_->lastFrame).arg(s_->lastSeconds, 0, 'f', 1)
                     : s_->lastSeconds < 1 ? tr("%1, rendered in %2 ms").arg(s_->lastFrame).arg(std::lround(1000 * s_->lastSeconds))
                                           : tr("%1, rendered in %2 s").arg(s_->lastFrame).arg(s_->lastSeconds, 0, 'f', 1));
}

}  // namespace relume
