// The workbench driven through its real widgets under Xvfb with Mesa (ctest label gui): the GL
// viewport against the CPU renderer, the Lights panel against the sample room's truth renders,
// undo, jobs (progress, cancel, a responsive event loop), saving and reopening, bad projects.
#include <QCheckBox>
#include <QDoubleSpinBox>
#include <QPushButton>
#include <QDir>
#include <QDirIterator>
#include <QElapsedTimer>
#include <QFile>
#include <QPainter>
#include <QPixmap>
#include <QSlider>
#include <QJsonArray>
#include <QJsonDocument>
#include <QToolButton>
#include <QMenu>
#include <QJsonObject>
#include <QListWidget>
#include <QDateTime>
#include <QLockFile>
#include <QSettings>
#include <QStatusBar>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QTimer>
#include <QTranslator>
#include <QMenuBar>
#include <QDockWidget>
#include <QtTest>
#include <QMouseEvent>
#include <algorithm>
#include <functional>
#include <map>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <numeric>

#include "document.h"
#include "job_runner.h"
#include "edit_tool.h"
#include "lights_panel.h"
#include "objects_panel.h"
#include "references_panel.h"
#include "inspector_panel.h"
#include "click_photo_view.h"
#include "clicks_panel.h"
#include "relume/project/room_io.h"
#include "relume/project/save_hooks.h"
#include "relume/reconstruct/click_build.h"
#include "photos_panel.h"
#include "process_exit.h"
#include "reconstruction_panel.h"
#include "relume/inspect/sparse_view.h"
#include <QTabWidget>
#include "relume/reconstruct/colmap_driver.h"
#include <QLineEdit>
#include "support/checkerboard.h"
#include <QChartView>
#include <QLabel>
#include <QLineSeries>
#include <QComboBox>
#include <QTableWidget>
#include <QTabWidget>
#include "relume/inspect/inspection.h"
#include "relume/inspect/inspector_view.h"
#include "relume/radiosity/hierarchy.h"
#include <QTreeWidget>
#include "relume/geometry/error.h"
#include "relume/geometry/polygon.h"
#include "relume/raytrace/ray_scene.h"
#include "main_window.h"
#include "sky_panel.h"
#include <QCheckBox>
#include <QComboBox>
#include <QSignalSpy>
#include "relume/geometry/progress.h"
#include "relume/ibr/fan.h"
#include "relume/ibr/mesh.h"
#include "relume/ibr/relit_objects.h"
#include "relume/image/image.h"
#include "relume/relight/compare.h"
#include "relume/relight/relighter.h"
#include "relume/viewport/viewport_widget.h"

using namespace relume;

namespace {

const QString kRoom = QStringLiteral(RELUME_SOURCE_DIR) + "/resources/sample_room";
std::string str(const QString& s) { return s.toStdString(); }

// PSNR of `img` against `ref` with no gain fitted, the peak at ref's 99.9th percentile.
double psnrNoGain(const ImageRGB& img, const ImageRGB& ref) {
  std::vector<float> v(ref.pixels);
  std::nth_element(v.begin(), v.begin() + long(0.999 * double(v.size())), v.end());
  const double peak = v[size_t(0.999 * double(v.size()))];
  double se = 0;
  for (size_t k = 0; k < ref.pixels.size(); ++k) se += std::pow(double(img.pixels[k]) - ref.pixels[k], 2);
  const double mse = se / double(ref.pixels.size());
  return 10 * std::log10(peak * peak / std::max(mse, 1e-30));
}

// Mean relative difference per channel: sum |img - ref| / sum ref.
glm::dvec3 meanRelativeDifference(const ImageRGB& img, const ImageRGB& ref) {
  glm::dvec3 diff(0.0), sum(0.0);
  for (size_t k = 0; k < ref.pixels.size(); ++k) {
    diff[int(k % 3)] += std::abs(double(img.pixels[k]) - ref.pixels[k]);
    sum[int(k % 3)] += ref.pixels[k];
  }
  return diff / glm::max(sum, glm::dvec3(1e-30));
}

// The 8-bit image a display shows: sRGB(exposure x radiance), as the photo was encoded.
QImage exposed(const ImageRGB& img, double exposure) {
  QImage out(img.width, img.height, QImage::Format_RGB888);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const glm::vec3 c = img.at(x, y) * float(exposure);
      auto q = [](float v) { return int(std::lround(255.f * linearToSrgb(std::clamp(v, 0.f, 1.f)))); };
      out.setPixelColor(x, y, QColor(q(c.x), q(c.y), q(c.z)));
    }
  return out;
}

double psnr8(const QImage& a, const QImage& b) {
  double se = 0;
  size_t n = 0;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x) {
      const QColor p = a.pixelColor(x, y), q = b.pixelColor(x, y);
      se += std::pow(p.red() - q.red(), 2) + std::pow(p.green() - q.green(), 2) + std::pow(p.blue() - q.blue(), 2);
      n += 3;
    }
  return 10 * std::log10(255.0 * 255.0 / std::max(se / double(n), 1e-30));
}

void saveShot(QWidget* w, const QString& name) {
  const QString dir = qEnvironmentVariable("RELUME_SCREENSHOT_DIR");
  if (dir.isEmpty()) return;
  QDir().mkpath(dir);
  // QWidget::grab() may show a GL viewport's previous frame: its current frame is painted over it.
  QPixmap shot = w->grab();
  QPainter painter(&shot);
  QList<ViewportWidget*> viewports = w->findChildren<ViewportWidget*>();
  if (auto* self = qobject_cast<ViewportWidget*>(w)) viewports.append(self);
  for (ViewportWidget* v : viewports)
    if (v->isVisible()) painter.drawImage(QRect(v->mapTo(w, QPoint(0, 0)), v->size()), v->grabFramebuffer());
  painter.end();
  shot.save(dir + "/" + name + ".png");
}

QJsonObject readJson(const QString& file) {
  QFile f(file);
  if (!f.open(QIODevice::ReadOnly)) return {};
  return QJsonDocument::fromJson(f.readAll()).object();
}

void writeJson(const QString& file, const QJsonObject& o) {
  QFile f(file);
  if (f.open(QIODevice::WriteOnly | QIODevice::Truncate)) f.write(QJsonDocument(o).toJson());
}

// A copy of a folder tree (a project), for edits that must not touch the original.
// Waits until the window's jobs have been idle for ten 20 ms probes in a row (a job that starts
// another from its continuation is waited for too), or `timeoutMs` passed; true when idle.
bool jobsSettled(MainWindow& w, int timeoutMs) {
  QElapsedTimer t;
  t.start();
  for (int idle = 0; idle < 10 && t.elapsed() < timeoutMs;) {
    QTest::qWait(20);
    idle = w.jobs()->busy() ? 0 : idle + 1;
  }
  return !w.jobs()->busy();
}

// The window shown as a user sees it (1400 x 820) and a daylight room opened in it as File ▸ Open
// does (the opening job waited for): true when the Sky panel holds the room.
bool openDaylightRoom(MainWindow& w, const QString& room) {
  w.setInteractive(false);
  w.resize(1400, 820);
  w.show();
  return QTest::qWaitForWindowExposed(&w) && w.openPath(room) && jobsSettled(w, 300000) && w.skyPanel()->isOpen();
}

// The example vase's fan (3 x 24 views at 128 px: quick to make, enough for the Sky panel's
// checks), written to `path`.
void writeExampleVaseFan(const QString& path) {
  ibr::FanOptions opt;
  opt.viewsPerRing = 24;
  opt.size = 128;
  opt.ringElevations = {20.0, 50.0};
  const auto fan = ibr::buildFan(ibr::readMesh(QStringLiteral(RELUME_SOURCE_DIR "/resources/examples/vase.obj").toStdString()), opt);
  ibr::writeFan(*fan, path.toStdString());
}

// Where world point p falls in the photo of `cam` (pixels).
glm::dvec2 photoPixel(const Camera& cam, const glm::dvec3& p) {
  glm::dvec2 px(-1.0);
  cam.project(p, px);
  return px;
}

// The colour a view's image `im` (the photo's frame at any size) shows at world point p; invalid
// behind the camera.
QColor colourSeen(const QImage& im, const Camera& cam, const glm::dvec3& p) {
  glm::dvec2 px;
  if (!cam.project(p, px)) return QColor();
  return im.pixelColor(int(px.x * double(im.width()) / cam.width), int(px.y * double(im.height()) / cam.height));
}

// The Sky panel under sun0 (the photos' sky), its render waited for.
bool showSun0(MainWindow& w) {
  SkyPanel* sky = w.skyPanel();
  if (!jobsSettled(w, 120000)) return false;
  const int sun0 = sky->skyBox()->findText("sun0", Qt::MatchContains);
  if (sun0 < 0) return false;
  if (sky->skyBox()->currentIndex() == sun0) return true;
  sky->skyBox()->setCurrentIndex(sun0);
  return jobsSettled(w, 180000);
}

// A press at `from`, a move and a release at `to` (photo pixels) on a photo view, as a drag.
void dragInView(ClickPhotoView* view, const glm::dvec2& from, const glm::dvec2& to, int steps = 1,
                const std::function<void()>& betweenMoves = {}) {
  auto send = [&](QEvent::Type type, const glm::dvec2& px, Qt::MouseButton button, Qt::MouseButtons buttons) {
    const QPointF pos = view->widgetPosition(QPointF(px.x, px.y));
    QMouseEvent e(type, pos, view->mapToGlobal(pos), button, buttons, Qt::NoModifier);
    QApplication::sendEvent(view, &e);
  };
  send(QEvent::MouseButtonPress, from, Qt::LeftButton, Qt::LeftButton);
  for (int k = 1; k <= steps; ++k) {
    send(QEvent::MouseMove, from + (to - from) * (double(k) / steps), Qt::NoButton, Qt::LeftButton);
    if (betweenMoves) betweenMoves();
  }
  send(QEvent::MouseButtonRelease, to, Qt::LeftButton, Qt::NoButton);
}

bool copyFolder(const QString& from, const QString& to) {
  QDirIterator it(from, QDir::Files | QDir::NoDotAndDotDot, QDirIterator::Subdirectories);
  while (it.hasNext()) {
    const QString src = it.next();
    const QString dst = to + "/" + QDir(from).relativeFilePath(src);
    if (!QDir().mkpath(QFileInfo(dst).path()) || !QFile::copy(src, dst)) return false;
  }
  return true;
}

// Every entry under `from` (hidden ones and empty folders too) copied to `to`: what a disk holds.
bool copyTree(const QString& from, const QString& to) {
  if (!QDir().mkpath(to)) return false;
  QDirIterator it(from, QDir::AllEntries | QDir::Hidden | QDir::System | QDir::NoDotAndDotDot, QDirIterator::Subdirectories);
  while (it.hasNext()) {
    const QString src = it.next();
    const QString dst = to + "/" + QDir(from).relativeFilePath(src);
    if (QFileInfo(src).isDir()) {
      if (!QDir().mkpath(dst)) return false;
    } else if (!QDir().mkpath(QFileInfo(dst).path()) || !QFile::copy(src, dst)) {
      return false;
    }
  }
  return true;
}

// Whether two folder trees hold the same files with the same bytes.
bool sameTree(const QString& a, const QString& b) {
  auto files = [](const QString& root) {
    QStringList out;
    QDirIterator it(root, QDir::Files | QDir::Hidden | QDir::System, QDirIterator::Subdirectories);
    while (it.hasNext()) out << QDir(root).relativeFilePath(it.next());
    out.sort();
    return out;
  };
  const QStringList fa = files(a);
  if (fa.isEmpty() || fa != files(b)) return false;
  for (const QString& rel : fa) {
    QFile x(a + "/" + rel), y(b + "/" + rel);
    if (!x.open(QIODevice::ReadOnly) || !y.open(QIODevice::ReadOnly) || x.readAll() != y.readAll()) return false;
  }
  return true;
}

// What a lamp switched on did to the Sky panel's 8-bit image: the pixels darker than with it off
// (beyond 8-bit rounding), the mean gain in grey levels, and per point of the room the linear
// on / off ratio over 7 x 7 pixels around its image (-1: behind the camera).
struct LampGain {
  long darker = 0;
  double gain = 0;
  double under = 0, away = 0;
};
LampGain lampGain(const QImage& on, const QImage& off, const Camera& cam, const glm::dvec3& under, const glm::dvec3& away) {
  LampGain g;
  for (int y = 0; y < on.height(); ++y)
    for (int x = 0; x < on.width(); ++x) {
      const int d = qGray(on.pixel(x, y)) - qGray(off.pixel(x, y));
      g.darker += d < -1;
      g.gain += d;
    }
  g.gain /= double(on.width()) * on.height();
  auto ratioAt = [&](const glm::dvec3& p) {
    glm::dvec2 q;
    if (!cam.project(p, q)) return -1.0;
    double a = 0, b = 0;
    for (int dy = -3; dy <= 3; ++dy)
      for (int dx = -3; dx <= 3; ++dx) {
        const int x = std::clamp(int(q.x) + dx, 0, on.width() - 1), y = std::clamp(int(q.y) + dy, 0, on.height() - 1);
        a += srgbToLinear(qGray(on.pixel(x, y)) / 255.f);
        b += srgbToLinear(qGray(off.pixel(x, y)) / 255.f);
      }
    return a / std::max(b, 1e-9);
  };
  g.under = ratioAt(under);
  g.away = ratioAt(away);
  return g;
}

}  // namespace

class WorkbenchTest : public QObject {
  Q_OBJECT
 private:
  std::unique_ptr<MainWindow> window_;
  QTemporaryDir tmp_;
  qint64 maxGapMs_ = 0;

  Document* doc() { return window_->document(); }
  const Camera& photoCamera() { return doc()->scene().findPhoto(doc()->data().photo)->camera; }
  int lampIndex(const char* name) { return doc()->scene().findLamp(name); }
  bool waitForJob(int timeoutMs) {
    QElapsedTimer t;
    t.start();
    while (window_->jobs()->busy() && t.elapsed() < timeoutMs) QTest::qWait(20);
    QTest::qWait(20);  // the job's end reaches the window (panels and tools enabled again)
    return !window_->jobs()->busy();
  }
  // The daylight sample room to open where a slot's subject is not the first open: under ctest a
  // fresh copy of the daylight_room fixture (`relume preprocess` of the room: its kept daylight
  // session, named by RELUME_TEST_DAYLIGHT_PROJECT), which opens without estimating or solving;
  // run by hand, the bundle itself, estimated and solved as it opens.
  QString daylightRoomToOpen() {
    const QString fixture = qEnvironmentVariable("RELUME_TEST_DAYLIGHT_PROJECT");
    if (fixture.isEmpty()) return RELUME_SOURCE_DIR "/resources/daylight_room";
    static int copies = 0;
    const QString copy = tmp_.path() + QString("/daylight_fixture_%1.relume").arg(++copies);
    return copyTree(fixture, copy) ? copy : fixture + " (could not be copied)";
  }
  // Until no job has run for 200 ms (a job whose end starts another, as Build then Open).
  bool waitForJobs(int timeoutMs) {
    QElapsedTimer t;
    t.start();
    for (int idle = 0; idle < 10 && t.elapsed() < timeoutMs;) {
      QTest::qWait(20);
      idle = window_->jobs()->busy() ? 0 : idle + 1;
    }
    return !window_->jobs()->busy();
  }

 private slots:
  void initTestCase() {
    QStandardPaths::setTestModeEnabled(true);
    QCoreApplication::setOrganizationName("RelumeTest");
    QSettings().remove("autosaves");  // an earlier run's leftovers are not this test's business
    window_ = std::make_unique<MainWindow>();
    window_->setInteractive(false);
    window_->resize(1280, 800);
    window_->show();
    QVERIFY(QTest::qWaitForWindowExposed(window_.get()));
    // Under ctest most entries start from the sample room preprocessed once per run (the fixture
    // sample_room_project, written by relume preprocess): a copy of it opened as File > Open does.
    // The entry without it (workbench_gui_preprocess) preprocesses here, as a user's first open.
    const QString fixture = qEnvironmentVariable("RELUME_TEST_PROJECT");
    if (!fixture.isEmpty()) {
      QVERIFY2(QFileInfo(fixture + "/relight/relight.json").isFile(),
               qPrintable(fixture + ": no preprocessed project there (ctest runs its fixture first)"));
      const QString copy = tmp_.path() + "/fixture.relume";
      QVERIFY(copyTree(fixture, copy));
      QVERIFY(window_->openPath(copy));
      QVERIFY(waitForJobs(300000));
      QVERIFY2(doc()->isOpen(), qPrintable(window_->lastError()));
      return;
    }
    // A full preprocess from the GUI, with a timer probing that the event loop keeps answering.
    QElapsedTimer sinceLast;
    sinceLast.start();
    QTimer probe;
    connect(&probe, &QTimer::timeout, [&] {
      // While the job runs (the room's arrival on the UI thread afterwards is measured apart).
      if (window_->jobs()->busy()) maxGapMs_ = std::max(maxGapMs_, sinceLast.elapsed());
      sinceLast.restart();
    });
    probe.start(10);
    QVERIFY(window_->openPath(kRoom));
    QVERIFY(window_->jobs()->busy());
    QElapsedTimer t;
    t.start();
    while (window_->jobs()->busy() && t.elapsed() < 600000) QTest::qWait(20);
    QVERIFY2(!window_->jobs()->busy(), "the preprocess did not finish");
    probe.stop();
    QVERIFY2(doc()->isOpen(), qPrintable(window_->lastError()));
    qInfo("event loop: longest gap between 10 ms probe ticks during the preprocess %lld ms", maxGapMs_);
    QVERIFY2(maxGapMs_ <= 100, qPrintable(QString("the UI froze for %1 ms").arg(maxGapMs_)));
    // The room's arrival on the UI thread (document, panels, the viewport's first upload) is not
    // part of this measure; it blocks the UI for a few hundred ms (see docs/architecture.md).
    QTest::qWait(20);
  }

  // GL and CPU paths show the same room, exposure and colour included, with no gain fitted.
  void glViewportMatchesCpuRenderer() {
    const Camera cam = photoCamera();
    QCOMPARE(cam.width, 640);
    const ImageRGB gl = window_->viewport()->renderLinear(cam, ViewMode::Relit);
    const ImageRGB cpu = doc()->session()->render(cam, RelightMethod::Full);
    const glm::dvec3 rel = meanRelativeDifference(gl, cpu);
    const double p = psnrNoGain(gl, cpu);
    qInfo("GL vs CPU (relit): mean relative difference %.4f %.4f %.4f, PSNR %.2f dB", rel.x, rel.y, rel.z, p);
    for (int c = 0; c < 3; ++c) QVERIFY(rel[c] <= 0.02);
    QVERIFY(p >= 35.0);
    const ImageRGB glRatio = window_->viewport()->renderLinear(cam, ViewMode::RatioOnly);
    const ImageRGB cpuRatio = doc()->session()->render(cam, RelightMethod::RatioOnly);
    qInfo("GL vs CPU (ratio-only): PSNR %.2f dB", psnrNoGain(glRatio, cpuRatio));
    QVERIFY(psnrNoGain(glRatio, cpuRatio) >= 35.0);

    // On screen: a 640 x 480 viewport's frame against the CPU image after the display transform.
    ViewportWidget screen;
    screen.setRoom(&doc()->scene(), &doc()->data(), doc()->session());
    screen.resize(640, 480);
    screen.show();
    QVERIFY(QTest::qWaitForWindowExposed(&screen));
    const QImage frame = screen.grabFramebuffer().convertToFormat(QImage::Format_RGB888);
    QCOMPARE(frame.size(), QSize(640, 480));
    const double p8 = psnr8(frame, exposed(cpu, doc()->data().photoExposure));
    qInfo("on-screen frame vs exposed CPU image: %.2f dB", p8);
    QVERIFY(p8 >= 35.0);
  }

  // Away from the photo's view, texels no photo saw (the ceiling here) show as a checker, never
  // black; in the photo's view nothing changes.
  void orbitShowsUnseenTexelsAsAChecker() {
    Camera up = Camera::lookAt(glm::dvec3(2.0, 2.6, 1.2), glm::dvec3(2.0, 2.61, 2.6), 640, 480, 400.0);
    const ImageRGB img = window_->viewport()->renderLinear(up, ViewMode::Relit);
    std::vector<double> lum;
    for (double x = 1.4; x <= 2.6; x += 0.011)  // clear of the lamps
      for (double y = 2.2; y <= 3.6; y += 0.011) {
        glm::dvec2 px;
        if (!up.project(glm::dvec3(x, y, 2.6), px) || px.x < 0 || px.y < 0 || px.x >= 640 || px.y >= 480) continue;
        const glm::vec3 c = img.at(int(px.x), int(px.y));
        lum.push_back(c.x + c.y + c.z);
      }
    QVERIFY(lum.size() > 1000);
    std::sort(lum.begin(), lum.end());
    const double p10 = lum[lum.size() / 10], p90 = lum[lum.size() * 9 / 10];
    qInfo("ceiling seen from below: luminance 10th percentile %.4f, 90th %.4f (ratio %.2f)", p10, p90, p90 / p10);
    QVERIFY(p10 > 0.0);         // never black
    QVERIFY(p90 / p10 > 2.0);   // two kinds of cells
  }

  // A wall seen from outside the room shows its back, black (and hides what lies behind it); the
  // same wall seen from inside shows its relit texture.
  void wallSeenFromBehindIsBlackAndFromTheFrontLit() {
    auto wallPixels = [&](const Camera& c, const ImageRGB& img) {
      std::vector<glm::vec3> out;
      for (double x = 0.6; x <= 3.4; x += 0.05)
        for (double z = 0.4; z <= 2.2; z += 0.05) {
          glm::dvec2 px;
          if (!c.project(glm::dvec3(x, 5.2, z), px) || px.x < 0 || px.y < 0 || px.x >= c.width || px.y >= c.height) continue;
          out.push_back(img.at(int(px.x), int(px.y)));
        }
      return out;
    };
    const Camera outside = Camera::lookAt(glm::dvec3(2.0, 8.0, 1.3), glm::dvec3(2.0, 5.2, 1.3), 640, 480, 300.0);
    const Camera inside = Camera::lookAt(glm::dvec3(2.0, 2.5, 1.3), glm::dvec3(2.0, 5.2, 1.3), 640, 480, 300.0);
    const auto behind = wallPixels(outside, window_->viewport()->renderLinear(outside, ViewMode::Relit));
    const auto front = wallPixels(inside, window_->viewport()->renderLinear(inside, ViewMode::Relit));
    QVERIFY(behind.size() > 1000 && front.size() > 1000);
    size_t black = 0, lit = 0;
    for (const auto& c : behind) black += c.x + c.y + c.z == 0.f;
    for (const auto& c : front) lit += c.x + c.y + c.z > 0.f;
    qInfo("back wall from outside: %zu of %zu points black; from inside: %zu of %zu lit", black, behind.size(), lit,
          front.size());
    QCOMPARE(black, behind.size());
    QCOMPARE(lit, front.size());
  }

