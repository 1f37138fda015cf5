#pragma once
// The workbench's language: English, French or German, chosen in Edit > Language (kept in
// QSettings, applied when the application starts). Unset, the system's language is used when
// Relume has it.
#include <QString>

namespace relume {

// Installs the translator for the chosen language; returns the language code in use ("en" when
// none applies). Call after the QApplication exists and before any window is built.
QString installTranslations();
QString chosenLanguage();           // "", "en", "fr" or "de" as stored
void chooseLanguage(const QString& code);

}  // namespace relume
