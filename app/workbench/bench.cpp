#include "bench.h"

#include <sys/resource.h>

#include <QApplication>
#include <QElapsedTimer>
#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QOffscreenSurface>
#include <QOpenGLContext>
#include <QOpenGLFramebufferObject>
#include <QOpenGLWidget>
#include <QSaveFile>
#include <QThread>
#include <QTemporaryDir>
#include <QTimer>
#include <QImageWriter>
#include <QRandomGenerator>
#include <filesystem>
#include <algorithm>
#include <cstdio>
#include <functional>
#include <vector>

#include "document.h"
#include "inspector_panel.h"
#include "relume/inspect/inspection.h"
#include "relume/inspect/inspector_view.h"
#include "job_runner.h"
#include "main_window.h"
#include "photos_panel.h"
#include "relume/ibr/fan.h"
#include "relume/ibr/mesh.h"
#include "relume/ibr/relit_objects.h"
#include "relume/daylight/relight.h"
#include "relume/daylight/sky.h"
#include "relume/image/image.h"
#include "relume/project/room_io.h"
#include "relume/viewport/gl_daylight.h"
#include "relume/viewport/gl_renderer.h"
#include "relume/viewport/viewport_widget.h"

namespace relume {

namespace {

// The same renderer in a QOpenGLWidget (which renders into a framebuffer object that the window
// composes): the presentation path the viewport's native GL window is compared with.
class BenchGlWidget : public QOpenGLWidget {
 public:
  BenchGlWidget(const Scene& scene, const RelightData& data, const RelightSession& session)
      : scene_(scene), data_(data), session_(session) {}
  ~BenchGlWidget() override {  // the renderer's GL objects go with its own context current
    makeCurrent();
    renderer_.reset();
    doneCurrent();
  }
  Camera camera;
  int frames = 0;
  double lastMs = 0;

 protected:
  void initializeGL() override {
    renderer_->initialize();
    renderer_->setRoom(scene_, data_);
    renderer_->setMesh(session_);
  }
  void paintGL() override {
    DisplaySettings d;
    d.output = DisplayOutput::Exposed;
    d.exposure = data_.photoExposure;
    const int w = int(width() * devicePixelRatio()), h = int(height() * devicePixelRatio());
    renderer_->draw(camera, ViewMode::Relit, d, defaultFramebufferObject(), {0, 0, w, h});
    lastMs = renderer_->lastDrawMilliseconds();
    ++frames;
  }

