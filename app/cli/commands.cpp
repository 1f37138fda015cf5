#include "commands.h"

#include <sys/resource.h>

#include <QCommandLineParser>
#include <QFile>
#include <QFileInfo>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QSaveFile>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <random>
#include <thread>

#include "relume/geometry/error.h"
#include "relume/geometry/polygon.h"
#include "relume/image/image.h"
#include "relume/project/relight_store.h"
#include "relume/project/room_io.h"
#include "relume/radiosity/hierarchy.h"
#include "relume/raytrace/ray_scene.h"
#include "relume/relight/solution_render.h"

namespace relume::cli {

namespace rad = relume::radiosity;

namespace {

std::string str(const QString& s) { return s.toStdString(); }
}  // namespace

Scene openRoom(const QString& path) {
  Scene scene = loadRoom(str(path));
  for (const auto& n : scene.notes) std::fprintf(stderr, "note: %s\n", n.c_str());
  return scene;
}

namespace {

size_t peakRssBytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return size_t(u.ru_maxrss) * 1024;
}

size_t currentRssBytes() {
  std::ifstream f("/proc/self/statm");
  size_t pages = 0, resident = 0;
  f >> pages >> resident;
  return resident * size_t(sysconf(_SC_PAGESIZE));
}

void addEngineOptions(QCommandLineParser& p) {
  p.addOption({"eps", "Refinement threshold (relative to the mean first-bounce irradiance).", "X"});
  p.addOption({"min-area", "Smallest element area in m^2.", "A"});
  p.addOption({"oracle", "Refinement oracle: bf or bfv.", "NAME"});
  p.addOption({"rays", "Visibility rays per link.", "N"});
  p.addOption({"tolerance", "Iteration stops when the largest change is below X times the mean radiosity.", "X"});
}

rad::Options engineOptions(const QCommandLineParser& p) {
  rad::Options o;
  auto number = [&](const char* name, double& target) {
    if (!p.isSet(name)) return;
    bool ok = false;
    const double v = p.value(name).toDouble(&ok);
    if (!ok || !(v > 0)) throw Error("", std::string("--") + name, "must be a positive number, not '" + str(p.value(name)) + "'");
    target = v;
  };
  number("eps", o.epsilon);
  number("min-area", o.minArea);
  number("tolerance", o.tolerance);
  double rays = o.visibilityRays;
  number("rays", rays);
  o.visibilityRays = std::max(1, int(rays));
  readOracle(p, o.oracle);
  return o;
}

QJsonArray rgb(const glm::dvec3& v) { return QJsonArray{v.x, v.y, v.z}; }

}  // namespace

void readOracle(const QCommandLineParser& p, rad::Oracle& target) {
  if (!p.isSet("oracle")) return;
  const QString v = p.value("oracle").toLower();
  if (v == "bf") target = rad::Oracle::BF;
  else if (v == "bfv") target = rad::Oracle::BFV;
  else throw Error("", "--oracle", "must be bf or bfv, not '" + str(v) + "'");
}

void writeJsonAtomically(const QString& path, const QJsonObject& obj) {
  QSaveFile f(path);
  if (!f.open(QIODevice::WriteOnly)) throw Error(str(path), "", "cannot write: " + str(f.errorString()));
  f.write(QJsonDocument(obj).toJson(QJsonDocument::Indented));
  if (!f.commit()) throw Error(str(path), "", "cannot write: " + str(f.errorString()));
}

Camera resized(const Camera& c, int width, int height) {
  Camera out = c;
  const double sx = double(width) / c.width, sy = double(height) / c.height;
  out.K[0][0] *= sx;
  out.K[2][0] *= sx;
  out.K[1][1] *= sy;
  out.K[2][1] *= sy;
  out.width = width;
  out.height = height;
  return out;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  if (v.empty()) return 0;
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

double seconds(std::chrono::steady_clock::time_point a) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count();
}


