// relume-workbench [ROOM|PROJECT]: the Relume workbench.
#include <QApplication>
#include <QCommandLineParser>
#include <QSurfaceFormat>
#include <QTimer>

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
    parser.process(app);
    if (parser.isSet("bench")) {
      rc = relume::runWorkbenchBench(parser.value("bench"), parser.positionalArguments(), parser.value("runs").toInt());
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
