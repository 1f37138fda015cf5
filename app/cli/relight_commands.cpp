// relume preprocess | relight | evaluate: Loscos et al. 2000 §4-5 from the command line.
#include <QCommandLineParser>
#include <QDir>
#include <QFileInfo>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QSaveFile>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "commands.h"
#include "relume/geometry/error.h"
#include "relume/ibr/fan.h"
#include "relume/ibr/relit_objects.h"
#include "relume/image/image.h"
#include "relume/project/relight_store.h"
#include "relume/project/room_io.h"
#include "relume/relight/compare.h"
#include "relume/relight/relighter.h"
#include "relume/relight/solution_render.h"

namespace relume::cli {

int lampNamed(const Scene& scene, const std::string& name, const glm::dvec3& scale, const std::string& where) {
  const int l = scene.findLamp(name);
  if (l < 0) {
    std::string names;
    for (const auto& lamp : scene.lamps) names += (names.empty() ? "" : ", ") + lamp.name;
    throw Error(where, "lamp '" + name + "'", "the room has no such lamp" + (names.empty() ? std::string() : " (lamps: " + names + ")"));
  }
  for (double c : {scale.x, scale.y, scale.z})
    if (!(c >= 0) || !std::isfinite(c)) throw Error(where, "lamp '" + name + "'", "a scale must be a finite number >= 0");
  return l;
}

namespace {

std::string str(const QString& s) { return s.toStdString(); }

// `n` comma-separated numbers of an option's value; `what` names the option in errors.
std::vector<double> numbersIn(const QString& text, int n, const std::string& what) {
  std::vector<double> x;
  for (const QString& e : text.split(',')) {
    bool ok = false;
    x.push_back(e.toDouble(&ok));
    if (!ok) throw Error("", what, "'" + str(text) + "' is not a list of numbers");
  }
  if (int(x.size()) != n) throw Error("", what, "'" + str(text) + "' needs " + std::to_string(n) + " numbers");
  return x;
}
QJsonArray rgbJson(const glm::dvec3& v) { return QJsonArray{v.x, v.y, v.z}; }

void addRelightOptions(QCommandLineParser& p) {
  p.addOption({"mean-reflectance", "Average reflectance of the room (Eq. 1's rho-hat), refined afterwards.", "X"});
  p.addOption({"colour-threshold", "CIELAB distance below which two colours are similar.", "X"});
  p.addOption({"visibility-threshold", "Attenuation difference below which visibility is similar.", "X"});
  p.addOption({"blocked-indirect", "Add back blocked light from secondary sources too (Eq. 5 in full; default: direct only)."});
  p.addOption({"reference",
               "Step 2 (reference patches): chosen (default: only where the user chose a reference), weighted, paper, "
               "or off (T_final = T_inter).",
               "MODE"});
  p.addOption({"equal-lamps", "Every lamp the same emittance (Eq. 2), no per-lamp least squares."});
  p.addOption({"lamps-from-equations", "Estimate lamps by Eq. 2 / least squares even when the HDR photos show them."});
  p.addOption({"no-inverse-gi",
               "Estimate reflectances and lamps as the paper does (from rho-hat, unshadowed elements only) instead of "
               "by inverse global illumination (measured indirect light, shadows, joint fit)."});
  p.addOption({"no-shared-materials", "Polygons no photo shows take the room's mean reflectance, not their material's."});
  p.addOption({"calibrated-photos",
               "The photos are photometrically calibrated (linear values in cd/m^2): lamps with a photometric file are "
               "taken at the file's flux instead of being estimated."});
  p.addOption({"eps", "Radiosity refinement threshold.", "X"});
  p.addOption({"oracle", "Radiosity refinement oracle: bf (the kernel's spread) or bfv (weighted by visibility, partly hidden links whole).", "NAME"});
  p.addOption({"reference-patch", "POLYGON=U,V: the polygon's default reference patch (plane coordinates, metres).", "P=U,V"});
  p.addOption({"reference-region",
               "POLYGON=U,V@U1,V1,R1[@U2,V2,R2...]: the occluded elements of POLYGON inside the discs (centre, radius; "
               "plane coordinates, metres) take their reflectance from the element at U,V. Repeatable; later wins.",
               "P=U,V@U,V,R"});
}

RelightOptions relightOptions(const QCommandLineParser& p) {
  RelightOptions o;
  auto number = [&](const char* name, double& target, double lo, double hi) {
    if (!p.isSet(name)) return;
    bool ok = false;
    const double v = p.value(name).toDouble(&ok);
    if (!ok || !(v > lo && v < hi))
      throw Error("", std::string("--") + name, "must be a number in (" + std::to_string(lo) + ", " + std::to_string(hi) + "), not '" + str(p.value(name)) + "'");
    target = v;
  };
  number("mean-reflectance", o.meanReflectance, 0, 1);
  number("colour-threshold", o.colourThreshold, 0, 1000);
  number("visibility-threshold", o.visibilityThreshold, 0, 1);
  number("eps", o.engine.epsilon, 0, 1e6);
  readOracle(p, o.engine.oracle);
  o.blockedIndirect = p.isSet("blocked-indirect");
  if (p.isSet("reference")) {
    const QString r = p.value("reference");
    if (r == "off") o.reference = RelightOptions::Reference::Off;
    else if (r == "paper") o.reference = RelightOptions::Reference::Paper;
    else if (r == "weighted") o.reference = RelightOptions::Reference::Weighted;
    else if (r == "chosen") o.reference = RelightOptions::Reference::Chosen;
    else throw Error("", "--reference", "must be chosen, weighted, paper or off, not '" + str(r) + "'");
  }
  o.lampLeastSquares = !p.isSet("equal-lamps");
  o.lampsFromPhoto = !p.isSet("lamps-from-equations");
  o.inverseGlobalIllumination = !p.isSet("no-inverse-gi");
  o.sharedMaterials = !p.isSet("no-shared-materials");
  o.calibratedPhotos = p.isSet("calibrated-photos");
  for (const QString& r : p.values("reference-patch")) {
    const int eq = r.indexOf('=');
    if (eq <= 0) throw Error("", "--reference-patch " + str(r), "expected POLYGON=U,V");
    const auto uv = numbersIn(r.mid(eq + 1), 2, "--reference-patch " + str(r));
    o.referenceOverride[str(r.left(eq))] = {uv[0], uv[1]};
  }
  for (const QString& r : p.values("reference-region")) {
    const int eq = r.indexOf('=');
    const QStringList parts = r.mid(eq + 1).split('@');
    const std::string what = "--reference-region " + str(r);
    if (eq <= 0 || parts.size() < 2) throw Error("", what, "expected POLYGON=U,V@U1,V1,R1[@...]");
    ReferenceRegion region;
    region.polygon = str(r.left(eq));
    const auto ref = numbersIn(parts[0], 2, what);
    region.reference = {ref[0], ref[1]};
    for (int k = 1; k < parts.size(); ++k) {
      const auto d = numbersIn(parts[k], 3, what);
      region.discs.emplace_back(d[0], d[1], d[2]);
    }
    o.referenceRegions.push_back(region);
  }
  return o;
}

void printEstimates(const RelightData& d) {
  const auto& e = d.estimates;
  std::fprintf(stderr, "mean reflectance: given %.3f; with Eq. 2's lamps the computed ones average %.3f, so those lamps were scaled by %.3f (%d rounds)\n",
               e.meanReflectanceGiven, e.meanReflectanceRefined, e.eq2Scale, e.reflectanceRounds);
  std::fprintf(stderr, "lamp emittances (exitance, RGB) — using %s%s%s:\n", e.lampModel.c_str(),
               e.lampModelReason.empty() ? "" : ": ", e.lampModelReason.c_str());
  for (const auto& l : e.lamps)
    std::fprintf(stderr, "  %-6s equal (Eq. 2) %.2f %.2f %.2f  least squares %.2f %.2f %.2f  photographed %.2f %.2f %.2f\n",
                 l.name.c_str(), l.equal.x, l.equal.y, l.equal.z, l.leastSquares.x, l.leastSquares.y, l.leastSquares.z,
                 l.photographed.x, l.photographed.y, l.photographed.z);
  if (e.jointFitElements > 0) {
    std::fprintf(stderr,
                 "inverse global illumination: %zu elements, mean reflectance %.3f, %.0f %% of the indirect light measured "
                 "in the photo\n",
                 e.jointFitElements, e.meanReflectanceRecovered, 100 * e.indirectMeasuredShare);
    for (const auto& l : e.lamps)
      std::fprintf(stderr, "  %-6s joint fit %.2f %.2f %.2f (+- %.1f %%)%s  used %.2f %.2f %.2f\n", l.name.c_str(), l.jointFit.x,
                   l.jointFit.y, l.jointFit.z, 100 * l.uncertainty, l.twoSided ? " per face" : "", l.used.x, l.used.y, l.used.z);
  }
  for (const auto& n : e.unseenByMaterial) std::fprintf(stderr, "  %s: no photo shows it; its material's reflectance\n", n.c_str());
  for (const auto& n : e.unseenWithoutMaterial)
    std::fprintf(stderr, "  %s: no photo shows it and no photographed polygon shares its material; the room's mean reflectance\n", n.c_str());
  std::fprintf(stderr,
               "texture-based refinement: %zu -> %zu elements (%zu subdivided, %zu cancelled); %zu occluded elements, "
               "%zu on the frontier, %zu corrected from the frontier, %zu from the polygon's default reference, %zu from painted "
               "regions; %.1f s\n",
               e.leavesBeforeTextureRefinement, e.leavesAfter, e.texturesSubdivided, e.subdivisionsCancelled, e.occludedLeaves,
               e.frontierLeaves, e.referencedByFrontier, e.referencedByDefault, e.referencedByRegion, e.seconds);
}

QJsonObject estimatesJson(const RelightData& d) {
  const auto& e = d.estimates;
  QJsonArray lamps;
  for (const auto& l : e.lamps)
    lamps.append(QJsonObject{{"name", QString::fromStdString(l.name)},
                             {"equal", rgbJson(l.equal)},
                             {"least_squares", rgbJson(l.leastSquares)},
                             {"photographed", rgbJson(l.photographed)},
                             {"used", rgbJson(l.used)},
                             {"joint_fit", rgbJson(l.jointFit)},
                             {"uncertainty", l.uncertainty},
                             {"two_sided", l.twoSided}});
  QJsonArray byMaterial, without;
  for (const auto& n : e.unseenByMaterial) byMaterial.append(QString::fromStdString(n));
  for (const auto& n : e.unseenWithoutMaterial) without.append(QString::fromStdString(n));
  return {{"mean_reflectance_given", e.meanReflectanceGiven},
          {"mean_reflectance_refined", e.meanReflectanceRefined},
          {"eq2_scale", e.eq2Scale},
          {"mean_reflectance_recovered", e.meanReflectanceRecovered},
          {"joint_fit_elements", double(e.jointFitElements)},
          {"indirect_measured_share", e.indirectMeasuredShare},
          {"unseen_polygons_by_material", byMaterial},
          {"unseen_polygons_without_material", without},
          {"lamp_model", QString::fromStdString(e.lampModel)},
          {"lamp_model_reason", QString::fromStdString(e.lampModelReason)},
          {"lamps", lamps},
          {"elements_after_texture_refinement", double(e.leavesAfter)},
          {"preprocess_seconds", e.seconds}};
}

// Lamp scales by name; every name must be a lamp of the room.
std::vector<glm::dvec3> lampScales(const Scene& scene, const std::map<std::string, glm::dvec3>& byName, const std::string& where) {
  std::vector<glm::dvec3> s(scene.lamps.size(), glm::dvec3(1.0));
  for (const auto& [name, v] : byName) s[size_t(lampNamed(scene, name, v, where))] = v;
  return s;
}

void virtualsOf(const Variant& v, std::vector<VirtualLamp>& lamps, std::vector<VirtualObject>& objects) {
  for (size_t i = 0; i < v.virtualLamps.size(); ++i)
    lamps.push_back({v.virtualLamps[i].name.empty() ? "virtual_lamp_" + std::to_string(i) : v.virtualLamps[i].name,
                     v.virtualLampPolygons[i], v.virtualLamps[i].radiance, v.virtualLamps[i].twoSided,
                     v.virtualLamps[i].photometry});
  for (const auto& b : v.virtualObjects) {
    if (!b.fan.empty()) continue;  // image-based: ibr::appendImageObjects
    const std::string name = b.name.empty() ? "virtual_object_" + std::to_string(objects.size()) : b.name;
    if (b.mesh.empty()) objects.push_back(boxObject(name, b.boxMin, b.boxMax, b.albedo));
    else objects.push_back(VirtualObject{name, b.mesh, b.albedo});
  }
}

const Photo& photoNamedian(const Scene& scene, const std::string& name) {
  const Photo* p = scene.findPhoto(name);
  if (!p) throw Error(scene.sourceFile, "photo '" + name + "'", "no photo has that name");
  return *p;
}

std::string resolve(const Scene& scene, const std::string& rel) { return rel.front() == '/' ? rel : scene.baseDir + "/" + rel; }

}  // namespace

int preprocessCommand(const QStringList& args, Progress& progress) {
  QCommandLineParser p;
  p.setApplicationDescription("Preprocess a room for relighting (Loscos et al. 2000 §4) and write a Relume project.");
  p.addPositionalArgument("ROOM", "Bundle folder, Relume project or .obj with its .json.");
  p.addOption({{"o", "output"}, "Project folder to write.", "PROJECT"});
  addRelightOptions(p);
  parseOrThrow(p, args, 1, "relume preprocess ROOM -o PROJECT");
  if (!p.isSet("output")) throw Error("", "command line", "-o PROJECT is required");
  const RelightOptions opt = relightOptions(p);
  progress.report(0, "reading " + str(p.positionalArguments()[0]));
  const Scene scene = openRoom(p.positionalArguments()[0]);
  if (!scene.skies.empty()) {
    // A daylight room: its light comes through the windows, and its preprocess is the daylight
    // session (reflectances under the photos' sky, the basis solutions), kept in the project.
    for (const QString& o : p.optionNames())
      if (o != "o" && o != "output")
        throw Error(scene.sourceFile, "--" + o.toStdString(),
                    "is an option of the lamp path; a daylight room's preprocess (as relume daylight-basis -o) takes none");
    std::fprintf(stderr, "a daylight room: estimating under the photos' sky and solving its basis (as relume daylight-basis -o)\n");
    return keepDaylightSession(scene, 64, str(p.value("output")), progress);
  }
  ProgressScope work(progress, 0.0, 0.9);
  const RelightData data = preprocessRoom(scene, opt, work);
  printEstimates(data);
  for (const auto& l : scene.lamps)
    if (l.photometry)
      std::fprintf(stderr,
                   "  %-6s emits as its photometric file %s says (%s, %.0f lm of lamps, %.0f lm from the luminaire); %s\n",
                   l.name.c_str(), l.photometryFile.c_str(), l.photometry->format.c_str(), l.photometry->lampLumens,
                   l.photometry->flux(),
                   opt.calibratedPhotos ? "the photos are calibrated: its exitance is the luminaire's flux over its area"
                                        : "its exitance is the photos' estimate, the file's lumens are not used");
  ProgressScope saving(progress, 0.9, 1.0);
  saveRelightProject(scene, data, str(p.value("output")), saving);
  std::fprintf(stderr, "wrote project %s\n", qPrintable(p.value("output")));
  return 0;
}

int relightCommand(const QStringList& args, Progress& progress) {
  QCommandLineParser p;
  p.setApplicationDescription("Relight a preprocessed project and write the image seen from its photo.");
  p.addPositionalArgument("PROJECT", "A project written by relume preprocess.");
  p.addOption({"lamp", "NAME=S or NAME=R,G,B: scale of a real lamp's emittance (0 off, 2 doubled). With --sky: the lamp "
                       "switched on beside the daylight at S x its radiance as the room gives it (the photos are taken "
                       "with the lamps off).", "NAME=S"});
  p.addOption({"virtual-lamp", "JSON file with virtual_lights (as in a scene.json variant).", "FILE"});
  p.addOption({"virtual-object",
               "JSON file with virtual_objects (box_min/box_max or obj, albedo; or an image-based object: fan, "
               "position, scale, rotation_degrees).",
               "FILE"});
  p.addOption({"method", "full (default) or ratio-only (original textures x B/B_orig).", "NAME"});
  p.addOption({"camera", "Photo whose camera to render (default: the textures' photo).", "NAME"});
  p.addOption({"sky", "Daylight: a daylight room's measured sky by name, an HDR fisheye (equidistant, 180 degrees, "
                      "looking up, image up = +Y), or a folder of them (a time-varying sky: one frame per image, in name "
                      "order, written to the -o folder as NAME.exr and NAME.png with frames.json); PROJECT is then the "
                      "room (bundle or project) with its windows.", "NAME|FISHEYE.exr|FOLDER"});
  p.addOption({"lens", "With --sky FISHEYE.exr or FOLDER: the fisheye's calibrated lens (`relume calibrate --fisheye`) "
                       "instead of the ideal equidistant projection.", "LENS.json"});
  p.addOption({"daylight", "With --sky: near-field (default: the windows' light through the room's basis solutions, "
                           "objects added to them), volume (the interactive path: objects lit by the SH irradiance volume and "
                           "64 samples through the windows, nothing solved again) or distant (the sky at infinity, for "
                           "comparison).", "METHOD"});
  p.addOption({{"o", "output"}, "Output image (.exr linear radiance, .png at the photo's exposure).", "IMG"});
  parseOrThrow(p, args, 1, "relume relight PROJECT --lamp A=0 [--virtual-lamp F] [--virtual-object F] -o IMG\n"
                           "       relume relight ROOM --sky NAME|FISHEYE.exr [--lamp A=1] [--virtual-lamp F] [--virtual-object F] [--daylight near-field|volume|distant] -o IMG\n"
                           "       relume relight ROOM --sky FOLDER [--lamp A=1] [--virtual-object F] [--daylight ...] -o FRAMES_DIR");
  if (!p.isSet("output")) throw Error("", "command line", "-o IMG is required");
  const QString out = p.value("output");
  const QString ext = QFileInfo(out).suffix().toLower();
  const bool skyFolder = p.isSet("sky") && QFileInfo(p.value("sky")).isDir();  // frames into a folder
  if (!skyFolder && ext != "exr" && ext != "png") throw Error(str(out), "", "the output must end in .exr or .png");
  std::map<std::string, glm::dvec3> scales;
  for (const QString& s : p.values("lamp")) {
    const int eq = s.indexOf('=');
    if (eq <= 0) throw Error("", "--lamp " + str(s), "expected NAME=S or NAME=R,G,B");
    const QStringList parts = s.mid(eq + 1).split(',');
    glm::dvec3 v;
    bool ok = parts.size() == 1 || parts.size() == 3;
    for (int c = 0; c < 3 && ok; ++c) v[c] = parts[parts.size() == 1 ? 0 : c].toDouble(&ok);
    if (!ok) throw Error("", "--lamp " + str(s), "expected NAME=S or NAME=R,G,B with numbers");
    scales[str(s.left(eq))] = v;
  }
  if (p.isSet("sky")) {
    if (p.isSet("method"))
      throw Error("", "--sky", "daylight relighting takes no --method (full / ratio-only are the lamp path's): see --daylight");
    std::vector<std::string> files, lampFiles;
    for (const QString& f : p.values("virtual-object")) files.push_back(str(f));
    for (const QString& f : p.values("virtual-lamp")) lampFiles.push_back(str(f));
    return daylightRelight(openRoom(p.positionalArguments()[0]), str(p.value("sky")), files, lampFiles, scales,
                           p.isSet("daylight") ? str(p.value("daylight")) : "near-field", str(p.value("camera")), str(out),
                           progress, str(p.value("lens")));
  }
  if (p.isSet("daylight")) throw Error("", "--daylight", "needs --sky");
  if (p.isSet("lens")) throw Error("", "--lens", "is the lens of a --sky fisheye: needs --sky");
  RelightMethod method = RelightMethod::Full;
  if (p.isSet("method")) {
    if (p.value("method") == "ratio-only") method = RelightMethod::RatioOnly;
    else if (p.value("method") != "full") throw Error("", "--method", "must be full or ratio-only");
  }
  const Scene scene = readProject(str(p.positionalArguments()[0]));
  const RelightData data = readRelightData(scene);
  const auto lampScale = lampScales(scene, scales, "--lamp");
  std::vector<VirtualLamp> vlamps;
  std::vector<VirtualObject> objects;
  for (const QString& f : p.values("virtual-lamp")) {
    const Variant v = readVariantFile(str(f));
    if (v.virtualLamps.empty()) throw Error(str(f), "virtual_lights", "lists no virtual lamp");
    virtualsOf(v, vlamps, objects);
  }
  std::vector<ibr::ImageObject> imageObjects;
  for (const QString& f : p.values("virtual-object")) {
    const Variant v = readVariantFile(str(f));
    if (v.virtualObjects.empty()) throw Error(str(f), "virtual_objects", "lists no virtual object");
    virtualsOf(v, vlamps, objects);
    ibr::appendImageObjects(v, str(f), imageObjects);
  }
  for (const auto& o : imageObjects) ibr::checkImageObject(scene, o);
  const Photo& photo = photoNamedian(scene, p.isSet("camera") ? str(p.value("camera")) : data.photo);
  RelightSession session(scene, data, vlamps, objects, progress,
                         method == RelightMethod::Full ? SessionMesh::Refined : SessionMesh::Interactive);
  for (size_t l = 0; l < lampScale.size(); ++l) session.setLampScale(int(l), lampScale[l]);
  const auto st = session.update(progress);
  ImageRGB img = session.render(photo.camera, method, progress);
  if (!imageObjects.empty()) {
    progress.report(0.95, "drawing the image-based objects and their shadows");
    const auto stats = ibr::drawImageObjects(session, imageObjects, photo.camera, img);
    for (size_t i = 0; i < stats.size(); ++i)
      std::fprintf(stderr, "image-based object '%s': fan view %d, %zu pixels, shadows on %zu pixels\n",
                   imageObjects[i].name.c_str(), stats[i].view, stats[i].objectPixels, stats[i].shadowPixels);
  }
  writeImage(str(out), img, float(data.photoExposure));
  std::fprintf(stderr, "relit in %d radiosity steps; wrote %s (%dx%d)\n", st.iterations, qPrintable(out), img.width, img.height);
  return 0;
}

QJsonObject relightBench(const Scene& sceneIn, int runs, Progress& progress) {
  using clock = std::chrono::steady_clock;
  auto ms = [](clock::time_point a) { return std::chrono::duration<double, std::milli>(clock::now() - a).count(); };
  Scene scene = sceneIn;
  for (auto& poly : scene.polygons) poly.albedo = glm::dvec3(0.5);
  std::vector<double> pre;
  RelightData data;
  for (int r = 0; r < std::max(1, std::min(runs, 3)); ++r) {
    progress.report(0.1 * r, "bench: preprocess run " + std::to_string(r + 1));
    const auto t0 = clock::now();
    data = preprocessRoom(scene, RelightOptions{});
    pre.push_back(ms(t0) / 1000.0);
  }
  QJsonObject out{{"preprocess_median_seconds", median(pre)}};
  const Camera& cam0 = photoNamedian(scene, data.photo).camera;
  const Camera cam = resized(cam0, 640, 480);  // the main view at 640 x 480
  for (auto mesh : {SessionMesh::Refined, SessionMesh::Interactive}) {
    const char* name = mesh == SessionMesh::Refined ? "refined_mesh" : "interactive_mesh";
    progress.report(0.4, std::string("bench: relighting on the ") + name);
    RelightSession s(scene, data, {}, {}, silentProgress(), mesh);
    std::vector<double> step, render, edit;
    for (int r = 0; r < std::max(runs, 5); ++r) {  // a lamp edit as the workbench makes it
      const auto t0 = clock::now();
      s.setLampScale(0, glm::dvec3(r % 2 ? 1.0 : 0.5));
      s.update();
      edit.push_back(ms(t0));
    }
    for (int r = 0; r < std::max(runs, 5); ++r) {
      s.setLampScale(0, glm::dvec3(r % 2 ? 1.0 : 0.0));
      const auto t0 = clock::now();
      s.engine().iterate();
      step.push_back(ms(t0));
      const auto t1 = clock::now();
      s.update();  // corner values for display
      s.render(cam, RelightMethod::Full);
      render.push_back(ms(t1));
    }
    out[name] = QJsonObject{{"links", double(s.engine().links().size())},
                            {"leaves", double(s.engine().totals().leaves)},
                            {"lamp_edit_radiosity_step_median_ms", median(step)},
                            {"lamp_edit_from_per_lamp_solutions_median_ms", median(edit)},
                            {"display_update_and_render_640x480_median_ms", median(render)}};
  }
  {  // a virtual box moved by 10 cm, back and forth
    progress.report(0.7, "bench: moving a virtual box");
    glm::dvec3 lo(1e300), hi(-1e300);
    for (const auto& p : scene.polygons)
      if (p.kind == PolygonKind::Real)
        for (const auto& v : p.vertices) {
          lo = glm::min(lo, v);
          hi = glm::max(hi, v);
        }
    // A 30 cm box on the floor at a third of the room, clear of furniture when possible.
    glm::dvec3 c(lo.x + 0.3 * (hi.x - lo.x), lo.y + 0.3 * (hi.y - lo.y), lo.z);
    VirtualObject box = boxObject("bench_box", c, c + glm::dvec3(0.3, 0.3, 0.3), glm::dvec3(0.5));
    for (auto mesh : {SessionMesh::Refined, SessionMesh::Interactive}) {
      const char* name = mesh == SessionMesh::Refined ? "virtual_object_move_10cm_refined_mesh" : "virtual_object_move_10cm_interactive_mesh";
      try {
        RelightSession s(scene, data, {}, {box}, silentProgress(), mesh);
        std::vector<double> t;
        size_t updated = 0;
        for (int r = 0; r < std::max(runs, 5); ++r) {
          const auto t0 = clock::now();
          updated = s.moveObject(0, glm::dvec3(r % 2 ? -0.1 : 0.1, 0, 0));
          t.push_back(ms(t0));
        }
        out[name] = QJsonObject{{"median_ms", median(t)}, {"links_updated", double(updated)}, {"links", double(s.engine().links().size())}};
      } catch (const Error& e) {
        out[name] = QJsonObject{{"skipped", QString::fromStdString(e.what())}};
      }
    }
  }
  {  // a virtual lamp inserted: forced refinement of its links onto the photographed polygons
    progress.report(0.85, "bench: inserting a virtual lamp");
    const double z = 0.0;
    glm::dvec3 lo(1e300), hi(-1e300);
    for (const auto& p : scene.polygons)
      for (const auto& v : p.vertices) {
        lo = glm::min(lo, v);
        hi = glm::max(hi, v);
      }
    const glm::dvec3 c(0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), lo.z + 0.7 * (hi.z - lo.z) + z);
    VirtualLamp v{"bench_lamp", {c + glm::dvec3(0, 0.3, 0), c + glm::dvec3(0.3, 0.3, 0), c + glm::dvec3(0.3, 0, 0), c}, glm::dvec3(20.0), false, nullptr};
    std::vector<double> t;
    for (int r = 0; r < std::max(1, std::min(runs, 3)); ++r) {
      RelightSession s(scene, data, {v});
      t.push_back(s.insertSeconds() * 1000.0);
    }
    out["virtual_lamp_insert_median_ms"] = median(t);
    // The workbench's edits on a live session (the refined mesh): a lamp added and removed, a box
    // added, the first lamp edit after the box moved (the per-lamp solutions are rebuilt), a lamp
    // edit after that, and Recompute after a reference patch changed (step 2 of that polygon on
    // the kept preprocess, then the session's new reflectance maps).
    progress.report(0.9, "bench: edits on a live session");
    Preprocessor pre(scene, RelightOptions{});
    RelightSession live(scene, pre.data());
    const glm::dvec3 bc(lo.x + 0.3 * (hi.x - lo.x), lo.y + 0.3 * (hi.y - lo.y), lo.z);
    const VirtualObject box = boxObject("bench_box", bc, bc + glm::dvec3(0.3, 0.3, 0.3), glm::dvec3(0.5));
    std::vector<double> add, remove, addBox, firstEdit, edit, recompute;
    int real = -1;
    for (size_t i = 0; i < scene.polygons.size() && real < 0; ++i)
      if (scene.polygons[i].kind == PolygonKind::Real && pre.data().textures[i].photographed()) real = int(i);
    const PlaneFrame frame = PlaneFrame::of(scene.polygons[size_t(real)].vertices);
    std::vector<glm::dvec2> uvs;
    for (const auto& p : scene.polygons[size_t(real)].vertices) uvs.push_back(frame.toUV(p));
    for (int r = 0; r < std::max(runs, 3); ++r) {
      auto t0 = clock::now();
      const int k = live.addVirtualLamp(v);
      add.push_back(ms(t0));
      t0 = clock::now();
      live.removeVirtualLamp(k);
      remove.push_back(ms(t0));
      try {
        t0 = clock::now();
        const int b = live.addObject(box);
        addBox.push_back(ms(t0));
        live.moveObject(b, glm::dvec3(0.05, 0, 0));
        t0 = clock::now();
        live.setLampScale(0, glm::dvec3(r % 2 ? 1.0 : 0.5));
        live.update();
        firstEdit.push_back(ms(t0));
        t0 = clock::now();
        live.setLampScale(0, glm::dvec3(r % 2 ? 0.5 : 1.0));
        live.update();
        edit.push_back(ms(t0));
        live.removeObject(b);
      } catch (const Error&) {  // no room for the box there
      }
      // A reference patch at a point of the polygon (alternating between two), then Recompute.
      const glm::dvec2 at = r % 2 ? 0.5 * (uvs[0] + uvs[2]) : (uvs[0] + uvs[1] + uvs[2]) / 3.0;
      t0 = clock::now();
      pre.redoReferences({{scene.polygons[size_t(real)].name, at}}, {});
      live.setReflectanceMaps(pre.data().textures);
      recompute.push_back(ms(t0));
    }
    out["live_session"] = QJsonObject{{"virtual_lamp_add_median_ms", median(add)},
                                      {"virtual_lamp_remove_median_ms", median(remove)},
                                      {"box_add_median_ms", median(addBox)},
                                      {"first_lamp_edit_after_a_move_median_ms", median(firstEdit)},
                                      {"lamp_edit_median_ms", median(edit)},
                                      {"recompute_one_reference_patch_median_ms", median(recompute)},
                                      {"reference_patch_polygon", QString::fromStdString(scene.polygons[size_t(real)].name)}};
  }
  return out;
}

