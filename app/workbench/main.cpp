// relume-workbench [ROOM|PROJECT]: the Relume workbench.
#include <QApplication>
#include <QCommandLineParser>
#include <QSurfaceFormat>
#include <QTimer>
#include <cstdio>

#include "bench.h"
#include "i18n.h"
#include "main_window.h"
#include "process_exit.h"
#include "relume/viewport/viewport_widget.h"

int main(int argc, char** argv) {
  int rc = 0;
  {
    // The viewport needs OpenGL 3.3 core; ask for it before any window exists.
    QSurfaceFormat::setDefaultFormat(relume::viewportSurfaceFormat());
    // Where the display gives Qt no vsync to pace frames by (X11, Mesa's software renderer), an
    // update request waits up to 5 ms of idle time before the frame is drawn: a sixth of a
    // viewport frame on two cores, added to every frame while a lamp slider or the orbit moves.
    // Draw as soon as the event loop has handled what is pending instead (requests between two
    // frames still make one frame; a user's own setting wins).
    if (!qEnvironmentVariableIsSet("QT_QPA_UPDATE_IDLE_TIME")) qputenv("QT_QPA_UPDATE_IDLE_TIME", "0");
    QApplication app(argc, argv);
    QApplication::setOrganizationName("Relume");
    QApplication::setApplicationName("relume-workbench");
    relume::installTranslations();
    QCommandLineParser parser;
    parser.setApplicationDescription("Relume workbench: relight photographed rooms.");
    parser.addHelpOption();
    parser.addPositionalArgument("ROOM", "A room bundle folder, a Relume project, or an OBJ with its JSON.", "[ROOM...]");
    parser.addOption({"bench", "Measure the workbench on the rooms given and write JSON to FILE.", "FILE"});
    parser.addOption({"runs", "Repetitions for --bench (default 9).", "N", "9"});
    parser.addOption({"bench-photos", "Photos imported by --bench (default 100; 0: none).", "N", "100"});
    parser.addOption({"bench-daylight", "A daylight room measured in the daylight viewport's renderer by --bench (repeatable).",
                      "ROOM"});
    parser.addOption({"bench-photo-size", "Their size, WIDTHxHEIGHT (default 6000x4000, 24 megapixels).", "WxH", "6000x4000"});
    parser.process(app);
    if (parser.isSet("bench")) {
      const QStringList wh = parser.value("bench-photo-size").split('x');
      const QSize size = wh.size() == 2 ? QSize(wh[0].toInt(), wh[1].toInt()) : QSize();
      if (size.width() <= 0 || size.height() <= 0) {
        std::fprintf(stderr, "relume-workbench: --bench-photo-size %s is not WIDTHxHEIGHT\n",
                     qPrintable(parser.value("bench-photo-size")));
        relume::endProcess(2);
      }
      rc = relume::runWorkbenchBench(parser.value("bench"), parser.positionalArguments(), parser.value("runs").toInt(),
                                     parser.value("bench-photos").toInt(), size, parser.values("bench-daylight"));
    } else {
      relume::MainWindow window;
      window.show();
      // Edits autosaved by a Relume that did not end cleanly come first.
      if (!window.recoverAutosave() && !parser.positionalArguments().isEmpty()) {
        const QString path = parser.positionalArguments().first();
        QTimer::singleShot(0, &window, [&window, path] { window.openPath(path); });
      }
      rc = app.exec();
    }
  }
  relume::endProcess(rc);
}
