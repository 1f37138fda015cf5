#pragma once
// How the workbench's processes end, once the application object is gone.
namespace relume {

// Flushes the standard streams and ends the process without running static destructors: Qt
// Charts 6.4 keeps a function-static QGraphicsTextItem (for measuring axis labels) whose
// destructor, run at exit after the application and its fonts are gone, crashes. Nothing of
// Relume's needs a static destructor (files are written and committed when saved).
[[noreturn]] void endProcess(int code);

}  // namespace relume
