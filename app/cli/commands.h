#pragma once
// The `relume` subcommands. Each returns the process exit code.
#include <QJsonObject>
#include <QStringList>

#include "relume/geometry/progress.h"

class QCommandLineParser;

namespace relume::cli {

// Parses `args` (help printed on --help); throws relume::Error unless `positional` arguments remain.
void parseOrThrow(QCommandLineParser& p, const QStringList& args, int positional, const char* usage);

int solveCommand(const QStringList& args, Progress& progress);
int renderCommand(const QStringList& args, Progress& progress);
int benchCommand(const QStringList& args, Progress& progress);
int importCommand(const QStringList& args, Progress& progress);
int preprocessCommand(const QStringList& args, Progress& progress);
int relightCommand(const QStringList& args, Progress& progress);
int evaluateCommand(const QStringList& args, Progress& progress);
int compareCommand(const QStringList& args, Progress& progress);
}  // namespace relume::cli
namespace relume {
struct Scene;
}
namespace relume::cli {
// The relighting figures of `relume bench` (medians of `runs`).
QJsonObject relightBench(const Scene& scene, int runs, Progress& progress);

}  // namespace relume::cli