void parseOrThrow(QCommandLineParser& p, const QStringList& args, int positional, const char* usage) {
  p.addHelpOption();
  if (!p.parse(args)) throw Error("", "command line", str(p.errorText()));
  if (p.isSet("help")) {
    std::fprintf(stdout, "%s\n%s", usage, qPrintable(p.helpText()));
    std::exit(0);
  }
  if (p.positionalArguments().size() != positional)
    throw Error("", "command line", std::string("expected: ") + usage);
}

int solveCommand(const QStringList& args, Progress& progress) {
  QCommandLineParser p;
  p.setApplicationDescription("Solve a room's radiosity and write per-polygon results.");
  p.addPositionalArgument("ROOM", "Bundle folder, Relume project or .obj with its .json.");
  p.addOption({"json", "Output JSON file.", "OUT.json"});
  addEngineOptions(p);
  parseOrThrow(p, args, 1, "relume solve ROOM --json OUT.json [--eps X]");
  if (!p.isSet("json")) throw Error("", "command line", "--json OUT.json is required");
  const rad::Options opt = engineOptions(p);
  progress.report(0, "reading " + str(p.positionalArguments()[0]));
  const Scene scene = openRoom(p.positionalArguments()[0]);
  rad::HierarchicalRadiosity h(rad::surfacesFromScene(scene), opt);
  const auto st = h.solve(progress);
  QJsonArray polys;
  for (size_t i = 0; i < scene.polygons.size(); ++i) {
    QJsonObject o;
    o["name"] = QString::fromStdString(scene.polygons[i].name);
    o["area"] = polygonArea(scene.polygons[i].vertices);
    o["radiosity"] = rgb(h.surfaceRadiosity(int(i)));
    o["irradiance"] = rgb(h.surfaceIrradiance(int(i)));
    polys.append(o);
  }
  const auto t = h.totals();
  QJsonObject totals{{"elements", qint64(t.elements)}, {"clusters", qint64(t.clusters)},
                     {"leaves", qint64(t.leaves)},     {"links", qint64(t.links)},
                     {"rays", qint64(t.rays)},         {"iterations", st.iterations},
                     {"residual", st.residual},        {"seconds", t.seconds},
                     {"peak_memory_bytes", qint64(peakRssBytes())}};
  writeJsonAtomically(p.value("json"), QJsonObject{{"polygons", polys}, {"totals", totals}});
  std::fprintf(stderr, "solved: %zu elements (%zu leaves), %zu links, %llu rays, %d iterations, %.3f s -> %s\n",
               t.elements, t.leaves, t.links, (unsigned long long)t.rays, st.iterations, t.seconds,
               qPrintable(p.value("json")));
  return 0;
}

int renderCommand(const QStringList& args, Progress& progress) {
  QCommandLineParser p;
  p.setApplicationDescription("Render the radiosity solution through a photo's camera.");
  p.addPositionalArgument("ROOM", "Bundle folder, Relume project or .obj with its .json.");
  p.addOption({"camera", "Photo whose camera to use (default: the main photo).", "NAME"});
  p.addOption({{"o", "output"}, "Output image (.exr linear, .png sRGB).", "IMG"});
  p.addOption({"show", "False colour: leaves, links or visibility.", "WHAT"});
  addEngineOptions(p);
  parseOrThrow(p, args, 1, "relume render ROOM --camera NAME -o IMG.exr|png [--show leaves|links|visibility]");
  if (!p.isSet("output")) throw Error("", "command line", "-o IMG is required");
  RenderShow show = RenderShow::Radiance;
  if (p.isSet("show")) {
    const QString s = p.value("show");
    if (s == "leaves") show = RenderShow::Leaves;
    else if (s == "links") show = RenderShow::Links;
    else if (s == "visibility") show = RenderShow::Visibility;
    else throw Error("", "--show", "must be leaves, links or visibility, not '" + str(s) + "'");
  }
  const rad::Options opt = engineOptions(p);
  const QString out = p.value("output");
  const QString ext = QFileInfo(out).suffix().toLower();
  if (ext != "exr" && ext != "png") throw Error(str(out), "", "the output must end in .exr or .png");
  progress.report(0, "reading " + str(p.positionalArguments()[0]));
  const Scene scene = openRoom(p.positionalArguments()[0]);
  const std::string camName = p.isSet("camera") ? str(p.value("camera")) : scene.mainPhoto;
  const Photo* photo = scene.findPhoto(camName);
  if (!photo) {
    std::string names;
    for (const auto& ph : scene.photos) names += (names.empty() ? "" : ", ") + ph.name;
    throw Error(scene.sourceFile, "camera '" + camName + "'",
                "no photo has that name" + (names.empty() ? std::string(" (the room lists no photos)") : " (photos: " + names + ")"));
  }
  rad::HierarchicalRadiosity h(rad::surfacesFromScene(scene), opt);
  h.solve(progress);
  progress.report(0.95, "rendering " + camName);
  const ImageRGB img = renderSolution(h, photo->camera, show, progress);
  writeImage(str(out), img);
  std::fprintf(stderr, "wrote %s (%dx%d)\n", qPrintable(out), img.width, img.height);
  return 0;
}

