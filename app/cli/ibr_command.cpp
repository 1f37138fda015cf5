// relume ibr-fan: the image fan of a mesh (Dinh, Metoyer, Turk), for image-based virtual objects.
#include <QCommandLineParser>
#include <cstdio>

#include "commands.h"
#include "relume/geometry/error.h"
#include "relume/ibr/fan.h"

namespace relume::cli {

namespace {
int intOption(const QCommandLineParser& p, const char* name, int fallback) {
  if (!p.isSet(name)) return fallback;
  bool ok = false;
  const int v = p.value(name).toInt(&ok);
  if (!ok) throw Error("", std::string("--") + name, "expected a whole number, got '" + p.value(name).toStdString() + "'");
  return v;
}
}  // namespace

int ibrFanCommand(const QStringList& args, Progress& progress) {
  QCommandLineParser p;
  p.setApplicationDescription(
      "Render a mesh's image fan: rings of orthographic views around it, per pixel coverage, normal code (225 "
      "codes, dithered), depth and albedo, for an image-based virtual object (relume relight --virtual-object).");
  p.addPositionalArgument("MESH", "The mesh (.obj with its .mtl colours, or .ply), metres, +Z up unless --up y.");
  p.addOption({{"o", "output"}, "The fan file to write (.fan).", "FAN"});
  p.addOption({"views", "Views per ring (default 96).", "N"});
  p.addOption({"size", "Pixels across a view (default 256).", "PX"});
  p.addOption({"rings", "Ring elevations in degrees (default 15,45,75).", "E1,E2,..."});
  p.addOption({"no-dither", "Code each normal to its nearest code (shows the banding dithering removes)."});
  p.addOption({"up", "The mesh's up axis: z (default) or y.", "AXIS"});
  parseOrThrow(p, args, 1, "relume ibr-fan MESH -o FAN [--views 96] [--size 256] [--rings 15,45,75] [--no-dither] [--up y]");
  if (!p.isSet("output")) throw Error("", "command line", "-o FAN is required");
  ibr::FanOptions o;
  o.viewsPerRing = intOption(p, "views", o.viewsPerRing);
  o.size = intOption(p, "size", o.size);
  if (p.isSet("rings")) {
    o.ringElevations.clear();
    for (const QString& s : p.value("rings").split(',')) {
      bool ok = false;
      const double e = s.toDouble(&ok);
      if (!ok) throw Error("", "--rings", "expected degrees separated by commas, got '" + p.value("rings").toStdString() + "'");
      o.ringElevations.push_back(e);
    }
  }
  o.dither = !p.isSet("no-dither");
  if (p.isSet("up")) {
    if (p.value("up") == "y") o.yUp = true;
    else if (p.value("up") != "z") throw Error("", "--up", "must be z or y");
  }
  const std::string mesh = p.positionalArguments()[0].toStdString(), out = p.value("output").toStdString();
  const auto t0 = std::chrono::steady_clock::now();
  progress.report(0, "reading " + mesh);
  const ibr::Mesh m = ibr::readMesh(mesh);
  const auto fan = ibr::buildFan(m, o, progress);
  ibr::writeFan(*fan, out);
  std::fprintf(stderr, "%zu triangles: %d views of %d x %d in %.1f s (radius %.3f m); wrote %s\n", m.triangles.size(),
               fan->viewCount(), fan->size, fan->size, seconds(t0), fan->radius, out.c_str());
  return 0;
}

}  // namespace relume::cli
