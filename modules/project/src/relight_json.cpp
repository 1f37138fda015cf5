// relight.json, the relighting data's description in a project (what saveRelightProject in
// relight_store.cpp writes), read from its bytes: no images, so that it can be fuzzed alone.
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <cmath>

#include "relume/geometry/error.h"
#include "relume/geometry/polygon.h"
#include "relume/project/relight_store.h"

namespace relume {

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

RelightData parseRelightJson(const std::string& bytes, const Scene& scene, const std::string& path) {
  QJsonParseError err{};
  const QJsonDocument doc = QJsonDocument::fromJson(QByteArray(bytes.data(), qsizetype(bytes.size())), &err);
  if (!doc.isObject()) throw Error(path, "", "is not valid JSON: " + err.errorString().toStdString());
  const QJsonObject root = doc.object();
  if (root["format"].toString() != "relume-relight") throw Error(path, "format", "is not 'relume-relight'");
  auto numbers = [&](const QJsonValue& v, int n, const char* what) {
    const QJsonArray a = v.toArray();
    bool ok = a.size() == n;
    for (const auto& e : a) ok = ok && e.isDouble() && std::isfinite(e.toDouble());
    if (!ok) throw Error(path, "", std::string(what) + " must be " + std::to_string(n) + " finite numbers");
    return a;
  };
  auto v3 = [&](const QJsonValue& v) {
    const QJsonArray a = numbers(v, 3, "a colour");
    return glm::dvec3(a[0].toDouble(), a[1].toDouble(), a[2].toDouble());
  };
  auto v2 = [&](const QJsonValue& v) {
    const QJsonArray a = numbers(v, 2, "a texture coordinate");
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
  op.calibratedPhotos = o["calibrated_photos"].toBool(op.calibratedPhotos);
  {
    const QString r = o["reference_correction"].toString("chosen");
    op.reference = r == "off"        ? RelightOptions::Reference::Off
                   : r == "paper"    ? RelightOptions::Reference::Paper
                   : r == "weighted" ? RelightOptions::Reference::Weighted
                                     : RelightOptions::Reference::Chosen;
  }
  op.textureRefineLevels = o["texture_refine_levels"].toInt(op.textureRefineLevels);
  op.textureMinArea = o["texture_min_area"].toDouble(op.textureMinArea);
  op.occludedFraction = o["occluded_fraction"].toDouble(op.occludedFraction);
  op.engine.epsilon = o["epsilon"].toDouble(op.engine.epsilon);
  op.interactiveEpsilon = o["interactive_epsilon"].toDouble(op.interactiveEpsilon);
  op.engine.minArea = o["min_area"].toDouble(op.engine.minArea);
  if (o.contains("oracle")) op.engine.oracle = o["oracle"].toString() == "bfv" ? radiosity::Oracle::BFV : radiosity::Oracle::BF;
  op.engine.visibilityRays = o["visibility_rays"].toInt(op.engine.visibilityRays);
  // Options a damaged or hand-edited file could make unusable (a solve that never ends).
  if (!(op.engine.visibilityRays >= 1 && op.engine.visibilityRays <= 4096))
    throw Error(path, "options visibility_rays", "must be from 1 to 4096");
  if (!(op.textureRefineLevels >= 0 && op.textureRefineLevels <= 16))
    throw Error(path, "options texture_refine_levels", "must be from 0 to 16");
  for (const auto& [key, x] : {std::pair<const char*, double>{"epsilon", op.engine.epsilon},
                               {"interactive_epsilon", op.interactiveEpsilon},
                               {"min_area", op.engine.minArea},
                               {"texture_min_area", op.textureMinArea}})
    if (!(x > 0 && x < 1e6)) throw Error(path, std::string("options ") + key, "must be a positive number");
  const QJsonObject est = root["estimates"].toObject();
  d.estimates.meanReflectanceGiven = est["mean_reflectance_given"].toDouble();
  d.estimates.meanReflectanceRefined = est["mean_reflectance_refined"].toDouble();
  d.estimates.eq2Scale = est["eq2_scale"].toDouble(1.0);
  d.estimates.meanReflectanceRecovered = est["mean_reflectance_recovered"].toDouble();
  // A count: a whole number from 0 to 2^53 (missing: 0).
  auto count = [&](const char* key) -> size_t {
    const QJsonValue v = est[key];
    if (v.isUndefined()) return 0;
    const double x = v.toDouble(-1);
    if (!(x >= 0 && x <= 9007199254740992.0) || x != std::floor(x))
      throw Error(path, std::string("estimates ") + key, "must be a whole number from 0 up");
    return size_t(x);
  };
  auto names = [&](const char* key) {
    std::vector<std::string> out;
    for (const auto& v : est[key].toArray()) out.push_back(v.toString().toStdString());
    return out;
  };
  d.estimates.jointFitElements = count("joint_fit_elements");
  d.estimates.indirectMeasuredShare = est["indirect_measured_share"].toDouble();
  d.estimates.reflectanceRounds = est["reflectance_rounds"].toInt();
  d.estimates.lampModel = est["lamp_model"].toString().toStdString();
  d.estimates.lampModelReason = est["lamp_model_reason"].toString().toStdString();
  d.estimates.unseenByMaterial = names("unseen_by_material");
  d.estimates.unseenWithoutMaterial = names("unseen_without_material");
  d.estimates.leavesBeforeTextureRefinement = count("leaves_before_texture_refinement");
  d.estimates.leavesAfter = count("leaves_after_texture_refinement");
  d.estimates.texturesSubdivided = count("texture_subdivisions");
  d.estimates.subdivisionsCancelled = count("texture_subdivisions_cancelled");
  d.estimates.occludedLeaves = count("occluded_elements");
  d.estimates.frontierLeaves = count("frontier_elements");
  d.estimates.referencedByFrontier = count("referenced_by_frontier");
  d.estimates.referencedByDefault = count("referenced_by_default");
  d.estimates.referencedByRegion = count("referenced_by_region");
  d.estimates.seconds = est["seconds"].toDouble();
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
    if (!(t.texel > 0) || !std::isfinite(t.origin.x) || !std::isfinite(t.origin.y) || t.width <= 0 || t.height <= 0 ||
        t.width > kMaxTextureSide || t.height > kMaxTextureSide)
      throw Error(path, "textures", "polygon '" + scene.polygons[i].name + "' has no valid texture grid (1 to " +
                                        std::to_string(kMaxTextureSide) + " texels a side)");
    d.textures.push_back(std::move(t));
  }
  return d;
}

}  // namespace relume