int importCommand(const QStringList& args, Progress& progress) {
  QCommandLineParser p;
  p.setApplicationDescription("Read a room and write it as a Relume project.");
  p.addPositionalArgument("ROOM", "Bundle folder, Relume project or .obj with its .json.");
  p.addOption({{"o", "output"}, "Project folder to write.", "PROJECT"});
  parseOrThrow(p, args, 1, "relume import ROOM -o PROJECT");
  if (!p.isSet("output")) throw Error("", "command line", "-o PROJECT is required");
  const Scene scene = openRoom(p.positionalArguments()[0]);
  // A preprocessed project stays preprocessed (its relighting data and workbench edits go along).
  const bool preprocessed =
      hasRelightData(scene.baseDir) && QFileInfo::exists(QString::fromStdString(scene.baseDir) + "/project.json");
  if (preprocessed) saveRelightProject(scene, readRelightData(scene), str(p.value("output")), progress);
  else saveProject(scene, str(p.value("output")), progress);
  std::fprintf(stderr, "wrote %sproject %s (%zu polygons, %zu lamps, %zu photos)\n", preprocessed ? "preprocessed " : "",
               qPrintable(p.value("output")), scene.polygons.size(), scene.lamps.size(), scene.photos.size());
  return 0;
}

int checkCommand(const QStringList& args, Progress&) {
  QCommandLineParser p;
  p.setApplicationDescription(
      "Read a room or project as every command would (and a project's relighting data), say what it holds, and exit "
      "with 0 only if all of it reads.");
  p.addPositionalArgument("ROOM", "Bundle folder, Relume project or .obj with its .json.");
  parseOrThrow(p, args, 1, "relume check ROOM");
  const QString path = p.positionalArguments()[0];
  const Scene scene = openRoom(path);
  std::printf("%s: %zu polygons, %zu lamps, %zu photos, %zu variants", qPrintable(path), scene.polygons.size(),
              scene.lamps.size(), scene.photos.size(), scene.variants.size());
  if (hasRelightData(scene.baseDir) && QFileInfo::exists(QString::fromStdString(scene.baseDir) + "/project.json")) {
    const RelightData data = readRelightData(scene);
    std::printf("; preprocessed (textures of photo '%s' for %zu polygons)", data.photo.c_str(), data.textures.size());
  }
  std::printf("\n");
  return 0;
}