int compareCommand(const QStringList& args, Progress&) {
  QCommandLineParser p;
  p.setApplicationDescription(
      "Score a rendering of a bundle's main view against a truth image (the benchmark protocol), or against another "
      "image of the same size (the protocol's 'all' mask of that image).");
  p.addPositionalArgument("RENDERING", "Linear EXR of the main view.");
  p.addPositionalArgument("BUNDLE", "The bundle folder, or a linear EXR to compare with.");
  p.addOption({"truth", "Variant name (truth/NAME.exr), 'unoccluded', or 'photo' for photos/main.exr.", "NAME"});
  parseOrThrow(p, args, 2, "relume compare RENDERING.exr BUNDLE|OTHER.exr [--truth VARIANT]");
  if (QFileInfo other(p.positionalArguments()[1]); other.isFile() && isRadianceFile(str(other.filePath()))) {
    if (p.isSet("truth")) throw Error("", "command line", "--truth names a bundle's image; with two images give no --truth");
    const ImageRGB a = readImageLinear(str(p.positionalArguments()[0])), b = readImageLinear(str(other.filePath()));
    if (a.width != b.width || a.height != b.height)
      throw Error(str(other.filePath()), "", "is " + std::to_string(b.width) + "x" + std::to_string(b.height) + ", the rendering " +
                                                 std::to_string(a.width) + "x" + std::to_string(a.height));
    const Comparison c = compareImages(a, b, benchmarkMasks(b, b).all);  // the protocol's "all" mask of the other image
    std::printf("all %.2f dB (gain %.3f %.3f %.3f)\n", c.psnr, c.gain.x, c.gain.y, c.gain.z);
    return 0;
  }
  const Scene scene = openRoom(p.positionalArguments()[1]);
  const Photo& main = photoNamedian(scene, scene.mainPhoto);
  const ImageRGB photo = readImageLinear(resolve(scene, main.hdr.empty() ? main.file : main.hdr));
  const ImageRGB unocc = readImageLinear(scene.baseDir + "/truth/unoccluded.exr");
  const std::string name = p.isSet("truth") ? str(p.value("truth")) : "photo";
  const ImageRGB truth = name == "photo" ? photo : readImageLinear(scene.baseDir + "/truth/" + name + ".exr");
  const ImageRGB img = readImageLinear(str(p.positionalArguments()[0]));
  const CompareMasks masks = benchmarkMasks(photo, unocc);
  const Comparison a = compareImages(img, truth, masks.all), b = compareImages(img, truth, masks.shadow);
  std::printf("all %.2f dB (gain %.3f %.3f %.3f)  shadow %.2f dB\n", a.psnr, a.gain.x, a.gain.y, a.gain.z, b.psnr);
  return 0;
}