  // Lamp A's slider to 0: its old shadow is gone (benchmark protocol); undo gives the frame back.
  void lampSliderToZeroThenUndo() {
    const Camera cam = photoCamera();
    const ImageRGB before = window_->viewport()->renderLinear(cam, ViewMode::Relit);
    const int a = lampIndex("A");
    QVERIFY(a >= 0);
    QSlider* slider = window_->lightsPanel()->slider(a);
    QCOMPARE(slider->value(), LightsPanel::positionOf(1.0));
    slider->setFocus();
    QTest::keyClick(slider, Qt::Key_Home);  // what a user does to pull it all the way down
    QCOMPARE(slider->value(), 0);
    QVERIFY(!window_->lightsPanel()->toggle(a)->isChecked());
    QCOMPARE(doc()->lampScale(a), glm::dvec3(0.0));
    const ImageRGB off = window_->viewport()->renderLinear(cam, ViewMode::Relit);
    saveShot(window_.get(), "main_window_lamp_A_off");

    const ImageRGB photo = readImageLinear((kRoom + "/photos/main.exr").toStdString());
    const ImageRGB unoccluded = readImageLinear((kRoom + "/truth/unoccluded.exr").toStdString());
    const ImageRGB truth = readImageLinear((kRoom + "/truth/A_off.exr").toStdString());
    const CompareMasks masks = benchmarkMasks(photo, unoccluded);
    const double p = compareImages(off, truth, masks.shadow).psnr;
    const double unchanged = compareImages(photo, truth, masks.shadow).psnr;
    qInfo("lamp A off from the slider: shadow-mask PSNR %.2f dB (photo unchanged %.2f dB)", p, unchanged);
    QVERIFY(p >= 30.0);
    QVERIFY(p >= unchanged + 10.0);

    doc()->undoStack()->undo();
    QCOMPARE(slider->value(), LightsPanel::positionOf(1.0));
    const ImageRGB back = window_->viewport()->renderLinear(cam, ViewMode::Relit);
    qInfo("after undo vs before: %.2f dB", psnrNoGain(back, before));
    QVERIFY(psnrNoGain(back, before) >= 50.0);
    doc()->undoStack()->redo();
    QCOMPARE(slider->value(), 0);
    doc()->undoStack()->undo();
  }

  // A slider drag is one undo step.
  void sliderDragIsOneUndoStep() {
    const int b = lampIndex("B");
    QSlider* slider = window_->lightsPanel()->slider(b);
    const int steps = doc()->undoStack()->index();
    slider->setSliderDown(true);
    for (int v = slider->value(); v <= LightsPanel::positionOf(2.0); v += 20) slider->setValue(v);
    slider->setValue(LightsPanel::positionOf(2.0));
    slider->setSliderDown(false);
    QCOMPARE(doc()->undoStack()->index(), steps + 1);
    QVERIFY(std::abs(doc()->lampScale(b).x - 2.0) < 0.02);
    doc()->undoStack()->undo();
    QCOMPARE(doc()->lampScale(b), glm::dvec3(1.0));
  }

  // Mean luminance of the image at world points (photo camera), skipping points it does not see.
  double meanAt(const ImageRGB& img, const std::vector<glm::dvec3>& pts) {
    double sum = 0;
    int n = 0;
    for (const auto& p : pts) {
      glm::dvec2 px;
      if (!photoCamera().project(p, px) || px.x < 0 || px.y < 0 || px.x >= img.width || px.y >= img.height) continue;
      const glm::vec3 c = img.at(int(px.x), int(px.y));
      sum += c.x + c.y + c.z;
      ++n;
    }
    return n ? sum / n : 0.0;
  }
  // Floor points on a grid that the photo camera sees directly (nothing between).
  std::vector<glm::dvec3> visibleFloor(double x0, double x1, double y0, double y1) {
    const auto& rays = doc()->session()->engine().rayScene();
    const glm::dvec3 eye = photoCamera().center();
    std::vector<glm::dvec3> out;
    for (double x = x0; x <= x1; x += 0.04)
      for (double y = y0; y <= y1; y += 0.04) {
        const glm::dvec3 p(x, y, 0.0);
        glm::dvec2 px;
        if (!photoCamera().project(p, px) || px.x < 2 || px.y < 2 || px.x >= 638 || px.y >= 478) continue;
        if (!rays.occluded(glm::vec3(eye), glm::vec3(p))) out.push_back(p);
      }
    return out;
  }

  // A lamp put on the ceiling over the table by a click, then lowered to 1 m above the table top:
  // the table brightens, and the floor the table hides from it keeps its light while the floor
  // around brightens (its shadow).
  void virtualLampByClick() {
    auto* vp = window_->viewport();
    const Camera cam = photoCamera();
    const ImageRGB before = vp->renderLinear(cam, ViewMode::Relit);
    // What the user sees of the table top, 8-bit on screen.
    auto screenTable = [&] {
      const QImage f = vp->grabFramebuffer();
      double sum = 0;
      int n = 0;
      for (double x = 1.4; x <= 2.2; x += 0.1)
        for (double y = 2.5; y <= 2.9; y += 0.1) {
          QPointF q;
          if (!vp->widgetPosition(glm::dvec3(x, y, 0.74), q)) continue;
          const QColor c = f.pixelColor((q * vp->devicePixelRatio()).toPoint());
          sum += c.red() + c.green() + c.blue();
          ++n;
        }
      return n ? sum / n : 0.0;
    };
    const double screenBefore = screenTable();
    // The ceiling above the table is out of the photo: look up at it in the free orbit.
    const glm::dvec3 ceiling(1.8, 2.7, 2.6);
    ViewportWidget::Orbit o;
    o.target[0] = ceiling.x;
    o.target[1] = ceiling.y;
    o.target[2] = ceiling.z;
    o.distance = 1.5;
    o.pitch = -1.3;  // from below
    o.yaw = -1.57;
    vp->setOrbitState(o);
    vp->setOrbit(true);
    QTest::qWait(50);
    QPointF pos;
    QVERIFY(vp->widgetPosition(ceiling, pos));
    QTest::mouseClick(window_->lightsPanel()->addLampButton(), Qt::LeftButton);
    QCOMPARE(window_->editTool()->mode(), EditTool::Mode::PlaceLamp);
    const int steps = doc()->undoStack()->index();
    // The click goes where a user's goes: to the viewport's native GL window.
    QTest::mouseClick(vp->glWindow(), Qt::LeftButton, {}, pos.toPoint());
    QCOMPARE(doc()->virtualLampCount(), size_t(1));
    QCOMPARE(doc()->undoStack()->index(), steps + 1);
    QCOMPARE(window_->editTool()->mode(), EditTool::Mode::Select);
    const VirtualLamp placed = doc()->session()->virtualLamp(0);
    glm::dvec3 c(0.0);
    for (const auto& v : placed.polygon) c += v / 4.0;
    qInfo("lamp placed at %.3f %.3f %.3f, %.2f m wide, add took %.0f ms", c.x, c.y, c.z,
          glm::length(placed.polygon[1] - placed.polygon[0]), doc()->lastUpdateMilliseconds());
    QVERIFY(std::abs(c.z - 2.58) < 1e-3);  // 2 cm under the ceiling, facing down
    QVERIFY(glm::length(glm::dvec2(c) - glm::dvec2(ceiling)) < 0.02);
    QVERIFY(polygonNormal(placed.polygon).z < -0.99);
    // Lowered on a 0.84 m suspension: 1 m above the table top (z 0.74).
    QDoubleSpinBox* drop = window_->lightsPanel()->virtualDrop(0);
    drop->setValue(0.86);
    emit drop->editingFinished();
    c = glm::dvec3(0.0);
    for (const auto& v : doc()->session()->virtualLamp(0).polygon) c += v / 4.0;
    QVERIFY(std::abs(c.z - 1.74) < 1e-6);
    // Its power up to 200 % of the brightest real lamp (its slider), as a designer would to see it.
    QSlider* power = window_->lightsPanel()->virtualSlider(0);
    power->setFocus();
    power->setValue(LightsPanel::positionOf(2.0));
    vp->lockToPhoto();
    const ImageRGB after = vp->renderLinear(cam, ViewMode::Relit);
    QTest::qWait(200);  // panels lay out their new rows, the viewport repaints
    const double screenAfter = screenTable();
    qInfo("on screen, the table top: %.0f -> %.0f (8-bit sum of RGB)", screenBefore, screenAfter);
    QVERIFY(screenAfter >= 1.2 * screenBefore);
    saveShot(window_.get(), "main_window_virtual_lamp");
    saveShot(window_->lightsPanel(), "lights_panel_virtual_lamp");
    saveShot(window_.get(), "main_window_virtual_lamp");
    saveShot(window_->lightsPanel(), "lights_panel_virtual_lamp");

    std::vector<glm::dvec3> table;
    for (double x = 1.3; x <= 2.3; x += 0.05)
      for (double y = 2.4; y <= 3.0; y += 0.05) table.emplace_back(x, y, 0.74);
    const double tableGain = meanAt(after, table) / meanAt(before, table);
    // Floor within 1.6 m of the table: hidden from the lamp's centre by the table, or not.
    const auto& rays = doc()->session()->engine().rayScene();
    std::vector<glm::dvec3> hidden, open;
    for (const auto& p : visibleFloor(0.2, 3.4, 1.0, 4.4)) {
      if (glm::length(glm::dvec2(p) - glm::dvec2(1.8, 2.7)) > 1.6) continue;
      (rays.occluded(glm::vec3(c), glm::vec3(p)) ? hidden : open).push_back(p);
    }
    const double hiddenGain = meanAt(after, hidden) / meanAt(before, hidden);
    const double openGain = meanAt(after, open) / meanAt(before, open);
    qInfo("virtual lamp 1 m above the table: table top x%.2f; floor it hides x%.2f (%zu points), floor around x%.2f "
          "(%zu points): hidden floor %.0f %% darker relative to the floor around",
          tableGain, hiddenGain, hidden.size(), openGain, open.size(), 100 * (1 - hiddenGain / openGain));
    QVERIFY(hidden.size() >= 20);
    QVERIFY(tableGain >= 1.2);
    QVERIFY(hiddenGain / openGain <= 0.7);
  }

  // A box placed on the floor by a click, dragged 40 px: it ends where the ray through the cursor
  // meets the floor, its shadow moves with it, few links are updated, the drag is one undo step.
  void boxPlacedAndDragged() {
    auto* vp = window_->viewport();
    vp->lockToPhoto();
    const Camera cam = photoCamera();
    const glm::dvec3 spot(0.7, 3.5, 0.0);
    QPointF pos;
    QVERIFY(vp->widgetPosition(spot, pos));
    QTest::mouseClick(window_->objectsPanel()->placeButton(), Qt::LeftButton);
    QTest::mouseClick(vp, Qt::LeftButton, {}, pos.toPoint());
    QCOMPARE(doc()->objectCount(), size_t(1));
    const std::string name = doc()->session()->object(0).name;
    const glm::dvec3 c0 = objectCentre(doc()->session()->object(0));
    qInfo("box placed, centre %.3f %.3f %.3f, add took %.0f ms", c0.x, c0.y, c0.z, doc()->lastUpdateMilliseconds());
    QVERIFY(glm::length(glm::dvec2(c0) - glm::dvec2(spot)) < 0.01);
    const ImageRGB before = vp->renderLinear(cam, ViewMode::Relit);
    // Umbra of the box from every real lamp's centre, at its old place.
    std::vector<glm::dvec3> lampCentres;
    for (const auto& l : doc()->scene().lamps) {
      glm::dvec3 m(0.0);
      for (const auto& v : doc()->scene().polygons[size_t(l.polygon)].vertices) m += v / 4.0;
      lampCentres.push_back(m);
    }
    auto umbra = [&](const std::vector<glm::dvec3>& pts) {  // per point: how many lamp centres are hidden
      std::vector<int> in;
      const auto& rays = doc()->session()->engine().rayScene();
      for (const auto& p : pts) {
        int n = 0;
        for (const auto& l : lampCentres) n += rays.occluded(glm::vec3(l), glm::vec3(p));
        in.push_back(n);
      }
      return in;
    };
    auto floorPts = visibleFloor(0.1, 1.6, 2.6, 4.6);
    const auto umbraBefore = umbra(floorPts);

    // Press on the box at its footprint's centre, drag 40 px to the right in 8 steps, release.
    const int steps = doc()->undoStack()->index();
    const QPoint start = pos.toPoint(), end = start + QPoint(40, 0);
    QTest::mousePress(vp, Qt::LeftButton, {}, start);
    std::vector<double> stepMs;
    for (int k = 1; k <= 8; ++k) {
      QMouseEvent move(QEvent::MouseMove, QPointF(start + QPoint(5 * k, 0)), vp->mapToGlobal(QPointF(start + QPoint(5 * k, 0))),
                       Qt::NoButton, Qt::LeftButton, Qt::NoModifier);
      QApplication::sendEvent(vp, &move);
      stepMs.push_back(doc()->lastUpdateMilliseconds());
    }
    std::sort(stepMs.begin(), stepMs.end());
    qInfo("drag steps (session: preview visibility + radiosity steps): median %.0f ms", stepMs[stepMs.size() / 2]);
    QTest::mouseRelease(vp, Qt::LeftButton, {}, end);
    QCOMPARE(doc()->undoStack()->index(), steps + 1);
    const glm::dvec3 c1 = objectCentre(doc()->session()->object(0));
    const ViewportPick ray = vp->pickAt(QPointF(end));
    const double t = (0.002 - ray.origin.z) / ray.direction.z;  // the plane the box stands on
    const glm::dvec3 target = ray.origin + t * ray.direction;
    qInfo("dragged 40 px: centre %.3f %.3f, ray meets the floor at %.3f %.3f (%.1f mm apart); %zu of %zu links "
          "updated when it settled, %.0f ms",
          c1.x, c1.y, target.x, target.y, 1000 * glm::length(glm::dvec2(c1) - glm::dvec2(target)),
          doc()->lastLinksUpdated(), doc()->session()->engine().links().size(), doc()->lastUpdateMilliseconds());
    QVERIFY(glm::length(glm::dvec2(c1) - glm::dvec2(c0)) > 0.05);
    QVERIFY(glm::length(glm::dvec2(c1) - glm::dvec2(target)) <= 0.01);
    QVERIFY(doc()->lastLinksUpdated() > 0);
    QVERIFY(doc()->lastLinksUpdated() < doc()->session()->engine().links().size() / 2);
    // The shadow moved: floor newly in the umbra darkened, floor that left it brightened.
    const ImageRGB after = vp->renderLinear(cam, ViewMode::Relit);
    const auto umbraAfter = umbra(floorPts);
    // Floor the camera sees at both places of the box, that lost or gained a lamp.
    // And floor the box's shadow neither reached nor left, away from both places: as it was.
    std::vector<glm::dvec3> entered, left, unchanged;
    const auto seenAfter = visibleFloor(0.1, 1.6, 2.6, 4.6);
    auto seen = [&](const glm::dvec3& p) {
      return std::any_of(seenAfter.begin(), seenAfter.end(), [&](const glm::dvec3& q) { return glm::length(p - q) < 1e-9; });
    };
    for (size_t i = 0; i < floorPts.size(); ++i) {
      if (!seen(floorPts[i])) continue;
      if (umbraAfter[i] > umbraBefore[i]) entered.push_back(floorPts[i]);
      if (umbraAfter[i] < umbraBefore[i]) left.push_back(floorPts[i]);
      if (umbraAfter[i] == umbraBefore[i] && umbraAfter[i] == 0 &&
          glm::length(glm::dvec2(floorPts[i]) - glm::dvec2(c0)) > 0.6 && glm::length(glm::dvec2(floorPts[i]) - glm::dvec2(c1)) > 0.6)
        unchanged.push_back(floorPts[i]);
    }
    const double darker = meanAt(after, entered) / meanAt(before, entered), brighter = meanAt(after, left) / meanAt(before, left);
    const double same = meanAt(after, unchanged) / meanAt(before, unchanged);
    qInfo("shadow moved: floor losing a lamp to the box x%.3f (%zu points), regaining one x%.3f (%zu points); floor away "
          "from it x%.3f (%zu points)",
          darker, entered.size(), brighter, left.size(), same, unchanged.size());
    QVERIFY(!entered.empty() && !left.empty() && !unchanged.empty());
    // A lamp's direct light is 10-40 % of the floor's where the box now hides it (three lamps, and
    // light from the walls): the change must stand well clear of the floor that kept its lamps.
    // Away from the box the floor changes only by the box's indirect light and by the radiosity
    // steps the settled solution has taken: measured 1.007-1.015 over runs (the drag's timing).
    QVERIFY(std::abs(same - 1.0) < 0.02);
    QVERIFY(darker < 0.95);
    QVERIFY(brighter > 1.05);
    window_->findChild<QDockWidget*>("ObjectsDock")->raise();
    QTest::qWait(200);
    vp->grabFramebuffer();  // a fresh frame for the window shot
    saveShot(window_.get(), "main_window_box");
    // Into the wall: refused, it stays.
    QString error;
    QVERIFY(!doc()->tryMoveObject(name, glm::dvec3(-3.0, 0, 0), 0.0, 0, &error));
    qInfo("refused: %s", qPrintable(error));
    QVERIFY(error.contains("intersects") || error.contains("outside"));
    QVERIFY(glm::length(objectCentre(doc()->session()->object(0)) - c1) < 1e-9);
    // Undo the drag: back where it was placed; redo: where it was dragged.
    doc()->undoStack()->undo();
    QVERIFY(glm::length(objectCentre(doc()->session()->object(0)) - c0) < 1e-6);
    doc()->undoStack()->redo();
    QVERIFY(glm::length(objectCentre(doc()->session()->object(0)) - c1) < 1e-6);
    window_->findChild<QDockWidget*>("ObjectsDock")->raise();
    QTest::qWait(50);
    saveShot(window_->objectsPanel(), "objects_panel");
    window_->findChild<QDockWidget*>("LightsDock")->raise();
  }

  // §4.4's interactive mesh (View menu): the session rebuilt with everything the user did, drags
  // on it, then back to the refined mesh.
  void interactiveMeshDrag() {
    const size_t refinedLeaves = doc()->session()->engine().totals().leaves;
    const size_t objects = doc()->objectCount(), lamps = doc()->virtualLampCount();
    QVERIFY(window_->switchMesh(true));
    QVERIFY2(waitForJob(300000), "the interactive mesh was not built");
    QCOMPARE(doc()->mesh(), SessionMesh::Interactive);
    QCOMPARE(doc()->objectCount(), objects);
    QCOMPARE(doc()->virtualLampCount(), lamps);
    const size_t leaves = doc()->session()->engine().totals().leaves;
    auto* vp = window_->viewport();
    vp->lockToPhoto();
    QVERIFY(objects > 0);
    const glm::dvec3 c0 = objectCentre(doc()->session()->object(0));
    QPointF pos;
    // Grabbed where the camera sees it (the table hides part of it): a point of one of its faces.
    bool found = false;
    for (const auto& face : doc()->session()->object(0).polygons) {
      glm::dvec3 m(0.0);
      for (const auto& v : face) m += v / double(face.size());
      if (vp->widgetPosition(m, pos) && !window_->editTool()->objectAt(vp->pickAt(pos)).empty()) {
        found = true;
        break;
      }
    }
    QVERIFY2(found, "no face of the box is in sight");
    const QPoint start = pos.toPoint(), end = start + QPoint(-30, 0);
    QTest::mousePress(vp, Qt::LeftButton, {}, start);
    std::vector<double> stepMs;
    for (int k = 1; k <= 6; ++k) {
      QMouseEvent move(QEvent::MouseMove, QPointF(start - QPoint(5 * k, 0)), vp->mapToGlobal(QPointF(start - QPoint(5 * k, 0))),
                       Qt::NoButton, Qt::LeftButton, Qt::NoModifier);
      QApplication::sendEvent(vp, &move);
      stepMs.push_back(doc()->lastUpdateMilliseconds());
    }
    QTest::mouseRelease(vp, Qt::LeftButton, {}, end);
    std::sort(stepMs.begin(), stepMs.end());
    const glm::dvec3 c1 = objectCentre(doc()->session()->object(0));
    // It moved as far as the cursor's ray moved on the plane it stands on.
    auto onFloor = [&](QPoint p) {
      const ViewportPick ray = vp->pickAt(QPointF(p));
      return ray.origin + ((0.002 - ray.origin.z) / ray.direction.z) * ray.direction;
    };
    const glm::dvec3 expected = c0 + (onFloor(end) - onFloor(start));
    qInfo("interactive mesh: %zu leaves (refined %zu); drag steps median %.0f ms; moved %.0f mm, %.1f mm from where "
          "the cursor's ray says",
          leaves, refinedLeaves, stepMs[stepMs.size() / 2], 1000 * glm::length(glm::dvec2(c1 - c0)),
          1000 * glm::length(glm::dvec2(c1) - glm::dvec2(expected)));
    QVERIFY(leaves < refinedLeaves);
    QVERIFY(glm::length(glm::dvec2(c1 - c0)) > 0.05);
    QVERIFY(glm::length(glm::dvec2(c1) - glm::dvec2(expected)) <= 0.01);
    doc()->undoStack()->undo();  // the drag, on this mesh too
    QVERIFY(glm::length(objectCentre(doc()->session()->object(0)) - c0) < 1e-6);
    QVERIFY(window_->switchMesh(false));
    QVERIFY2(waitForJob(300000), "the refined mesh was not rebuilt");
    QCOMPARE(doc()->mesh(), SessionMesh::Refined);
    QCOMPARE(doc()->session()->engine().totals().leaves >= refinedLeaves * 9 / 10, true);
  }

