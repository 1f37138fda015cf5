#include "relume/project/relight_store.h"

#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <QSaveFile>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "relume/geometry/error.h"
#include "relume/image/image.h"
#include "relume/project/room_io.h"
#include "relume/project/save_hooks.h"

namespace relume {

namespace {

QJsonArray vec(const glm::dvec3& v) { return {v.x, v.y, v.z}; }
QJsonArray vec(const glm::dvec2& v) { return {v.x, v.y}; }
QJsonArray names(const std::vector<std::string>& v) {
  QJsonArray a;
  for (const auto& n : v) a.append(QString::fromStdString(n));
  return a;
}

std::string texName(size_t i, const char* layer) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "relight/tex_%03zu.%s.exr", i, layer);
  return buf;
}

ImageRGB layerImage(const PolygonTexture& t, const std::vector<glm::vec3>& layer) {
  ImageRGB img(t.width, t.height);
  for (int y = 0; y < t.height; ++y)
    for (int x = 0; x < t.width; ++x) img.set(x, y, layer[t.index(x, y)]);
  return img;
}

QJsonObject optionsJson(const RelightOptions& o) {
  return {{"mean_reflectance", o.meanReflectance},
          {"colour_threshold", o.colourThreshold},
          {"visibility_threshold", o.visibilityThreshold},
          {"blocked_indirect", o.blockedIndirect},
          {"lamp_least_squares", o.lampLeastSquares},
          {"lamps_from_photo", o.lampsFromPhoto},
          {"inverse_global_illumination", o.inverseGlobalIllumination},
          {"shared_materials", o.sharedMaterials},
          {"calibrated_photos", o.calibratedPhotos},
          {"reference_correction", o.reference == RelightOptions::Reference::Off        ? "off"
                                   : o.reference == RelightOptions::Reference::Paper    ? "paper"
                                   : o.reference == RelightOptions::Reference::Weighted ? "weighted"
                                                                                        : "chosen"},
          {"texture_refine_levels", o.textureRefineLevels},
          {"texture_min_area", o.textureMinArea},
          {"occluded_fraction", o.occludedFraction},
          {"epsilon", o.engine.epsilon},
          {"interactive_epsilon", o.interactiveEpsilon},
          {"min_area", o.engine.minArea},
          {"oracle", o.engine.oracle == radiosity::Oracle::BF ? "bf" : "bfv"},
          {"visibility_rays", o.engine.visibilityRays}};
}

}  // namespace

QJsonArray referenceRegionsJson(const std::vector<ReferenceRegion>& regions) {
  QJsonArray out;
  for (const auto& r : regions) {
    QJsonArray discs;
    for (const auto& d : r.discs) discs.append(vec(d));
    out.append(QJsonObject{{"polygon", QString::fromStdString(r.polygon)}, {"reference", vec(r.reference)}, {"discs", discs}});
  }
  return out;
}

bool hasRelightData(const std::string& folder) {
  return QFileInfo::exists(QDir(QString::fromStdString(folder)).filePath("relight/relight.json"));
}