int evaluateCommand(const QStringList& args, Progress& progress) {
  QCommandLineParser p;
  p.setApplicationDescription(
      "Preprocess a ground-truth bundle from its photos, geometry, cameras and lamp polygons only, render every "
      "variant with the full and the ratio-only method and compare with the truth images.");
  p.addPositionalArgument("BUNDLE", "A bundle folder (scene.json with variants and truth images).");
  p.addOption({"out", "Folder for report.json and the images.", "DIR"});
  p.addOption({"geometry",
               "Use this room's polygons, lamps and cameras (e.g. a project of `relume triangulate`) with the "
               "bundle's photos' truth images.",
               "ROOM"});
  addRelightOptions(p);
  p.addOption({"oracle-lamps", "ORACLE, for telling estimation from rendering error: the bundle's true lamp radiances are used "
                               "instead of the estimates."});
  p.addOption({"oracle-albedos", "ORACLE: the bundle's true polygon albedos are the engine's reflectances instead of the "
                                 "estimates (with --oracle-lamps: what is left is rendering error)."});
  parseOrThrow(p, args, 1, "relume evaluate BUNDLE --out DIR [--geometry PROJECT]");
  if (!p.isSet("out")) throw Error("", "command line", "--out DIR is required");
  const QString outDir = p.value("out");
  if (!QDir().mkpath(outDir)) throw Error(str(outDir), "", "cannot create the folder");
  RelightOptions opt = relightOptions(p);
  opt.oracleLamps = p.isSet("oracle-lamps");
  opt.oracleAlbedos = p.isSet("oracle-albedos");
  Scene scene = openRoom(p.positionalArguments()[0]);
  if (!scene.skies.empty()) {  // a daylight bundle: lit through its windows by measured skies
    if (p.isSet("geometry")) throw Error(str(p.value("geometry")), "--geometry", "not yet for daylight bundles");
    return evaluateDaylight(scene, outDir, progress);
  }
  // The truth is the bundle's: with --geometry, its lamps and polygons matched to the model's.
  Scene truthScene;
  if (p.isSet("geometry")) {
    const Scene bundle = scene;
    const Scene g = openRoom(p.value("geometry"));
    for (const auto& v : scene.variants)
      for (const auto& [lamp, scale] : v.lampScale)
        if (g.findLamp(lamp) < 0)
          throw Error(g.sourceFile, "lamp " + lamp, "variant " + v.name + " of the bundle switches it, but this room has no such lamp");
    scene.polygons = g.polygons;
    scene.lamps = g.lamps;
    scene.photos = g.photos;
    for (auto& ph : scene.photos) {
      ph.file = resolve(g, ph.file);
      if (!ph.hdr.empty()) ph.hdr = resolve(g, ph.hdr);
    }
    scene.mainPhoto = g.mainPhoto;
    truthScene = scene;
    const BundleMatch match = matchToBundle(g, bundle);
    for (size_t l = 0; l < g.lamps.size(); ++l) {  // unmatched: no truth (NaN), reported as such
      if (match.lamp[l] < 0 && opt.oracleLamps)
        throw Error(g.sourceFile, "lamp " + g.lamps[l].name,
                    "matches no lamp of the bundle (by name, or a lamp within 0.5 m): --oracle-lamps has no truth for it");
      truthScene.lamps[l].radiance =
          match.lamp[l] >= 0 ? bundle.lamps[size_t(match.lamp[l])].radiance : glm::dvec3(std::nan(""));
    }
    for (size_t i = 0; i < g.polygons.size(); ++i)  // unmatched: no truth (NaN), left out of the report
      truthScene.polygons[i].albedo = match.polygon[i] >= 0 ? bundle.polygons[size_t(match.polygon[i])].albedo
                                                            : glm::dvec3(std::nan(""));
    // The oracles are the bundle's truths, too.
    if (opt.oracleLamps) scene.lamps = truthScene.lamps;
    if (opt.oracleAlbedos)
      for (size_t i = 0; i < g.polygons.size(); ++i)
        if (match.polygon[i] >= 0) scene.polygons[i].albedo = truthScene.polygons[i].albedo;
  } else {
    truthScene = scene;
  }
  // What a real user does not have is removed before anything else sees the scene (kept apart
  // to judge the estimates with).
  if (!opt.oracleAlbedos)
    for (auto& poly : scene.polygons) poly.albedo = glm::dvec3(0.5);
  if (!opt.oracleLamps)
    for (auto& l : scene.lamps) l.radiance = glm::dvec3(0.0);
  ProgressScope pre(progress, 0.0, 0.5);
  const RelightData data = preprocessRoom(scene, opt, pre);
  printEstimates(data);
  QJsonArray reflectances;
  {
    // Recovered reflectance per photographed polygon (mean of its reflectance map over the texels
    // a photo shows away from the polygon's outline there: photographedMean) against the
    // bundle's albedo, and each lamp against its true exitance.
    for (size_t i = 0; i < scene.polygons.size(); ++i) {
      const auto& t = data.textures[i];
      if (scene.polygons[i].kind != PolygonKind::Real || t.albedo.size() != t.source.size()) continue;
      size_t n = 0;
      const glm::dvec3 m = t.photographedMean(t.albedo, &n), truth = truthScene.polygons[i].albedo;
      if (n == 0 || std::isnan(truth.x)) continue;
      reflectances.append(QJsonObject{{"polygon", QString::fromStdString(scene.polygons[i].name)},
                                      {"recovered", rgbJson(m)},
                                      {"truth", rgbJson(truth)}});
      if (polygonArea(scene.polygons[i].vertices) >= 1.0)
        std::fprintf(stderr, "  reflectance %-12s %.3f (truth %.3f)\n", scene.polygons[i].name.c_str(), (m.x + m.y + m.z) / 3,
                     (truth.x + truth.y + truth.z) / 3);
    }
    for (size_t l = 0; l < scene.lamps.size(); ++l) {
      const double t = std::numbers::pi * (truthScene.lamps[l].radiance.x + truthScene.lamps[l].radiance.y + truthScene.lamps[l].radiance.z) / 3;
      const auto& u = data.lampExitance[l];
      if (std::isnan(t))
        std::fprintf(stderr, "  lamp %-6s exitance %.1f, no lamp of the bundle matches it\n", scene.lamps[l].name.c_str(),
                     (u.x + u.y + u.z) / 3);
      else
        std::fprintf(stderr, "  lamp %-6s exitance %.1f, truth %.1f (%+.1f %%)\n", scene.lamps[l].name.c_str(),
                     (u.x + u.y + u.z) / 3, t, 100 * ((u.x + u.y + u.z) / 3 / t - 1));
    }
  }
  const Photo& main = photoNamedian(scene, data.photo);
  if (main.hdr.empty()) throw Error(scene.sourceFile, "photo " + main.name, "has no linear (EXR) version to compare against");
  const ImageRGB photo = readImageLinear(resolve(scene, main.hdr));
  const std::string unoccPath = scene.baseDir + "/truth/unoccluded.exr";
  const ImageRGB unoccTruth = readImageLinear(unoccPath);
  const CompareMasks masks = benchmarkMasks(photo, unoccTruth);
  const auto dir = [&](const std::string& f) { return str(QDir(outDir).filePath(QString::fromStdString(f))); };
  const float exposure = float(data.photoExposure);
  auto scores = [&](const ImageRGB& img, const ImageRGB& truth) {
    const Comparison a = compareImages(img, truth, masks.all), s = compareImages(img, truth, masks.shadow);
    return QJsonObject{{"psnr_all", a.psnr}, {"psnr_shadow", s.psnr}, {"gain_all", rgbJson(a.gain)}, {"gain_shadow", rgbJson(s.gain)}};
  };
  QJsonObject report{{"bundle", QString::fromStdString(scene.baseDir)},
                     {"reflectances", reflectances},
                     {"estimates", estimatesJson(data)},
                     {"mask_pixels", QJsonObject{{"all", double(std::count(masks.all.begin(), masks.all.end(), 1))},
                                                  {"shadow", double(std::count(masks.shadow.begin(), masks.shadow.end(), 1))}}}};

  ProgressScope base(progress, 0.5, 0.65);
  RelightSession session(scene, data, {}, {}, base);
  RelightSession plain(scene, data, {}, {}, silentProgress(), SessionMesh::Interactive);
  // Original lighting reprojected, and the unoccluded image.
  {
    const ImageRGB orig = session.render(main.camera, RelightMethod::Full);
    const ImageRGB unocc = session.renderUnoccluded(main.camera);
    writeImage(dir("original.full.exr"), orig);
    const ImageRGB origTex = session.render(main.camera, RelightMethod::RatioOnly);
    report["original_textures"] = scores(origTex, photo);
    writeImage(dir("unoccluded.exr"), unocc);
    writeImage(dir("unoccluded.png"), sideBySide({&photo, &unocc, &unoccTruth}), exposure);
    report["original_reprojected"] = scores(orig, photo);
    report["unoccluded"] = QJsonObject{{"full", scores(unocc, unoccTruth)}, {"photo_unchanged", scores(photo, unoccTruth)}};
    ImageRGB mesh = renderSolution(session.engine(), main.camera, RenderShow::Leaves);
    for (size_t i = 0; i < mesh.pixels.size(); ++i) mesh.pixels[i] *= photo.pixels[i] * exposure;
    writeImage(dir("mesh.png"), mesh);
    std::fprintf(stderr, "original lighting reprojected: %.2f dB (all); unoccluded vs truth: %.2f dB (shadow), photo %.2f dB\n",
                 report["original_reprojected"].toObject()["psnr_all"].toDouble(),
                 report["unoccluded"].toObject()["full"].toObject()["psnr_shadow"].toDouble(),
                 report["unoccluded"].toObject()["photo_unchanged"].toObject()["psnr_shadow"].toDouble());
  }
  QJsonArray variants;
  int done = 0;
  for (const auto& v : scene.variants) {
    progress.report(0.65 + 0.35 * done++ / std::max<size_t>(1, scene.variants.size()), "variant " + v.name);
    if (v.hdr.empty()) continue;
    const ImageRGB truth = readImageLinear(resolve(scene, v.hdr));
    const auto scale = lampScales(scene, v.lampScale, scene.sourceFile);
    std::vector<VirtualLamp> vlamps;
    std::vector<VirtualObject> objects;
    virtualsOf(v, vlamps, objects);
    std::unique_ptr<RelightSession> own, ownPlain;
    RelightSession* s = &session;
    RelightSession* sp = &plain;
    if (!vlamps.empty() || !objects.empty()) {
      own = std::make_unique<RelightSession>(scene, data, vlamps, objects, progress);
      ownPlain = std::make_unique<RelightSession>(scene, data, vlamps, objects, progress, SessionMesh::Interactive);
      s = own.get();
      sp = ownPlain.get();
    }
    auto render = [&](RelightSession* x, RelightMethod m) {
      for (size_t l = 0; l < scale.size(); ++l) x->setLampScale(int(l), scale[l]);
      x->update(progress);
      ImageRGB img = x->render(main.camera, m);
      for (size_t l = 0; l < scale.size(); ++l) x->setLampScale(int(l), glm::dvec3(1.0));
      x->update(progress);
      return img;
    };
    const ImageRGB full = render(s, RelightMethod::Full);
    const ImageRGB ratio = render(s, RelightMethod::RatioOnly);
    const ImageRGB fullI = render(sp, RelightMethod::Full);
    const ImageRGB ratioI = render(sp, RelightMethod::RatioOnly);
    writeImage(dir(v.name + ".full.exr"), full);
    writeImage(dir(v.name + ".ratio-only.exr"), ratio);
    writeImage(dir(v.name + ".png"), sideBySide({&photo, &ratio, &full, &truth}), exposure);
    const QJsonObject f = scores(full, truth), r = scores(ratio, truth), u = scores(photo, truth),
                      fi = scores(fullI, truth), ri = scores(ratioI, truth);
    variants.append(QJsonObject{{"name", QString::fromStdString(v.name)},
                                {"full", f},
                                {"ratio_only", r},
                                {"interactive_mesh", QJsonObject{{"full", fi}, {"ratio_only", ri}}},
                                {"photo_unchanged", u}});
    auto pr = [](const QJsonObject& o) { return std::make_pair(o["psnr_all"].toDouble(), o["psnr_shadow"].toDouble()); };
    std::fprintf(stderr,
                 "%-18s full %5.2f/%5.2f  ratio-only %5.2f/%5.2f | interactive mesh: full %5.2f/%5.2f  ratio-only %5.2f/%5.2f "
                 "| photo %5.2f/%5.2f dB (all/shadow)\n",
                 v.name.c_str(), pr(f).first, pr(f).second, pr(r).first, pr(r).second, pr(fi).first, pr(fi).second,
                 pr(ri).first, pr(ri).second, pr(u).first, pr(u).second);
  }
  report["variants"] = variants;
  QSaveFile f(QDir(outDir).filePath("report.json"));
  if (!f.open(QIODevice::WriteOnly) || f.write(QJsonDocument(report).toJson()) < 0 || !f.commit())
    throw Error(dir("report.json"), "", "cannot write");
  std::fprintf(stderr, "wrote %s\n", dir("report.json").c_str());
  return 0;
}

}  // namespace relume::cli