  // An OBJ mesh (a tetrahedron) placed on the floor by a click: it stands there; turns undo exactly.
  void objMeshPlaced() {
    const QString obj = tmp_.path() + "/tetrahedron.obj";
    {
      QFile f(obj);
      QVERIFY(f.open(QIODevice::WriteOnly | QIODevice::Text));
      f.write("# a lopsided tetrahedron, 0.4 m high, +Z up (not symmetric about its centre)\n"
              "v -0.2 -0.2 0\nv 0.3 -0.2 0\nv -0.2 0.1 0\nv -0.1 -0.1 0.4\n"
              "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n");
    }
    auto* vp = window_->viewport();
    vp->lockToPhoto();
    const size_t before = doc()->objectCount();
    QVERIFY(window_->objectsPanel()->placeObj(obj));
    QCOMPARE(window_->editTool()->mode(), EditTool::Mode::PlaceMesh);
    const glm::dvec3 spot(0.8, 2.5, 0.0);
    QPointF pos;
    QVERIFY(vp->widgetPosition(spot, pos));
    QTest::mouseClick(vp, Qt::LeftButton, {}, pos.toPoint());
    QCOMPARE(doc()->objectCount(), before + 1);
    const VirtualObject& o = doc()->session()->object(int(before));
    QCOMPARE(o.name, std::string("tetrahedron 1"));
    QCOMPARE(o.polygons.size(), size_t(4));
    glm::dvec3 lo(1e300), hi(-1e300);
    for (const auto& p : o.polygons)
      for (const auto& v : p) {
        lo = glm::min(lo, v);
        hi = glm::max(hi, v);
      }
    qInfo("tetrahedron placed: footprint centre %.3f %.3f, from z %.3f to %.3f, add took %.0f ms", 0.5 * (lo.x + hi.x),
          0.5 * (lo.y + hi.y), lo.z, hi.z, doc()->lastUpdateMilliseconds());
    QVERIFY(glm::length(glm::dvec2(0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y)) - glm::dvec2(spot)) < 0.01);
    QVERIFY(std::abs(lo.z - 0.002) < 1e-6 && std::abs(hi.z - 0.402) < 1e-6);
    // A file that is not a mesh says so and arms nothing.
    QVERIFY(!window_->objectsPanel()->placeObj(tmp_.path() + "/missing.obj"));
    QCOMPARE(window_->editTool()->mode(), EditTool::Mode::Select);
    // Turned by 37 degrees and back by undo: exactly where it was, though its shape is not
    // symmetric about its centre (it turns about a pivot that follows its moves).
    const auto placed = doc()->session()->object(int(before)).polygons;
    QString error;
    QVERIFY2(doc()->tryMoveObject(o.name, glm::dvec3(0.0), 37.0, 0, &error), qPrintable(error));
    QVERIFY2(doc()->tryMoveObject(o.name, glm::dvec3(0.1, 0.05, 0.0), 0.0, 0, &error), qPrintable(error));
    QVERIFY2(doc()->tryMoveObject(o.name, glm::dvec3(0.0), -61.0, 0, &error), qPrintable(error));
    for (int k = 0; k < 3; ++k) doc()->undoStack()->undo();
    double worst = 0;
    const auto back = doc()->session()->object(int(before)).polygons;
    for (size_t f = 0; f < back.size(); ++f)
      for (size_t v = 0; v < back[f].size(); ++v) worst = std::max(worst, glm::length(back[f][v] - placed[f][v]));
    qInfo("turned, moved, turned, all undone: %.2g m from where it was", worst);
    QVERIFY(worst < 1e-9);
    doc()->undoStack()->undo();
    QCOMPARE(doc()->objectCount(), before);
  }

  // An image-based object (Dinh, Metoyer, Turk) from the Objects panel: a fan placed by a click
  // on the floor, drawn by the viewport as the CPU renderer draws it (object and shadow), relit
  // when a lamp changes, dragged, turned and scaled, saved with the project and read back.
  void imageBasedObjectPlacedAndDragged() {
    // The example vase's fan, coarser than the default (the test's time), built by the library.
    ibr::FanOptions opt;
    opt.viewsPerRing = 24;
    opt.size = 256;
    const auto fan = ibr::buildFan(ibr::readMesh(str(QStringLiteral(RELUME_SOURCE_DIR) + "/resources/examples/vase.obj")), opt);
    const QString fanFile = tmp_.path() + "/vase.fan";
    ibr::writeFan(*fan, str(fanFile));
    auto* vp = window_->viewport();
    vp->lockToPhoto();
    const Camera cam = photoCamera();
    const ImageRGB before = vp->renderLinear(cam, ViewMode::Relit);
    QVERIFY(window_->objectsPanel()->placeImageFile(fanFile));
    QCOMPARE(window_->editTool()->mode(), EditTool::Mode::PlaceImage);
    const glm::dvec3 spot(2.0, 2.0, 0.0);
    QPointF pos;
    QVERIFY(vp->widgetPosition(spot, pos));
    QTest::mouseClick(vp, Qt::LeftButton, {}, pos.toPoint());
    QVERIFY2(doc()->imageObjects().size() == 1, qPrintable(window_->statusBar()->currentMessage()));
    const ibr::ImageObject placed = doc()->imageObjects()[0];
    QCOMPARE(placed.name, std::string("vase 1"));
    QVERIFY(glm::length(glm::dvec2(placed.place.position) - glm::dvec2(spot)) < 0.01);
    QTest::qWait(50);  // the viewport gets the object and its light at the next turn of the event loop

    // GL against the CPU renderer (ibr::drawImageObjects with the same lights), both over the
    // session's relit image: the object's pixels and the shadow's.
    const ImageRGB gl = vp->renderLinear(cam, ViewMode::Relit);
    const auto lights = doc()->imageObjectLighting();
    ImageRGB cpu = doc()->session()->render(cam, RelightMethod::Full);
    std::vector<uint8_t> mask;
    ibr::drawImageObjects(*doc()->session(), doc()->imageObjects(), lights, cam, cpu, &mask);
    size_t objectPixels = 0, shadowPixels = 0, glShadowPixels = 0;
    double seObject = 0, peak = 0, cpuTaken = 0, glTaken = 0;
    for (int y = 0; y < cam.height; ++y)
      for (int x = 0; x < cam.width; ++x) {
        const size_t i = size_t(y) * cam.width + x;
        const double b = glm::dot(glm::dvec3(before.at(x, y)), glm::dvec3(1.0 / 3));
        const double c = glm::dot(glm::dvec3(cpu.at(x, y)), glm::dvec3(1.0 / 3));
        const double g = glm::dot(glm::dvec3(gl.at(x, y)), glm::dvec3(1.0 / 3));
        if (mask[i] == 255) {
          ++objectPixels;
          seObject += glm::dot(glm::dvec3(gl.at(x, y) - cpu.at(x, y)), glm::dvec3(gl.at(x, y) - cpu.at(x, y))) / 3;
          peak = std::max(peak, c);
        } else if (mask[i] == 0 && b > 0) {  // the room: what the shadow took off
          if (c < 0.97 * b) ++shadowPixels;
          if (g < 0.97 * b) ++glShadowPixels;
          cpuTaken += std::max(0.0, b - c);
          glTaken += std::max(0.0, b - g);
        }
      }
    if (const QString dir = qEnvironmentVariable("RELUME_SCREENSHOT_DIR"); !dir.isEmpty()) {
      QDir().mkpath(dir);
      exposed(gl, doc()->data().photoExposure).save(dir + "/image_object_gl.png");
      exposed(cpu, doc()->data().photoExposure).save(dir + "/image_object_cpu.png");
      exposed(before, doc()->data().photoExposure).save(dir + "/image_object_before.png");
    }
    const double objectPsnr = 10 * std::log10(peak * peak / std::max(seObject / double(std::max<size_t>(objectPixels, 1)), 1e-30));
    qInfo("image-based object, GL vs CPU: %zu object pixels at %.2f dB; shadow (3 %% darker or more) %zu pixels GL, %zu "
          "CPU; light taken off the room GL / CPU %.3f",
          objectPixels, objectPsnr, glShadowPixels, shadowPixels, glTaken / std::max(cpuTaken, 1e-30));
    QVERIFY(objectPixels > 500);
    QVERIFY(objectPsnr >= 30.0);
    QVERIFY(shadowPixels > 200);
    QVERIFY(std::abs(double(glShadowPixels) / double(shadowPixels) - 1.0) < 0.25);
    QVERIFY(std::abs(glTaken / cpuTaken - 1.0) < 0.25);

    // A lamp switched off: the object darkens, and so does the viewport's picture of it.
    auto objectMean = [&](const ImageRGB& img) {
      double sum = 0;
      size_t n = 0;
      for (size_t i = 0; i < mask.size(); ++i)
        if (mask[i] == 255) {
          sum += glm::dot(glm::dvec3(img.pixels[3 * i], img.pixels[3 * i + 1], img.pixels[3 * i + 2]), glm::dvec3(1.0 / 3));
          ++n;
        }
      return sum / double(std::max<size_t>(n, 1));
    };
    const int a = lampIndex("A");
    const glm::dvec3 scaleA = doc()->lampScale(a);
    doc()->editLampScale(a, glm::dvec3(0.0));
    QTest::qWait(50);
    const double lit = objectMean(gl), dimmed = objectMean(vp->renderLinear(cam, ViewMode::Relit));
    qInfo("lamp A off: the object's mean radiance x%.3f", dimmed / lit);
    QVERIFY(dimmed < 0.9 * lit);
    doc()->undoStack()->undo();
    QCOMPARE(doc()->lampScale(a), scaleA);

    // Dragged 40 px to the right along the floor: it follows the cursor; one undo step.
    const int steps = doc()->undoStack()->index();
    // Where the object stands now (the panels beside the viewport may have changed its size).
    QVERIFY(vp->widgetPosition(placed.place.position, pos));
    const QPoint start = pos.toPoint() + QPoint(0, -8), end = start + QPoint(40, 0);
    QVERIFY(!window_->editTool()->imageObjectAt(vp->pickAt(QPointF(start))).empty());
    QTest::mousePress(vp, Qt::LeftButton, {}, start);
    for (int k = 1; k <= 8; ++k) {
      QMouseEvent move(QEvent::MouseMove, QPointF(start + QPoint(5 * k, 0)), vp->mapToGlobal(QPointF(start + QPoint(5 * k, 0))),
                       Qt::NoButton, Qt::LeftButton, Qt::NoModifier);
      QApplication::sendEvent(vp, &move);
    }
    QTest::mouseRelease(vp, Qt::LeftButton, {}, end);
    QCOMPARE(doc()->undoStack()->index(), steps + 1);
    const glm::dvec3 p1 = doc()->imageObjects()[0].place.position;
    auto onPlane = [&](const QPoint& w) {
      const ViewportPick r = vp->pickAt(QPointF(w));
      return r.origin + (placed.place.position.z - r.origin.z) / r.direction.z * r.direction;
    };
    const glm::dvec3 expected = placed.place.position + onPlane(end) - onPlane(start);
    qInfo("image-based object dragged 40 px: %.3f %.3f (the cursor's ray says %.3f %.3f)", p1.x, p1.y, expected.x, expected.y);
    QVERIFY(glm::length(p1 - expected) < 0.005);
    // Turned and scaled from its row; into the wall refused.
    window_->findChild<QDockWidget*>("ObjectsDock")->raise();
    window_->objectsPanel()->imageTurn(0)->setValue(90);
    QVERIFY(std::abs(doc()->imageObjects()[0].place.yaw - std::numbers::pi / 2) < 1e-9);
    window_->objectsPanel()->imageScale(0)->setValue(1.25);
    QCOMPARE(doc()->imageObjects()[0].place.scale, 1.25);
    QString error;
    ibr::Placement wall = doc()->imageObjects()[0].place;
    wall.position.x = -0.05;
    QVERIFY(!doc()->tryPlaceImageObject("vase 1", wall, 0, &error));
    qInfo("refused: %s", qPrintable(error));
    QVERIFY(error.contains("vase.fan") && error.contains("vase 1"));
    QTest::qWait(200);
    vp->grabFramebuffer();
    saveShot(window_.get(), "main_window_image_object");
    saveShot(window_->objectsPanel(), "objects_panel_image_object");

    // Saved with the project (its fan inside it) and read back where it stands.
    const QString folder = tmp_.path() + "/image_object.relume";
    QVERIFY(window_->saveTo(folder));
    QVERIFY(waitForJob(120000));
    QVERIFY2(!doc()->isDirty(), qPrintable(window_->lastError()));
    QVERIFY(QFile::exists(folder + "/objects/image_1.fan"));
    const auto room = loadRoomForWorkbench(folder, silentProgress());
    QCOMPARE(room->imageObjects.size(), size_t(1));
    QCOMPARE(room->imageObjects[0].name, std::string("vase 1"));
    QVERIFY(glm::length(room->imageObjects[0].place.position - doc()->imageObjects()[0].place.position) < 1e-9);
    QVERIFY(std::abs(room->imageObjects[0].place.yaw - doc()->imageObjects()[0].place.yaw) < 1e-9);
    QCOMPARE(room->imageObjects[0].place.scale, 1.25);
    QCOMPARE(room->imageObjects[0].fan->viewCount(), fan->viewCount());
    // A damaged fan is refused by name and arms nothing; a mesh gets its fan rendered as a job
    // (progress, Cancel), then the tool is armed with it.
    const QString damaged = tmp_.path() + "/damaged.fan";
    QVERIFY(QFile::copy(fanFile, damaged));
    {
      QFile f(damaged);
      QVERIFY(f.open(QIODevice::ReadWrite));
      f.seek(f.size() / 2);
      f.write("damage");
    }
    QString said;
    auto saying = connect(window_->objectsPanel(), &ObjectsPanel::message, this, [&](const QString& m) { said = m; });
    QVERIFY(!window_->objectsPanel()->placeImageFile(damaged));
    qInfo("damaged fan: %s", qPrintable(said));
    QVERIFY(said.contains("damaged.fan") && said.contains("damaged"));
    QCOMPARE(window_->editTool()->mode(), EditTool::Mode::Select);
    const QString tetra = tmp_.path() + "/tetra.obj";
    {
      QFile f(tetra);
      QVERIFY(f.open(QIODevice::WriteOnly | QIODevice::Text));
      f.write("v -0.2 -0.2 0\nv 0.3 -0.2 0\nv -0.2 0.1 0\nv -0.1 -0.1 0.4\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n");
    }
    QVERIFY(window_->objectsPanel()->placeImageFile(tetra));
    QVERIFY(window_->jobs()->busy());
    QVERIFY(waitForJob(120000));
    QCOMPARE(window_->editTool()->mode(), EditTool::Mode::PlaceImage);
    window_->editTool()->setMode(EditTool::Mode::Select);
    disconnect(saying);
    // Undo everything back to before it was placed: no image-based object; the room as it was.
    while (!doc()->imageObjects().empty() && doc()->undoStack()->canUndo()) doc()->undoStack()->undo();
    QVERIFY(doc()->imageObjects().empty());
    QTest::qWait(50);
    const double back = psnrNoGain(vp->renderLinear(cam, ViewMode::Relit), before);
    qInfo("all undone vs before it was placed: %.2f dB", back);
    QVERIFY(back >= 60.0);
    window_->findChild<QDockWidget*>("LightsDock")->raise();
  }

  // Reference patches (§4.3): the user picks the floor's reference texel in the viewport, and
  // paints a region over the table's shadow with the texel its occluded elements take their
  // colour from, then recomputes: the project's relighting data carries both choices and the
  // floor's shadow-free texture follows them; lamps, virtual lamps and objects are kept.
  void referencePatchPickedAndRecomputed() {
    auto* vp = window_->viewport();
    vp->lockToPhoto();
    auto* panel = window_->referencesPanel();
    window_->findChild<QDockWidget*>("ReferencesDock")->raise();
    QTest::qWait(50);
    const auto items = panel->list()->findItems("floor", Qt::MatchExactly, 0);
    QCOMPARE(items.size(), 1);
    panel->list()->setCurrentItem(items.front());
    QVERIFY(panel->pickButton()->isEnabled());
    QVERIFY(!panel->recomputeButton()->isEnabled());
    QTest::mouseClick(panel->pickButton(), Qt::LeftButton);
    QCOMPARE(window_->editTool()->mode(), EditTool::Mode::PickReference);
    const glm::dvec3 spot(3.2, 2.3, 0.0);  // unshadowed floor the photo shows
    QPointF pos;
    QVERIFY(vp->widgetPosition(spot, pos));
    QTest::mouseClick(vp, Qt::LeftButton, {}, pos.toPoint());
    QCOMPARE(window_->editTool()->mode(), EditTool::Mode::Select);
    const int floor = doc()->scene().findPolygon("floor");
    const glm::dvec2 uv = doc()->session()->engine().toUV(floor, spot);
    QVERIFY(doc()->referenceOverrides().count("floor"));
    QVERIFY(glm::length(doc()->referenceOverrides().at("floor") - uv) < 0.01);
    QVERIFY(doc()->referencesPending());
    QVERIFY(panel->recomputeButton()->isEnabled());

    // A region painted over the table's shadow (a drag), then its reference texel (a click).
    const glm::dvec3 shadow(1.8, 2.3, 0.0);
    QPointF shadowPos;
    QVERIFY(vp->widgetPosition(shadow, shadowPos));
    const QColor plain = vp->grabFramebuffer().pixelColor(shadowPos.toPoint());
    panel->brush()->setValue(0.2);
    QTest::mouseClick(panel->paintButton(), Qt::LeftButton);
    QCOMPARE(window_->editTool()->mode(), EditTool::Mode::PaintRegion);
    QPointF from, to;
    QVERIFY(vp->widgetPosition(shadow - glm::dvec3(0.3, 0, 0), from));
    QVERIFY(vp->widgetPosition(shadow + glm::dvec3(0.3, 0, 0), to));
    QTest::mousePress(vp, Qt::LeftButton, {}, from.toPoint());
    for (int k = 1; k <= 6; ++k) {
      const QPointF p = from + (to - from) * (k / 6.0);
      QMouseEvent move(QEvent::MouseMove, p, vp->mapToGlobal(p), Qt::NoButton, Qt::LeftButton, Qt::NoModifier);
      QApplication::sendEvent(vp, &move);
    }
    QTest::mouseRelease(vp, Qt::LeftButton, {}, to.toPoint());
    QVERIFY(window_->editTool()->stroke().discs.size() >= 4);
    QVERIFY(doc()->referenceRegions().empty());
    const int stepsBefore = doc()->undoStack()->index();
    QTest::mouseClick(vp, Qt::LeftButton, {}, pos.toPoint());  // the reference: the spot above
    QCOMPARE(window_->editTool()->mode(), EditTool::Mode::Select);
    QCOMPARE(doc()->referenceRegions().size(), size_t(1));
    QCOMPARE(doc()->undoStack()->index(), stepsBefore + 1);
    const ReferenceRegion painted = doc()->referenceRegions().front();
    QCOMPARE(painted.polygon, std::string("floor"));
    QVERIFY(glm::length(painted.reference - uv) < 0.01);
    QVERIFY(painted.contains(doc()->session()->engine().toUV(floor, shadow)));
    QVERIFY(!painted.contains(doc()->session()->engine().toUV(floor, shadow + glm::dvec3(0.6, 0, 0))));
    // The region shows over the image (magenta) while the panel is open.
    QTest::qWait(50);
    const QColor marked = vp->grabFramebuffer().pixelColor(shadowPos.toPoint());
    qInfo("painted region over the shadow: %d %d %d -> %d %d %d", plain.red(), plain.green(), plain.blue(), marked.red(),
          marked.green(), marked.blue());
    QVERIFY(marked.blue() - marked.green() > plain.blue() - plain.green() + 15);
    QVERIFY(marked.red() - marked.green() > plain.red() - plain.green() + 15);
    saveShot(window_.get(), "main_window_reference_region");
    doc()->undoStack()->undo();
    QVERIFY(doc()->referenceRegions().empty());
    doc()->undoStack()->redo();
    QCOMPARE(doc()->referenceRegions().size(), size_t(1));
    saveShot(panel, "references_panel");

    // The occluded (blue) and frontier (yellow) elements over the image, on request.
    {
      const ImageRGB relit = vp->renderLinear(photoCamera(), ViewMode::Relit);
      QTest::mouseClick(panel->showButton(), Qt::LeftButton);
      QCOMPARE(vp->viewMode(), ViewMode::References);
      const ImageRGB shown = vp->renderLinear(photoCamera(), ViewMode::References);
      int bluer = 0, yellower = 0, n = 0;
      for (int y = 0; y < shown.height; ++y)
        for (int x = 0; x < shown.width; ++x) {
          const glm::vec3 a = relit.at(x, y), b = shown.at(x, y);
          ++n;
          if (b.z > 1.3f * a.z && b.x < a.x) ++bluer;
          if (b.x > 1.05f * a.x && b.z < 0.8f * a.z) ++yellower;
        }
      qInfo("references view: %.1f %% of the pixels occluded (blue), %.1f %% frontier (yellow)", 100.0 * bluer / n,
            100.0 * yellower / n);
      QVERIFY(bluer > n / 100);
      QVERIFY(yellower > n / 1000);
      // The floor in the table's shadow is occluded.
      glm::dvec2 px;
      QVERIFY(photoCamera().project(glm::dvec3(1.8, 2.2, 0.0), px));
      QVERIFY(shown.at(int(px.x), int(px.y)).z > 1.3f * relit.at(int(px.x), int(px.y)).z);
      saveShot(vp, "viewport_references");
      QTest::mouseClick(panel->showButton(), Qt::LeftButton);
      QCOMPARE(vp->viewMode(), ViewMode::Relit);
    }
    const auto before = doc()->data().textures[size_t(floor)].unoccluded;
    const size_t vlamps = doc()->virtualLampCount(), objects = doc()->objectCount();
    const glm::dvec3 scaleA = doc()->lampScale(lampIndex("A"));
    const RelightSession* live = doc()->session();
    QElapsedTimer recomputeTime;
    recomputeTime.start();
    QTest::mouseClick(panel->recomputeButton(), Qt::LeftButton);
    QVERIFY(window_->jobs()->busy());
    QVERIFY2(waitForJob(600000), "the recompute did not finish");
    qInfo("Recompute (step 2 of the floor, then the live session's new maps): %lld ms, of which %.0f ms on the UI thread",
          recomputeTime.elapsed(), doc()->lastUpdateMilliseconds());
    QVERIFY2(doc()->session() == live, "the live session takes the new maps; it is not rebuilt");
    QVERIFY2(window_->lastError().isEmpty() || !window_->jobs()->busy(), qPrintable(window_->lastError()));
    QVERIFY(!doc()->referencesPending());
    QVERIFY(doc()->data().referenceOverride.count("floor"));
    QVERIFY(glm::length(doc()->data().referenceOverride.at("floor") - uv) < 0.01);
    QCOMPARE(doc()->virtualLampCount(), vlamps);
    QCOMPARE(doc()->objectCount(), objects);
    QCOMPARE(doc()->session()->lampScale(lampIndex("A")), scaleA);
    const auto& after = doc()->data().textures[size_t(floor)].unoccluded;
    QCOMPARE(after.size(), before.size());
    double changed = 0, total = 0;
    for (size_t i = 0; i < after.size(); ++i) {
      changed += glm::length(after[i] - before[i]);
      total += glm::length(before[i]);
    }
    const auto& est = doc()->data().estimates;
    qInfo("reference patch of the floor at %.2f %.2f: %zu occluded elements took a polygon's reference; the floor's "
          "shadow-free texture moved by %.2f %% (mean relative)",
          uv.x, uv.y, est.referencedByDefault, 100 * changed / std::max(total, 1e-30));
    QVERIFY(est.referencedByDefault > 0);
    QVERIFY(changed > 0);
    QVERIFY(doc()->data().referenceRegions == doc()->referenceRegions());
    qInfo("%zu occluded elements took the painted region's reference", est.referencedByRegion);
    QVERIFY(est.referencedByRegion > 10);
    // The viewport shows the new session, and it still matches the CPU renderer.
    const ImageRGB gl = vp->renderLinear(photoCamera(), ViewMode::Relit);
    const ImageRGB cpu = doc()->session()->render(photoCamera(), RelightMethod::Full);
    QVERIFY(psnrNoGain(gl, cpu) >= 35.0);
    window_->findChild<QDockWidget*>("LightsDock")->raise();
  }

  // The Photos panel: a folder with a bracket of three exposures (EXIF exposure times), two
  // photos, four checkerboard photos and two files that are not photos imports the good ones into
  // the capture, lists the bad ones with the reason, groups the bracket, loads thumbnails and
  // histograms off the UI thread, merges the bracket to HDR with its response curve, and
  // calibrates the camera from the checkerboards.
  void photosImportedMergedAndCalibrated() {
    auto* panel = window_->photosPanel();
    auto* dock = window_->findChild<QDockWidget*>("PhotosDock");
    dock->show();
    const QString in = tmp_.path() + "/shoot", capture = tmp_.path() + "/capture";
    QVERIFY(QDir().mkpath(in));
    const std::string room = std::string(RELUME_SOURCE_DIR) + "/resources/sample_room/photos/";
    const ImageRGB radiance = readImageLinear(room + "main.exr");
    double mean = 0;
    for (int y = 0; y < radiance.height; ++y)
      for (int x = 0; x < radiance.width; ++x) mean += double(radiance.at(x, y).y);
    mean /= double(radiance.width) * radiance.height;
    const double times[] = {1.0 / 60, 1.0 / 15, 1.0 / 4};
    for (int k = 0; k < 3; ++k) {
      Image8 im;
      im.width = radiance.width;
      im.height = radiance.height;
      im.pixels.resize(size_t(im.width) * im.height * 3);
      const double gain = 0.18 / (mean * times[1]) * times[k];
      for (int y = 0; y < im.height; ++y)
        for (int x = 0; x < im.width; ++x)
          for (int c = 0; c < 3; ++c)
            im.pixels[(size_t(y) * im.width + x) * 3 + c] = (unsigned char)std::lround(
                255.0 * linearToSrgb(float(std::clamp(double(radiance.at(x, y)[c]) * gain, 0.0, 1.0))));
      recon::PhotoInfo exif;
      exif.exposureTime = times[k];
      exif.fNumber = 8;
      exif.iso = 100;
      exif.focalMm = 24;
      exif.make = "Relume";
      exif.model = "Test";
      writeImage8((in + QString("/a%1.tif").arg(k)).toStdString(), im, recon::exifMetadata(exif));
    }
    QVERIFY(QFile::copy(QString::fromStdString(room + "view0.png"), in + "/view0.png"));
    {  // a JPEG with its EXIF (OpenImageIO's TIFF writer keeps no ISO)
      recon::PhotoInfo exif;
      exif.fNumber = 5.6;
      exif.iso = 400;
      exif.focal35mm = 28;
      exif.make = "Relume";
      exif.model = "Test";
      writeImage8((in + "/view1.jpg").toStdString(), readImage8(room + "view1.png"), recon::exifMetadata(exif));
    }
    const glm::dvec3 board(4 * 0.025, 2.5 * 0.025, 0);
    const glm::dvec3 eyes[] = {{0.0, -0.1, -0.45}, {0.25, 0.1, -0.4}, {-0.1, 0.25, -0.42}, {0.3, -0.15, -0.5}};
    for (int k = 0; k < 4; ++k)
      writeImage8((in + QString("/board%1.png").arg(k)).toStdString(),
                  test::renderCheckerboard(Camera::lookAt(board + eyes[k], board, 640, 480, 600), -0.12, 9, 6, 0.025));
    {
      QFile bad(in + "/broken.jpg");
      QVERIFY(bad.open(QIODevice::WriteOnly));
      bad.write("this is not a photo");
      QFile png(in + "/view0.png"), cut(in + "/truncated.png");
      QVERIFY(png.open(QIODevice::ReadOnly) && cut.open(QIODevice::WriteOnly));
      cut.write(png.read(200));
    }
    panel->setCaptureFolder(capture);
    // The import (a job) and the thumbnails and histograms (a thread pool) run off the UI thread:
    // the event loop answers all through.
    qint64 gap = 0;
    {
      QElapsedTimer wall, tick;
      QTimer probe;
      QObject::connect(&probe, &QTimer::timeout, [&] { gap = std::max(gap, tick.restart()); });
      wall.start();
      tick.start();
      probe.start(10);
      QVERIFY(panel->importFolder(in));
      QVERIFY2(waitForJob(120000), "the import did not finish");
      while (panel->thumbnailsPending() > 0 && wall.elapsed() < 60000) QTest::qWait(10);
    }
    QCOMPARE(panel->thumbnailsPending(), 0);
    const auto& entries = panel->entries();
    QCOMPARE(int(entries.size()), 11);
    int bad = 0, bracket = -1;
    for (const auto& e : entries) {
      const QString name = QFileInfo(e.path).fileName();
      if (name == "broken.jpg" || name == "truncated.png") {
        ++bad;
        QVERIFY2(e.problem.contains(name), qPrintable(e.problem));
        continue;
      }
      QVERIFY2(e.problem.isEmpty(), qPrintable(name + ": " + e.problem));
      QVERIFY2(QFileInfo(e.path).absolutePath() == QDir(capture + "/originals").absolutePath(), qPrintable(e.path));
      QVERIFY(!e.thumbnail.isNull());
      if (name.startsWith("a")) {
        QCOMPARE(e.members, 3);
        QVERIFY(bracket < 0 || e.bracket == bracket);
        bracket = e.bracket;
        QCOMPARE(e.info.fNumber, 8.0);
        QCOMPARE(e.info.exposureTime > 0, true);
      } else {
        if (name == "view1.jpg") {
          QCOMPARE(e.info.iso, 400.0);
          QVERIFY(std::abs(e.info.fNumber - 5.6) < 1e-3);
          QCOMPARE(e.info.focal35mm, 28.0);
        }
        QVERIFY(e.members <= 1);
      }
    }
    QCOMPARE(bad, 2);
    qInfo("photos: %zu listed, %d unreadable with a reason; longest event-loop gap while thumbnails loaded %lld ms",
          entries.size(), bad, gap);
    // Decoding thumbnails on the UI thread would freeze it for seconds; 150 ms leaves room for a
    // loaded 2-core machine (84-101 ms measured here).
    QVERIFY(gap < 150);
    // The selected photo's histogram: three channels over every thumbnail pixel.
    auto* list = panel->list();
    for (int r = 0; r < list->topLevelItemCount(); ++r)
      if (list->topLevelItem(r)->text(0) == "a1.tif") list->setCurrentItem(list->topLevelItem(r));
    QTest::qWait(50);
    auto* histogram = static_cast<QChartView*>(panel->histogramChart())->chart();
    QCOMPARE(histogram->series().size(), 3);
    saveShot(panel, "photos_panel");

    // The bracket merged: a radiance image beside its middle exposure, and the recovered response.
    QVERIFY(panel->mergeBrackets());
    QVERIFY2(waitForJob(120000), "the merge did not finish");
    QVERIFY(QFile::exists(capture + "/photos/a1.tif"));
    QVERIFY(QFile::exists(capture + "/photos/a1.exr"));
    QVERIFY(!QFile::exists(capture + "/photos/view0.exr"));
    const ImageRGB merged = readImageLinear((capture + "/photos/a1.exr").toStdString());
    QCOMPARE(merged.width, radiance.width);
    // Relative radiance: its ratios between a dark and a bright region are the scene's.
    auto regionMean = [](const ImageRGB& img, int x0, int y0) {
      double m = 0;
      for (int y = y0; y < y0 + 20; ++y)
        for (int x = x0; x < x0 + 20; ++x) m += double(img.at(x, y).y);
      return m / 400;
    };
    const double truthRatio = regionMean(radiance, 300, 60) / regionMean(radiance, 300, 420);
    const double mergedRatio = regionMean(merged, 300, 60) / regionMean(merged, 300, 420);
    qInfo("merged bracket: radiance ratio %.3f against the scene's %.3f", mergedRatio, truthRatio);
    QVERIFY(std::abs(mergedRatio / truthRatio - 1) < 0.1);
    auto* response = static_cast<QChartView*>(panel->responseChart())->chart();
    QCOMPARE(response->series().size(), 3);
    QVERIFY(static_cast<QLineSeries*>(response->series()[0])->count() > 200);
    panel->findChild<QTabWidget*>()->setCurrentIndex(1);
    QTest::qWait(50);
    saveShot(panel, "photos_response");

    // Calibration: too few photos is refused; the four checkerboards give the camera.
    list->clearSelection();
    QVERIFY(!panel->calibrateSelected());
    QVERIFY(panel->calibrationLabel()->text().contains("3"));
    for (int r = 0; r < list->topLevelItemCount(); ++r)
      if (list->topLevelItem(r)->text(0).startsWith("board")) list->topLevelItem(r)->setSelected(true);
    QVERIFY(panel->calibrateSelected());
    QVERIFY2(waitForJob(120000), "the calibration did not finish");
    QVERIFY(panel->intrinsics());
    const auto& K = *panel->intrinsics();
    qInfo("calibration from 4 boards: fx %.1f fy %.1f cx %.1f cy %.1f k1 %.3f, rms %.3f px", K.fx, K.fy, K.cx, K.cy, K.k1, K.rms);
    QVERIFY(std::abs(K.fx - 600) < 10 && std::abs(K.cy - 240) < 6);
    QVERIFY(K.rms < 0.5);
    QVERIFY(QFile::exists(capture + "/intrinsics.json"));
    QVERIFY(panel->calibrationLabel()->text().contains("Reprojection error"));
    panel->findChild<QTabWidget*>()->setCurrentIndex(2);
    QTest::qWait(50);
    saveShot(panel, "photos_calibration");
    saveShot(window_.get(), "main_window_photos");
    panel->findChild<QTabWidget*>()->setCurrentIndex(0);
    // Another photo of the same name (other bytes) is kept beside the first, not over it.
    {
      const QString again = tmp_.path() + "/shoot2";
      QVERIFY(QDir().mkpath(again));
      QVERIFY(QFile::copy(QString::fromStdString(room + "view2.png"), again + "/view0.png"));
      const size_t before = panel->entries().size();
      QVERIFY(panel->importFolder(again));
      QVERIFY2(waitForJob(120000), "the second import did not finish");
      QCOMPARE(panel->entries().size(), before + 1);
      QVERIFY(QFile::exists(capture + "/originals/view0.png") && QFile::exists(capture + "/originals/view0_2.png"));
      QFile a(capture + "/originals/view0.png"), b(QString::fromStdString(room + "view0.png"));
      QVERIFY(a.open(QIODevice::ReadOnly) && b.open(QIODevice::ReadOnly));
      QVERIFY(a.readAll() == b.readAll());
    }
    dock->hide();
  }

  // The Reconstruction panel: COLMAP on the sample room's photos registers every view; the
  // metric frame from two picked points with a typed distance and three picked floor points puts
  // the model in metres (on disk too); Cancel during feature extraction leaves no COLMAP process
  // and no model.
  void reconstructionFromThePanel() {
    auto* panel = window_->reconstructionPanel();
    auto* dock = window_->findChild<QDockWidget*>("ReconstructionDock");
    dock->show();
    dock->raise();
    const QString photos = QString(RELUME_SOURCE_DIR) + "/resources/sample_room/photos", ws = tmp_.path() + "/ws";
    panel->photosFolder()->setText(photos);
    panel->workspace()->setText(ws);
    QVERIFY(panel->run());
    QVERIFY2(waitForJob(600000), "COLMAP did not finish");
    QVERIFY2(panel->result(), qPrintable(window_->lastError()));
    const auto& run = *panel->result();
    const int pngs = int(QDir(photos).entryList({"*.png"}, QDir::Files).size());
    qInfo("COLMAP from the panel: %zu of %d photos registered, %zu points, mean reprojection error %.2f px",
          run.registered.size(), pngs, run.model.points.size(), recon::meanReprojectionError(run.model));
    QCOMPARE(int(run.registered.size()), pngs);
    QVERIFY(run.leftOut.empty());
    QCOMPARE(panel->photosList()->topLevelItemCount(), pngs);
    QCOMPARE(panel->view()->pointCount(), run.model.points.size());
    QVERIFY(run.model.points.size() > 50);

    // Points that a click in the view selects (visible, not hidden behind others' screen spots).
    auto* view = panel->view();
    std::vector<std::pair<long long, QPointF>> clickable;
    {
      std::vector<glm::dvec3> xyz;
      std::vector<std::array<uint8_t, 3>> rgb;
      std::vector<Camera> cams;
      std::vector<long long> ids;
      for (const auto& [id, p] : run.model.points) xyz.push_back(p.xyz), rgb.push_back(p.rgb), ids.push_back(id);
      for (const auto& [id, im] : run.model.images) cams.push_back(run.model.camera(im));
      view->setModel(xyz, rgb, cams);
      QTest::qWait(50);
      for (size_t i = 0; i < xyz.size(); ++i) {
        QPointF at;
        if (view->widgetPosition(xyz[i], at) && view->pointAt(at) == int(i)) clickable.emplace_back(ids[i], at);
      }
    }
    QVERIFY(clickable.size() >= 5);
    // The two farthest apart on screen for the scale; three spread ones for the floor.
    size_t a = 0, b = 1;
    for (size_t i = 0; i < clickable.size(); ++i)
      for (size_t j = i + 1; j < clickable.size(); ++j)
        if (QLineF(clickable[i].second, clickable[j].second).length() > QLineF(clickable[a].second, clickable[b].second).length())
          a = i, b = j;
    std::vector<size_t> floorPick;
    for (size_t i = 0; i < clickable.size() && floorPick.size() < 3; ++i) {
      if (i == a || i == b) continue;
      bool spread = true;
      for (size_t f : floorPick) spread = spread && QLineF(clickable[i].second, clickable[f].second).length() > 40;
      if (spread) floorPick.push_back(i);
    }
    QCOMPARE(floorPick.size(), size_t(3));
    panel->setPicking(ReconstructionPanel::Picking::Scale);
    QTest::mouseClick(view, Qt::LeftButton, {}, clickable[a].second.toPoint());
    QTest::mouseClick(view, Qt::LeftButton, {}, clickable[b].second.toPoint());
    QCOMPARE(panel->scalePoints(), (std::vector<long long>{clickable[a].first, clickable[b].first}));
    panel->distance()->setValue(2.5);
    panel->setPicking(ReconstructionPanel::Picking::Floor);
    for (size_t f : floorPick) QTest::mouseClick(view, Qt::LeftButton, {}, clickable[f].second.toPoint());
    QCOMPARE(panel->floorPoints().size(), size_t(3));
    QVERIFY(panel->applyMetricFrame());
    const recon::ColmapModel onDisk = recon::readColmapModel(panel->result()->modelFolder);
    const double d = glm::length(onDisk.points.at(clickable[a].first).xyz - onDisk.points.at(clickable[b].first).xyz);
    double worstZ = 0;
    for (long long id : panel->floorPoints()) worstZ = std::max(worstZ, std::abs(onDisk.points.at(id).xyz.z));
    qInfo("metric frame: picked points %.6f m apart (typed 2.5), floor points within %.2e m of z = 0, cameras at z = %.2f",
          d, worstZ, recon::meanCameraCentre(onDisk).z);
    QVERIFY(std::abs(d - 2.5) < 1e-4);
    QVERIFY(worstZ < 1e-4);
    QVERIFY(recon::meanCameraCentre(onDisk).z > 0);
    QVERIFY(readJson(ws + "/workspace.json")["metric"].toBool());
    saveShot(panel, "reconstruction_panel");
    saveShot(window_.get(), "main_window_reconstruction");
    // Or in the frame of known cameras (the sample room's): every camera centre within 2 cm.
    QVERIFY(!panel->alignToKnownCameras(tmp_.path()));  // no model, no room: refused, nothing written
    QVERIFY(panel->alignToKnownCameras(kRoom));
    const recon::ColmapModel aligned = recon::readColmapModel(panel->result()->modelFolder);
    const Scene sample = loadRoom(str(kRoom));
    std::vector<double> centreErrors;
    for (const auto& [id, im] : aligned.images) {
      const Photo* ph = sample.findPhoto(QFileInfo(QString::fromStdString(im.name)).completeBaseName().toStdString());
      QVERIFY(ph);
      centreErrors.push_back(glm::length(im.center() - ph->camera.center()));
    }
    std::sort(centreErrors.begin(), centreErrors.end());
    const double worstCentre = centreErrors.back(), medianCentre = centreErrors[centreErrors.size() / 2];
    qInfo("aligned to the sample room's cameras: centres within %.4f m, median %.4f m (the fit says %.4f m at most)",
          worstCentre, medianCentre, panel->lastAlignment().max);
    // COLMAP's multi-threaded extraction and mapping vary from run to run: the worst camera of the
    // seven has come out between 1 and 3.2 cm here; the median is what `relume align` is held to
    // (tests/cli/reconstruct_test.sh), the worst only to stay near it.
    QVERIFY(medianCentre <= 0.02);
    QVERIFY(worstCentre <= 0.05);
    QVERIFY(readJson(ws + "/workspace.json")["metric"].toBool());

    // Cancel while COLMAP extracts features: nothing is left running, and no model is written.
    const QString ws2 = tmp_.path() + "/ws2";
    panel->workspace()->setText(ws2);
    bool extracting = false;
    auto conn = connect(window_->jobs(), &JobRunner::progressed, this, [&](double, const QString& text) {
      if (text.contains("feature")) extracting = true;
    });
    QVERIFY(panel->run());
    QElapsedTimer t;
    t.start();
    while (!extracting && t.elapsed() < 60000) QTest::qWait(5);
    QVERIFY(extracting);
    QElapsedTimer stop;
    stop.start();
    window_->jobs()->cancel();
    QVERIFY(waitForJob(30000));
    disconnect(conn);
    qInfo("Cancel during feature extraction: the job ended %lld ms after it", stop.elapsed());
    QVERIFY(stop.elapsed() < 2000);
    QVERIFY(!QFile::exists(ws2 + "/sparse/points3D.txt") && !QFile::exists(ws2 + "/sparse/cameras.txt"));
    bool colmapAlive = false;
    for (const QString& pid : QDir("/proc").entryList(QDir::Dirs)) {
      QFile comm("/proc/" + pid + "/comm");
      if (comm.open(QIODevice::ReadOnly) && comm.readAll().trimmed() == "colmap") colmapAlive = true;
    }
    QVERIFY(!colmapAlive);
    // The panel still shows the first model.
    QCOMPARE(panel->result()->registered.size(), size_t(pngs));
    dock->hide();
  }

  // The inspector: the engine's elements in 3-D. A floor element picked by a click lists exactly
  // the links the engine holds for it; coloured by the visibility of lamp A's links, the floor
  // shows INVISIBLE, PARTIAL and VISIBLE where the test's own rays from lamp A say so.
  void inspectorShowsTheEngine() {
    auto* dock = window_->inspectorDock();
    auto* panel = window_->inspectorPanel();
    dock->show();
    QTest::qWait(50);
    QElapsedTimer first;
    first.start();
    panel->refresh();
    QTest::qWait(50);
    const double firstMs = double(first.nsecsElapsed()) * 1e-6;
    QVERIFY(panel->elements().node.size() > 1000);
    const auto& h = doc()->session()->engine();
    QCOMPARE(panel->elements().node.size(), inspect::elementMesh(h).node.size());
    const int floor = doc()->scene().findPolygon("floor");
    {  // With every polygon shown, a click on the floor picks the floor, not the culled ceiling above it.
      panel->view()->resetCamera();
      QTest::qWait(50);
      const int floorNode = h.findLeaf(floor, h.toUV(floor, glm::dvec3(3.2, 2.3, 0.0)));
      QPointF at;
      QVERIFY(panel->view()->widgetPosition(inspect::nodeCentre(h, floorNode), at));
      QTest::mouseClick(panel->view(), Qt::LeftButton, {}, at.toPoint());
      QCOMPARE(panel->pickedNode(), floorNode);
    }
    panel->polygonFilter()->setCurrentIndex(panel->polygonFilter()->findData(floor));
    QTest::qWait(50);
    for (int s : panel->elements().surface) QCOMPARE(s, floor);
    panel->view()->resetCamera();
    QTest::qWait(50);

    // A click on a floor element in the view.
    const glm::dvec3 spot(3.2, 2.3, 0.0);  // unshadowed floor the photo shows
    const int node = h.findLeaf(floor, h.toUV(floor, spot));
    QPointF pos;
    QVERIFY(panel->view()->widgetPosition(inspect::nodeCentre(h, node), pos));
    QElapsedTimer pick;
    pick.start();
    QTest::mouseClick(panel->view(), Qt::LeftButton, {}, pos.toPoint());
    const double pickMs = double(pick.nsecsElapsed()) * 1e-6;
    QCOMPARE(panel->pickedNode(), node);
    std::vector<float> engineF;
    for (const auto& l : h.links())
      if (l.receiver == node || l.source == node) engineF.push_back(l.formFactor);
    auto* table = panel->linksTable();
    QCOMPARE(table->rowCount(), int(engineF.size()));
    std::vector<float> shownF;
    for (int r = 0; r < table->rowCount(); ++r) shownF.push_back(table->item(r, 3)->text().toFloat());
    std::sort(engineF.begin(), engineF.end());
    std::sort(shownF.begin(), shownF.end());
    for (size_t k = 0; k < engineF.size(); ++k) QVERIFY(std::abs(shownF[k] - engineF[k]) <= 1e-4f * engineF[k] + 1e-12f);
    qInfo("inspector: first view %.0f ms (%zu elements), pick + links %.0f ms (%d links of the picked element)", firstMs,
          inspect::elementMesh(h).node.size(), pickMs, table->rowCount());
    // The pick shows in the viewport too (the element in cyan over the floor), and a click in the
    // viewport picks the element there.
    QVERIFY(!panel->pickedOutline().empty());
    auto* vp = window_->viewport();
    vp->lockToPhoto();
    QPointF inView;
    QVERIFY(vp->widgetPosition(inspect::nodeCentre(h, node), inView));
    QTest::qWait(50);
    const QColor marked = vp->grabFramebuffer().pixelColor(inView.toPoint());
    panel->pickNode(-1);
    QTest::qWait(50);
    const QColor plain = vp->grabFramebuffer().pixelColor(inView.toPoint());
    qInfo("picked element in the viewport: %d %d %d, unpicked %d %d %d", marked.red(), marked.green(), marked.blue(), plain.red(),
          plain.green(), plain.blue());
    QVERIFY(marked.blue() - marked.red() > plain.blue() - plain.red() + 30);
    const glm::dvec3 other(2.6, 2.0, 0.0);
    QVERIFY(vp->widgetPosition(other, inView));
    QTest::mouseClick(vp, Qt::LeftButton, {}, inView.toPoint());
    QCOMPARE(panel->pickedNode(), h.findLeaf(floor, h.toUV(floor, other)));
    QVERIFY(panel->view()->selected() >= 0);
    panel->pickNode(node);

    // Lamp A's visibility classes against the test's own rays: 4 x 4 points on the lamp, 3 x 3 on
    // each floor element; all blocked: INVISIBLE, none: VISIBLE, some: PARTIAL.
    panel->quantity()->setCurrentIndex(panel->quantity()->findData(int(inspect::Quantity::LampVisibility)));
    const int lampA = doc()->scene().lamps[size_t(lampIndex("A"))].polygon;
    panel->lamp()->setCurrentIndex(panel->lamp()->findData(lampA));
    QTest::qWait(100);
    const auto classes = inspect::elementValues(*doc()->session(), panel->elements(), inspect::Quantity::LampVisibility, lampA);
    const auto& lamp = doc()->scene().polygons[size_t(lampA)].vertices;
    std::vector<glm::vec3> lampPoints;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) {
        const double a = (i + 0.5) / 4, b = (j + 0.5) / 4;  // bilinear over the lamp quad
        lampPoints.push_back(glm::vec3((1 - a) * (1 - b) * lamp[0] + a * (1 - b) * lamp[1] + a * b * lamp[2] + (1 - a) * b * lamp[3]));
      }
    const glm::vec3 lampNormal(glm::normalize(polygonNormal(lamp)));
    int agree = 0, total = 0, contradictions = 0, invisible = 0, partial = 0, visible = 0, darkElement = -1, litElement = -1;
    const auto& elements = panel->elements();
    for (size_t e = 0; e < elements.node.size(); ++e) {
      const auto& N = h.nodes()[size_t(elements.node[e])];
      int blocked = 0, rays = 0;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
          const glm::dvec2 uv(N.u0 + (i + 0.5) / 3 * (N.u1 - N.u0), N.v0 + (j + 0.5) / 3 * (N.v1 - N.v0));
          const glm::vec3 p(h.toWorld(floor, uv) + glm::dvec3(0, 0, 1e-4));
          for (const auto& q : lampPoints) {
            ++rays;
            blocked += h.rayScene().occluded(p, q - 1e-4f * lampNormal);
          }
        }
      const int mine = blocked == rays ? 1 : blocked == 0 ? 0 : 2;
      const int shown = std::isnan(classes[e]) ? -1 : int(classes[e]);
      if (shown < 0) continue;
      ++total;
      agree += mine == shown;
      contradictions += (mine == 1 && shown == 0) || (mine == 0 && shown == 1);
      invisible += shown == 1;
      partial += shown == 2;
      visible += shown == 0;
      if (mine == 1 && shown == 1 && darkElement < 0) darkElement = int(e);
      if (mine == 0 && shown == 0 && litElement < 0) litElement = int(e);
    }
    qInfo("lamp A on the floor: %d visible, %d partial, %d invisible; the test's rays agree on %.1f %%, %d contradictions",
          visible, partial, invisible, 100.0 * agree / std::max(total, 1), contradictions);
    QVERIFY(invisible > 10 && partial > 10 && visible > 10);
    QVERIFY(agree >= 0.9 * total);
    QCOMPARE(contradictions, 0);
    // And the view shows it: a hidden element in the dark blue, a lit one in the warm yellow.
    QVERIFY(darkElement >= 0 && litElement >= 0);
    const QImage frame = panel->view()->grabFramebuffer();
    auto colourAt = [&](int e) {
      const auto& o = elements.outline[size_t(e)];
      glm::dvec3 c(0.0);
      for (const auto& p : o) c += p;
      QPointF at;
      if (!panel->view()->widgetPosition(c / double(o.size()), at)) return QColor();
      return frame.pixelColor(int(at.x() * frame.devicePixelRatio()), int(at.y() * frame.devicePixelRatio()));
    };
    const QColor dark = colourAt(darkElement), lit = colourAt(litElement);
    qInfo("hidden element shown as %d %d %d, lit one as %d %d %d", dark.red(), dark.green(), dark.blue(), lit.red(), lit.green(),
          lit.blue());
    QVERIFY(dark.blue() > dark.red() + 20);
    QVERIFY(lit.red() > lit.blue() + 60);
    saveShot(window_.get(), "main_window_inspector");
    saveShot(panel, "inspector_visibility");
    panel->quantity()->setCurrentIndex(panel->quantity()->findData(int(inspect::Quantity::Irradiance)));
    panel->polygonFilter()->setCurrentIndex(0);
    QTest::qWait(100);
    saveShot(panel, "inspector_irradiance");
    panel->findChild<QTabWidget*>()->setCurrentIndex(1);
    QTest::qWait(100);
    saveShot(panel, "inspector_counts");
    panel->findChild<QTabWidget*>()->setCurrentIndex(0);
    // The other mesh (§4.4's coarser interactive one) as a second session, built as a job; the
    // document's session stays as it was.
    const RelightSession* own = doc()->session();
    const size_t refinedElements = panel->elements().node.size();
    panel->mesh()->setCurrentIndex(1);
    QVERIFY(window_->jobs()->busy());
    QVERIFY2(waitForJob(300000), "the other mesh was not built");
    QCOMPARE(panel->mesh()->currentIndex(), 1);
    QVERIFY(panel->session() != own);
    QCOMPARE(doc()->session(), own);
    QCOMPARE(panel->elements().node.size(), inspect::elementMesh(panel->session()->engine()).node.size());
    qInfo("inspector: %zu elements on the refined mesh, %zu on the interactive one", refinedElements,
          panel->elements().node.size());
    QVERIFY(panel->elements().node.size() < refinedElements);
    panel->mesh()->setCurrentIndex(0);
    QCOMPARE(panel->session(), own);
    QCOMPARE(panel->elements().node.size(), refinedElements);
    dock->hide();
  }

  // Save, then open the saved project in a fresh window: the edits come back.
  void saveAndReopen() {
    const int a = lampIndex("A"), c = lampIndex("C");
    doc()->editLampScale(a, glm::dvec3(0.0));
    doc()->editLampScale(c, glm::dvec3(1.5, 1.2, 0.8));
    window_->viewport()->setExposureEV(0.5);
    QVERIFY(doc()->isDirty());
    QVERIFY(window_->windowTitle().contains("*") || window_->isWindowModified());
    const QString folder = tmp_.path() + "/sample.relume";
    QVERIFY(window_->saveTo(folder));
    QVERIFY(waitForJob(120000));
    QVERIFY2(!doc()->isDirty(), qPrintable(window_->lastError()));
    QVERIFY(QFile::exists(folder + "/workbench.json"));

    MainWindow second;
    second.setInteractive(false);
    second.show();
    QVERIFY(second.openPath(folder));
    QElapsedTimer t;
    t.start();
    while (second.jobs()->busy() && t.elapsed() < 300000) QTest::qWait(20);
    QVERIFY2(second.document()->isOpen(), qPrintable(second.lastError()));
    QCOMPARE(second.document()->lampScale(a), glm::dvec3(0.0));
    QVERIFY(glm::length(second.document()->lampScale(c) - glm::dvec3(1.5, 1.2, 0.8)) < 1e-9);
    QCOMPARE(second.viewport()->exposureEV(), 0.5);
    QCOMPARE(second.document()->virtualLampCount(), doc()->virtualLampCount());
    QCOMPARE(second.document()->objectCount(), doc()->objectCount());
    for (size_t i = 0; i < doc()->virtualLampCount(); ++i) {
      QCOMPARE(second.document()->session()->virtualLamp(int(i)).name, doc()->session()->virtualLamp(int(i)).name);
      QVERIFY(second.document()->session()->virtualLamp(int(i)).polygon == doc()->session()->virtualLamp(int(i)).polygon);
      QCOMPARE(second.document()->lampDrop(doc()->session()->virtualLamp(int(i)).name),
               doc()->lampDrop(doc()->session()->virtualLamp(int(i)).name));
    }
    for (size_t i = 0; i < doc()->objectCount(); ++i)
      QVERIFY(second.document()->session()->object(int(i)).polygons == doc()->session()->object(int(i)).polygons);
    QVERIFY(second.document()->referenceOverrides() == doc()->referenceOverrides());
    QVERIFY(second.document()->data().referenceOverride == doc()->data().referenceOverride);
    QVERIFY(!second.document()->referenceOverrides().empty());
    QVERIFY(second.document()->referenceRegions() == doc()->referenceRegions());
    QVERIFY(second.document()->data().referenceRegions == doc()->data().referenceRegions);
    QVERIFY(!second.document()->referenceRegions().empty());
    QVERIFY(!second.document()->isDirty());
    // The reopened session shows what the first one showed.
    const Camera cam = photoCamera();
    const double p = psnrNoGain(second.viewport()->renderLinear(cam, ViewMode::Relit),
                                window_->viewport()->renderLinear(cam, ViewMode::Relit));
    qInfo("reopened project vs the session it was saved from: %.2f dB", p);
    // The reopened session refines the virtual lamp's links afresh (forced onto the photographed
    // polygons as it is built) where the live one refined them by the oracle and then moved it.
    QVERIFY(p >= 30.0);

    // The mesh chosen in View > Interactive mesh is kept too; a damaged choice is refused by name.
    QCOMPARE(readJson(folder + "/workbench.json")["mesh"].toString(), QString("refined"));
    const QString copy = tmp_.path() + "/interactive.relume";
    QVERIFY(copyFolder(folder, copy));
    QJsonObject state = readJson(copy + "/workbench.json");
    state["mesh"] = "interactive";
    writeJson(copy + "/workbench.json", state);
    const auto room = loadRoomForWorkbench(copy, silentProgress());
    QCOMPARE(room->mesh, SessionMesh::Interactive);
    QVERIFY(room->session->engine().totals().leaves < doc()->session()->engine().totals().leaves);
    state["mesh"] = "coarse";
    writeJson(copy + "/workbench.json", state);
    try {
      loadRoomForWorkbench(copy, silentProgress());
      QFAIL("a mesh named coarse was accepted");
    } catch (const relume::Error& e) {
      QVERIFY2(QString(e.what()).contains("workbench.json") && QString(e.what()).contains("mesh"), e.what());
    }
  }

  // Autosave writes a side folder (never the user's project); after a crash the next start
  // recovers it as an unsaved document that belongs to the user's project.
  void autosaveAndRecovery() {
    const QString project = tmp_.path() + "/sample.relume";
    QVERIFY(QFile::exists(project + "/project.json"));
    const int b = lampIndex("B");
    doc()->editLampScale(b, glm::dvec3(0.5));
    QVERIFY(doc()->isDirty());
    window_->setAutosaveInterval(100);
    QSettings settings;
    QElapsedTimer t;
    t.start();
    while ((settings.value(MainWindow::autosaveKey() + "/folder").toString() != MainWindow::autosaveFolder() ||
            window_->autosaveRunning()) &&
           t.elapsed() < 120000) {
      QTest::qWait(50);
      settings.sync();
    }
    window_->setAutosaveInterval(120000);
    const QString folder = settings.value(MainWindow::autosaveKey() + "/folder").toString();
    qInfo("autosaved to %s after %lld ms", qPrintable(folder), t.elapsed());
    QCOMPARE(folder, MainWindow::autosaveFolder());
    QVERIFY(QFile::exists(folder + "/workbench.json"));
    QVERIFY(!QFileInfo(folder).absoluteFilePath().startsWith(QFileInfo(project).absoluteFilePath()));
    {  // the user's project still holds what was saved, not the autosaved edit
      QFile f(project + "/workbench.json");
      QVERIFY(f.open(QIODevice::ReadOnly));
      const QJsonObject saved = QJsonDocument::fromJson(f.readAll()).object();
      QCOMPARE(saved["lamps"].toObject()["B"].toArray().at(0).toDouble(), 1.0);
    }
    // A crash: the process ends without closing; its autosave stays. (Moved to the name another
    // process would have used: this process never recovers its own autosave.)
    const QString dead = QFileInfo(folder).absolutePath() + "/999999.relume";
    QDir(dead).removeRecursively();
    QVERIFY(QDir().rename(folder, dead));
    settings.setValue("autosaves/999999/folder", dead);
    settings.setValue("autosaves/999999/source", settings.value(MainWindow::autosaveKey() + "/source"));
    settings.setValue("autosaves/999999/time", settings.value(MainWindow::autosaveKey() + "/time"));
    settings.remove(MainWindow::autosaveKey());
    // A Relume still running (its lock held) keeps its autosave: never offered.
    const QString alive = QFileInfo(folder).absolutePath() + "/999998.relume";
    QDir(alive).removeRecursively();
    QVERIFY(QDir().mkpath(alive));
    QFile::copy(dead + "/project.json", alive + "/project.json");
    QLockFile aliveLock(alive + ".lock");
    QVERIFY(aliveLock.tryLock(0));
    settings.setValue("autosaves/999998/folder", alive);
    settings.setValue("autosaves/999998/time", QDateTime::currentDateTime().addSecs(60));  // newer
    settings.sync();
    MainWindow next;
    next.setInteractive(false);
    next.show();
    QVERIFY(next.recoverAutosave(true));
    t.restart();
    while (next.jobs()->busy() && t.elapsed() < 300000) QTest::qWait(20);
    QVERIFY2(next.document()->isOpen(), qPrintable(next.lastError()));
    QCOMPARE(next.document()->lampScale(b), glm::dvec3(0.5));
    QVERIFY(next.document()->isDirty());
    QCOMPARE(next.document()->projectPath(), project);
    QVERIFY(!QFile::exists(dead));
    // Until it is saved, a second crash would still find it (as this process's own autosave).
    settings.sync();
    QCOMPARE(settings.value(MainWindow::autosaveKey() + "/folder").toString(), MainWindow::autosaveFolder());
    QVERIFY(QFile::exists(alive + "/project.json"));  // the live one was left alone
    aliveLock.unlock();
    QDir(alive).removeRecursively();
    settings.remove("autosaves/999998");
    QVERIFY(!next.recoverAutosave(true));  // never this process's own
    // Saved to the user's project: nothing is left to recover, and saving again still works
    // (the recovered document reads its photos from the autosave folder, which stays meanwhile).
    QVERIFY(next.saveTo(project));
    t.restart();
    while (next.jobs()->busy() && t.elapsed() < 120000) QTest::qWait(20);
    QVERIFY2(!next.document()->isDirty(), qPrintable(next.lastError()));
    settings.sync();
    QVERIFY(settings.value(MainWindow::autosaveKey() + "/folder").toString().isEmpty());
    next.document()->editLampScale(b, glm::dvec3(0.7));
    QVERIFY(next.saveTo(project));
    t.restart();
    while (next.jobs()->busy() && t.elapsed() < 120000) QTest::qWait(20);
    QVERIFY2(!next.document()->isDirty(), qPrintable(next.lastError()));
    doc()->undoStack()->undo();
    QCOMPARE(doc()->lampScale(b), glm::dvec3(1.0));
  }

  // A crash at any file-system step of the workbench's Save, or of an autosave over an earlier
  // autosave, leaves at its path the previous project or the new one, whole: never neither, never
  // a mix, and the next open says what the save left beside it. What a crash at a step leaves is
  // what the disk holds at that step: the test copies the project's folder (with the save's side
  // folders) at every step of one real save, then opens each copy as the next start would.
  void crashAtEverySaveStep() {
    const int b = lampIndex("B");
    const glm::dvec3 before = doc()->lampScale(b);
    // Runs `save`, which writes the project `name` in `parent`, and checks every step's copy.
    auto everyStep = [&](const QString& parent, const QString& name, bool exchange, const std::function<bool()>& save) {
      const QString target = parent + "/" + name;
      const QString old = tmp_.path() + "/crash-old";
      QDir(old).removeRecursively();
      QVERIFY(copyTree(target, old));
      const QStringList sideNames{"." + name + ".saving", "." + name + ".previous", "." + name + ".discard"};
      QStringList snapshots, steps;
      detail::SaveTestHooks hooks;
      hooks.exchange = exchange;
      hooks.step = [&](const char* what) {  // on the save's own thread, which waits meanwhile
        const QString snap = tmp_.path() + QString("/crash-step-%1").arg(snapshots.size() + 1);
        QDir(snap).removeRecursively();
        QDir().mkpath(snap);
        // Hard links, as fast as the save (which never writes into a file it wrote before).
        for (const QString& n : QStringList{name} + sideNames) {
          if (!QFileInfo::exists(parent + "/" + n)) continue;
          std::error_code ec;
          std::filesystem::copy(str(parent + "/" + n), str(snap + "/" + n),
                                std::filesystem::copy_options::recursive | std::filesystem::copy_options::create_hard_links, ec);
          if (ec) {  // another file system (the autosave folder under $HOME, /tmp a tmpfs): copies
            QDir(snap + "/" + n).removeRecursively();
            if (!copyTree(parent + "/" + n, snap + "/" + n)) qWarning("cannot copy %s", qPrintable(n));
          }
        }
        snapshots << snap;
        steps << what;
      };
      const detail::SaveTestHooks previous = detail::setSaveTestHooks(hooks);
      const bool started = save();
      QElapsedTimer t;
      t.start();
      while ((window_->jobs()->busy() || window_->autosaveRunning()) && t.elapsed() < 180000) QTest::qWait(20);
      const bool finished = !window_->jobs()->busy() && !window_->autosaveRunning();
      detail::setSaveTestHooks(previous);
      QVERIFY(started && finished);
      QVERIFY2(!sameTree(target, old), "the save changed nothing: the test would prove nothing");
      QVERIFY2(snapshots.size() >= 8, qPrintable(steps.join(", ")));
      int asOld = 0, asNew = 0;
      for (int k = 0; k < snapshots.size(); ++k) {
        const QString at = snapshots[k] + "/" + name;
        const QString step = QString("after step %1 (%2)").arg(k + 1).arg(steps[k]);
        // The next start opens the path (putting back a project a fallback save had moved aside).
        Scene scene;
        try {
          scene = loadRoom(str(at));
        } catch (const std::exception& e) {
          QFAIL(qPrintable(step + ": the path does not open: " + e.what()));
        }
        const bool isOld = sameTree(at, old), isNew = sameTree(at, target);
        QVERIFY2(isOld || isNew, qPrintable(step + ": the path holds neither the previous project nor the new one"));
        asOld += isOld;
        asNew += isNew && !isOld;
        for (const QString& side : sideNames) {
          if (!QFileInfo::exists(snapshots[k] + "/" + side)) continue;
          // Never taken for a project, and reported when the project beside it opens.
          bool refused = false;
          try {
            loadRoom(str(snapshots[k] + "/" + side));
          } catch (const relume::Error&) {
            refused = true;
          }
          QVERIFY2(refused, qPrintable(step + ": " + side + " opened as a project"));
          const bool reported = std::any_of(scene.notes.begin(), scene.notes.end(),
                                            [&](const std::string& n) { return n.find(str(side)) != std::string::npos; });
          QVERIFY2(reported, qPrintable(step + ": " + side + " left beside the project is not reported"));
        }
      }
      qInfo("%s, %s: %lld steps, the previous project at %d of them, the new one at %d", qPrintable(name),
            exchange ? "atomic exchange" : "two renames", qlonglong(snapshots.size()), asOld, asNew);
      QVERIFY(asOld > 0 && asNew > 0);
      // What the workbench opens from the copies: the relighting data read whole, at the first
      // and the last step (every other copy is byte for byte one of these two).
      for (const QString& snap : {snapshots.front(), snapshots.back()}) {
        try {
          QVERIFY(loadRoomForWorkbench(snap + "/" + name, silentProgress())->session != nullptr);
        } catch (const std::exception& e) {
          QFAIL(qPrintable(snap + ": the workbench cannot open it: " + e.what()));
        }
      }
      for (const QString& snap : snapshots) QDir(snap).removeRecursively();
    };

    // File > Save over an existing project, with the atomic exchange and without it.
    for (const bool exchange : {true, false}) {
      const QString parent = tmp_.path() + (exchange ? "/crash-exchange" : "/crash-renames");
      QVERIFY(window_->saveTo(parent + "/room.relume"));
      QVERIFY(waitForJob(120000));
      QVERIFY2(!doc()->isDirty(), qPrintable(window_->lastError()));
      doc()->editLampScale(b, glm::dvec3(exchange ? 0.25 : 0.4));
      everyStep(parent, "room.relume", exchange, [&] { return window_->saveTo(parent + "/room.relume"); });
      if (QTest::currentTestFailed()) break;
    }
    // An autosave over the previous autosave: the next start recovers one of the two.
    if (!QTest::currentTestFailed()) {
      const QString autosave = MainWindow::autosaveFolder();
      doc()->editLampScale(b, glm::dvec3(0.6));
      QVERIFY(window_->autosaveNow());
      QElapsedTimer t;
      t.start();
      while (window_->autosaveRunning() && t.elapsed() < 120000) QTest::qWait(20);
      QVERIFY(QFile::exists(autosave + "/project.json"));
      doc()->editLampScale(b, glm::dvec3(0.8));
      everyStep(QFileInfo(autosave).absolutePath(), QFileInfo(autosave).fileName(), true, [&] { return window_->autosaveNow(); });
    }
    doc()->editLampScale(b, before);
  }

  // Unreadable, truncated and newer-schema projects open nothing and say why.
  void badProjectsSayWhy() {
    const QString good = tmp_.path() + "/sample.relume";
    QVERIFY(QFile::exists(good + "/project.json"));
    auto tryOpen = [&](const QString& path) {
      MainWindow w;
      w.setInteractive(false);
      if (!w.openPath(path)) return QString("did not start");
      QElapsedTimer t;
      t.start();
      while (w.jobs()->busy() && t.elapsed() < 60000) QTest::qWait(20);
      return w.document()->isOpen() ? QString() : w.lastError();
    };
    // Truncated project.json.
    const QString truncated = tmp_.path() + "/truncated.relume";
    QDir().mkpath(truncated);
    QFile::copy(good + "/project.json", truncated + "/project.json");
    {
      QFile f(truncated + "/project.json");
      QVERIFY(f.open(QIODevice::ReadWrite));
      f.resize(f.size() / 2);
    }
    QString why = tryOpen(truncated);
    qInfo("truncated: %s", qPrintable(why));
    QVERIFY(why.contains("project.json"));
    // A newer schema of the workbench state.
    const QString newer = tmp_.path() + "/newer.relume";
    QVERIFY(QDir().rename(good, newer));
    {
      QFile f(newer + "/workbench.json");
      QVERIFY(f.open(QIODevice::WriteOnly | QIODevice::Truncate));
      f.write(R"({"format": "relume-workbench", "version": 99, "lamps": {}})");
    }
    why = tryOpen(newer);
    qInfo("newer: %s", qPrintable(why));
    QVERIFY(why.contains("workbench.json") && why.contains("newer"));
    // Unreadable: nothing there at all.
    why = tryOpen(tmp_.path() + "/nowhere.relume");
    qInfo("missing: %s", qPrintable(why));
    QVERIFY(why.contains("nowhere.relume"));
    QVERIFY(doc()->isOpen());  // the open document never changed
  }

  // Preprocess started from the GUI and cancelled: nothing changes, no thread is left running.
  void cancelledPreprocessChangesNothing() {
    const Scene before = doc()->scene();
    const RelightSession* session = doc()->session();
    QVERIFY(window_->openPath(kRoom));
    QTest::qWait(1500);
    QElapsedTimer t;
    t.start();
    window_->jobs()->cancel();
    QVERIFY(waitForJob(10000));
    qInfo("cancel took %lld ms", t.elapsed());
    QVERIFY(t.elapsed() <= 1000);
    QCOMPARE(doc()->session(), session);
    QCOMPARE(doc()->scene().polygons.size(), before.polygons.size());
    QVERIFY(!window_->jobs()->busy());
  }

  // The French UI shows French menus and panel titles.
  // The Model panel: the sample room's corners clicked through the photo views at their
  // clicks.json positions (at 300 %, so that a screen pixel's centre is the clicked pixel
  // centre), measured points typed, polygons picked in order, then "Build model": the project
  // reproduces what `relume triangulate` makes of the same clicks within 1 mm, and opens.
  void modelFromClicks() {
    const QString room = tmp_.path() + "/clickroom";
    for (const QString sub : {"colmap", "photos"}) {
      QVERIFY(QDir().mkpath(room + "/" + sub));
      for (const QString& f : QDir(kRoom + "/" + sub).entryList(QDir::Files))
        QVERIFY(QFile::copy(kRoom + "/" + sub + "/" + f, room + "/" + sub + "/" + f));
    }
    auto* panel = window_->clicksPanel();
    window_->clicksDock()->show();
    window_->clicksDock()->raise();
    QTest::qWait(50);
    // Bad input first: a photos folder without photos says so and opens nothing.
    QVERIFY(QDir().mkpath(tmp_.path() + "/nophotos/ws") && QDir().mkpath(tmp_.path() + "/nophotos/photos"));
    QVERIFY(!panel->load(tmp_.path() + "/nophotos/ws", tmp_.path() + "/nophotos/photos"));
    QVERIFY2(panel->summary()->text().contains("photos"), qPrintable(panel->summary()->text()));
    QVERIFY(!panel->isLoaded());

    panel->workspaceEdit()->setText(room + "/colmap");
    QVERIFY(panel->load(room + "/colmap"));
    QVERIFY(panel->hasCameras());
    QCOMPARE(panel->photoNames().size(), size_t(7));
    const recon::Clicks truth = recon::readClicks(str(kRoom + "/clicks.json"));

    auto clickView = [&](ClickPhotoView* view, const glm::dvec2& px) {
      const QPointF p(px.x, px.y);
      view->setZoom(3, QPointF(view->width() / 2.0, view->height() / 2.0));
      view->centerOn(p);
      const QPointF w = view->widgetPosition(p);
      QCOMPARE(w, QPointF(w.toPoint()));  // a whole screen pixel: the click is exact
      QTest::mouseClick(view, Qt::LeftButton, Qt::ShiftModifier, w.toPoint());  // exactly there, rings or not
    };
    // Distance from a pixel to the epipolar curve drawn in a view.
    auto curveDistance = [](const QPolygonF& curve, const glm::dvec2& q) {
      double best = 1e300;
      for (int k = 0; k + 1 < curve.size(); ++k) {
        const glm::dvec2 a(curve[k].x(), curve[k].y()), b(curve[k + 1].x(), curve[k + 1].y());
        const double t = std::clamp(glm::dot(q - a, b - a) / std::max(1e-12, glm::dot(b - a, b - a)), 0.0, 1.0);
        best = std::min(best, glm::length(q - (a + t * (b - a))));
      }
      return best;
    };
    std::map<std::string, std::string> nameOf;  // the file's point name -> the panel's
    int proposalsTried = 0, proposalsFound = 0;
    double worstEpipolar = 0;
    bool shot = false, acceptTested = false;
    for (const auto& [name, pt] : truth.points) {
      if (pt.clicks.empty()) {  // a corner no photo shows: typed
        QTest::mouseClick(panel->newPointButton(), Qt::LeftButton);
        for (int a = 0; a < 3; ++a) panel->measuredEdit(a)->setValue((*pt.typed)[a]);
        QTest::mouseClick(panel->measuredButton(), Qt::LeftButton);
        nameOf[name] = str(panel->currentPoint());
        continue;
      }
      QTest::mouseClick(panel->newPointButton(), Qt::LeftButton);
      const auto& first = pt.clicks.front();
      for (size_t k = 1; k < pt.clicks.size(); ++k) {
        const auto& other = pt.clicks[k];
        panel->showPhotos(QString::fromStdString(first.first), QString::fromStdString(other.first));
        if (k == 1) clickView(panel->viewA(), first.second);
        // Before the click in the second photo: its epipolar curve and the proposals.
        panel->waitForProposals();
        const double e = curveDistance(panel->viewB()->epipolar(), other.second);
        worstEpipolar = std::max(worstEpipolar, e);
        ++proposalsTried;
        const auto& props = panel->viewB()->proposals();
        if (!props.empty() && std::hypot(props[0].x() - other.second.x, props[0].y() - other.second.y) <= 2) ++proposalsFound;
        if (getenv("DEBUG_PROPOSALS"))
          qInfo("%s %s->%s: %s", name.c_str(), first.first.c_str(), other.first.c_str(),
                props.empty() ? "none" : qPrintable(QString("%1 px").arg(std::hypot(props[0].x() - other.second.x, props[0].y() - other.second.y))));
        if (!shot && props.size() >= 2 && name == "p9") {
          shot = true;
          panel->viewA()->fit();
          panel->viewB()->fit();
          QTest::qWait(50);
          saveShot(panel, "clicks_panel_proposals");
          clickView(panel->viewA(), first.second);  // back as it was for the click
        }
        if (!acceptTested && !props.empty()) {
          // A click on the best proposal's ring accepts it (one undo step), at the proposal.
          acceptTested = true;
          const QPointF ring = props[0];
          const std::vector<QPointF> before = props;
          panel->viewB()->centerOn(ring);
          QTest::mouseClick(panel->viewB(), Qt::LeftButton, {}, panel->viewB()->widgetPosition(ring).toPoint() + QPoint(3, 0));
          bool accepted = false;
          for (const auto& [p2, q] : panel->clicks().points.at(str(panel->currentPoint())).clicks)
            accepted = accepted || (p2 == other.first && std::hypot(q.x - ring.x(), q.y - ring.y()) < 1e-9);
          QVERIFY(accepted);
          QTest::mouseClick(panel->undoButton(), Qt::LeftButton);
          panel->waitForProposals();
          QVERIFY(panel->viewB()->proposals() == before);  // undone: the point waits for its match again
        }
        clickView(panel->viewB(), other.second);
      }
      nameOf[name] = str(panel->currentPoint());
      const auto& made = panel->clicks().points.at(nameOf[name]);
      QCOMPARE(made.clicks.size(), pt.clicks.size());
      for (const auto& [photo, px] : pt.clicks) {
        bool same = false;
        for (const auto& [p2, q] : made.clicks) same = same || (p2 == photo && glm::length(q - px) < 1e-9);
        QVERIFY2(same, (name + " in " + photo).c_str());
      }
      if (pt.typed) {
        for (int a = 0; a < 3; ++a) panel->measuredEdit(a)->setValue((*pt.typed)[a]);
        QTest::mouseClick(panel->measuredButton(), Qt::LeftButton);
      }
    }
    qInfo("Model panel: %zu points; epipolar curves within %.3f px of the true clicks; best proposal within 2 px for %d of %d",
          panel->clicks().points.size(), worstEpipolar, proposalsFound, proposalsTried);
    QCOMPARE(panel->clicks().points.size(), truth.points.size());
    QVERIFY(worstEpipolar <= 1.5);
    QVERIFY(proposalsFound * 10 >= proposalsTried * 7);  // the issue asks for 70 %
    // Every clicked point shows its reprojection error (sub-pixel here: the clicks are exact).
    for (const auto& [n, st] : panel->pointStates()) QVERIFY2(st.triangulated && st.maxError < 1, n.c_str());

    // Polygons: corners picked in order in the list, the constraints and lamps ticked there.
    auto* list = panel->pointsList();
    auto* polys = panel->polygonsList();
    for (const auto& poly : truth.polygons) {
      list->clearSelection();
      for (const auto& c : poly.corners) {
        const auto items = list->findItems(QString::fromStdString(nameOf.at(c)), Qt::MatchExactly, 0);
        QCOMPARE(items.size(), 1);
        items[0]->setSelected(true);
      }
      QCOMPARE(panel->picked().size(), poly.corners.size());
      panel->polygonNameEdit()->setText(QString::fromStdString(poly.name));
      QTest::mouseClick(panel->polygonButton(), Qt::LeftButton);
      const auto items = polys->findItems(QString::fromStdString(poly.name), Qt::MatchExactly, 0);
      QCOMPARE(items.size(), 1);
      if (poly.group != poly.name) items[0]->setText(2, QString::fromStdString(poly.group));
      QTest::qWait(0);
      if (!poly.lamp.empty()) {
        auto* it = polys->findItems(QString::fromStdString(poly.name), Qt::MatchExactly, 0)[0];
        it->setText(3, QString::fromStdString(poly.lamp));
        QTest::qWait(0);
        it = polys->findItems(QString::fromStdString(poly.name), Qt::MatchExactly, 0)[0];
        it->setCheckState(3, Qt::Checked);
        QTest::qWait(0);
      }
      if (poly.rectangle) {
        polys->findItems(QString::fromStdString(poly.name), Qt::MatchExactly, 0)[0]->setCheckState(4, Qt::Checked);
        QTest::qWait(0);
      }
      const recon::ClickPolygon& made = panel->clicks().polygons.back();
      QCOMPARE(made.name, poly.name);
      QCOMPARE(made.group, poly.group);
      QCOMPARE(made.lamp, poly.lamp);
      QCOMPARE(made.rectangle, poly.rectangle);
    }
    QCOMPARE(panel->clicks().polygons.size(), truth.polygons.size());
    // Undo and redo: the last polygon's rectangle tick, then the polygon itself.
    const size_t n = panel->clicks().polygons.size();
    QTest::mouseClick(panel->undoButton(), Qt::LeftButton);
    QVERIFY(!panel->clicks().polygons.back().rectangle);
    QTest::mouseClick(panel->undoButton(), Qt::LeftButton);
    QTest::mouseClick(panel->undoButton(), Qt::LeftButton);
    QTest::mouseClick(panel->undoButton(), Qt::LeftButton);
    QCOMPARE(panel->clicks().polygons.size(), n - 1);
    for (int k = 0; k < 4; ++k) QTest::mouseClick(panel->redoButton(), Qt::LeftButton);
    QCOMPARE(panel->clicks().polygons.size(), n);
    QVERIFY(panel->clicks().polygons.back().rectangle);
    // The 3-D tab: every point and every polygon with the cameras, drawn (green faces on the
    // dark background).
    panel->tabs()->setCurrentWidget(reinterpret_cast<QWidget*>(panel->view3d()));
    QTest::qWait(100);
    QCOMPARE(panel->view3d()->pointCount(), truth.points.size());
    QCOMPARE(panel->view3d()->polygonCount(), truth.polygons.size());
    {
      const QImage img = panel->view3d()->grabFramebuffer();
      int green = 0, yellow = 0, magenta = 0;
      for (int y = 0; y < img.height(); y += 2)
        for (int x = 0; x < img.width(); x += 2) {
          const QColor c = img.pixelColor(x, y);
          green += c.green() > c.red() + 30 && c.green() > c.blue() + 30;
          yellow += c.red() > 150 && c.green() > 120 && c.blue() < c.green() - 80 && std::abs(c.red() - c.green()) < 60;
          magenta += c.red() > c.green() + 60 && c.blue() > c.green() + 60;
        }
      qInfo("3-D tab: %d of %d sampled pixels green (the polygons), %d yellow (lamps), %d magenta",
            green, (img.width() / 2) * (img.height() / 2), yellow, magenta);
      QVERIFY(green > img.width() * img.height() / 4 / 50);
      QVERIFY(yellow > 0);      // the sample room's lamps, drawn in the lamp colour
      QCOMPARE(magenta, 0);     // overlapping translucent faces keep their colours
    }
    saveShot(panel, "clicks_panel_3d");
    panel->tabs()->setCurrentIndex(0);
    // What the panel holds is on disk already (atomically, as every edit is made).
    QCOMPARE(recon::clicksJson(recon::readClicks(str(panel->clicksFile()), true)), recon::clicksJson(panel->clicks()));

    // A polygon on a point clicked once: Build says which point, and writes no project.
    const QString badProject = tmp_.path() + "/bad.relume";
    panel->showPhotos("main", "view1");
    QTest::mouseClick(panel->newPointButton(), Qt::LeftButton);
    clickView(panel->viewA(), glm::dvec2(320.5, 240.5));
    const std::string once = str(panel->currentPoint());
    panel->setPicked({once, nameOf.at("p0"), nameOf.at("p1")});
    panel->polygonNameEdit()->setText("bad");
    QTest::mouseClick(panel->polygonButton(), Qt::LeftButton);
    QVERIFY(panel->build(badProject));
    QVERIFY(waitForJob(60000));
    QVERIFY2(window_->lastError().contains(QString::fromStdString(once)) && window_->lastError().contains("bad"),
             qPrintable(window_->lastError()));
    QVERIFY(!QFileInfo::exists(badProject));
    QTest::mouseClick(panel->undoButton(), Qt::LeftButton);  // the polygon
    QTest::mouseClick(panel->undoButton(), Qt::LeftButton);  // the point
    QCOMPARE(panel->clicks().points.size(), truth.points.size());
    QCOMPARE(panel->clicks().polygons.size(), truth.polygons.size());
    panel->viewA()->fit();
    panel->viewB()->fit();
    QTest::qWait(50);
    saveShot(panel, "clicks_panel");

    // Build: the same scene as the library's path for `relume triangulate`, then it opens.
    const QString project = tmp_.path() + "/clicked.relume";
    panel->projectEdit()->setText(project);
    QTest::mouseClick(panel->buildButton(), Qt::LeftButton);
    QVERIFY(waitForJobs(600000));  // the build, then the open it queues
    QVERIFY2(doc()->projectPath() == QFileInfo(project).absoluteFilePath(), qPrintable(window_->lastError()));
    QTemporaryDir cliTmp;
    const recon::ClickBuild cli = recon::buildFromClicks(truth, recon::openClickWorkspace(str(room + "/colmap")), {},
                                                         str(cliTmp.path()), silentProgress());
    const Scene built = readProject(str(project));
    QCOMPARE(built.polygons.size(), cli.scene.polygons.size());
    double worst = 0;
    for (const auto& p : cli.scene.polygons) {
      const Polygon* q = nullptr;
      for (const auto& b : built.polygons)
        if (b.name == p.name) q = &b;
      QVERIFY2(q && q->vertices.size() == p.vertices.size(), p.name.c_str());
      for (size_t k = 0; k < p.vertices.size(); ++k) worst = std::max(worst, glm::length(q->vertices[k] - p.vertices[k]));
    }
    qInfo("Build model: %zu polygons, largest corner distance to the library's triangulation %.3g m", built.polygons.size(), worst);
    QVERIFY(worst <= 1e-3);
    QCOMPARE(built.lamps.size(), cli.scene.lamps.size());
    QVERIFY(QFileInfo::exists(project + "/clicks.json") && QFileInfo::exists(project + "/triangulation.json"));
    QVERIFY(doc()->isOpen());
    QCOMPARE(doc()->scene().polygons.size(), built.polygons.size());
    saveShot(window_.get(), "main_window_clicks");

    // No reconstruction: the same clicks (as a saved session left them) with the focal length
    // typed and four clicked corners measured (control points, to the millimetre): the cameras are
    // solved from the clicks, and the corners land within a centimetre of the model above.
    const QString bare = tmp_.path() + "/bare";
    QVERIFY(QDir().mkpath(bare + "/ws") && QDir().mkpath(bare + "/photos"));
    for (const QString& f : QDir(kRoom + "/photos").entryList(QDir::Files))
      QVERIFY(QFile::copy(kRoom + "/photos/" + f, bare + "/photos/" + f));
    QVERIFY(QFile::copy(kRoom + "/clicks.json", bare + "/ws/clicks.json"));
    QVERIFY(panel->load(bare + "/ws"));
    QVERIFY(!panel->hasCameras());
    QCOMPARE(panel->clicks().points.size(), truth.points.size());
    const recon::ColmapModel known = recon::readColmapModel(str(kRoom + "/colmap"));
    panel->focalEdit()->setValue(known.cameras.begin()->second.fx());
    int measured = 0;
    for (const auto& [name, pt] : truth.points) {
      if (pt.clicks.size() < 3 || measured == 4) continue;
      panel->setCurrentPoint(QString::fromStdString(name));
      const glm::dvec3 X = cli.report.points.at(name).X;
      for (int a = 0; a < 3; ++a) panel->measuredEdit(a)->setValue(std::round(X[a] * 1000) / 1000);
      QTest::mouseClick(panel->measuredButton(), Qt::LeftButton);
      QVERIFY(panel->clicks().points.at(name).typed.has_value());
      ++measured;
    }
    const QString bareProject = tmp_.path() + "/bare.relume";
    QVERIFY(panel->build(bareProject));
    QVERIFY(waitForJobs(600000));
    QVERIFY2(doc()->projectPath() == QFileInfo(bareProject).absoluteFilePath(), qPrintable(window_->lastError()));
    QVERIFY(panel->hasCameras());  // solved, and kept for the clicking from now on
    const Scene solved = readProject(str(bareProject));
    std::vector<double> d;
    for (const auto& p : built.polygons)
      for (const auto& q : solved.polygons)
        if (q.name == p.name && q.vertices.size() == p.vertices.size())
          for (size_t k = 0; k < p.vertices.size(); ++k) d.push_back(glm::length(q.vertices[k] - p.vertices[k]));
    QCOMPARE(d.size(), size_t(std::accumulate(built.polygons.begin(), built.polygons.end(), size_t(0),
                                              [](size_t n, const Polygon& p) { return n + p.vertices.size(); })));
    std::sort(d.begin(), d.end());
    qInfo("Build model without a reconstruction: corners %.4f m (median), %.4f m (largest) from the model built with the known cameras",
          d[d.size() / 2], d.back());
    QVERIFY(d[d.size() / 2] <= 0.01);
    window_->clicksDock()->hide();
    // The sample room again for what follows (its preprocessed copy where the entry began from one).
    const QString again = QFileInfo::exists(tmp_.path() + "/fixture.relume") ? tmp_.path() + "/fixture.relume" : kRoom;
    QVERIFY(window_->openPath(again));
    QVERIFY(waitForJobs(600000));
    QVERIFY(doc()->isOpen());
  }

  void daylightRoomInTheSkyPanel() {
    // The project's own daylight room opened as a user would: it goes to the Sky panel (no lamp
    // room document), is relit under its photos' sky, another sun, with a virtual box, and under
    // a folder of skies played back — each compared with Cycles' render of the same.
    const QString room = RELUME_SOURCE_DIR "/resources/daylight_room";
    MainWindow w;
    QVERIFY2(openDaylightRoom(w, room), qPrintable(w.lastError()));
    SkyPanel* sky = w.skyPanel();
    auto settle = [&](int timeoutMs) { return jobsSettled(w, timeoutMs); };
    QVERIFY(w.skyDock()->isVisible());
    QVERIFY(!w.document()->isOpen());
    QCOMPARE(sky->skyBox()->count(), 3);
    QCOMPARE(sky->framesShown(), 1);
    QCOMPARE(sky->shown().size(), QSize(320, 240));
    auto png = [&](const char* rel) { return QImage(room + "/" + rel).convertToFormat(QImage::Format_RGB888); };
    const QImage photo = png("photos/main.png");
    // Under the photos' own sky, nothing changes: the photo comes back.
    const double same = psnr8(sky->shown(), photo);
    qInfo("under the photos' sky: %.1f dB against the photo", same);
    QVERIFY(same > 35);
    const QImage underPhotoSky = sky->shown();
    // Another sun: closer to Cycles' render of it than the unchanged photo is, by far.
    const int before = sky->framesShown();
    sky->skyBox()->setCurrentIndex(1);  // sun1
    QVERIFY(settle(120000));
    QCOMPARE(sky->framesShown(), before + 1);
    const QImage sun1 = png("truth/sun1.png");
    qInfo("sun1: relit %.1f dB, the photo %.1f dB against Cycles", psnr8(sky->shown(), sun1), psnr8(photo, sun1));
    QVERIFY(psnr8(sky->shown(), sun1) > psnr8(photo, sun1) + 6);
    // The box of variant virtual_box_sun0 under the photos' sky.
    sky->skyBox()->setCurrentIndex(0);
    QVERIFY(settle(120000));
    QCOMPARE(sky->objectsBox()->count(), 3);  // none, and each variant's objects (the two box variants)
    sky->objectsBox()->setCurrentIndex(1);
    QVERIFY(settle(180000));
    const QImage box = png("truth/virtual_box_sun0.png");
    qInfo("virtual box: relit %.1f dB, the photo %.1f dB against Cycles", psnr8(sky->shown(), box), psnr8(photo, box));
    QVERIFY(psnr8(sky->shown(), box) > psnr8(photo, box) + 6);
    saveShot(&w, "sky_panel");
    // The variant's box dragged 0.4 m towards the window along the floor and let go: the project
    // saved below keeps it there (the variant's own box, not the other variant's).
    {
      ClickPhotoView* view = sky->view();
      QCOMPARE(sky->objectHandles(), std::vector<QString>{QString("orange_box")});
      const Camera cam = loadRoom(room.toStdString()).findPhoto("main")->camera;
      glm::dvec2 from(-1.0), to(-1.0);
      QVERIFY(cam.project({2.275, 2.125, 0.0}, from) && cam.project({2.675, 2.125, 0.0}, to));
      auto send = [&](QEvent::Type type, const glm::dvec2& px, Qt::MouseButton button, Qt::MouseButtons buttons) {
        const QPointF pos = view->widgetPosition(QPointF(px.x, px.y));
        QMouseEvent e(type, pos, view->mapToGlobal(pos), button, buttons, Qt::NoModifier);
        QApplication::sendEvent(view, &e);
      };
      send(QEvent::MouseButtonPress, from, Qt::LeftButton, Qt::LeftButton);
      send(QEvent::MouseMove, 0.5 * (from + to), Qt::NoButton, Qt::LeftButton);
      send(QEvent::MouseMove, to, Qt::NoButton, Qt::LeftButton);
      send(QEvent::MouseButtonRelease, to, Qt::LeftButton, Qt::NoButton);
      QVERIFY(settle(180000));
      QCOMPARE(view->markers().size(), size_t(1));
      QVERIFY(std::hypot(view->markers()[0].pixel.x() - to.x, view->markers()[0].pixel.y() - to.y) < 0.05);
    }
    sky->photoToggle()->setChecked(true);
    QVERIFY(psnr8(sky->view()->image().convertToFormat(QImage::Format_RGB888), photo) > 40);  // the photo as taken
    sky->photoToggle()->setChecked(false);
    // A folder of skies: one entry, its frames played back in turn.
    const QString frames = tmp_.path() + "/skies";
    QDir().mkpath(frames);
    QVERIFY(QFile::copy(room + "/sky/fisheye_sun1.exr", frames + "/a.exr"));
    QVERIFY(QFile::copy(room + "/sky/fisheye_sun2.exr", frames + "/b.exr"));
    sky->objectsBox()->setCurrentIndex(0);
    QVERIFY(settle(120000));
    QVERIFY(sky->addSkyFolder(frames));
    QCOMPARE(sky->skyBox()->count(), 4);
    QCOMPARE(sky->frameCount(), 2);
    QVERIFY(settle(120000));
    QCOMPARE(sky->shownName(), QString("a"));
    const QImage first = sky->shown();
    sky->setPlaying(true);
    QElapsedTimer t;
    t.start();
    while (sky->shownName() != "b" && t.elapsed() < 120000) QTest::qWait(20);
    QCOMPARE(sky->shownName(), QString("b"));  // playback went on to the second frame
    const QImage second = sky->shown();
    sky->setPlaying(false);
    QVERIFY(settle(120000));  // the frame being rendered when Play stopped is still shown
    qInfo("playback: frame b against frame a %.1f dB", psnr8(second, first));
    QVERIFY(psnr8(second, first) < 30);  // under another sun: another image
    // A folder with a broken image: refused, naming it; the list unchanged.
    const QString bad = tmp_.path() + "/badskies";
    QDir().mkpath(bad);
    QVERIFY(QFile::copy(room + "/sky/fisheye_sun1.exr", bad + "/a.exr"));
    {
      QFile f(bad + "/b.exr");
      QVERIFY(f.open(QIODevice::WriteOnly));
      f.write("not an image");
    }
    QSignalSpy said(sky, &SkyPanel::message);
    QVERIFY(!sky->addSkyFolder(bad));
    QCOMPARE(sky->skyBox()->count(), 4);
    QVERIFY(!said.isEmpty() && said.last().first().toString().contains("b.exr"));
    // Saved as a project (File > Save), the room opens again without estimating or solving: the
    // project keeps the daylight session, and the Sky panel shows the same relit photo.
    const QString project = tmp_.path() + "/daylight.relume";
    sky->skyBox()->setCurrentIndex(0);  // the photos' sky, as the project opens
    QVERIFY(settle(120000));
    const QImage beforeSave = sky->shown();
    QVERIFY(w.saveTo(project));
    QVERIFY(settle(120000));
    QVERIFY(QFileInfo(project + "/daylight/solution.bin").size() > 1000);
    QCOMPARE(sky->path(), project);
    QSignalSpy notes(sky, &SkyPanel::message);
    QVERIFY(w.openPath(project));
    QVERIFY(settle(300000));
    QVERIFY(sky->isOpen());
    QVERIFY(settle(120000));
    QStringList heard;
    for (const auto& m : notes) heard << m.first().toString();
    QVERIFY2(heard.join("\n").contains("opened the project's kept daylight solution"), qPrintable(heard.join("\n")));
    QCOMPARE(sky->framesShown(), 1);
    // The session as it was saved (its hierarchy refined for the suns shown since the first open,
    // so a little finer than the first open's): the image it showed, and the first open's nearly.
    qInfo("reopened from the project: %.1f dB against the image before saving, %.1f dB against the first open's",
          psnr8(sky->shown(), beforeSave), psnr8(sky->shown(), underPhotoSky));
    QVERIFY(psnr8(sky->shown(), beforeSave) > 80);
    QVERIFY(psnr8(sky->shown(), underPhotoSky) > 45);
    // The project holds the variants' boxes, the dragged one where it was left.
    QCOMPARE(sky->objectsBox()->count(), 3);
    const Scene saved = loadRoom(project.toStdString());
    std::map<std::string, glm::dvec3> boxMin;
    for (const auto& v : saved.variants)
      if (v.virtualObjects.size() == 1) boxMin[v.name] = v.virtualObjects[0].boxMin;
    QCOMPARE(boxMin.size(), size_t(2));
    qInfo("the dragged box's corner in the saved project: %.4f, %.4f, %.4f", boxMin["virtual_box_sun0"].x,
          boxMin["virtual_box_sun0"].y, boxMin["virtual_box_sun0"].z);
    QVERIFY(glm::length(boxMin["virtual_box_sun0"] - glm::dvec3(2.5, 1.95, 0.0)) < 0.01);
    QVERIFY(glm::length(boxMin["virtual_box_sun1"] - glm::dvec3(2.1, 1.95, 0.0)) < 1e-9);
    // The moved variant keeps no image of the room under it (Cycles drew the box where it was);
    // the other keeps its own.
    for (const auto& v : saved.variants) {
      if (v.name == "virtual_box_sun0") QVERIFY(v.file.empty() && v.hdr.empty());
      if (v.name == "virtual_box_sun1")
        QVERIFY(!v.hdr.empty() && QFileInfo(QString::fromStdString(saved.baseDir + "/" + v.hdr)).isFile());
    }
  }

  void daylightInteractiveMethodDrawnByOpenGl() {
    // The interactive method with its OpenGL renderer (shadow maps per window sample and per sun
    // direction) beside its CPU path: the same light, so the same picture; both far closer to
    // Cycles' render of the box than the photo is; a drag draws anew on the GPU.
    const QString room = RELUME_SOURCE_DIR "/resources/daylight_room";
    MainWindow w;
    QVERIFY2(openDaylightRoom(w, daylightRoomToOpen()), qPrintable(w.lastError()));
    SkyPanel* sky = w.skyPanel();
    auto settle = [&](int timeoutMs) { return jobsSettled(w, timeoutMs); };
    QVERIFY(!sky->gpuToggle()->isEnabled());  // near-field: nothing for OpenGL to draw
    QVERIFY(sky->gpuToggle()->isChecked());
    sky->objectsBox()->setCurrentIndex(1);  // the box of virtual_box_sun0
    QVERIFY(settle(180000));
    sky->methodBox()->setCurrentIndex(1);
    QVERIFY(settle(180000));
    QVERIFY(sky->gpuToggle()->isEnabled());
    QVERIFY(sky->lastGpuDrawMilliseconds() > 0);  // drawn by OpenGL
    const QImage gpu = sky->shown().convertToFormat(QImage::Format_RGB888);
    saveShot(&w, "sky_panel_opengl");
    const double drawMs = sky->lastGpuDrawMilliseconds();
    sky->gpuToggle()->setChecked(false);
    QVERIFY(settle(180000));
    const QImage cpu = sky->shown().convertToFormat(QImage::Format_RGB888);
    auto png = [&](const char* rel) { return QImage(room + "/" + rel).convertToFormat(QImage::Format_RGB888); };
    const QImage photo = png("photos/main.png"), truth = png("truth/virtual_box_sun0.png");
    qInfo("interactive method: OpenGL against the CPU path %.1f dB; against Cycles OpenGL %.1f dB, CPU %.1f dB, the "
          "photo %.1f dB; OpenGL frame %.1f ms",
          psnr8(gpu, cpu), psnr8(gpu, truth), psnr8(cpu, truth), psnr8(photo, truth), drawMs);
    QVERIFY(psnr8(gpu, cpu) > 35);
    QVERIFY(psnr8(gpu, truth) > psnr8(photo, truth) + 6);
    // Dragged on the GPU path: each move draws a frame, the last one where the box was let go.
    sky->gpuToggle()->setChecked(true);
    QVERIFY(settle(180000));
    const int before = sky->framesShown();
    ClickPhotoView* view = sky->view();
    const Camera cam = loadRoom(room.toStdString()).findPhoto("main")->camera;
    glm::dvec2 from(-1.0), to(-1.0);
    QVERIFY(cam.project({2.275, 2.125, 0.0}, from) && cam.project({2.275, 2.725, 0.0}, to));
    auto send = [&](QEvent::Type type, const glm::dvec2& px, Qt::MouseButton button, Qt::MouseButtons buttons) {
      const QPointF pos = view->widgetPosition(QPointF(px.x, px.y));
      QMouseEvent e(type, pos, view->mapToGlobal(pos), button, buttons, Qt::NoModifier);
      QApplication::sendEvent(view, &e);
    };
    send(QEvent::MouseButtonPress, from, Qt::LeftButton, Qt::LeftButton);
    send(QEvent::MouseMove, to, Qt::NoButton, Qt::LeftButton);
    send(QEvent::MouseButtonRelease, to, Qt::LeftButton, Qt::NoButton);
    QVERIFY(settle(180000));
    QVERIFY(sky->framesShown() > before);
    const QImage moved = sky->shown().convertToFormat(QImage::Format_RGB888);
    qInfo("the box dragged 0.6 m on the OpenGL path: %.1f dB against before", psnr8(moved, gpu));
    QVERIFY(psnr8(moved, gpu) < 35);  // the box and its shadow went elsewhere
    saveShot(&w, "sky_panel_opengl_dragged");
  }

  void daylightSkyThroughACalibratedLensInTheSkyPanel() {
    // The user's sky camera: a fisheye image added through a calibrated lens (the JSON of
    // `relume calibrate --fisheye`), chosen from the lens button's menu. A lens that is the ideal
    // projection relights as the ideal lens does; a distorted one reads the sky otherwise (the
    // sun lands elsewhere); a lens of another image size and a file that is no lens are refused,
    // naming the file, with nothing added and the lens kept.
    const QString room = RELUME_SOURCE_DIR "/resources/daylight_room";
    MainWindow w;
    QVERIFY2(openDaylightRoom(w, daylightRoomToOpen()), qPrintable(w.lastError()));
    SkyPanel* sky = w.skyPanel();
    auto settle = [&](int timeoutMs) { return jobsSettled(w, timeoutMs); };
    QCOMPARE(sky->lensButton()->text(), QString("Lens: ideal"));
    QCOMPARE(sky->lensButton()->menu()->actions().size(), 2);
    auto lensFile = [&](const QString& name, int size, double k1) {
      const QString f = tmp_.path() + "/" + name;
      QFile out(f);
      if (!out.open(QIODevice::WriteOnly)) return QString();
      const double focal = size / std::numbers::pi;  // 90 degrees at the image's edge: the ideal 180-degree lens
      out.write(QJsonDocument(QJsonObject{{"model", "OPENCV_FISHEYE"}, {"width", size}, {"height", size}, {"fx", focal},
                                          {"fy", focal}, {"cx", size / 2.0}, {"cy", size / 2.0}, {"k1", k1}})
                    .toJson());
      return f;
    };
    const QString fisheye = room + "/sky/fisheye_sun1.exr";
    QVERIFY(sky->addSkyFile(fisheye));  // through the ideal lens
    QVERIFY(settle(120000));
    const QImage ideal = sky->shown();
    QVERIFY(sky->setSkyLens(lensFile("ideal_lens.json", 256, 0.0)));
    QCOMPARE(sky->lensButton()->text(), QString("Lens: ideal_lens.json"));
    QVERIFY(sky->addSkyFile(fisheye));
    QVERIFY(settle(120000));
    QCOMPARE(sky->skyBox()->count(), 5);
    const QImage calibrated = sky->shown();
    qInfo("the ideal lens as a calibrated one: %.1f dB against the ideal lens", psnr8(calibrated, ideal));
    QVERIFY(psnr8(calibrated, ideal) > 45);
    saveShot(&w, "sky_panel_lens");
    // A lens that bends the view (k1 = -0.1: the horizon 96 px from the centre, not 128): the same
    // pixels are other directions, the sun another one, the sunlit patch elsewhere.
    QVERIFY(sky->setSkyLens(lensFile("bent_lens.json", 256, -0.1)));
    QVERIFY(sky->addSkyFile(fisheye));
    QVERIFY(settle(120000));
    qInfo("a bent lens: %.1f dB against the ideal lens", psnr8(sky->shown(), ideal));
    QVERIFY(psnr8(sky->shown(), ideal) < 35);
    // Refusals: a lens of other images, and a file that is no lens.
    QSignalSpy said(sky, &SkyPanel::message);
    QVERIFY(sky->setSkyLens(lensFile("other_lens.json", 512, 0.0)));
    QVERIFY(!sky->addSkyFile(fisheye));
    QCOMPARE(sky->skyBox()->count(), 6);
    QVERIFY(!said.isEmpty() && said.last().first().toString().contains("fisheye_sun1.exr") &&
            said.last().first().toString().contains("512x512") && said.last().first().toString().contains("other_lens.json"));
    const QString notLens = tmp_.path() + "/not_a_lens.json";
    {
      QFile f(notLens);
      QVERIFY(f.open(QIODevice::WriteOnly));
      f.write("{\"model\": \"OPENCV\"}");
    }
    QVERIFY(!sky->setSkyLens(notLens));
    QVERIFY(said.last().first().toString().contains("not_a_lens.json"));
    QCOMPARE(sky->skyLens(), tmp_.path() + "/other_lens.json");  // the lens chosen before stays
    QCOMPARE(sky->lensButton()->text(), QString("Lens: other_lens.json"));
  }

  void daylightWithALampInTheSkyPanel() {
    // A lamp beside the daylight: the daylight room with a 20 cm panel 3 cm below its ceiling
    // (facing down, radiance given), opened as a user would. The Sky panel lists the lamp, off;
    // checked, the relit photo only gains light (it was taken with the lamp off), most of it near
    // the lamp; the distant baseline (the sky alone) leaves the lamps out and says so.
    const QString room = tmp_.path() + "/lamproom";
    QVERIFY(copyFolder(RELUME_SOURCE_DIR "/resources/daylight_room", room));
    {
      QFile f(room + "/scene.json");
      QVERIFY(f.open(QIODevice::ReadOnly));
      QJsonObject s = QJsonDocument::fromJson(f.readAll()).object();
      f.close();
      const double z = s["room"].toArray()[2].toDouble() - 0.03, x = 1.2, y = 1.6, a = 0.1;
      const QJsonArray quad{QJsonArray{x - a, y - a, z}, QJsonArray{x - a, y + a, z}, QJsonArray{x + a, y + a, z},
                            QJsonArray{x + a, y - a, z}};
      QJsonArray polys = s["polygons"].toArray();
      polys.append(QJsonObject{{"name", "lamp_L"}, {"group", "lamp_L"}, {"kind", "light"}, {"vertices", quad}});
      s["polygons"] = polys;
      QJsonArray lights = s["lights"].toArray();
      lights.append(QJsonObject{{"name", "L"}, {"polygon", quad}, {"radiance_rgb", QJsonArray{60.0, 55.0, 45.0}}});
      s["lights"] = lights;
      QVERIFY(f.open(QIODevice::WriteOnly | QIODevice::Truncate));
      f.write(QJsonDocument(s).toJson());
    }
    MainWindow w;
    QVERIFY2(openDaylightRoom(w, room), qPrintable(w.lastError()));
    SkyPanel* sky = w.skyPanel();
    auto settle = [&](int timeoutMs) { return jobsSettled(w, timeoutMs); };
    QCOMPARE(sky->lampList()->count(), 1);
    QVERIFY(sky->lampList()->isVisible() && sky->lampList()->isEnabled());
    QCOMPARE(sky->lampList()->item(0)->checkState(), Qt::Unchecked);
    const QImage off = sky->shown().convertToFormat(QImage::Format_RGB888);
    const int before = sky->framesShown();
    sky->lampList()->item(0)->setCheckState(Qt::Checked);
    QVERIFY(settle(180000));
    QCOMPARE(sky->framesShown(), before + 1);
    const QImage on = sky->shown().convertToFormat(QImage::Format_RGB888);
    QCOMPARE(on.size(), off.size());
    // Per pixel: never darker (beyond 8-bit rounding), brighter on average; on the floor more
    // right under the lamp than 2.5 m away from it (in linear light: the display's sRGB undone).
    const Camera cam = loadRoom(room.toStdString()).findPhoto("main")->camera;
    QCOMPARE(QSize(cam.width, cam.height), on.size());
    const LampGain g = lampGain(on, off, cam, {1.2, 1.6, 0.0}, {3.0, 3.4, 0.0});
    qInfo("lamp on: %ld pixels darker than with it off; mean gain %.2f grey levels; on the floor under the lamp x%.3f, "
          "2.5 m away x%.3f",
          g.darker, g.gain, g.under, g.away);
    QCOMPARE(g.darker, 0L);
    QVERIFY(g.gain > 2.0);
    QVERIFY(g.under > 0 && g.away > 0);
    QVERIFY(g.under > g.away);
    saveShot(&w, "sky_panel_lamp");
    // The distant baseline: the sky alone, the lamp list disabled and the lamp left out.
    const int shownBefore = sky->framesShown();
    sky->methodBox()->setCurrentIndex(2);
    QVERIFY(settle(180000));
    QCOMPARE(sky->framesShown(), shownBefore + 1);
    QVERIFY(!sky->lampList()->isEnabled());
    // The distant baseline without objects is the photo itself, lamp checked or not.
    const QImage photo = QImage(room + "/photos/main.png").convertToFormat(QImage::Format_RGB888);
    QVERIFY2(psnr8(sky->shown(), photo) > 45, "the distant baseline under the photos' sky is the photo");
  }

  void daylightWithAVirtualLampFromAFile() {
    // A virtual lamp beside the daylight from a file (virtual_lights, as `relume relight
    // --virtual-lamp`): the same 20 cm panel as daylightWithALampInTheSkyPanel's, in the room as
    // it is. Near-field, the relit photo only gains light, most of it under the lamp; on the
    // interactive path (daylight alone) the lamp is left out, the user told so, and the image is
    // the one without it.
    const QString room = RELUME_SOURCE_DIR "/resources/daylight_room";
    const QString file = tmp_.path() + "/pendant.json";
    {
      QFile f(file);
      QVERIFY(f.open(QIODevice::WriteOnly));
      f.write(R"({"virtual_lights": [{"name": "pendant", "radiance_rgb": [60.0, 55.0, 45.0],
                  "polygon": [[1.1, 1.5, 2.57], [1.1, 1.7, 2.57], [1.3, 1.7, 2.57], [1.3, 1.5, 2.57]]}]})");
    }
    MainWindow w;
    QVERIFY2(openDaylightRoom(w, daylightRoomToOpen()), qPrintable(w.lastError()));
    SkyPanel* sky = w.skyPanel();
    auto settle = [&](int timeoutMs) { return jobsSettled(w, timeoutMs); };
    QVERIFY(settle(120000));
    const QImage off = sky->shown().convertToFormat(QImage::Format_RGB888);
    const int entries = sky->objectsBox()->count(), before = sky->framesShown();
    QVERIFY(sky->addObjectsFile(file));
    QCOMPARE(sky->objectsBox()->count(), entries + 1);
    QCOMPARE(sky->objectsBox()->currentText(), QString("pendant.json"));
    QVERIFY(settle(180000));
    QCOMPARE(sky->framesShown(), before + 1);
    const QImage on = sky->shown().convertToFormat(QImage::Format_RGB888);
    QCOMPARE(on.size(), off.size());
    const LampGain g = lampGain(on, off, loadRoom(room.toStdString()).findPhoto("main")->camera, {1.2, 1.6, 0.0}, {3.0, 3.4, 0.0});
    qInfo("virtual lamp on: %ld pixels darker; mean gain %.2f grey levels; on the floor under it x%.3f, 2.5 m away x%.3f",
          g.darker, g.gain, g.under, g.away);
    QCOMPARE(g.darker, 0L);
    QVERIFY(g.gain > 2.0);
    QVERIFY(g.under > g.away && g.away > 0);
    saveShot(&w, "sky_panel_virtual_lamp");
    // The interactive path lights by daylight alone: the lamp left out, and said.
    QSignalSpy said(sky, &SkyPanel::message);
    sky->methodBox()->setCurrentIndex(1);
    QVERIFY(settle(180000));
    bool told = false;
    for (const auto& m : said) told = told || m.first().toString().contains("near-field");
    QVERIFY(told);
    QVERIFY2(psnr8(sky->shown(), off) > 40, "without the lamp the interactive path shows the room as before");
    // Said once for the choice, not again with every render under another sky.
    said.clear();
    const int frames = sky->framesShown();
    sky->skyBox()->setCurrentIndex((sky->skyBox()->currentIndex() + 1) % sky->skyBox()->count());
    QVERIFY(settle(180000));
    QCOMPARE(sky->framesShown(), frames + 1);
    for (const auto& m : said) QVERIFY2(!m.first().toString().contains("near-field"), qPrintable(m.first().toString()));
    // A file with a box and a photometric downlight (not lit under daylight yet): the box is kept
    // as an entry, the lamp left out, and the user told which.
    const QString mixed = tmp_.path() + "/box_and_downlight.json";
    const QString ies = tmp_.path() + "/downlight_copy.ies";  // (removed below, before a second save)
    QVERIFY(QFile::copy(RELUME_SOURCE_DIR "/resources/examples/downlight.ies", ies));
    {
      QFile f(mixed);
      QVERIFY(f.open(QIODevice::WriteOnly));
      f.write(QString(R"({"virtual_objects": [{"name": "box", "box_min": [2.1, 1.95, 0.0], "box_max": [2.45, 2.3, 0.35],
                  "albedo": [0.8, 0.38, 0.06]}],
                  "virtual_lights": [{"name": "downlight", "radiance_rgb": [80.0, 72.0, 60.0], "photometry": "%1",
                  "polygon": [[2.8, 1.9, 2.55], [2.8, 2.1, 2.55], [3.0, 2.1, 2.55], [3.0, 1.9, 2.55]]}]})")
                  .arg(ies)
                  .toUtf8());
    }
    said.clear();
    const int count = sky->objectsBox()->count();
    QVERIFY(sky->addObjectsFile(mixed));
    QCOMPARE(sky->objectsBox()->count(), count + 1);
    QCOMPARE(sky->objectsBox()->currentText(), QString("box_and_downlight.json"));
    bool lampLeftOut = false;
    for (const auto& m : said) lampLeftOut = lampLeftOut || m.first().toString().contains("downlight");
    QVERIFY(lampLeftOut);
    QVERIFY(settle(180000));

    // The box dragged as a user would, on the interactive path: its cross (the middle of its base)
    // taken 0.7 m along the floor, the box rendered under the cursor at every move (nothing solved
    // again), and where it stood the floor as without it; dragged towards the top of the image
    // (the floor plane meets that ray outside the room), refused and said, the box staying.
    QCOMPARE(sky->methodBox()->currentIndex(), 1);
    ClickPhotoView* view = sky->view();
    QCOMPARE(sky->objectHandles(), std::vector<QString>{QString("box")});
    QCOMPARE(view->markers().size(), size_t(1));
    const Camera cam = loadRoom(room.toStdString()).findPhoto("main")->camera;
    auto pixelOf = [&](const glm::dvec3& x) {
      glm::dvec2 px(-1.0);
      cam.project(x, px);
      return px;
    };
    auto rgbAt = [](const QImage& img, const glm::dvec2& px) {
      return QColor(img.convertToFormat(QImage::Format_RGB888).pixel(int(px.x), int(px.y)));
    };
    auto orange = [](const QColor& c) { return c.red() > 2 * c.blue() + 20; };  // albedo (0.8, 0.38, 0.06)
    const glm::dvec2 base = pixelOf({2.275, 2.125, 0.0}), oldTop = pixelOf({2.275, 2.125, 0.35});
    const glm::dvec3 to(1.575, 2.125, 0.0);
    const glm::dvec2 target = pixelOf(to), newTop = pixelOf(to + glm::dvec3(0, 0, 0.35));
    QVERIFY(std::hypot(view->markers()[0].pixel.x() - base.x, view->markers()[0].pixel.y() - base.y) < 0.01);
    QVERIFY(target.x > 0 && target.x < cam.width && target.y > 0 && target.y < cam.height);
    QVERIFY(orange(rgbAt(sky->shown(), oldTop)));
    auto send = [&](QEvent::Type type, const glm::dvec2& px, Qt::MouseButton button, Qt::MouseButtons buttons) {
      const QPointF pos = view->widgetPosition(QPointF(px.x, px.y));
      QMouseEvent e(type, pos, view->mapToGlobal(pos), button, buttons, Qt::NoModifier);
      QApplication::sendEvent(view, &e);
    };
    const int framesBefore = sky->framesShown();
    send(QEvent::MouseButtonPress, base, Qt::LeftButton, Qt::LeftButton);
    constexpr int kSteps = 4;
    std::vector<qint64> stepMs;
    for (int k = 1; k <= kSteps; ++k) {
      QElapsedTimer step;
      step.start();
      send(QEvent::MouseMove, base + (target - base) * (double(k) / kSteps), Qt::NoButton, Qt::LeftButton);
      while (w.jobs()->busy() || step.elapsed() < 5) QTest::qWait(1);  // the move's render shown
      stepMs.push_back(step.elapsed());
      QVERIFY(settle(60000));
    }
    std::sort(stepMs.begin(), stepMs.end());
    qInfo("drag steps on the interactive path (move to image shown): median %lld ms", stepMs[stepMs.size() / 2]);
    send(QEvent::MouseButtonRelease, target, Qt::LeftButton, Qt::NoButton);
    QVERIFY(settle(60000));
    qInfo("box dragged 0.7 m: %d renders during the drag", sky->framesShown() - framesBefore);
    QVERIFY(sky->framesShown() - framesBefore >= kSteps);  // rendered as it moved, not only at the release
    QCOMPARE(view->markers().size(), size_t(1));
    QVERIFY(std::hypot(view->markers()[0].pixel.x() - target.x, view->markers()[0].pixel.y() - target.y) < 0.05);
    QVERIFY(orange(rgbAt(sky->shown(), newTop)));
    saveShot(&w, "sky_panel_drag");
    const QImage afterDrag = sky->shown();
    // A click on the cross with a hand's jitter (a pixel) moves nothing.
    {
      const int frames = sky->framesShown();
      const QPointF at = view->widgetPosition(QPointF(target.x, target.y));
      auto jitter = [&](QEvent::Type type, const QPointF& pos, Qt::MouseButton button, Qt::MouseButtons buttons) {
        QMouseEvent e(type, pos, view->mapToGlobal(pos), button, buttons, Qt::NoModifier);
        QApplication::sendEvent(view, &e);
      };
      jitter(QEvent::MouseButtonPress, at, Qt::LeftButton, Qt::LeftButton);
      jitter(QEvent::MouseMove, at + QPointF(1, 0), Qt::NoButton, Qt::LeftButton);
      jitter(QEvent::MouseButtonRelease, at + QPointF(1, 0), Qt::LeftButton, Qt::NoButton);
      QVERIFY(settle(60000));
      QCOMPARE(sky->framesShown(), frames);
      QVERIFY(std::hypot(view->markers()[0].pixel.x() - target.x, view->markers()[0].pixel.y() - target.y) < 0.05);
    }
    said.clear();
    const int framesAfter = sky->framesShown();
    send(QEvent::MouseButtonPress, target, Qt::LeftButton, Qt::LeftButton);
    send(QEvent::MouseMove, glm::dvec2(target.x, 1.0), Qt::NoButton, Qt::LeftButton);
    send(QEvent::MouseButtonRelease, glm::dvec2(target.x, 1.0), Qt::LeftButton, Qt::NoButton);
    QVERIFY(settle(60000));
    QVERIFY(!said.isEmpty() && said.first().first().toString().startsWith("Not moved"));
    qInfo("dragged out of the room: %s", qPrintable(said.first().first().toString()));
    QCOMPARE(sky->framesShown(), framesAfter);
    QVERIFY(std::hypot(view->markers()[0].pixel.x() - target.x, view->markers()[0].pixel.y() - target.y) < 0.05);
    QCOMPARE(sky->shown(), afterDrag);
    // Towards a floor point behind the far wall (y = 4.4 m): the wall is what the cursor points at.
    const glm::dvec2 behind = pixelOf({0.3, 5.0, 0.0});  // seen past the table and the crate
    QVERIFY(behind.x > 0 && behind.x < cam.width && behind.y > 0 && behind.y < cam.height);
    said.clear();
    send(QEvent::MouseButtonPress, target, Qt::LeftButton, Qt::LeftButton);
    send(QEvent::MouseMove, behind, Qt::NoButton, Qt::LeftButton);
    send(QEvent::MouseButtonRelease, behind, Qt::LeftButton, Qt::NoButton);
    QVERIFY(settle(60000));
    QCOMPARE(said.size(), 1);
    qInfo("dragged behind the wall: %s", qPrintable(said.first().first().toString()));
    QVERIFY(said.first().first().toString().startsWith("Not moved") && said.first().first().toString().contains("wall_back"));
    QCOMPARE(sky->framesShown(), framesAfter);
    QVERIFY(std::hypot(view->markers()[0].pixel.x() - target.x, view->markers()[0].pixel.y() - target.y) < 0.05);
    // Where the box stood, the room as it is under this sky without objects; where it stands now,
    // not.
    sky->objectsBox()->setCurrentIndex(0);
    QVERIFY(settle(60000));
    QVERIFY(view->markers().empty());
    const QImage noBox = sky->shown();
    const QColor atNew = rgbAt(afterDrag, newTop), atOld = rgbAt(afterDrag, oldTop), floorOld = rgbAt(noBox, oldTop);
    qInfo("after the drag: the new place (%d, %d, %d), the old place (%d, %d, %d), there without objects (%d, %d, %d)",
          atNew.red(), atNew.green(), atNew.blue(), atOld.red(), atOld.green(), atOld.blue(), floorOld.red(), floorOld.green(),
          floorOld.blue());
    QVERIFY(!orange(rgbAt(noBox, newTop)));
    QVERIFY(std::abs(atOld.red() - floorOld.red()) <= 12 && std::abs(atOld.green() - floorOld.green()) <= 12 &&
            std::abs(atOld.blue() - floorOld.blue()) <= 12);
    // Saved as a project, what the files placed is kept: each file's objects and lamps as a
    // variant named after it, the box where it was dragged to, the downlight's photometric file
    // copied in (it is the user's, even if daylight leaves it out).
    const QString project = tmp_.path() + "/with_files.relume";
    QVERIFY(w.saveTo(project));
    QVERIFY(settle(120000));
    const Scene saved = loadRoom(project.toStdString());
    const Variant *boxes = nullptr, *pendant = nullptr;
    for (const auto& v : saved.variants) {
      if (v.name == "box_and_downlight") boxes = &v;
      if (v.name == "pendant") pendant = &v;
    }
    QVERIFY(boxes && pendant);
    QCOMPARE(boxes->virtualObjects.size(), size_t(1));
    const glm::dvec3 corner = boxes->virtualObjects[0].boxMin;
    qInfo("the file's dragged box in the saved project: corner %.4f, %.4f, %.4f", corner.x, corner.y, corner.z);
    QVERIFY(glm::length(corner - glm::dvec3(1.4, 1.95, 0.0)) < 0.01);
    QCOMPARE(boxes->virtualLamps.size(), size_t(1));
    QVERIFY(QFileInfo(QString::fromStdString(saved.baseDir + "/" + boxes->virtualLamps[0].photometryFile)).isFile());
    QCOMPARE(pendant->virtualLamps.size(), size_t(1));
    QVERIFY(pendant->virtualObjects.empty());
    // The downlight's file gone since: saved again, the lamp is left out and said, and the save
    // goes through (it would fail on the missing file every time).
    QVERIFY(QFile::remove(ies));
    said.clear();
    const QString again = tmp_.path() + "/without_the_ies.relume";
    QVERIFY(w.saveTo(again));
    QVERIFY(settle(120000));
    bool toldGone = false;
    for (const auto& m : said) toldGone = toldGone || (m.first().toString().contains("downlight") && m.first().toString().contains("gone"));
    QVERIFY(toldGone);
    const Scene savedAgain = loadRoom(again.toStdString());
    bool found = false;
    for (const auto& v : savedAgain.variants)
      if (v.name == "box_and_downlight") {
        found = true;
        QVERIFY(v.virtualLamps.empty());
        QCOMPARE(v.virtualObjects.size(), size_t(1));
      }
    QVERIFY(found);
  }

  void frenchInterface() {
    QTranslator fr;
    QVERIFY(fr.load(":/i18n/relume_fr.qm"));
    QCoreApplication::installTranslator(&fr);
    {
      MainWindow w;
      QStringList menus;
      for (QAction* a : w.menuBar()->actions()) menus << a->text();
      qInfo("French menus: %s", qPrintable(menus.join(", ")));
      QCOMPARE(menus, QStringList({"&Fichier", "É&dition", "&Affichage", "É&clairage", "&Aide"}));
      QCOMPARE(w.findChild<QDockWidget*>("LightsDock")->windowTitle(), QString("Éclairage"));
      QCOMPARE(w.findChild<QDockWidget*>("ObjectsDock")->windowTitle(), QString("Objets"));
    }
    QCoreApplication::removeTranslator(&fr);
  }

  void screenshots() {
    doc()->undoStack()->setIndex(0);
    window_->viewport()->setExposureEV(0);
    window_->viewport()->lockToPhoto();
    QTest::qWait(200);
    saveShot(window_.get(), "main_window");
    saveShot(window_->lightsPanel(), "lights_panel");
    window_->viewport()->setViewMode(ViewMode::Leaves);
    QTest::qWait(100);
    saveShot(window_->viewport(), "viewport_leaves");
    window_->viewport()->setViewMode(ViewMode::Unoccluded);
    QTest::qWait(100);
    saveShot(window_->viewport(), "viewport_unoccluded");
    window_->viewport()->setViewMode(ViewMode::Relit);
    window_->viewport()->setFalseColour(true);
    QTest::qWait(100);
    saveShot(window_->viewport(), "viewport_false_colour");
    window_->viewport()->setFalseColour(false);
    window_->viewport()->setOrbit(true);
    QTest::qWait(100);
    saveShot(window_->viewport(), "viewport_orbit");
  }

  void daylightImageBasedObjectInTheSkyPanel() {
    // An image-based object from a file in the Sky panel (as `relume relight --sky` draws it): the
    // example vase standing in sun0's sunlit patch. What a user sees: the vase where it stands,
    // its sun shadow on the floor away from the sun, the interactive method drawing it too (with
    // OpenGL, as the CPU path does), dragged by its cross and saved where it was dragged,
    // and the distant method leaving it out, said.
    writeExampleVaseFan(tmp_.path() + "/sky_vase.fan");
    const QString file = tmp_.path() + "/sky_vase.json";
    {
      QFile f(file);
      QVERIFY(f.open(QIODevice::WriteOnly));
      f.write(R"({"virtual_objects": [{"name": "vase", "fan": "sky_vase.fan", "position": [2.5, 2.0, 0.0]}]})");
    }
    const QString room = RELUME_SOURCE_DIR "/resources/daylight_room";
    MainWindow w;
    QVERIFY2(openDaylightRoom(w, daylightRoomToOpen()), qPrintable(w.lastError()));
    SkyPanel* sky = w.skyPanel();
    auto settle = [&](int timeoutMs) { return jobsSettled(w, timeoutMs); };
    QVERIFY(showSun0(w));
    const QImage off = sky->shown().convertToFormat(QImage::Format_RGB888);
    QVERIFY(sky->addObjectsFile(file));
    QCOMPARE(sky->objectsBox()->currentText(), QString("sky_vase.json"));
    QVERIFY(settle(180000));
    const QImage on = sky->shown().convertToFormat(QImage::Format_RGB888);
    QCOMPARE(on.size(), off.size());
    const Scene scene = loadRoom(room.toStdString());
    const Camera cam = scene.findPhoto("main")->camera;
    auto at = [&](const QImage& im, const glm::dvec3& p) { return colourSeen(im, cam, p); };
    // The vase's body (terracotta: red over green), where the floor was.
    const QColor body = at(on, {2.5, 2.0, 0.25}), floorThere = at(off, {2.5, 2.0, 0.25});
    qInfo("vase body %d %d %d, the floor there before %d %d %d", body.red(), body.green(), body.blue(), floorThere.red(),
          floorThere.green(), floorThere.blue());
    QVERIFY(body != floorThere);
    QVERIFY(body.red() > 1.6 * body.green());  // (the floor's brown: 1.3)
    QVERIFY(floorThere.red() < 1.5 * floorThere.green());
    // Its sun shadow: 40 cm from its foot away from the sun (sun0: 30 degrees up, from 100 degrees
    // east of +Y), the floor at least a third darker; 40 cm towards the sun, as before.
    const double r = 100 * std::numbers::pi / 180;
    const glm::dvec3 away(-std::sin(r), -std::cos(r), 0.0);
    const QColor shade = at(on, glm::dvec3(2.5, 2.0, 0.001) + 0.4 * away), lit = at(off, glm::dvec3(2.5, 2.0, 0.001) + 0.4 * away);
    const QColor sunSide = at(on, glm::dvec3(2.5, 2.0, 0.001) - 0.4 * away), sunSideOff = at(off, glm::dvec3(2.5, 2.0, 0.001) - 0.4 * away);
    qInfo("floor 40 cm from the vase away from the sun: %d (was %d); towards it: %d (was %d)", shade.green(), lit.green(),
          sunSide.green(), sunSideOff.green());
    QVERIFY(shade.green() < 0.67 * lit.green());
    QVERIFY(std::abs(sunSide.green() - sunSideOff.green()) <= 3);
    saveShot(&w, "sky_panel_image_object");
    // The interactive method draws it as well, with OpenGL (its silhouettes in the shadow maps, its
    // pixels by the library's tables), and the CPU path the same picture.
    sky->methodBox()->setCurrentIndex(1);
    QVERIFY(settle(180000));
    QVERIFY(sky->gpuToggle()->isEnabled() && sky->gpuToggle()->isChecked());
    const QImage interactive = sky->shown().convertToFormat(QImage::Format_RGB888);
    const QColor body2 = at(interactive, {2.5, 2.0, 0.25}), shade2 = at(interactive, glm::dvec3(2.5, 2.0, 0.001) + 0.4 * away);
    qInfo("interactive (OpenGL): vase body %d %d %d, its shadow %d", body2.red(), body2.green(), body2.blue(), shade2.green());
    QVERIFY(body2.red() > 1.6 * body2.green());
    QVERIFY(shade2.green() < 0.67 * lit.green());
    saveShot(&w, "sky_panel_image_object_opengl");
    sky->gpuToggle()->setChecked(false);
    QVERIFY(settle(180000));
    const QImage interactiveCpu = sky->shown().convertToFormat(QImage::Format_RGB888);
    const QColor body3 = at(interactiveCpu, {2.5, 2.0, 0.25}), shade3 = at(interactiveCpu, glm::dvec3(2.5, 2.0, 0.001) + 0.4 * away);
    qInfo("interactive, OpenGL against the CPU path: %.1f dB; vase body %d %d %d, its shadow %d on the CPU path",
          psnr8(interactive, interactiveCpu), body3.red(), body3.green(), body3.blue(), shade3.green());
    QVERIFY(psnr8(interactive, interactiveCpu) > 35);
    QVERIFY(std::abs(body2.red() - body3.red()) <= 4 && std::abs(body2.green() - body3.green()) <= 4);
    QVERIFY(std::abs(shade2.green() - shade3.green()) <= 4);
    sky->gpuToggle()->setChecked(true);
    QVERIFY(settle(180000));
    // Dragged by its cross as a box is, 60 cm along the floor: drawn where it now stands, the floor
    // where it stood; saved, the project's variant has it there.
    ClickPhotoView* view = sky->view();
    QCOMPARE(view->markers().size(), size_t(1));
    auto pixelOf = [&](const glm::dvec3& p) { return photoPixel(cam, p); };
    const glm::dvec2 base = pixelOf({2.5, 2.0, 0.0});
    QVERIFY(std::hypot(view->markers()[0].pixel.x() - base.x, view->markers()[0].pixel.y() - base.y) < 0.5);
    const glm::dvec3 to(1.9, 2.0, 0.0);
    const glm::dvec2 target = pixelOf(to);
    bool settledBetween = true;
    dragInView(view, base, target, 2, [&] { settledBetween = settle(60000) && settledBetween; });
    QVERIFY(settledBetween);
    QVERIFY(settle(60000));
    QVERIFY(std::hypot(view->markers()[0].pixel.x() - target.x, view->markers()[0].pixel.y() - target.y) < 0.5);
    const QImage dragged = sky->shown().convertToFormat(QImage::Format_RGB888);
    const QColor newBody = at(dragged, to + glm::dvec3(0, 0, 0.25)), oldPlace = at(dragged, {2.5, 2.0, 0.25});
    qInfo("dragged 60 cm: vase body %d %d %d there, where it stood %d %d %d", newBody.red(), newBody.green(), newBody.blue(),
          oldPlace.red(), oldPlace.green(), oldPlace.blue());
    QVERIFY(newBody.red() > 1.6 * newBody.green());
    QVERIFY(oldPlace.red() < 1.5 * oldPlace.green());
    saveShot(&w, "sky_panel_image_object_dragged");
    const QString saved = tmp_.path() + "/sky_vase_project";
    QVERIFY(sky->saveProject(saved));
    QVERIFY(settle(180000));
    const Scene back = loadRoom(saved.toStdString());
    const VirtualBox* kept = nullptr;
    for (const auto& v : back.variants)
      for (const auto& b : v.virtualObjects)
        if (!b.fan.empty()) kept = &b;
    QVERIFY(kept);
    qInfo("saved: the vase at %.3f %.3f %.3f, its fan %s", kept->position.x, kept->position.y, kept->position.z, kept->fan.c_str());
    QVERIFY(glm::length(kept->position - to) < 0.01);
    QVERIFY(QFileInfo(saved + "/" + QString::fromStdString(kept->fan)).isFile());
    // The distant method leaves it out, and says so.
    QSignalSpy said(sky, &SkyPanel::message);
    sky->methodBox()->setCurrentIndex(2);
    QVERIFY(settle(180000));
    bool told = false;
    for (const auto& m : said) told = told || m.first().toString().contains("image-based");
    QVERIFY(told);
    const QColor distantBody = at(sky->shown().convertToFormat(QImage::Format_RGB888), to + glm::dvec3(0, 0, 0.25));
    QVERIFY(distantBody.red() < 1.5 * distantBody.green());
  }

  void daylightBoxAndImageBasedObjectTogetherInTheSkyPanel() {
    // A file that places an image-based object (the example vase, in sun0's sunlit patch) and a box
    // between it and the window: both are drawn, where the box's sun shadow lies the vase's takes
    // no more light, each is dragged by its own cross (though the box bears the vase's name), and a
    // save keeps each where it was left.
    writeExampleVaseFan(tmp_.path() + "/mixed_vase.fan");
    const QString alone = tmp_.path() + "/vase_alone.json", mixed = tmp_.path() + "/vase_and_box.json";
    for (const auto& [name, text] :
         {std::pair{alone, QByteArray(R"({"virtual_objects": [{"name": "vase", "fan": "mixed_vase.fan", "position": [2.5, 2.0, 0.0]}]})")},
          std::pair{mixed, QByteArray(R"({"virtual_objects": [{"name": "vase", "fan": "mixed_vase.fan", "position": [2.5, 2.0, 0.0]},
              {"name": "vase", "box_min": [2.75, 1.8, 0.0], "box_max": [2.9, 2.2, 0.6], "albedo": [0.2, 0.3, 0.8]}]})")}}) {
      QFile f(name);
      QVERIFY(f.open(QIODevice::WriteOnly));
      f.write(text);
    }
    const QString room = RELUME_SOURCE_DIR "/resources/daylight_room";
    MainWindow w;
    QVERIFY2(openDaylightRoom(w, daylightRoomToOpen()), qPrintable(w.lastError()));
    SkyPanel* sky = w.skyPanel();
    auto settle = [&](int timeoutMs) { return jobsSettled(w, timeoutMs); };
    QVERIFY(showSun0(w));
    const Scene scene = loadRoom(room.toStdString());
    const Camera cam = scene.findPhoto("main")->camera;
    auto at = [&](const QImage& im, const glm::dvec3& p) { return colourSeen(im, cam, p); };
    // The sun (30 degrees up, from 100 degrees east of +Y): a floor point 30 cm from the vase's
    // foot away from it lies in the vase's shadow, and in the box's too once the box stands there.
    const double r = 100 * std::numbers::pi / 180;
    const glm::dvec3 away(-std::sin(r), -std::cos(r), 0.0), behind = glm::dvec3(2.5, 2.0, 0.001) + 0.3 * away;
    QVERIFY(sky->addObjectsFile(alone));
    QVERIFY(settle(180000));
    const QColor vaseShadow = at(sky->shown().convertToFormat(QImage::Format_RGB888), behind);
    QVERIFY(sky->addObjectsFile(mixed));
    QCOMPARE(sky->objectsBox()->currentText(), QString("vase_and_box.json"));
    QVERIFY(settle(180000));
    const QImage both = sky->shown().convertToFormat(QImage::Format_RGB888);
    saveShot(&w, "sky_panel_box_and_image_object");
    // The box (blue, its face towards the camera) drawn where it stands, the vase (terracotta) too.
    const QColor box = at(both, {2.825, 1.8, 0.3}), vase = at(both, {2.5, 2.0, 0.2}), bothShadows = at(both, behind);
    qInfo("box face %d %d %d; vase body %d %d %d; the floor in both shadows %d %d %d, in the vase's alone %d %d %d", box.red(),
          box.green(), box.blue(), vase.red(), vase.green(), vase.blue(), bothShadows.red(), bothShadows.green(),
          bothShadows.blue(), vaseShadow.red(), vaseShadow.green(), vaseShadow.blue());
    QVERIFY(box.blue() > box.red() + 15);
    QVERIFY(vase.red() > 1.4 * vase.green());
    // Where the box's shadow already took the sun, the vase's takes it no more: the floor there as
    // in the vase's shadow alone, not darker (the sun is not taken twice).
    QVERIFY(bothShadows.green() >= 0.8 * vaseShadow.green());
    QVERIFY(bothShadows.green() > 10);
    // The interactive method draws both with OpenGL as its CPU path does: the box before the vase,
    // the vase's shadow from the shadow maps, where the box's already lies taking no more.
    {
      const int method = sky->methodBox()->currentIndex();
      sky->methodBox()->setCurrentIndex(1);
      QVERIFY(settle(180000));
      QVERIFY(sky->gpuToggle()->isEnabled() && sky->gpuToggle()->isChecked());
      const QImage gl = sky->shown().convertToFormat(QImage::Format_RGB888);
      sky->gpuToggle()->setChecked(false);
      QVERIFY(settle(180000));
      const QImage cpu = sky->shown().convertToFormat(QImage::Format_RGB888);
      sky->gpuToggle()->setChecked(true);
      const QColor glBox = at(gl, {2.825, 1.8, 0.3}), glVase = at(gl, {2.5, 2.0, 0.2}), glShadows = at(gl, behind);
      const QColor cpuBox = at(cpu, {2.825, 1.8, 0.3}), cpuVase = at(cpu, {2.5, 2.0, 0.2}), cpuShadows = at(cpu, behind);
      qInfo("interactive, box and vase: OpenGL against the CPU path %.1f dB; box face %d / %d, vase body %d / %d, the floor in "
            "both shadows %d / %d (green, OpenGL / CPU)",
            psnr8(gl, cpu), glBox.green(), cpuBox.green(), glVase.green(), cpuVase.green(), glShadows.green(), cpuShadows.green());
      QVERIFY(psnr8(gl, cpu) > 35);
      QVERIFY(std::abs(glBox.blue() - cpuBox.blue()) <= 4 && std::abs(glVase.red() - cpuVase.red()) <= 4);
      QVERIFY(std::abs(glShadows.green() - cpuShadows.green()) <= 4);
      sky->methodBox()->setCurrentIndex(method);
      QVERIFY(settle(180000));
    }
    // Two crosses, one per object; the vase's dragged 60 cm along the floor, the box's left alone.
    ClickPhotoView* view = sky->view();
    QCOMPARE(view->markers().size(), size_t(2));
    auto pixelOf = [&](const glm::dvec3& p) { return photoPixel(cam, p); };
    auto nearest = [&](const glm::dvec2& px) {
      size_t best = 0;
      for (size_t k = 1; k < view->markers().size(); ++k)
        if (std::hypot(view->markers()[k].pixel.x() - px.x, view->markers()[k].pixel.y() - px.y) <
            std::hypot(view->markers()[best].pixel.x() - px.x, view->markers()[best].pixel.y() - px.y))
          best = k;
      return std::hypot(view->markers()[best].pixel.x() - px.x, view->markers()[best].pixel.y() - px.y);
    };
    const glm::dvec2 base = pixelOf({2.5, 2.0, 0.0}), boxBase = pixelOf({2.825, 2.0, 0.0});
    QVERIFY(nearest(base) < 0.5);
    QVERIFY(nearest(boxBase) < 0.5);
    const glm::dvec3 to(1.9, 2.0, 0.0);
    const glm::dvec2 target = pixelOf(to);
    dragInView(view, base, target);
    QVERIFY(settle(60000));
    QVERIFY(nearest(target) < 0.5);
    QVERIFY(nearest(boxBase) < 0.5);
    const QImage dragged = sky->shown().convertToFormat(QImage::Format_RGB888);
    const QColor moved = at(dragged, to + glm::dvec3(0, 0, 0.2)), boxStill = at(dragged, {2.825, 1.8, 0.3});
    qInfo("dragged: vase body %d %d %d, box face %d %d %d", moved.red(), moved.green(), moved.blue(), boxStill.red(),
          boxStill.green(), boxStill.blue());
    QVERIFY(moved.red() > 1.4 * moved.green());
    QVERIFY(boxStill.blue() > boxStill.red() + 15);
    const QString saved = tmp_.path() + "/vase_and_box_project";
    QVERIFY(sky->saveProject(saved));
    QVERIFY(settle(180000));
    const Scene back = loadRoom(saved.toStdString());
    const Variant* v = nullptr;
    for (const auto& x : back.variants)
      if (x.virtualObjects.size() == 2) v = &x;
    QVERIFY(v);
    const VirtualBox& savedVase = v->virtualObjects[0];
    const VirtualBox& savedBox = v->virtualObjects[1];
    qInfo("saved: vase at %.3f %.3f, box from %.3f %.3f", savedVase.position.x, savedVase.position.y, savedBox.boxMin.x,
          savedBox.boxMin.y);
    QVERIFY(!savedVase.fan.empty());
    QVERIFY(glm::length(savedVase.position - to) < 0.01);
    QVERIFY(savedBox.fan.empty());
    QVERIFY(glm::length(savedBox.boxMin - glm::dvec3(2.75, 1.8, 0.0)) < 1e-6);
  }

  void cleanupTestCase() { window_.reset(); }
};

// QTEST_MAIN's work, then the process ends as the workbench's does (see process_exit.h).
int main(int argc, char** argv) {
  int rc = 0;
  {
    QApplication app(argc, argv);
    app.setAttribute(Qt::AA_Use96Dpi, true);
    QTEST_DISABLE_KEYPAD_NAVIGATION
    WorkbenchTest tc;
    QTEST_SET_MAIN_SOURCE_PATH
    rc = QTest::qExec(&tc, argc, argv);
  }
  relume::endProcess(rc);
}
#include "workbench_test.moc"
