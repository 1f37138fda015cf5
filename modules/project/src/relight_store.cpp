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

namespace relume {

namespace {

QJsonArray vec(const glm::dvec3& v) { return {v.x, v.y, v.z}; }
QJsonArray vec(const glm::dvec2& v) { return {v.x, v.y}; }

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
          {"reference_correction", o.reference == RelightOptions::Reference::Off     ? "off"
                                   : o.reference == RelightOptions::Reference::Paper ? "paper"
                                                                                     : "weighted"},
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

std::vector<ReferenceRegion> referenceRegionsFromJson(const QJsonArray& a, const std::string& file) {
  std::vector<ReferenceRegion> out;
  auto numbers = [&](const QJsonValue& v, int n, const char* what) {
    const QJsonArray x = v.toArray();
    std::vector<double> r;
    for (const auto& e : x)
      if (e.isDouble() && std::isfinite(e.toDouble())) r.push_back(e.toDouble());
    if (int(r.size()) != n || x.size() != n)
      throw Error(file, "reference_regions", std::string(what) + " must be " + std::to_string(n) + " finite numbers");
    return r;
  };
  for (const auto& v : a) {
    const QJsonObject o = v.toObject();
    ReferenceRegion r;
    r.polygon = o["polygon"].toString().toStdString();
    if (r.polygon.empty()) throw Error(file, "reference_regions", "a region names no polygon");
    const auto ref = numbers(o["reference"], 2, "a reference");
    r.reference = {ref[0], ref[1]};
    for (const auto& d : o["discs"].toArray()) {
      const auto x = numbers(d, 3, "a disc (u, v, radius)");
      if (x[2] <= 0) throw Error(file, "reference_regions", "a disc's radius must be positive");
      r.discs.emplace_back(x[0], x[1], x[2]);
    }
    if (r.discs.empty()) throw Error(file, "reference_regions", "the region on '" + r.polygon + "' has no disc");
    out.push_back(std::move(r));
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
    QJsonArray texs;
    for (size_t i = 0; i < data.textures.size(); ++i) {
      progress.report(double(i) / data.textures.size(), "writing textures of " + scene.polygons[i].name);
      const auto& t = data.textures[i];
      std::vector<glm::vec3> src(t.source.size());
      for (size_t k = 0; k < src.size(); ++k) src[k] = glm::vec3(float(t.source[k]));
      writeImage(staging + "/" + texName(i, "orig"), layerImage(t, t.original));
      writeImage(staging + "/" + texName(i, "final"), layerImage(t, t.unoccluded.empty() ? t.original : t.unoccluded));
      writeImage(staging + "/" + texName(i, "albedo"), layerImage(t, t.albedo.empty() ? std::vector<glm::vec3>(src.size()) : t.albedo));
      writeImage(staging + "/" + texName(i, "source"), layerImage(t, src));
      texs.append(QJsonObject{{"polygon", QString::fromStdString(scene.polygons[i].name)},
                              {"origin", vec(t.origin)},
                              {"texel", t.texel},
                              {"width", t.width},
                              {"height", t.height}});
    }
    if (data.glow.width > 0) {
      writeImage(staging + "/relight/glow.exr", data.glow);
      ImageRGB which(data.glow.width, data.glow.height);
      for (size_t k = 0; k < data.glowLamp.size(); ++k)
        which.set(int(k % which.width), int(k / which.width), glm::vec3(float(data.glowLamp[k] + 1)));
      writeImage(staging + "/relight/glow_lamp.exr", which);
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
    if (extra) extra(staging);
  });
}

RelightData readRelightData(const Scene& scene) {
  const QDir dir(QString::fromStdString(scene.baseDir));
  const std::string path = dir.filePath("relight/relight.json").toStdString();
  QFile f(QString::fromStdString(path));
  if (!f.exists()) throw Error(scene.baseDir, "", "the project has not been preprocessed (run relume preprocess)");
  if (!f.open(QIODevice::ReadOnly)) throw Error(path, "", "cannot open: " + f.errorString().toStdString());
  QJsonParseError err{};
  const QJsonDocument doc = QJsonDocument::fromJson(f.readAll(), &err);
  if (!doc.isObject()) throw Error(path, "", "is not valid JSON: " + err.errorString().toStdString());
  const QJsonObject root = doc.object();
  if (root["format"].toString() != "relume-relight") throw Error(path, "format", "is not 'relume-relight'");
  auto v3 = [&](const QJsonValue& v) {
    const QJsonArray a = v.toArray();
    if (a.size() != 3) throw Error(path, "", "a colour must have 3 numbers");
    return glm::dvec3(a[0].toDouble(), a[1].toDouble(), a[2].toDouble());
  };
  auto v2 = [&](const QJsonValue& v) {
    const QJsonArray a = v.toArray();
    if (a.size() != 2) throw Error(path, "", "a texture coordinate must have 2 numbers");
    return glm::dvec2(a[0].toDouble(), a[1].toDouble());
  };
  RelightData d;
  d.photo = root["photo"].toString().toStdString();
  d.photoExposure = root["photo_exposure"].toDouble(1.0);
  d.colourScale = root["colour_scale"].toDouble(1.0);
  const QJsonObject o = root["options"].toObject();
  auto& op = d.options;
  op.meanReflectance = o["mean_reflectance"].toDouble(op.meanReflectance);
  op.colourThreshold = o["colour_threshold"].toDouble(op.colourThreshold);
  op.visibilityThreshold = o["visibility_threshold"].toDouble(op.visibilityThreshold);
  op.blockedIndirect = o["blocked_indirect"].toBool(op.blockedIndirect);
  op.lampLeastSquares = o["lamp_least_squares"].toBool(op.lampLeastSquares);
  op.lampsFromPhoto = o["lamps_from_photo"].toBool(op.lampsFromPhoto);
  op.inverseGlobalIllumination = o["inverse_global_illumination"].toBool(op.inverseGlobalIllumination);
  op.sharedMaterials = o["shared_materials"].toBool(op.sharedMaterials);
  {
    const QString r = o["reference_correction"].toString("weighted");
    op.reference = r == "off" ? RelightOptions::Reference::Off
                   : r == "paper" ? RelightOptions::Reference::Paper
                                  : RelightOptions::Reference::Weighted;
  }
  op.textureRefineLevels = o["texture_refine_levels"].toInt(op.textureRefineLevels);
  op.textureMinArea = o["texture_min_area"].toDouble(op.textureMinArea);
  op.occludedFraction = o["occluded_fraction"].toDouble(op.occludedFraction);
  op.engine.epsilon = o["epsilon"].toDouble(op.engine.epsilon);
  op.interactiveEpsilon = o["interactive_epsilon"].toDouble(op.interactiveEpsilon);
  op.engine.minArea = o["min_area"].toDouble(op.engine.minArea);
  op.engine.oracle = o["oracle"].toString() == "bfv" ? radiosity::Oracle::BFV : radiosity::Oracle::BF;
  op.engine.visibilityRays = o["visibility_rays"].toInt(op.engine.visibilityRays);
  const QJsonObject est = root["estimates"].toObject();
  d.estimates.meanReflectanceGiven = est["mean_reflectance_given"].toDouble();
  d.estimates.meanReflectanceRefined = est["mean_reflectance_refined"].toDouble();
  d.estimates.eq2Scale = est["eq2_scale"].toDouble(1.0);
  d.estimates.meanReflectanceRecovered = est["mean_reflectance_recovered"].toDouble();
  d.estimates.jointFitElements = size_t(est["joint_fit_elements"].toDouble());
  d.estimates.indirectMeasuredShare = est["indirect_measured_share"].toDouble();
  d.estimates.lampModel = est["lamp_model"].toString().toStdString();
  for (const auto& lv : est["lamps"].toArray()) {
    const QJsonObject lo = lv.toObject();
    d.estimates.lamps.push_back({lo["name"].toString().toStdString(), v3(lo["exitance_equal"]),
                                 v3(lo["exitance_least_squares"]), v3(lo["exitance_photographed"]), v3(lo["exitance_used"]),
                                 v3(lo["exitance_joint_fit"]), lo["uncertainty"].toDouble(), lo["two_sided"].toBool()});
  }
  for (const auto& l : scene.lamps) {
    bool found = false;
    for (const auto& e : d.estimates.lamps)
      if (e.name == l.name) {
        d.lampExitance.push_back(e.used);
        found = true;
        break;
      }
    if (!found) throw Error(path, "lamp " + l.name, "has no estimate (re-run relume preprocess)");
  }
  const QJsonObject refs = root["reference_patches"].toObject(), overrides = root["reference_overrides"].toObject();
  for (auto it = refs.begin(); it != refs.end(); ++it) d.referencePatch[it.key().toStdString()] = v2(it.value());
  for (auto it = overrides.begin(); it != overrides.end(); ++it) d.referenceOverride[it.key().toStdString()] = v2(it.value());
  d.options.referenceOverride = d.referenceOverride;
  d.referenceRegions = d.options.referenceRegions = referenceRegionsFromJson(root["reference_regions"].toArray(), path);
  const QJsonArray texs = root["textures"].toArray();
  if (size_t(texs.size()) != scene.polygons.size())
    throw Error(path, "textures", "lists " + std::to_string(texs.size()) + " polygons, the project has " +
                                      std::to_string(scene.polygons.size()) + " (re-run relume preprocess)");
  for (size_t i = 0; i < scene.polygons.size(); ++i) {
    const QJsonObject to = texs[int(i)].toObject();
    if (to["polygon"].toString().toStdString() != scene.polygons[i].name)
      throw Error(path, "textures", "polygon " + std::to_string(i) + " is not '" + scene.polygons[i].name + "'");
    PolygonTexture t;
    t.polygon = int(i);
    t.frame = PlaneFrame::of(scene.polygons[i].vertices);
    t.origin = v2(to["origin"]);
    t.texel = to["texel"].toDouble();
    t.width = to["width"].toInt();
    t.height = to["height"].toInt();
    if (!(t.texel > 0) || t.width <= 0 || t.height <= 0)
      throw Error(path, "textures", "polygon '" + scene.polygons[i].name + "' has no valid texture grid");
    auto load = [&](const char* layer) {
      const std::string file = dir.filePath(QString::fromStdString(texName(i, layer))).toStdString();
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
    for (size_t k = 0; k < src.size(); ++k) t.source[k] = TexelSource(std::clamp(int(std::lround(src[k].x)), 0, 3));
    d.textures.push_back(std::move(t));
  }
  if (QFileInfo::exists(dir.filePath("relight/glow.exr"))) {
    d.glow = readImageLinear(dir.filePath("relight/glow.exr").toStdString());
    const ImageRGB which = readImageLinear(dir.filePath("relight/glow_lamp.exr").toStdString());
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