 private:
  const Scene& scene_;
  const RelightData& data_;
  const RelightSession& session_;
  std::unique_ptr<GlRelightRenderer> renderer_ = std::make_unique<GlRelightRenderer>();
};

// Runs the event loop until `done()` or `timeoutMs`, waiting for events as an application's
// exec() does (a loop that polls would take one of the two cores from llvmpipe's threads and the
// X server while a frame is drawn and shown); a 10 ms timer wakes the wait to look at `done`.
void waitUntil(const std::function<bool()>& done, qint64 timeoutMs) {
  QElapsedTimer t;
  t.start();
  QTimer tick;
  tick.start(10);
  while (!done() && t.elapsed() < timeoutMs) QCoreApplication::processEvents(QEventLoop::AllEvents | QEventLoop::WaitForMoreEvents);
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

double peakRssMiB() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_maxrss) / 1024.0;
}

QJsonObject benchRoom(const QString& room, int runs) {
  MainWindow w;
  w.setInteractive(false);
  w.show();
  QElapsedTimer t;
  t.start();
  if (!w.openPath(room)) throw std::runtime_error("cannot start opening " + room.toStdString());
  w.jobs()->waitForIdle();
  if (!w.document()->isOpen()) throw std::runtime_error(w.lastError().toStdString());
  const double openSeconds = double(t.elapsed()) / 1000.0;
  Document* doc = w.document();
  ViewportWidget* vp = w.viewport();
  std::fprintf(stderr, "bench: %s open in %.1f s\n", qPrintable(room), openSeconds);

  // Lamp slider: the session's new radiosity after a lamp scale changed (radiosity steps).
  std::vector<double> lamp;
  for (int r = 0; r < runs; ++r) {
    doc->applyLampScale(0, glm::dvec3(r % 2 ? 1.0 : 0.5));
    lamp.push_back(doc->lastUpdateMilliseconds());
  }
  doc->applyLampScale(0, glm::dvec3(1.0));

  // The viewport alone in a window of each size: GPU time of a frame, and frames per second on
  // screen (repaint = draw + present), in the orbit view (the whole frame is drawn).
  QJsonArray sizes;
  vp->setParent(nullptr);
  vp->setOrbit(true);
  int viewportFrames = 0;
  double viewportMs = 0;
  QObject::connect(vp, &ViewportWidget::frameDrawn, vp, [&](double ms) {
    ++viewportFrames;
    viewportMs = ms;
  });
  // Frames per second on screen through one path, as an application sees it: ask for a frame,
  // let the event loop draw and present it, repeat; and the median draw time of those frames.
  auto onScreen = [&](const std::function<void()>& request, const int& count, const double& lastMs, double& medianMs) {
    for (int k = 0; k < 5; ++k) {  // warm-up
      const int before = count;
      request();
      waitUntil([&] { return count != before; }, 10000);
    }
    std::vector<double> ms;
    const int target = std::max(10, runs * 4), start = count;
    QElapsedTimer wall;
    wall.start();
    while (count - start < target && wall.elapsed() < 60000) {
      const int before = count;
      request();
      waitUntil([&] { return count != before || wall.elapsed() >= 60000; }, 60000);
      if (count != before) ms.push_back(lastMs);
    }
    medianMs = median(ms);
    return (count - start) / (double(wall.nsecsElapsed()) * 1e-9);
  };
  // Lamp edits alternate 0.6 and 1 across every phase: an edit to the value the lamp already has
  // would bring no frame.
  int lampEdits = 0;
  // An edit (run r of `runs`) to the next frame on screen, milliseconds.
  auto toFrame = [&](const std::function<void(int)>& edit) {
    std::vector<double> ms;
    for (int r = 0; r < runs; ++r) {
      QElapsedTimer e;
      e.start();
      const int before = viewportFrames;
      edit(r);
      waitUntil([&] { return viewportFrames != before; }, 10000);
      ms.push_back(double(e.nsecsElapsed()) * 1e-6);
    }
    return ms;
  };
  for (QSize s : {QSize(640, 480), QSize(1280, 960)}) {
    vp->resize(s);
    vp->show();
    double gpu = 0;
    const double fps = onScreen([&] { vp->requestFrame(); }, viewportFrames, viewportMs, gpu);
    // Slider event -> new frame on screen: the edit, the session's update, the upload, a frame.
    const std::vector<double> edit = toFrame([&](int) { doc->editLampScale(0, glm::dvec3(lampEdits++ % 2 ? 1.0 : 0.6), 0); });
    // The same frames through a QOpenGLWidget.
    double widgetFps = 0, widgetGpu = 0;
    {
      auto* glWidget = new BenchGlWidget(doc->scene(), doc->data(), *doc->session());
      glWidget->setFormat(viewportSurfaceFormat());
      glWidget->camera = vp->currentCamera();
      glWidget->resize(s);
      glWidget->show();
      widgetFps = onScreen([&] { glWidget->update(); }, glWidget->frames, glWidget->lastMs, widgetGpu);
      delete glWidget;
    }
    sizes.append(QJsonObject{{"width", s.width()},
                             {"height", s.height()},
                             {"frame_gpu_median_ms", gpu},
                             {"frames_per_second_on_screen", fps},
                             {"qopenglwidget_frame_gpu_median_ms", widgetGpu},
                             {"qopenglwidget_frames_per_second_on_screen", widgetFps},
                             {"slider_to_frame_median_ms", median(edit)}});
    std::fprintf(stderr,
                 "bench: %dx%d frame %.2f ms (GPU), %.1f frames/s on screen (viewport: QOpenGLWindow), %.1f frames/s "
                 "(QOpenGLWidget, frame %.2f ms), slider->frame %.1f ms\n",
                 s.width(), s.height(), gpu, fps, widgetFps, widgetGpu, median(edit));
  }
  // Image-based objects (Dinh, Metoyer, Turk): ten bumpy balls of 25 000 triangles (one fan,
  // the default 3 rings x 96 views of 256^2) standing on the floor, in the 1280 x 960 viewport:
  // frames per second, and a lamp edit to the frame on screen (the objects' light and tables anew).
  QJsonObject images;
  {
    QElapsedTimer build;
    build.start();
    std::shared_ptr<const ibr::ImageFan> fan = ibr::buildFan(ibr::bumpyBall(160, 80, 0.25, 0.06), ibr::FanOptions{});
    const double fanSeconds = double(build.elapsed()) / 1000.0;
    glm::dvec3 lo(1e300), hi(-1e300);
    for (const auto& p : doc->scene().polygons)
      for (const auto& v : p.vertices) {
        lo = glm::min(lo, v);
        hi = glm::max(hi, v);
      }
    int placed = 0;
    for (double y = lo.y + 0.5; y < hi.y - 0.4 && placed < 10; y += 0.7)
      for (double x = lo.x + 0.5; x < hi.x - 0.4 && placed < 10; x += 0.7) {
        ibr::ImageObject o;
        o.name = "bench ball " + std::to_string(placed + 1);
        o.fan = fan;
        o.fanFile = "(bench)";
        o.place.position = glm::dvec3(x, y, lo.z + 0.002);
        o.place.yaw = 0.7 * placed;
        if (doc->tryAddImageObject(o)) ++placed;
      }
    vp->resize(1280, 960);
    vp->show();
    double gpu = 0;
    const double fps = onScreen([&] { vp->requestFrame(); }, viewportFrames, viewportMs, gpu);
    const std::vector<double> edit = toFrame([&](int) { doc->editLampScale(0, glm::dvec3(lampEdits++ % 2 ? 1.0 : 0.6), 0); });
    // One object moved by 2 cm (a drag's step) to the frame on screen: its light, every shadow map.
    std::vector<double> move;
    if (placed > 0)
      move = toFrame([&](int r) {
        const ibr::ImageObject& o = doc->imageObjects().front();
        ibr::Placement p = o.place;
        p.position.x += (r % 2 ? -0.02 : 0.02);
        doc->tryPlaceImageObject(o.name, p, 0);
      });
    images = QJsonObject{{"objects", placed},
                         {"move_one_to_frame_median_ms", move.empty() ? 0.0 : median(move)},
                         {"triangles_each", double(fan->meshTriangles)},
                         {"fan_seconds", fanSeconds},
                         {"width", 1280},
                         {"height", 960},
                         {"frame_gpu_median_ms", gpu},
                         {"frames_per_second_on_screen", fps},
                         {"lamp_edit_to_frame_median_ms", median(edit)}};
    std::fprintf(stderr,
                 "bench: %d image-based objects at 1280x960: frame %.2f ms (GPU), %.1f frames/s on screen, lamp edit->frame "
                 "%.1f ms, one moved->frame %.1f ms (fan of %llu triangles in %.1f s)\n",
                 placed, gpu, fps, median(edit), move.empty() ? 0.0 : median(move), static_cast<unsigned long long>(fan->meshTriangles), fanSeconds);
    while (!doc->imageObjects().empty()) doc->removeImageObject(doc->imageObjects().back().name);
    QApplication::processEvents();
  }
  vp->hide();
  vp->setParent(&w);

  // The inspector alone in a 1280 x 720 window: its first view of the session's mesh (elements,
  // colours, the first frame), a pick (the element under the cursor, its links listed and drawn,
  // the next frame), and frames per second on screen while orbiting.
  QJsonObject inspector;
  {
    auto* panel = new InspectorPanel(doc, w.jobs());
    panel->resize(1280, 720);
    auto* view = panel->view();
    int frames = 0;
    QObject::connect(view, &inspect::InspectorView::frameDrawn, view, [&](double) { ++frames; });
    auto waitFrame = [&](int before) { waitUntil([&] { return frames != before; }, 10000); };
    QElapsedTimer first;
    first.start();
    panel->show();
    panel->refresh();
    waitFrame(0);
    const double firstMs = double(first.nsecsElapsed()) * 1e-6;
    std::vector<double> pick;
    const auto& els = panel->elements();
    for (int r = 0; r < std::max(runs, 5) && !els.node.empty(); ++r) {
      const auto& o = els.outline[size_t(r * 7919) % els.outline.size()];
      glm::dvec3 c(0.0);
      for (const auto& p : o) c += p;
      QPointF at;
      view->widgetPosition(c / double(o.size()), at);
      QElapsedTimer t;
      t.start();
      const int before = frames;
      const int e = view->elementAt(at);
      panel->pickNode(e >= 0 ? els.node[size_t(e)] : -1);
      waitFrame(before);
      pick.push_back(double(t.nsecsElapsed()) * 1e-6);
    }
    const int start = frames, target = std::max(30, runs * 6);
    QElapsedTimer wall;
    wall.start();
    std::vector<double> frameMs;
    while (frames - start < target && wall.elapsed() < 60000) {
      const int before = frames;
      view->orbit(2.0, 0.0);
      waitFrame(before);
      frameMs.push_back(view->lastFrameMilliseconds());
    }
    const double fps = (frames - start) / (double(wall.nsecsElapsed()) * 1e-9);
    inspector = QJsonObject{{"elements", double(els.node.size())},
                            {"first_view_ms", firstMs},
                            {"pick_and_links_median_ms", median(pick)},
                            {"orbit_frames_per_second", fps},
                            {"orbit_frame_median_ms", median(frameMs)},
                            {"width", 1280},
                            {"height", 720}};
    std::fprintf(stderr, "bench: inspector first view %.0f ms (%zu elements), pick %.1f ms, orbit %.1f frames/s\n", firstMs,
                 els.node.size(), median(pick), fps);
    delete panel;
  }
  const auto totals = doc->session()->engine().totals();
  return QJsonObject{{"image_based_objects", images},
                     {"room", room},
                     {"open_seconds", openSeconds},
                     {"leaves", double(totals.leaves)},
                     {"links", double(totals.links)},
                     {"lamp_update_median_ms", median(lamp)},
                     {"viewport", sizes},
                     {"inspector", inspector},
                     {"peak_rss_mib", peakRssMiB()}};
}

// Importing `count` photos of width x height pixels (JPEG) into the Photos panel and loading their
// thumbnails: how long it takes, and how well the window answers meanwhile — a 2 ms timer on the
// UI thread records every gap between its ticks (the longest one is the longest time an event,
// a click or a repaint, waited).
QJsonObject benchPhotos(int count, int width, int height) {
  QTemporaryDir dir;
  if (!dir.isValid()) throw std::runtime_error("cannot make a temporary folder");
  const QString src = dir.path() + "/src";
  QDir().mkpath(src);
  {
    // A photo-like image: smooth shading with sensor noise (what keeps a JPEG from being trivial).
    QImage img(width, height, QImage::Format_RGB888);
    QRandomGenerator rng(7);
    for (int y = 0; y < height; ++y) {
      uchar* row = img.scanLine(y);
      for (int x = 0; x < width; ++x) {
        const int n = int(rng.bounded(17)) - 8;
        row[3 * x + 0] = uchar(std::clamp(40 + 160 * x / width + n, 0, 255));
        row[3 * x + 1] = uchar(std::clamp(60 + 120 * y / height + n, 0, 255));
        row[3 * x + 2] = uchar(std::clamp(90 + 60 * (x + y) / (width + height) + n, 0, 255));
      }
    }
    QImageWriter wr(src + "/photo_000.jpg");
    wr.setQuality(90);
    if (!wr.write(img)) throw std::runtime_error("cannot write a benchmark photo: " + wr.errorString().toStdString());
  }
  for (int i = 1; i < count; ++i)
    std::filesystem::copy_file((src + "/photo_000.jpg").toStdString(),
                               (src + QString("/photo_%1.jpg").arg(i, 3, 10, QChar('0'))).toStdString());
  const double fileMiB = double(QFileInfo(src + "/photo_000.jpg").size()) / (1024.0 * 1024.0);

  JobRunner jobs;
  PhotosPanel panel(&jobs);
  panel.resize(900, 700);
  panel.show();
  panel.setCaptureFolder(dir.path() + "/capture");
  QApplication::processEvents();

  std::vector<double> gaps;
  QElapsedTimer tick;
  QTimer timer;
  timer.setTimerType(Qt::PreciseTimer);
  QObject::connect(&timer, &QTimer::timeout, &timer, [&] {
    gaps.push_back(double(tick.nsecsElapsed()) * 1e-6);
    tick.restart();
  });
  bool imported = false, loaded = false;
  QObject::connect(&jobs, &JobRunner::finished, &jobs, [&](bool, bool, const QString&) { imported = true; });
  QObject::connect(&panel, &PhotosPanel::thumbnailsLoaded, &panel, [&] { loaded = true; });
  QElapsedTimer wall;
  wall.start();
  tick.start();
  timer.start(2);
  if (!panel.importFolder(src)) throw std::runtime_error("the Photos panel did not start importing");
  double importSeconds = 0;
  while (!(loaded && imported) && wall.elapsed() < 600000) {
    QApplication::processEvents(QEventLoop::AllEvents, 5);
    if (imported && importSeconds == 0) importSeconds = double(wall.nsecsElapsed()) * 1e-9;
  }
  timer.stop();
  const double allSeconds = double(wall.nsecsElapsed()) * 1e-9;
  if (!loaded) throw std::runtime_error("the thumbnails did not load within 10 minutes");
  int thumbs = 0;
  for (const auto& e : panel.entries()) thumbs += !e.thumbnail.isNull();
  std::vector<double> sorted = gaps;
  std::sort(sorted.begin(), sorted.end());
  const double longest = sorted.empty() ? 0 : sorted.back();
  const double p99 = sorted.empty() ? 0 : sorted[std::min(sorted.size() - 1, size_t(0.99 * double(sorted.size())))];
  int over100 = 0;
  for (double g : gaps) over100 += g > 100.0;
  std::fprintf(stderr,
               "bench: %d photos of %dx%d (%.1f MiB each): imported in %.1f s, %d thumbnails in %.1f s; UI thread's "
               "longest wait %.1f ms (99th percentile %.1f ms, median %.1f ms, %d over 100 ms)\n",
               count, width, height, fileMiB, importSeconds, thumbs, allSeconds, longest, p99, median(gaps), over100);
  return QJsonObject{{"photos", count},
                     {"width", width},
                     {"height", height},
                     {"file_mib", fileMiB},
                     {"import_seconds", importSeconds},
                     {"thumbnails", thumbs},
                     {"all_thumbnails_seconds", allSeconds},
                     {"ui_longest_wait_ms", longest},
                     {"ui_wait_p99_ms", p99},
                     {"ui_wait_median_ms", median(gaps)},
                     {"ui_waits_over_100_ms", over100}};
}



// The daylight viewport's renderer on a daylight room: see bench.h.
QJsonObject benchDaylightView(const QString& roomPath, int runs) {
  const Scene scene = loadRoom(roomPath.toStdString());
  const Photo* main = scene.findPhoto(scene.mainPhoto);
  if (!main || main->hdr.empty()) throw std::runtime_error(roomPath.toStdString() + ": no HDR main photo (not a daylight room)");
  const ImageRGB photo = readImageLinear(main->hdr.front() == '/' ? main->hdr : scene.baseDir + "/" + main->hdr);
  const daylight::SkyRegions cells(64);
  const daylight::SkyRadiance photoSky = daylight::averageSky(daylight::readRoomSky(scene, scene.photoSky), cells);
  QElapsedTimer t;
  t.start();
  std::string how;
  auto session = daylight::openDaylightRelighting(scene, photo, main->camera, photoSky, {}, silentProgress(), &how);
  std::fprintf(stderr, "bench: daylight session of %s in %.1f s%s%s\n", qPrintable(roomPath), double(t.elapsed()) / 1000,
               how.empty() ? "" : ": ", how.c_str());
  // The first variant's virtual objects (else a 40 cm box on the floor's middle), under its sky.
  std::vector<Polygon> faces;
  std::string skyName = scene.photoSky;
  for (const auto& v : scene.variants)
    if (faces.empty() && !v.virtualObjects.empty()) {
      faces = daylight::variantObjects(scene, v, scene.sourceFile);
      if (!v.sky.empty()) skyName = v.sky;
    }
  if (faces.empty()) throw std::runtime_error(roomPath.toStdString() + ": no variant with virtual objects to move");
  const daylight::SkyRadiance sky = skyName == scene.photoSky ? photoSky : daylight::averageSky(daylight::readRoomSky(scene, skyName), cells);

  QOffscreenSurface surface;
  QOpenGLContext context;
  QSurfaceFormat format;
  format.setVersion(3, 3);
  format.setProfile(QSurfaceFormat::CoreProfile);
  context.setFormat(format);
  if (!context.create()) throw std::runtime_error("no OpenGL 3.3 context");
  surface.setFormat(context.format());
  surface.create();
  if (!context.makeCurrent(&surface)) throw std::runtime_error("cannot make the OpenGL context current");
  QJsonArray rows;
  QJsonObject image;
  {
    QOpenGLFramebufferObject target(1280, 960, QOpenGLFramebufferObject::Depth);
    GlDaylightRenderer gl;
    gl.initialize();
    gl.setRoom(session->roomPolygons(), session->camera());
    DisplaySettings display;
    display.exposure = 1.0;
    for (int samples : std::vector<int>{16, 64, 256}) {
      daylight::InteractiveOptions o = session->interactive();
      o.directSamples = samples;
      session->setInteractive(o);
      const daylight::InteractiveSky& light = session->interactiveSky(sky);
      gl.setSky(light);
      for (int size : std::vector<int>{64, 128, 256}) {
        gl.setMapSize(size);
        std::vector<double> lightMs, moved, maps, still;
        for (int r = 0; r < std::max(runs, 3) + 1; ++r) {  // (the first: shaders compiled, caches warmed)
          std::vector<Polygon> shifted = faces;
          glm::dvec3 lo(1e300), hi(-1e300);
          for (auto& f : shifted)
            for (auto& q : f.vertices) {
              q.x += 0.05 * (r % 2 ? 1 : -1);
              lo = glm::min(lo, q), hi = glm::max(hi, q);
            }
          QElapsedTimer c;
          c.start();
          const daylight::ObjectIndirect indirect = session->objectIndirect(sky, shifted);
          const daylight::ShadowReach reach = session->shadowReach(light, 0.5 * (lo + hi), 0.5 * glm::length(hi - lo));
          const double cpuMs = double(c.nsecsElapsed()) / 1e6;
          gl.setObjects(shifted, indirect, reach);
          gl.draw(display, target.handle(), {0, 0, 1280, 960});
          const double movedMs = gl.lastDrawMilliseconds(), mapMs = gl.lastMapMilliseconds();
          gl.draw(display, target.handle(), {0, 0, 1280, 960});
          if (r == 0) continue;
          lightMs.push_back(cpuMs);
          moved.push_back(movedMs);
          maps.push_back(mapMs);
          still.push_back(gl.lastDrawMilliseconds());
        }
        QJsonObject row{{"window_samples", int(light.window.size())},
                        {"shadow_maps", gl.mapCount()},
                        {"map_size", size},
                        {"sun_map_size", gl.sunMapSize()},
                        {"frame_object_moved_median_ms", median(moved)},
                        {"maps_median_ms", median(maps)},
                        {"frame_still_median_ms", median(still)},
                        {"frames_per_second_object_moving", 1000.0 / std::max(median(moved), 1e-6)},
                        {"library_light_moved_median_ms", median(lightMs)}};
        std::fprintf(stderr,
                     "bench: daylight view 1280x960, %d maps (window samples' %d^2, the sun's %d^2): moved %.1f ms (maps %.1f ms), still %.1f ms, library "
                     "light for the move %.1f ms\n",
                     gl.mapCount(), size, gl.sunMapSize(), median(moved), median(maps), median(still), median(lightMs));
        rows.append(row);
      }
    }
    // An image-based object instead (a bumpy ball of 25 000 triangles, the default fan of 3 rings x
    // 96 views of 256^2) where the box stands, moved 5 cm a frame, 64 window samples' maps of 128^2:
    // the library's light for it (ibr::daylightAt and the drawn views' tables) and the frame (its
    // silhouettes into every map, then the view), against the CPU path's frame (the room's render
    // and ibr::drawImageObjectsInDaylight) in the same run.
    std::shared_ptr<const ibr::ImageFan> ballFan = ibr::buildFan(ibr::bumpyBall(160, 80, 0.25, 0.06), ibr::FanOptions{});
    glm::dvec3 lo(1e300), hi(-1e300);
    for (const auto& f : faces)
      for (const auto& q : f.vertices) lo = glm::min(lo, q), hi = glm::max(hi, q);
    {
      daylight::InteractiveOptions o = session->interactive();
      o.directSamples = 64;
      session->setInteractive(o);
    }
    gl.setMapSize(128);
    gl.setObjects({}, {}, {});
    std::vector<double> lightMs, moved, maps, cpuMs;
    for (int r = 0; r < std::max(runs, 3) + 1; ++r) {
      ibr::ImageObject ball;
      ball.name = "bench ball";
      ball.fan = ballFan;
      ball.fanFile = "(bench)";
      ball.place.position = glm::dvec3(0.5 * (lo.x + hi.x) + 0.05 * (r % 2 ? 1 : -1), 0.5 * (lo.y + hi.y), lo.z);
      const ibr::ImageFan& fan = *ballFan;
      QElapsedTimer c;
      c.start();
      const daylight::InteractiveSky& light = session->interactiveSky(sky);
      if (r == 0) gl.setSky(light);
      ibr::DisplayDaylight d = ibr::daylightForDisplay(*session, sky, ball, session->camera().center(),
                                                       size_t(GlDaylightRenderer::imageLamps()));
      const daylight::ShadowReach reach =
          session->shadowReach(light, ball.place.toWorld(fan, fan.centre), fan.radius * ball.place.scale);
      const double libraryMs = double(c.nsecsElapsed()) / 1e6;
      gl.setImageObjects({ball}, {d.light}, {d.tables});
      gl.setObjects({}, {}, reach);
      gl.draw(display, target.handle(), {0, 0, 1280, 960});
      const double movedMs = gl.lastDrawMilliseconds(), mapMs = gl.lastMapMilliseconds();
      c.restart();
      ImageRGB cpu = session->render(sky, {}, daylight::DaylightMethod::Volume);
      ibr::drawImageObjectsInDaylight(*session, sky, {ball}, cpu);
      const double cpuFrame = double(c.nsecsElapsed()) / 1e6;
      if (r == 0) continue;
      lightMs.push_back(libraryMs);
      moved.push_back(movedMs);
      maps.push_back(mapMs);
      cpuMs.push_back(cpuFrame);
    }
    image = QJsonObject{{"window_samples", 64},
                      {"shadow_maps", gl.mapCount()},
                      {"map_size", 128},
                      {"library_light_moved_median_ms", median(lightMs)},
                      {"frame_object_moved_median_ms", median(moved)},
                      {"maps_median_ms", median(maps)},
                      {"moved_total_median_ms", median(lightMs) + median(moved)},
                      {"cpu_path_frame_median_ms", median(cpuMs)}};
    std::fprintf(stderr,
                 "bench: daylight view 1280x960, an image-based object moved: library light %.1f ms, frame %.1f ms (maps %.1f ms); "
                 "the CPU path's frame %.1f ms\n",
                 median(lightMs), median(moved), median(maps), median(cpuMs));
    gl.setImageObjects({}, {}, {});
  }
  context.doneCurrent();
  return QJsonObject{{"room", roomPath}, {"width", 1280}, {"height", 960}, {"photo_width", photo.width},
                     {"photo_height", photo.height}, {"objects_faces", int(faces.size())}, {"frames", rows},
                     {"image_based_object", image}};
}

}  // namespace

