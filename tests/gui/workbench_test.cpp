// The workbench driven through its real widgets under Xvfb with Mesa (ctest label gui): the GL
// viewport against the CPU renderer, the Lights panel against the sample room's truth renders,
// undo, jobs (progress, cancel, a responsive event loop), saving and reopening, bad projects.
#include <QCheckBox>
#include <QDir>
#include <QElapsedTimer>
#include <QFile>
#include <QSlider>
#include <QStandardPaths>
#include <QTemporaryDir>
#include <QTimer>
#include <QTranslator>
#include <QMenuBar>
#include <QDockWidget>
#include <QtTest>
#include <algorithm>
#include <cmath>

#include "document.h"
#include "job_runner.h"
#include "lights_panel.h"
#include "main_window.h"
#include "relume/geometry/progress.h"
#include "relume/image/image.h"
#include "relume/relight/compare.h"
#include "relume/relight/relighter.h"
#include "relume/viewport/viewport_widget.h"

using namespace relume;

namespace {

const QString kRoom = QStringLiteral(RELUME_SOURCE_DIR) + "/resources/sample_room";

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
  w->grab().save(dir + "/" + name + ".png");
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
    return !window_->jobs()->busy();
  }

 private slots:
  void initTestCase() {
    QStandardPaths::setTestModeEnabled(true);
    QCoreApplication::setOrganizationName("RelumeTest");
    window_ = std::make_unique<MainWindow>();
    window_->setInteractive(false);
    window_->resize(1280, 800);
    window_->show();
    QVERIFY(QTest::qWaitForWindowExposed(window_.get()));
    // A full preprocess from the GUI, with a timer probing that the event loop keeps answering.
    QElapsedTimer sinceLast;
    sinceLast.start();
    QTimer probe;
    connect(&probe, &QTimer::timeout, [&] {
      maxGapMs_ = std::max(maxGapMs_, sinceLast.elapsed());
      sinceLast.restart();
    });
    probe.start(10);
    QVERIFY(window_->openPath(kRoom));
    QVERIFY(window_->jobs()->busy());
    QVERIFY2(waitForJob(600000), "the preprocess did not finish");
    probe.stop();
    QVERIFY2(doc()->isOpen(), qPrintable(window_->lastError()));
    qInfo("event loop: longest gap between 10 ms probe ticks during the preprocess %lld ms", maxGapMs_);
    QVERIFY2(maxGapMs_ <= 100, qPrintable(QString("the UI froze for %1 ms").arg(maxGapMs_)));
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
    QVERIFY(!second.document()->isDirty());
    // The reopened session shows what the first one showed.
    const Camera cam = photoCamera();
    const double p = psnrNoGain(second.viewport()->renderLinear(cam, ViewMode::Relit),
                                window_->viewport()->renderLinear(cam, ViewMode::Relit));
    qInfo("reopened project vs the session it was saved from: %.2f dB", p);
    QVERIFY(p >= 40.0);
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
      const auto docks = w.findChildren<QDockWidget*>();
      QVERIFY(!docks.isEmpty());
      QCOMPARE(docks.front()->windowTitle(), QString("Éclairage"));
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

  void cleanupTestCase() { window_.reset(); }
};

QTEST_MAIN(WorkbenchTest)
#include "workbench_test.moc"
