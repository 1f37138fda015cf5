#pragma once
// The `relume` subcommands. Each returns the process exit code.
#include <QJsonObject>
#include <QStringList>
#include <chrono>
#include <map>
#include <string>
#include <vector>

#include "relume/geometry/camera.h"
#include "relume/geometry/progress.h"
#include "relume/geometry/scene.h"
#include "relume/image/image.h"

class QCommandLineParser;
namespace relume::radiosity {
enum class Oracle;
}


namespace relume::cli {

// Writes JSON through a temporary file renamed into place.
void writeJsonAtomically(const QString& path, const QJsonObject& obj);
double median(std::vector<double> v);
double seconds(std::chrono::steady_clock::time_point since);

// The same camera seeing the same view at another resolution (focal length and principal point scaled).
Camera resized(const Camera& camera, int width, int height);

// --oracle bf|bfv into `target` when given (relume::Error for another value).
void readOracle(const QCommandLineParser& p, radiosity::Oracle& target);

// Parses `args` (help printed on --help); throws relume::Error unless `positional` arguments remain.
void parseOrThrow(QCommandLineParser& p, const QStringList& args, int positional, const char* usage);

int solveCommand(const QStringList& args, Progress& progress);
int renderCommand(const QStringList& args, Progress& progress);
int benchCommand(const QStringList& args, Progress& progress);
int importCommand(const QStringList& args, Progress& progress);
int checkCommand(const QStringList& args, Progress& progress);
int preprocessCommand(const QStringList& args, Progress& progress);
int relightCommand(const QStringList& args, Progress& progress);
int evaluateCommand(const QStringList& args, Progress& progress);
int compareCommand(const QStringList& args, Progress& progress);
int reconstructCommand(const QStringList& args, Progress& progress);
int alignCommand(const QStringList& args, Progress& progress);
int triangulateCommand(const QStringList& args, Progress& progress);
int hdrMergeCommand(const QStringList& args, Progress& progress);
int calibrateCommand(const QStringList& args, Progress& progress);
int skyCommand(const QStringList& args, Progress& progress);
int daylightBasisCommand(const QStringList& args, Progress& progress);
// A daylight room (its scene lists measured skies) written as a project that keeps its daylight
// session: reflectances estimated under the photos' sky, every basis solution (daylight-basis -o,
// and preprocess on a daylight room).
int keepDaylightSession(const Scene& room, int regions, const std::string& out, Progress& progress);
// Images side by side (4 px apart), for looking at.
ImageRGB sideBySide(const std::vector<const ImageRGB*>& imgs);
int photometryCommand(const QStringList& args, Progress& progress);
int ibrFanCommand(const QStringList& args, Progress& progress);
}  // namespace relume::cli
namespace relume {
struct Scene;
}
namespace relume::cli {
// relume::loadRoom, printing what reading had to tell the user (Scene::notes) on stderr.
Scene openRoom(const QString& path);
// relume evaluate on a daylight bundle (one with measured skies): every variant with the near-field
// and the distant method, report.json with the all and change masks.
int evaluateDaylight(const Scene& bundle, const QString& outDir, Progress& progress);
// relume relight ROOM --sky NAME|FISHEYE.exr: the main photo (or `camera`'s) under that sky, with
// virtual objects, virtual lamps (files with virtual_lights, near-field only) and the room's lamps
// named in `lampScale` switched on (S x their radiance), by the near-field, volume or distant method.
int daylightRelight(const Scene& room, const std::string& sky, const std::vector<std::string>& objectFiles,
                    const std::vector<std::string>& lampFiles, const std::map<std::string, glm::dvec3>& lampScale,
                    const std::string& method, const std::string& camera, const std::string& out, Progress& progress,
                    const std::string& lensFile = {});
// The index of the room's lamp `name`, its `scale` checked (finite, >= 0); relume::Error naming
// `where` and listing the room's lamps when it has no such lamp.
int lampNamed(const Scene& scene, const std::string& name, const glm::dvec3& scale, const std::string& where);
// The relighting figures of `relume bench` (medians of `runs`).
QJsonObject relightBench(const Scene& scene, int runs, Progress& progress);
// The reconstruction figures: COLMAP on the room's photos, triangulation and polygon fitting.
QJsonObject reconstructBench(const Scene& scene, int runs, Progress& progress);
// The image-based object figures: a 1M-triangle mesh's fan, tables for a new lamp setting, one
// object and its shadows composited into a relit 640 x 480 image (medians of `runs`).
QJsonObject ibrBench(const Scene& scene, int runs, Progress& progress);
// The daylight figures of a room with windows and measured skies: the 64 basis solutions, the
// sky's averaging, a new sun, the combination (Eq. 3), the relit main photo, a box added.
QJsonObject daylightBench(const Scene& scene, int runs, Progress& progress);

}  // namespace relume::cli
