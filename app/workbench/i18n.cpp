#include "i18n.h"

#include <QCoreApplication>
#include <QLibraryInfo>
#include <QLocale>
#include <QSettings>
#include <QTranslator>

namespace relume {

QString chosenLanguage() { return QSettings().value("language").toString(); }

void chooseLanguage(const QString& code) { QSettings().setValue("language", code); }

QString installTranslations() {
  QString code = chosenLanguage();
  if (code.isEmpty()) code = QLocale::system().name().left(2);
  if (code != "fr" && code != "de") return "en";
  auto* ours = new QTranslator(QCoreApplication::instance());
  if (!ours->load(":/i18n/relume_" + code + ".qm")) {
    delete ours;
    return "en";
  }
  QCoreApplication::installTranslator(ours);
  // Qt's own strings (standard buttons of dialogs), when the system has them.
  auto* qt = new QTranslator(QCoreApplication::instance());
  if (qt->load("qtbase_" + code, QLibraryInfo::path(QLibraryInfo::TranslationsPath))) QCoreApplication::installTranslator(qt);
  else delete qt;
  return code;
}

}  // namespace relume
