#pragma once
#include <QSize>
#include <QString>

namespace relume {
// relume-workbench --bench OUT.json ROOM...: opens each room in the workbench and measures the
// lamp-slider update, the viewport's frame time at several sizes (GPU time, drawing only) and the
// frames per second on screen (presentation included), slider event -> new frame, and peak
// memory; then (photos > 0) imports that many JPEG photos of photoSize into the Photos panel and
// records how long the UI thread ever waited while they and their thumbnails load. Medians;
// writes JSON. Returns the process exit code.
int runWorkbenchBench(const QString& out, const QStringList& rooms, int runs, int photos, QSize photoSize);
}  // namespace relume