void saveRelightProject(const Scene& sceneIn, const RelightData& data, const std::string& folder, Progress& progress,
                        const std::function<void(const std::string&)>& extra) {
  Scene scene = sceneIn;
  // The project carries what was estimated, never what the room came with.
  for (size_t i = 0; i < scene.polygons.size(); ++i) {
    const auto& t = data.textures[i];
    scene.polygons[i].albedo = t.albedo.empty() ? glm::dvec3(0.0) : glm::dvec3(t.mean(t.albedo, t.origin, t.uvOf(t.width, t.height)));
  }
  for (size_t l = 0; l < scene.lamps.size(); ++l) scene.lamps[l].radiance = data.lampExitance[l] / std::numbers::pi;
  saveProject(scene, folder, progress, [&](const std::string& staging) {
    const QDir dir(QString::fromStdString(staging));
    if (!dir.mkpath("relight")) throw Error(folder, "relight", "cannot create the folder");
    detail::saveStep("relight folder created");
    auto write = [&](const std::string& file, const ImageRGB& image) {
      writeImage(staging + "/" + file, image);
      detail::saveStep("texture written");
    };
    QJsonArray texs;
    for (size_t i = 0; i < data.textures.size(); ++i) {
      progress.report(double(i) / data.textures.size(), "writing textures of " + scene.polygons[i].name);
      const auto& t = data.textures[i];
      std::vector<glm::vec3> src(t.source.size());
      for (size_t k = 0; k < src.size(); ++k) src[k] = glm::vec3(float(t.source[k]));
      write(texName(i, "orig"), layerImage(t, t.original));
      write(texName(i, "final"), layerImage(t, t.unoccluded.empty() ? t.original : t.unoccluded));
      write(texName(i, "albedo"), layerImage(t, t.albedo.empty() ? std::vector<glm::vec3>(src.size()) : t.albedo));
      write(texName(i, "source"), layerImage(t, src));
      texs.append(QJsonObject{{"polygon", QString::fromStdString(scene.polygons[i].name)},
                              {"origin", vec(t.origin)},
                              {"texel", t.texel},
                              {"width", t.width},
                              {"height", t.height}});
    }
    if (data.glow.width > 0) {
      write("relight/glow.exr", data.glow);
      ImageRGB which(data.glow.width, data.glow.height);
      for (size_t k = 0; k < data.glowLamp.size(); ++k)
        which.set(int(k % which.width), int(k / which.width), glm::vec3(float(data.glowLamp[k] + 1)));
      write("relight/glow_lamp.exr", which);
    }
    const auto& e = data.estimates;
    QJsonArray lamps;
    for (const auto& l : e.lamps)
      lamps.append(QJsonObject{{"name", QString::fromStdString(l.name)},
                               {"exitance_equal", vec(l.equal)},
                               {"exitance_least_squares", vec(l.leastSquares)},
                               {"exitance_photographed", vec(l.photographed)},
                               {"exitance_used", vec(l.used)},
                               {"exitance_joint_fit", vec(l.jointFit)},
                               {"uncertainty", l.uncertainty},
                               {"two_sided", l.twoSided}});
    QJsonObject refs, overrides;
    for (const auto& [k, v] : data.referencePatch) refs[QString::fromStdString(k)] = vec(v);
    for (const auto& [k, v] : data.referenceOverride) overrides[QString::fromStdString(k)] = vec(v);

    QJsonObject root{{"format", "relume-relight"},
                     {"version", 1},
                     {"photo", QString::fromStdString(data.photo)},
                     {"photo_exposure", data.photoExposure},
                     {"colour_scale", data.colourScale},
                     {"options", optionsJson(data.options)},
                     {"estimates",
                      QJsonObject{{"mean_reflectance_given", e.meanReflectanceGiven},
                                  {"mean_reflectance_refined", e.meanReflectanceRefined},
                                  {"eq2_scale", e.eq2Scale},
                                  {"mean_reflectance_recovered", e.meanReflectanceRecovered},
                                  {"joint_fit_elements", double(e.jointFitElements)},
                                  {"indirect_measured_share", e.indirectMeasuredShare},
                                  {"reflectance_rounds", e.reflectanceRounds},
                                  {"unseen_by_material", names(e.unseenByMaterial)},
                                  {"unseen_without_material", names(e.unseenWithoutMaterial)},
                                  {"lamp_model", QString::fromStdString(e.lampModel)},
                                  {"lamp_model_reason", QString::fromStdString(e.lampModelReason)},
                                  {"lamps", lamps},
                                  {"leaves_before_texture_refinement", double(e.leavesBeforeTextureRefinement)},
                                  {"leaves_after_texture_refinement", double(e.leavesAfter)},
                                  {"texture_subdivisions", double(e.texturesSubdivided)},
                                  {"texture_subdivisions_cancelled", double(e.subdivisionsCancelled)},
                                  {"occluded_elements", double(e.occludedLeaves)},
                                  {"frontier_elements", double(e.frontierLeaves)},
                                  {"referenced_by_frontier", double(e.referencedByFrontier)},
                                  {"referenced_by_default", double(e.referencedByDefault)},
                                  {"referenced_by_region", double(e.referencedByRegion)},
                                  {"seconds", e.seconds}}},
                     {"reference_patches", refs},
                     {"reference_overrides", overrides},
                     {"reference_regions", referenceRegionsJson(data.referenceRegions)},
                     {"textures", texs}};
    QSaveFile f(dir.filePath("relight/relight.json"));
    if (!f.open(QIODevice::WriteOnly) || f.write(QJsonDocument(root).toJson()) < 0 || !f.commit())
      throw Error(folder, "relight/relight.json", "cannot write: " + f.errorString().toStdString());
    detail::saveStep("relight.json written");
    if (extra) extra(staging);
  });
}

RelightData readRelightData(const Scene& scene) {
  const QDir dir(QString::fromStdString(scene.baseDir));
  const std::string path = fileInFolder(scene.baseDir, "relight/relight.json", scene.baseDir, "");
  QFile f(QString::fromStdString(path));
  if (!f.exists()) throw Error(scene.baseDir, "", "the project has not been preprocessed (run relume preprocess)");
  if (!f.open(QIODevice::ReadOnly)) throw Error(path, "", "cannot open: " + f.errorString().toStdString());
  const QByteArray bytes = f.readAll();
  RelightData d = parseRelightJson(std::string(bytes.constData(), size_t(bytes.size())), scene, path);
  for (size_t i = 0; i < d.textures.size(); ++i) {
    PolygonTexture& t = d.textures[i];
    auto load = [&](const char* layer) {
      const std::string file = fileInFolder(scene.baseDir, texName(i, layer), path, "textures");
      const ImageRGB img = readImageLinear(file);
      if (img.width != t.width || img.height != t.height) throw Error(file, "", "has the wrong size for its texture grid");
      std::vector<glm::vec3> out(size_t(t.width) * t.height);
      for (int y = 0; y < t.height; ++y)
        for (int x = 0; x < t.width; ++x) out[t.index(x, y)] = img.at(x, y);
      return out;
    };
    t.original = load("orig");
    t.unoccluded = load("final");
    t.albedo = load("albedo");
    const auto src = load("source");
    t.source.resize(src.size());
    for (size_t k = 0; k < src.size(); ++k) t.source[k] = TexelSource(std::clamp(int(std::lround(src[k].x)), 0, 5));
  }
  if (QFileInfo::exists(dir.filePath("relight/glow.exr"))) {
    d.glow = readImageLinear(fileInFolder(scene.baseDir, "relight/glow.exr", path, "glow"));
    const ImageRGB which = readImageLinear(fileInFolder(scene.baseDir, "relight/glow_lamp.exr", path, "glow"));
    if (which.width != d.glow.width || which.height != d.glow.height)
      throw Error(dir.filePath("relight/glow_lamp.exr").toStdString(), "", "does not match glow.exr in size");
    d.glowLamp.resize(size_t(which.width) * which.height);
    for (size_t k = 0; k < d.glowLamp.size(); ++k) {
      const int l = int(std::lround(which.at(int(k % which.width), int(k / which.width)).x)) - 1;
      d.glowLamp[k] = l >= 0 && size_t(l) < scene.lamps.size() ? l : -1;
    }
  }
  return d;
}

}  // namespace relume