int benchCommand(const QStringList& args, Progress& progress) {
  QCommandLineParser p;
  p.setApplicationDescription("Speed and memory figures of the radiosity engine, as JSON.");
  p.addPositionalArgument("ROOM", "Bundle folder, Relume project or .obj with its .json.");
  p.addOption({"json", "Output JSON file.", "OUT.json"});
  p.addOption({"runs", "Repetitions per figure (median reported; default 5).", "N"});
  p.addOption({"edit-links", "Link count for the lamp-edit figure (default 50000).", "N"});
  p.addOption({"daylight-only", "Only the daylight figures (a room with windows and measured skies)."});
  p.addOption({"ibr-only", "Only the image-based object figures (a room with lamps and a photo)."});
  addEngineOptions(p);
  parseOrThrow(p, args, 1, "relume bench ROOM --json OUT.json [--runs N]");
  if (!p.isSet("json")) throw Error("", "command line", "--json OUT.json is required");
  const int runs = std::max(1, p.value("runs").isEmpty() ? 5 : p.value("runs").toInt());
  const size_t editLinks = p.isSet("edit-links") ? size_t(p.value("edit-links").toLongLong()) : 50000;
  const rad::Options opt = engineOptions(p);
  const Scene scene = openRoom(p.positionalArguments()[0]);
  const auto surfaces = rad::surfacesFromScene(scene);
  QJsonObject out;
  out["room"] = QString::fromStdString(scene.sourceFile);
  out["runs"] = runs;
  out["threads"] = int(std::thread::hardware_concurrency());
  auto finish = [&] {
    out["peak_memory_bytes"] = qint64(peakRssBytes());
    writeJsonAtomically(p.value("json"), out);
    std::fprintf(stderr, "%s\n", QJsonDocument(out).toJson(QJsonDocument::Indented).constData());
    return 0;
  };
  if (p.isSet("daylight-only")) {
    if (scene.skies.empty()) throw Error(scene.sourceFile, "--daylight-only", "the room has no measured sky");
    out["daylight"] = daylightBench(scene, runs, progress);
    return finish();
  }
  if (p.isSet("ibr-only")) {
    if (scene.lamps.empty() || scene.photos.empty())
      throw Error(scene.sourceFile, "--ibr-only", "the room needs a lamp and a photo to draw an image-based object in");
    out["image_based_objects"] = ibrBench(scene, runs, progress);
    return finish();
  }

  // 1. Full solve at the given (default) settings.
  std::vector<double> solveTimes;
  rad::Totals t{};
  for (int r = 0; r < runs; ++r) {
    progress.report(double(r) / runs * 0.3, "bench: solve run " + std::to_string(r + 1));
    const auto t0 = std::chrono::steady_clock::now();
    rad::HierarchicalRadiosity h(surfaces, opt);
    h.solve();
    solveTimes.push_back(seconds(t0));
    t = h.totals();
  }
  out["solve"] = QJsonObject{{"median_seconds", median(solveTimes)}, {"links", qint64(t.links)},
                             {"elements", qint64(t.elements)},     {"leaves", qint64(t.leaves)},
                             {"rays", qint64(t.rays)},             {"epsilon", opt.epsilon}};

  // 2. Occlusion rays: segments between random points on random pairs of polygons.
  {
    std::vector<std::vector<glm::dvec3>> polys;
    for (const auto& s : surfaces) polys.push_back(s.vertices);
    RayScene rs(polys);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> U(0, 1);
    auto pointOn = [&](const std::vector<glm::dvec3>& v) {
      double a = U(rng), b = U(rng);
      if (a + b > 1) a = 1 - a, b = 1 - b;
      const size_t k = 1 + size_t(U(rng) * double(v.size() - 2)) % (v.size() - 2);
      return glm::vec3(v[0] + a * (v[k] - v[0]) + b * (v[k + 1] - v[0]));
    };
    const size_t n = 2'000'000;
    std::vector<Segment> segs(n);
    for (auto& s : segs) s = {pointOn(polys[rng() % polys.size()]), pointOn(polys[rng() % polys.size()])};
    std::vector<uint8_t> blocked(n);
    std::vector<double> rates;
    for (int r = 0; r < runs; ++r) {
      progress.report(0.3 + 0.1 * r / runs, "bench: occlusion rays run " + std::to_string(r + 1));
      const auto t0 = std::chrono::steady_clock::now();
      rs.occluded(segs, blocked);
      rates.push_back(double(n) / seconds(t0));
    }
    size_t nb = 0;
    for (auto b : blocked) nb += b;
    out["occlusion"] = QJsonObject{{"rays_per_run", qint64(n)},
                                   {"median_rays_per_second", median(rates)},
                                   {"blocked_fraction", double(nb) / double(n)}};
  }

  // 3. Lamp edit at about `editLinks` links: epsilon lowered until the link count reaches it.
  {
    // Coarse to fine: the first epsilon whose solution has at least `editLinks` links.
    rad::Options o = opt;
    o.epsilon = 0.2;
    std::unique_ptr<rad::HierarchicalRadiosity> h;
    size_t rssBefore = 0, rssAfter = 0;
    for (int k = 0; k < 40; ++k) {
      progress.report(0.4 + 0.01 * k, "bench: solving at epsilon " + std::to_string(o.epsilon));
      h.reset();
      rssBefore = currentRssBytes();  // grows only when the allocator needs fresh pages
      h = std::make_unique<rad::HierarchicalRadiosity>(surfaces, o);
      h->solve();
      rssAfter = currentRssBytes();
      if (h->totals().links >= editLinks) break;
      o.epsilon *= 0.8;
    }
    const auto tt = h->totals();
    int lampSurface = scene.lamps.empty() ? -1 : scene.lamps.front().polygon;
    std::vector<double> editMs;
    std::vector<int> iters;
    if (lampSurface >= 0) {
      const glm::dvec3 e0 = h->surfaces()[lampSurface].exitance;
      for (int r = 0; r < std::max(runs, 5); ++r) {
        const double scale = (r % 2 == 0) ? 0.0 : 1.0;  // switch the lamp off, then on again
        const auto t0 = std::chrono::steady_clock::now();
        h->setExitance(lampSurface, e0 * scale);
        const auto st = h->iterate();
        editMs.push_back(1000.0 * seconds(t0));
        iters.push_back(st.iterations);
      }
    }
    QJsonArray itArr;
    for (int i : iters) itArr.append(i);
    out["lamp_edit"] = QJsonObject{{"links", qint64(tt.links)},
                                   {"epsilon", o.epsilon},
                                   {"median_ms", median(editMs)},
                                   {"iterations", itArr},
                                   {"tolerance", o.tolerance},
                                   {"link_bytes_per_link", double(tt.linkBytes) / double(std::max<size_t>(1, tt.links))},
                                   {"engine_bytes_per_link", double(tt.engineBytes) / double(std::max<size_t>(1, tt.links))},
                                   {"rss_growth_bytes_per_link",
                                    double(rssAfter - std::min(rssAfter, rssBefore)) / double(std::max<size_t>(1, tt.links))}};
  }
  if (!scene.lamps.empty() && !scene.photos.empty()) {
    ProgressScope rp(progress, 0.7, 1.0);
    out["relight"] = relightBench(scene, runs, rp);
    ProgressScope ip(progress, 0.85, 0.97);
    out["image_based_objects"] = ibrBench(scene, runs, ip);
  }
  if (!scene.skies.empty()) {
    ProgressScope dp(progress, 0.9, 0.97);
    out["daylight"] = daylightBench(scene, runs, dp);
  }
  {
    ProgressScope rp(progress, 0.97, 1.0);
    out["reconstruct"] = reconstructBench(scene, runs, rp);
  }
  return finish();
}

ImageRGB sideBySide(const std::vector<const ImageRGB*>& imgs) {
  const int w = imgs[0]->width, h = imgs[0]->height, gap = 4;
  ImageRGB out(int(imgs.size()) * (w + gap) - gap, h);
  for (size_t k = 0; k < imgs.size(); ++k)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) out.set(int(k) * (w + gap) + x, y, imgs[k]->at(x, y));
  return out;
}

}  // namespace relume::cli