int runWorkbenchBench(const QString& out, const QStringList& rooms, int runs, int photos, QSize photoSize,
                      const QStringList& daylightRooms) {
  QJsonArray results;
  QJsonObject photoResult;
  QJsonArray daylightResults;
  try {
    for (const QString& r : rooms) results.append(benchRoom(r, runs));
    if (photos > 0) photoResult = benchPhotos(photos, photoSize.width(), photoSize.height());
    for (const QString& d : daylightRooms) daylightResults.append(benchDaylightView(d, runs));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "relume-workbench --bench: %s\n", e.what());
    return 1;
  }
  QJsonObject all{{"runs", runs}, {"rooms", results}};
  if (photos > 0) all["photos"] = photoResult;
  if (!daylightRooms.isEmpty()) all["daylight_view"] = daylightResults;
  all["peak_rss_mib"] = peakRssMiB();
  QSaveFile f(out);
  if (!f.open(QIODevice::WriteOnly) ||
      f.write(QJsonDocument(all).toJson()) < 0 ||
      !f.commit()) {
    std::fprintf(stderr, "relume-workbench --bench: cannot write %s\n", qPrintable(out));
    return 1;
  }
  std::fprintf(stderr, "wrote %s\n", qPrintable(out));
  return 0;
}

}  // namespace relume
