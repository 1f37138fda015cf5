#pragma once
#include <QSize>
#include <QString>
#include <QStringList>

namespace relume {
// relume-workbench --bench OUT.json ROOM...: opens each room in the workbench and measures the
// lamp-slider update, the viewport's frame time at several sizes (GPU time, drawing only) and the
// frames per second on screen (presentation included), slider event -> new frame, and peak
// memory; then (photos > 0) imports that many JPEG photos of photoSize into the Photos panel and
// records how long the UI thread ever waited while they and their thumbnails load. Medians;
// writes JSON. Each of `daylightRooms` (a daylight room: windows and a measured sky) is measured
// in the daylight viewport's renderer (GlDaylightRenderer) at 1280 x 960: the frame time against
// the number of shadow maps (window samples 16, 64, 256, and the sun's four at 256^2) and the window
// maps' size (64, 128, 256), a frame with the variant's box moved (its maps made again) and one without; and the
// library's light for a moved box (its indirect light per vertex and the shadows' tiles); then an
// image-based object moved instead (the library's light and the frame, against the CPU path's).
// Returns the process exit code.
int runWorkbenchBench(const QString& out, const QStringList& rooms, int runs, int photos, QSize photoSize,
                      const QStringList& daylightRooms = {});
}  // namespace relume
