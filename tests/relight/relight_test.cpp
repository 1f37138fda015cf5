// Relighting on the sample room, judged against its own truth renders (Blender, same camera).
#include <gtest/gtest.h>

#include <QDir>
#include <QTemporaryDir>
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cmath>
#include <glm/geometric.hpp>
#include <map>
#include <memory>
#include <numbers>

#include "relume/geometry/error.h"
#include "relume/geometry/polygon.h"
#include "relume/image/image.h"
#include "relume/project/relight_store.h"
#include "relume/project/room_io.h"
#include "relume/relight/compare.h"
#include "relume/relight/relighter.h"

using namespace relume;

namespace {

const std::string kRoom = std::string(RELUME_SOURCE_DIR) + "/resources/sample_room";

struct SampleRoom {
  Scene scene;
  RelightData data;
  ImageRGB photo, unoccludedTruth, aOffTruth;
  CompareMasks masks;
};

// Preprocessed once for the whole suite (a few seconds), from what a photographer has: photos,
// cameras, geometry and which polygons are lamps — the albedos and lamp strengths are wiped.
// Under ctest, where each test is a process of its own, the room comes preprocessed from the
// fixture sample_room_project (`relume preprocess` of the same bundle, which reads neither the
// albedos nor the lamp strengths; RELUME_TEST_PROJECT names it) and is read back as a user's
// project is; run by hand or under the sanitizers, the binary preprocesses it itself, once.
const SampleRoom& room() {
  static std::unique_ptr<SampleRoom> r = [] {
    auto s = std::make_unique<SampleRoom>();
    const char* fixture = std::getenv("RELUME_TEST_PROJECT");
    if (fixture && *fixture) {
      s->scene = readProject(fixture);
      s->data = readRelightData(s->scene);
    } else {
      s->scene = readBundle(kRoom);
      for (auto& p : s->scene.polygons) p.albedo = glm::dvec3(0.5);
      for (auto& l : s->scene.lamps) l.radiance = glm::dvec3(0.0);
      s->data = preprocessRoom(s->scene, RelightOptions{});
    }
    s->photo = readImageLinear(kRoom + "/photos/main.exr");
    s->unoccludedTruth = readImageLinear(kRoom + "/truth/unoccluded.exr");
    s->aOffTruth = readImageLinear(kRoom + "/truth/A_off.exr");
    s->masks = benchmarkMasks(s->photo, s->unoccludedTruth);
    return s;
  }();
  return *r;
}

const Camera& mainCamera() { return room().scene.findPhoto("main")->camera; }

double shadowPsnr(const ImageRGB& img, const ImageRGB& truth) { return compareImages(img, truth, room().masks.shadow).psnr; }

// The claim "lamp A's old shadow is gone": over the shadow regions the relit image matches the
// truth render with A off to 30 dB, and beats leaving the photo as it was by 10 dB.
::testing::AssertionResult oldShadowGone(const ImageRGB& img) {
  const double p = shadowPsnr(img, room().aOffTruth), unchanged = shadowPsnr(room().photo, room().aOffTruth);
  if (p >= 30.0 && p >= unchanged + 10.0) return ::testing::AssertionSuccess() << p << " dB";
  return ::testing::AssertionFailure() << "shadow-mask PSNR " << p << " dB (photo unchanged: " << unchanged << " dB)";
}

}  // namespace

TEST(Relight, EstimatesLampsNearTheirTrueEmittance) {
  // scene.json's true radiances (exitance = pi x radiance) are read here only to judge. Lamps the
  // photo does not show are estimated from how they light the room: within 40 %, not better.
  const Scene truth = readBundle(kRoom);
  for (size_t l = 0; l < truth.lamps.size(); ++l) {
    const double trueGrey = M_PI * (truth.lamps[l].radiance.x + truth.lamps[l].radiance.y + truth.lamps[l].radiance.z) / 3;
    const auto& u = room().data.lampExitance[l];
    EXPECT_NEAR((u.x + u.y + u.z) / 3, trueGrey, 0.4 * trueGrey) << truth.lamps[l].name;
  }
}

TEST(Relight, OriginalLightingReprojectsThePhoto) {
  RelightSession s(room().scene, room().data);
  const ImageRGB img = s.render(mainCamera(), RelightMethod::Full);
  EXPECT_GE(compareImages(img, room().photo, room().masks.all).psnr, 35.0);
}

TEST(Relight, UnoccludedImageHasTheRealShadowsRemoved) {
  RelightSession s(room().scene, room().data);
  const ImageRGB img = s.renderUnoccluded(mainCamera());
  const double p = shadowPsnr(img, room().unoccludedTruth), unchanged = shadowPsnr(room().photo, room().unoccludedTruth);
  EXPECT_GE(p, 28.0);
  EXPECT_GE(p, unchanged + 8.0);
}

TEST(Relight, LampOffRemovesItsOldShadow) {
  RelightSession s(room().scene, room().data);
  s.setLampScale(room().scene.findLamp("A"), glm::dvec3(0.0));
  s.update();
  EXPECT_TRUE(oldShadowGone(s.render(mainCamera(), RelightMethod::Full)));
}

TEST(Relight, TheShadowTestFailsOnAnImageThatKeepsTheOldShadow) {
  // The photo itself keeps lamp A's shadow (and A's light): the criterion must reject it.
  EXPECT_FALSE(oldShadowGone(room().photo));
}

TEST(Relight, VirtualBoxCastsItsShadowWhereGeometrySays) {
  const glm::dvec3 lo(0.7, 1.5, 0.0), hi(1.1, 1.9, 0.35);
  RelightSession before(room().scene, room().data);
  RelightSession after(room().scene, room().data, {}, {boxObject("box", lo, hi, glm::dvec3(0.6, 0.2, 0.2))});
  const ImageRGB a = before.render(mainCamera(), RelightMethod::Full), b = after.render(mainCamera(), RelightMethod::Full);
  // Floor points classified by geometry alone: hidden from every lamp's centre by the box, or
  // seen by all of them and far from the box.
  auto blockedBy = [&](const glm::dvec3& p, const glm::dvec3& q) {  // segment p-q against the box (slabs)
    double t0 = 0, t1 = 1;
    for (int k = 0; k < 3; ++k) {
      const double d = q[k] - p[k];
      if (std::abs(d) < 1e-12) {
        if (p[k] < lo[k] || p[k] > hi[k]) return false;
        continue;
      }
      double ta = (lo[k] - p[k]) / d, tb = (hi[k] - p[k]) / d;
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    }
    return t0 <= t1;
  };
  std::vector<glm::dvec3> lampCentres;
  for (const auto& l : room().scene.lamps) {
    glm::dvec3 c(0.0);
    for (const auto& v : room().scene.polygons[l.polygon].vertices) c += v;
    lampCentres.push_back(c / double(room().scene.polygons[l.polygon].vertices.size()));
  }
  double umbraRatio = 0, litRatio = 0;
  int nUmbra = 0, nLit = 0;
  for (double x = 0.2; x < 3.8; x += 0.05)
    for (double y = 0.8; y < 4.8; y += 0.05) {
      const glm::dvec3 p(x, y, 0.0);
      if (x > lo.x - 0.02 && x < hi.x + 0.02 && y > lo.y - 0.02 && y < hi.y + 0.02) continue;
      glm::dvec2 px;
      if (!mainCamera().project(p, px) || px.x < 1 || px.y < 1 || px.x >= a.width - 1 || px.y >= a.height - 1) continue;
      int blocked = 0;
      for (const auto& c : lampCentres) blocked += blockedBy(p, c);
      const glm::vec3 ca = a.at(int(px.x), int(px.y)), cb = b.at(int(px.x), int(px.y));
      const double la = ca.x + ca.y + ca.z, lb = cb.x + cb.y + cb.z;
      if (la <= 0) continue;
      const double dist = glm::length(glm::dvec2(x, y) - glm::dvec2(0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y)));
      if (blocked == int(lampCentres.size())) {
        umbraRatio += lb / la;
        ++nUmbra;
      } else if (blocked == 0 && dist > 1.5) {
        litRatio += lb / la;
        ++nLit;
      }
    }
  ASSERT_GT(nUmbra, 0) << "the box should hide some visible floor from every lamp";
  ASSERT_GT(nLit, 20);
  EXPECT_LT(umbraRatio / nUmbra, 0.6) << "floor in the box's umbra should lose most of its light";
  EXPECT_NEAR(litRatio / nLit, 1.0, 0.03) << "floor far from the box should not change";
  // The box itself is shaded by the solution, not black.
  glm::dvec2 c;
  ASSERT_TRUE(mainCamera().project(glm::dvec3(0.9, 1.5, 0.2), c));
  const glm::vec3 face = b.at(int(c.x), int(c.y));
  EXPECT_GT(face.x, 0.05f * (a.at(int(c.x), int(c.y)).x));
  EXPECT_GT(face.x, face.z) << "the box's red albedo shows";
}

TEST(Relight, VirtualLampBrightensWhatItFaces) {
  VirtualLamp v{"spot", {{1.8, 2.5, 1.6}, {1.8, 2.8, 1.6}, {2.1, 2.8, 1.6}, {2.1, 2.5, 1.6}}, glm::dvec3(0.0)};
  // One-sided: the polygon faces down when its vertices turn clockwise seen from above.
  v.polygon = {{1.8, 2.5, 1.6}, {2.1, 2.5, 1.6}, {2.1, 2.8, 1.6}, {1.8, 2.8, 1.6}};
  std::reverse(v.polygon.begin(), v.polygon.end());
  v.radiance = glm::dvec3(20.0);
  RelightSession s(room().scene, room().data, {v});
  const ImageRGB lit = s.render(mainCamera(), RelightMethod::Full);
  s.setVirtualLampRadiance(0, glm::dvec3(0.0));
  s.update();
  const ImageRGB off = s.render(mainCamera(), RelightMethod::Full);
  glm::dvec2 px;
  ASSERT_TRUE(mainCamera().project(glm::dvec3(1.95, 2.65, 0.74), px));  // the table top below it
  EXPECT_GT(lit.at(int(px.x), int(px.y)).y, 1.3f * off.at(int(px.x), int(px.y)).y);
}

TEST(Relight, AVirtualLampWithANarrowBeamLightsWhereItsDistributionSays) {
  // The same 30 cm lamp 0.86 m above the table, as a Lambertian face and with a photometric
  // distribution I ~ cos^20 gamma of the same power: straight below, the beam gives (20 + 1) / 2
  // times the Lambertian face's direct light; 75 degrees off its axis, next to nothing.
  VirtualLamp v{"spot", {{1.8, 2.5, 1.6}, {1.8, 2.8, 1.6}, {2.1, 2.8, 1.6}, {2.1, 2.5, 1.6}}, glm::dvec3(20.0)};  // facing down
  auto beam = std::make_shared<PhotometricDistribution>();
  beam->c = {0.0};
  for (double g = 0; g <= 90.0; g += 2.5) {
    beam->gamma.push_back(g);
    beam->candela.push_back(std::pow(std::cos(g * M_PI / 180), 20));
  }
  VirtualLamp spot = v;
  spot.photometry = beam;
  glm::dvec2 table, wall;
  ASSERT_TRUE(mainCamera().project(glm::dvec3(1.95, 2.65, 0.74), table));
  ASSERT_TRUE(mainCamera().project(glm::dvec3(3.3, 5.2, 0.8), wall));  // the back wall, low
  auto increase = [&](const VirtualLamp& lamp, const glm::dvec2& px) {
    RelightSession s(room().scene, room().data, {lamp});
    const float lit = s.render(mainCamera(), RelightMethod::Full).at(int(px.x), int(px.y)).y;
    s.setVirtualLampRadiance(0, glm::dvec3(0.0));
    s.update();
    return lit - s.render(mainCamera(), RelightMethod::Full).at(int(px.x), int(px.y)).y;
  };
  EXPECT_GT(increase(spot, table), 4.0 * increase(v, table));
  EXPECT_LT(increase(spot, wall), 0.5 * increase(v, wall));
}

TEST(Relight, ProjectRoundTripRelightsTheSame) {
  QTemporaryDir dir;
  const std::string folder = dir.filePath("p").toStdString();
  saveRelightProject(room().scene, room().data, folder);
  const Scene project = readProject(folder);
  const RelightData back = readRelightData(project);
  RelightSession a(room().scene, room().data), b(project, back);
  for (auto* s : {&a, &b}) {
    s->setLampScale(0, glm::dvec3(0.0));
    s->update();
  }
  const ImageRGB ia = a.render(mainCamera(), RelightMethod::Full), ib = b.render(mainCamera(), RelightMethod::Full);
  EXPECT_GE(compareImages(ib, ia, std::vector<uint8_t>(room().masks.all.size(), 1)).psnr, 45.0);
  // The project holds estimates, not the bundle's values.
  const Scene truth = readBundle(kRoom);
  EXPECT_NE(project.lamps[0].radiance, truth.lamps[0].radiance);
}

TEST(Relight, BadInputIsRefusedWithAClearError) {
  const Scene& scene = room().scene;
  auto message = [](auto&& fn) {
    try {
      fn();
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  // A box through the left wall.
  EXPECT_NE(message([&] { checkVirtualObject(scene, boxObject("crate", {-0.2, 1.0, 0.0}, {0.3, 1.4, 0.4}, glm::dvec3(0.5))); })
                .find("intersects polygon 'wall_left'"),
            std::string::npos);
  EXPECT_NE(message([&] { checkVirtualObject(scene, boxObject("crate", {1.0, 1.0, 0.0}, {1.3, 1.4, 0.4}, glm::dvec3(1.5))); })
                .find("albedo"),
            std::string::npos);
  // Two virtual objects through each other: refused naming both. One standing on the other, or
  // beside it touching, is where a user puts things.
  {
    const VirtualObject table = boxObject("table", {1.0, 1.0, 0.0}, {1.6, 1.6, 0.7}, glm::dvec3(0.5));
    const VirtualObject through = boxObject("vase", {1.2, 1.2, 0.5}, {1.4, 1.4, 0.9}, glm::dvec3(0.5));
    const VirtualObject on = boxObject("vase", {1.2, 1.2, 0.7}, {1.4, 1.4, 0.9}, glm::dvec3(0.5));
    const VirtualObject beside = boxObject("crate", {1.6, 1.0, 0.0}, {1.9, 1.3, 0.3}, glm::dvec3(0.5));
    const std::string refused = message([&] { checkVirtualObjectsApart(scene, through, {&table}); });
    EXPECT_NE(refused.find("virtual object 'vase'"), std::string::npos) << refused;
    EXPECT_NE(refused.find("intersects virtual object 'table'"), std::string::npos) << refused;
    EXPECT_EQ(message([&] { checkVirtualObjectsApart(scene, on, {&table, &beside}); }), "no error");
    EXPECT_EQ(message([&] { checkVirtualObjectsApart(scene, beside, {&table, &on}); }), "no error");
    // A live session refuses adding the vase through the table, and keeps what it had.
    RelightSession s(scene, room().data, {}, {table});
    EXPECT_NE(message([&] { s.addObject(through); }).find("intersects virtual object 'table'"), std::string::npos);
    EXPECT_EQ(s.objectCount(), 1u);
  }
  // A camera that sees none of the polygons (turned to look away, out of the room).
  Scene away = scene;
  for (auto& ph : away.photos) ph.camera.t = glm::dvec3(0, 0, -50);
  EXPECT_NE(message([&] { preprocessRoom(away, RelightOptions{}); }).find("sees none of the polygons"), std::string::npos);
  Scene noPhotos = scene;
  noPhotos.photos.clear();
  EXPECT_NE(message([&] { preprocessRoom(noPhotos, RelightOptions{}); }).find("no photo"), std::string::npos);
  Scene noLamps = scene;
  noLamps.lamps.clear();
  EXPECT_NE(message([&] { preprocessRoom(noLamps, RelightOptions{}); }).find("no lamp"), std::string::npos);
}

TEST(Relight, MovingAVirtualBoxUpdatesOnlyTheLinksItCrossesAndMatchesAFreshSolution) {
  const glm::dvec3 lo(0.7, 1.5, 0.0), hi(1.1, 1.9, 0.35), step(0.6, 0.3, 0.0);
  RelightSession moving(room().scene, room().data, {}, {boxObject("box", lo, hi, glm::dvec3(0.6, 0.2, 0.2))});
  const size_t updated = moving.moveObject(0, step);
  EXPECT_GT(updated, 0u);
  EXPECT_LT(updated, moving.engine().links().size() / 2) << "passive links are kept";
  RelightSession fresh(room().scene, room().data, {}, {boxObject("box", lo + step, hi + step, glm::dvec3(0.6, 0.2, 0.2))});
  const ImageRGB a = moving.render(mainCamera(), RelightMethod::Full), b = fresh.render(mainCamera(), RelightMethod::Full);
  const ImageRGB before = RelightSession(room().scene, room().data, {}, {boxObject("box", lo, hi, glm::dvec3(0.6, 0.2, 0.2))})
                              .render(mainCamera(), RelightMethod::Full);
  const std::vector<uint8_t> all(room().masks.all.size(), 1);
  const double moved = compareImages(a, b, all).psnr, stale = compareImages(before, b, all).psnr;
  EXPECT_GE(moved, 35.0);
  EXPECT_GE(moved, stale + 5.0) << "the moved box's image must match its new place, not its old one";
  // Into the wall: refused, and the box stays where it was.
  EXPECT_THROW(moving.moveObject(0, glm::dvec3(-2.0, 0, 0)), Error);
}

// The user's §4.3 choices: a polygon's default reference patch, and a region painted over the
// table's shadow on the floor whose occluded elements all take the reflectance of one chosen
// element. Both travel with the project; bad ones are refused with the polygon named.
TEST(Relight, TheUserPicksReferencePatchesAndPaintsRegionsAndTheProjectKeepsThem) {
  RelightOptions o;
  const int floorIndex = room().scene.findPolygon("floor");
  const PlaneFrame f = PlaneFrame::of(room().scene.polygons[floorIndex].vertices);
  const glm::dvec2 uv = f.toUV(glm::dvec3(3.5, 1.0, 0.0));
  o.referenceOverride["floor"] = uv;
  const glm::dvec2 shadow = f.toUV(glm::dvec3(1.8, 2.7, 0.0)), lit = f.toUV(glm::dvec3(0.6, 1.2, 0.0));
  o.referenceRegions.push_back({"floor", {glm::dvec3(shadow, 0.3)}, lit});
  const RelightData d = preprocessRoom(room().scene, o);
  ASSERT_EQ(d.referenceOverride.count("floor"), 1u);
  ASSERT_EQ(d.referenceRegions.size(), 1u);
  EXPECT_GT(d.estimates.referencedByRegion, 20u) << "the table's shadow has occluded elements";
  // Reflectance (the albedo texture) inside the region against the chosen element's.
  auto meanAlbedo = [&](const RelightData& data, glm::dvec2 c, double r) {
    const auto& t = data.textures[size_t(floorIndex)];
    glm::dvec3 sum(0.0);
    double n = 0;
    for (int y = 0; y < t.height; ++y)
      for (int x = 0; x < t.width; ++x)
        if (glm::length(t.uvOf(x + 0.5, y + 0.5) - c) < r) {
          sum += glm::dvec3(t.albedo[t.index(x, y)]);
          n += 1;
        }
    return sum / std::max(n, 1.0);
  };
  const glm::dvec3 reference = meanAlbedo(d, lit, 0.04);
  auto error = [&](const RelightData& data) { return glm::length(meanAlbedo(data, shadow, 0.2) - reference) / glm::length(reference); };
  std::printf("reflectance under the table vs the chosen element: %.1f %% painted, %.1f %% automatic\n",
              100 * error(d), 100 * error(room().data));
  EXPECT_LT(error(d), 0.05);
  QTemporaryDir dir;
  const std::string folder = dir.filePath("p").toStdString();
  saveRelightProject(room().scene, d, folder);
  const RelightData back = readRelightData(readProject(folder));
  ASSERT_EQ(back.referenceOverride.count("floor"), 1u);
  EXPECT_NEAR(back.referenceOverride.at("floor").x, uv.x, 1e-9);
  ASSERT_EQ(back.options.referenceRegions.size(), 1u);
  EXPECT_TRUE(back.options.referenceRegions[0] == d.referenceRegions[0]);
  o.referenceOverride = {{"no_such_polygon", uv}};
  EXPECT_THROW(preprocessRoom(room().scene, o), Error);
  o.referenceOverride = {{"floor", glm::dvec2(1e3, 1e3)}};
  EXPECT_THROW(preprocessRoom(room().scene, o), Error);
  o.referenceOverride.clear();
  o.referenceRegions = {{"floor", {glm::dvec3(shadow, 0.3)}, glm::dvec2(1e3, 1e3)}};
  EXPECT_THROW(preprocessRoom(room().scene, o), Error) << "a reference outside the polygon";
  o.referenceRegions = {{"floor", {glm::dvec3(shadow, -1.0)}, lit}};
  EXPECT_THROW(preprocessRoom(room().scene, o), Error) << "a negative radius";
}

// The workbench's Recompute: changing one polygon's reference choices redoes only that polygon's
// step 2 (and the global final reflectance pass) on the kept preprocess state, and gives what the
// whole preprocess with those choices gives.
TEST(Relight, RedoingStepTwoForOnePolygonGivesTheWholePreprocess) {
  const Scene& scene = room().scene;
  const int floorIndex = scene.findPolygon("floor");
  const PlaneFrame f = PlaneFrame::of(scene.polygons[floorIndex].vertices);
  const std::map<std::string, glm::dvec2> overrides{{"floor", f.toUV(glm::dvec3(3.5, 1.0, 0.0))}};
  const std::vector<ReferenceRegion> regions{
      {"floor", {glm::dvec3(f.toUV(glm::dvec3(1.8, 2.7, 0.0)), 0.5)}, f.toUV(glm::dvec3(0.6, 1.43, 0.0))}};
  RelightOptions o;
  o.referenceOverride = overrides;
  o.referenceRegions = regions;
  const RelightData whole = preprocessRoom(scene, o);

  Preprocessor pre(scene, RelightOptions{});
  const RelightData before = pre.data();
  EXPECT_TRUE(pre.redoReferences({}, {}).empty()) << "nothing changed, nothing redone";
  // Mean relative difference of a texture layer over the texels a photo saw.
  auto difference = [](const PolygonTexture& a, const PolygonTexture& b, auto layer) {
    double sum = 0, n = 0;
    for (size_t i = 0; i < a.source.size(); ++i) {
      if (a.source[i] == TexelSource::Outside) continue;
      const glm::dvec3 x((a.*layer)[i]), y((b.*layer)[i]);
      sum += glm::length(x - y) / std::max(glm::length(y), 1e-6);
      n += 1;
    }
    return sum / std::max(n, 1.0);
  };
  EXPECT_THROW(pre.redoReferences({{"floor", glm::dvec2(1e3, 1e3)}}, {}), Error);
  EXPECT_EQ(difference(pre.data().textures[floorIndex], before.textures[floorIndex], &PolygonTexture::albedo), 0.0)
      << "a refused choice changes nothing";

  const std::vector<int> redone = pre.redoReferences(overrides, regions);
  ASSERT_EQ(redone, std::vector<int>{floorIndex});
  const RelightData& after = pre.data();
  EXPECT_EQ(after.estimates.referencedByRegion, whole.estimates.referencedByRegion);
  EXPECT_EQ(after.estimates.referencedByDefault, whole.estimates.referencedByDefault);
  EXPECT_EQ(after.referenceOverride.count("floor"), 1u);
  EXPECT_EQ(after.referenceRegions.size(), 1u);
  const double floorUnocc = difference(after.textures[floorIndex], whole.textures[floorIndex], &PolygonTexture::unoccluded);
  const double floorChanged = difference(before.textures[floorIndex], whole.textures[floorIndex], &PolygonTexture::unoccluded);
  std::printf("floor T_final against the whole preprocess: %.5f %% redone, %.3f %% before the redo; step 2 %.2f s, whole %.2f s\n",
              100 * floorUnocc, 100 * floorChanged, after.estimates.stepTwoSeconds, whole.estimates.seconds);
  EXPECT_LT(floorUnocc, 1e-4);
  EXPECT_GT(floorChanged, 10 * floorUnocc) << "the choices must change the floor for this test to mean anything";
  for (size_t s = 0; s < scene.polygons.size(); ++s) {
    if (scene.polygons[s].kind != PolygonKind::Real) continue;
    EXPECT_LT(difference(after.textures[s], whole.textures[s], &PolygonTexture::albedo), 2e-3) << scene.polygons[s].name;
    // (Polygons no photo shows are drawn from the solution, which every reflectance changes.)
    if (int(s) != floorIndex && whole.textures[s].photographed())
      EXPECT_EQ(difference(after.textures[s], before.textures[s], &PolygonTexture::unoccluded), 0.0)
          << scene.polygons[s].name << ": T_final of a polygon whose choices did not change stays";
  }
  // A live session (a lamp dimmed, a box in the room) given the new maps shows what a session
  // built on them shows.
  const VirtualObject box = boxObject("box", {2.6, 1.0, 0.0}, {3.0, 1.4, 0.4}, glm::dvec3(0.6));
  RelightSession live(scene, before, {}, {box});
  live.setLampScale(0, glm::dvec3(0.3));
  live.update();
  const ImageRGB old = live.render(mainCamera(), RelightMethod::Full);
  const auto t0 = std::chrono::steady_clock::now();
  live.setReflectanceMaps(after.textures);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  RelightSession fresh(scene, after, {}, {box});
  fresh.setLampScale(0, glm::dvec3(0.3));
  fresh.update();
  const ImageRGB a = live.render(mainCamera(), RelightMethod::Full), b = fresh.render(mainCamera(), RelightMethod::Full);
  const double psnr = compareImages(a, b, room().masks.all).psnr;
  const double psnrOld = compareImages(old, b, room().masks.all).psnr;
  std::printf("live session given the new maps against a new session: %.1f dB (%.2f s); before them %.1f dB\n", psnr,
              seconds, psnrOld);
  EXPECT_GT(psnr, 45.0);
  EXPECT_GT(psnr, psnrOld + 10.0) << "the new maps must change what the session shows for this to mean anything";
  EXPECT_GT(compareImages(live.render(mainCamera(), RelightMethod::Full), fresh.render(mainCamera(), RelightMethod::Full),
                          room().masks.shadow).psnr, 40.0);
  // Clearing the choices goes back to the automatic result.
  ASSERT_EQ(pre.redoReferences({}, {}), std::vector<int>{floorIndex});
  EXPECT_LT(difference(pre.data().textures[floorIndex], before.textures[floorIndex], &PolygonTexture::unoccluded), 1e-4);
  EXPECT_TRUE(pre.data().referenceOverride.empty());
}

// Lamp edits are weighted sums of per-lamp solutions (radiosity is linear in the emittances);
// they must show what radiosity steps on the same links show.
TEST(Relight, LampEditsFromPerLampSolutionsMatchRadiositySteps) {
  RelightSession s(room().scene, room().data, {}, {boxObject("box", {0.7, 1.5, 0.0}, {1.1, 1.9, 0.35}, glm::dvec3(0.5))});
  s.setLampScale(0, glm::dvec3(0.0));
  s.setLampScale(1, glm::dvec3(2.0, 1.0, 0.5));
  EXPECT_EQ(s.update().iterations, 0) << "a lamp edit alone takes no radiosity steps";
  const ImageRGB combined = s.render(mainCamera(), RelightMethod::Full);
  s.moveObject(0, glm::dvec3(0.0));  // a geometry change: the next update iterates
  EXPECT_EQ(s.update().iterations, 0) << "moveObject already iterated";
  const ImageRGB stepped = s.render(mainCamera(), RelightMethod::Full);
  const std::vector<uint8_t> all(room().masks.all.size(), 1);
  EXPECT_GE(compareImages(combined, stepped, all).psnr, 50.0);
}

namespace {
VirtualLamp lampOverTable() {
  // Facing down (clockwise seen from above), 0.3 m wide, 0.86 m above the table top.
  return VirtualLamp{"spot", {{1.8, 2.8, 1.6}, {2.1, 2.8, 1.6}, {2.1, 2.5, 1.6}, {1.8, 2.5, 1.6}}, glm::dvec3(20.0)};
}
}  // namespace

TEST(Relight, AVirtualLampAddedToALiveSessionShowsWhatASessionBuiltWithItShows) {
  const std::vector<uint8_t> all(room().masks.all.size(), 1);
  RelightSession live(room().scene, room().data);
  const ImageRGB original = live.render(mainCamera(), RelightMethod::Full);
  EXPECT_EQ(live.addVirtualLamp(lampOverTable()), 0);
  EXPECT_EQ(live.virtualLampCount(), 1u);
  const ImageRGB added = live.render(mainCamera(), RelightMethod::Full);
  const ImageRGB built = RelightSession(room().scene, room().data, {lampOverTable()}).render(mainCamera(), RelightMethod::Full);
  EXPECT_GE(compareImages(added, built, all).psnr, 30.0);
  glm::dvec2 px;
  ASSERT_TRUE(mainCamera().project(glm::dvec3(1.95, 2.65, 0.74), px));  // the table top below it
  EXPECT_GT(added.at(int(px.x), int(px.y)).y, 1.3f * original.at(int(px.x), int(px.y)).y);
  // Dimmed through the per-lamp solutions, then moved by 1 m: the table loses its light.
  live.setVirtualLampRadiance(0, glm::dvec3(10.0));
  live.update();
  const float half = live.render(mainCamera(), RelightMethod::Full).at(int(px.x), int(px.y)).y;
  EXPECT_NEAR(half - original.at(int(px.x), int(px.y)).y, 0.5f * (added.at(int(px.x), int(px.y)).y - original.at(int(px.x), int(px.y)).y),
              0.05f * added.at(int(px.x), int(px.y)).y);
  EXPECT_GT(live.moveVirtualLamp(0, glm::dvec3(-1.2, 1.2, 0.0)), 0u);
  EXPECT_NEAR(live.virtualLamp(0).polygon[0].x, 0.6, 1e-9);
  const float moved = live.render(mainCamera(), RelightMethod::Full).at(int(px.x), int(px.y)).y;
  EXPECT_LT(moved, half);
  // Removed: the room shows as it did before.
  live.removeVirtualLamp(0);
  EXPECT_EQ(live.virtualLampCount(), 0u);
  EXPECT_GE(compareImages(live.render(mainCamera(), RelightMethod::Full), original, all).psnr, 45.0);
  // Degenerate input is refused with the lamp's name.
  VirtualLamp flat = lampOverTable();
  flat.polygon[2] = flat.polygon[1];
  flat.polygon[3] = flat.polygon[0];
  EXPECT_THROW(live.addVirtualLamp(flat), Error);
  EXPECT_EQ(live.virtualLampCount(), 0u);
}

TEST(Relight, AVirtualObjectAddedTurnedAndRemovedOnALiveSession) {
  const std::vector<uint8_t> all(room().masks.all.size(), 1);
  const glm::dvec3 albedo(0.6, 0.2, 0.2);
  // 0.4 x 0.2 m: turned by 90 degrees about its centre it is the 0.2 x 0.4 box.
  const glm::dvec3 c(0.9, 1.7, 0.175);
  const VirtualObject wide = boxObject("box", c - glm::dvec3(0.2, 0.1, 0.175), c + glm::dvec3(0.2, 0.1, 0.175), albedo);
  const VirtualObject deep = boxObject("box", c - glm::dvec3(0.1, 0.2, 0.175), c + glm::dvec3(0.1, 0.2, 0.175), albedo);
  RelightSession live(room().scene, room().data);
  const ImageRGB original = live.render(mainCamera(), RelightMethod::Full);
  EXPECT_EQ(live.addObject(wide), 0);
  const ImageRGB added = live.render(mainCamera(), RelightMethod::Full);
  const ImageRGB builtWide = RelightSession(room().scene, room().data, {}, {wide}).render(mainCamera(), RelightMethod::Full);
  EXPECT_GE(compareImages(added, builtWide, all).psnr, 30.0);
  EXPECT_LE(compareImages(added, original, all).psnr, compareImages(added, builtWide, all).psnr - 5.0);
  const size_t updated = live.moveObject(0, glm::dvec3(0.0), std::numbers::pi / 2);
  EXPECT_GT(updated, 0u);
  EXPECT_LT(updated, live.engine().links().size() / 2);
  EXPECT_NEAR(objectCentre(live.object(0)).x, c.x, 1e-9);
  const ImageRGB turned = live.render(mainCamera(), RelightMethod::Full);
  const ImageRGB builtDeep = RelightSession(room().scene, room().data, {}, {deep}).render(mainCamera(), RelightMethod::Full);
  EXPECT_GE(compareImages(turned, builtDeep, all).psnr, 30.0);
  EXPECT_GE(compareImages(turned, builtDeep, all).psnr, compareImages(added, builtDeep, all).psnr + 3.0);
  // Into the wall: refused, nothing moves.
  EXPECT_THROW(live.moveObject(0, glm::dvec3(-2.0, 0, 0), 0.3), Error);
  EXPECT_NEAR(objectCentre(live.object(0)).x, c.x, 1e-9);
  live.removeObject(0);
  EXPECT_EQ(live.objectCount(), 0u);
  EXPECT_GE(compareImages(live.render(mainCamera(), RelightMethod::Full), original, all).psnr, 40.0);
}

// A project reopened with its virtual lamp and object (built into the session's clusters): both
// can be removed, and the room shows as it did without them.
TEST(Relight, VirtualThingsBuiltIntoASessionCanBeRemoved) {
  const std::vector<uint8_t> all(room().masks.all.size(), 1);
  const ImageRGB original = RelightSession(room().scene, room().data).render(mainCamera(), RelightMethod::Full);
  RelightSession s(room().scene, room().data, {lampOverTable()},
                   {boxObject("box", {0.7, 1.5, 0.0}, {1.1, 1.9, 0.35}, glm::dvec3(0.6, 0.2, 0.2))});
  s.removeVirtualLamp(0);
  s.removeObject(0);
  EXPECT_EQ(s.virtualLampCount(), 0u);
  EXPECT_EQ(s.objectCount(), 0u);
  const double p = compareImages(s.render(mainCamera(), RelightMethod::Full), original, all).psnr;
  EXPECT_GE(p, 40.0);
  // A degenerate face is refused before anything changes.
  VirtualObject flat = boxObject("flat", {0.7, 1.5, 0.0}, {1.1, 1.9, 0.35}, glm::dvec3(0.5));
  flat.polygons[0] = {flat.polygons[0][0], flat.polygons[0][0], flat.polygons[0][0]};
  EXPECT_THROW(s.addObject(flat), Error);
  EXPECT_EQ(s.objectCount(), 0u);
  EXPECT_GE(compareImages(s.render(mainCamera(), RelightMethod::Full), original, all).psnr, p - 0.01);
}

// A drag previews visibility with few rays; once settled, the image is the one full-quality moves
// give, along the whole path it took.
TEST(Relight, ADraggedObjectSettlesToTheFullQualitySolution) {
  const std::vector<uint8_t> all(room().masks.all.size(), 1);
  const VirtualObject box = boxObject("box", {0.7, 1.5, 0.0}, {1.1, 1.9, 0.35}, glm::dvec3(0.6, 0.2, 0.2));
  RelightSession dragged(room().scene, room().data, {}, {box}), stepped(room().scene, room().data, {}, {box});
  dragged.setDragPreview(true);
  for (int k = 0; k < 4; ++k) {
    dragged.moveObject(0, glm::dvec3(0.15, 0.08, 0.0));
    stepped.moveObject(0, glm::dvec3(0.15, 0.08, 0.0));
  }
  const double preview = compareImages(dragged.render(mainCamera(), RelightMethod::Full),
                                       stepped.render(mainCamera(), RelightMethod::Full), all).psnr;
  EXPECT_GT(dragged.settleObject(0), 0u);
  const double settled = compareImages(dragged.render(mainCamera(), RelightMethod::Full),
                                       stepped.render(mainCamera(), RelightMethod::Full), all).psnr;
  std::printf("preview vs full-quality moves %.1f dB, settled %.1f dB\n", preview, settled);
  EXPECT_GE(settled, 60.0);
  EXPECT_GE(settled, preview);
}

// What the workbench draws: per polygon, triangles that cover the polygon exactly and meet edge to
// edge. An edge that is not on the polygon's outline is used once in each direction; a T-junction
// (a leaf's edge with a smaller neighbour's corner inside it) would leave edges used once only,
// and shows on screen as a crack of background pixels.
TEST(Relight, TheDisplayMeshCoversEachPolygonWithoutCracks) {
  // A box, and a tetrahedron: triangular faces cut leaves into triangles, which T-vertices split.
  VirtualObject tetra{"tetrahedron", {}, glm::dvec3(0.6)};
  const glm::dvec3 a(2.6, 1.0, 0.0), b(3.4, 1.0, 0.0), c(3.0, 1.7, 0.0), d(3.0, 1.23, 0.8);
  tetra.polygons = {{a, c, b}, {a, b, d}, {b, c, d}, {c, a, d}};
  RelightSession s(room().scene, room().data, {},
                   {boxObject("box", {0.7, 1.5, 0.0}, {1.1, 1.9, 0.35}, glm::dvec3(0.5)), tetra});
  const DisplayMesh mesh = s.displayMesh();
  ASSERT_FALSE(mesh.ranges.empty());
  const auto& engine = s.engine();
  size_t interiorEdges = 0;
  for (const auto& r : mesh.ranges) {
    const auto& poly = engine.surfaces()[size_t(r.surface)].vertices;
    std::vector<glm::dvec2> outline;
    for (const auto& v : poly) outline.push_back(engine.toUV(r.surface, v));
    auto onOutline = [&](glm::dvec2 a, glm::dvec2 b) {
      for (size_t i = 0; i < outline.size(); ++i) {
        const glm::dvec2 p = outline[i], q = outline[(i + 1) % outline.size()];
        const glm::dvec2 d = q - p;
        auto off = [&](glm::dvec2 x) { return std::abs(d.x * (x.y - p.y) - d.y * (x.x - p.x)) / glm::length(d); };
        if (off(a) < 1e-6 && off(b) < 1e-6) return true;
      }
      return false;
    };
    std::map<std::pair<std::pair<float, float>, std::pair<float, float>>, int> directed;
    double area = 0;
    for (size_t t = r.first; t < r.first + r.count; t += 3) {
      glm::dvec2 p[3];
      for (int k = 0; k < 3; ++k) p[k] = glm::dvec2(mesh.vertices[mesh.indices[t + size_t(k)]].uv);
      area += 0.5 * ((p[1].x - p[0].x) * (p[2].y - p[0].y) - (p[2].x - p[0].x) * (p[1].y - p[0].y));
      for (int k = 0; k < 3; ++k) {
        const glm::vec2 a(p[k]), b(p[(k + 1) % 3]);
        ++directed[{{a.x, a.y}, {b.x, b.y}}];
      }
    }
    // No vertex of the surface lies inside a triangle's edge (a T-junction, even one that a
    // zero-area triangle pairs up).
    {
      const double cell = 0.05;
      std::map<std::pair<int, int>, std::vector<glm::dvec2>> grid;
      auto key = [&](glm::dvec2 q) { return std::make_pair(int(std::floor(q.x / cell)), int(std::floor(q.y / cell))); };
      for (size_t t = r.first; t < r.first + r.count; ++t) {
        const glm::dvec2 q(mesh.vertices[mesh.indices[t]].uv);
        auto& list = grid[key(q)];
        if (std::find(list.begin(), list.end(), q) == list.end()) list.push_back(q);
      }
      for (size_t t = r.first; t < r.first + r.count; t += 3)
        for (int k = 0; k < 3; ++k) {
          const glm::dvec2 a(mesh.vertices[mesh.indices[t + size_t(k)]].uv), b(mesh.vertices[mesh.indices[t + size_t((k + 1) % 3)]].uv);
          const double len = glm::length(b - a);
          if (len <= 0) continue;
          const auto lo = key(glm::min(a, b)), hi = key(glm::max(a, b));
          for (int i = lo.first; i <= hi.first; ++i)
            for (int j = lo.second; j <= hi.second; ++j) {
              const auto it = grid.find({i, j});
              if (it == grid.end()) continue;
              for (const auto& q : it->second) {
                const double along = glm::dot(q - a, b - a) / (len * len);
                const double off = std::abs((b - a).x * (q - a).y - (b - a).y * (q - a).x) / len;
                ASSERT_FALSE(along > 1e-6 && along < 1 - 1e-6 && off < 1e-7)
                    << "surface " << r.surface << ": vertex (" << q.x << ", " << q.y << ") inside the edge (" << a.x << ", "
                    << a.y << ") - (" << b.x << ", " << b.y << ")";
              }
            }
        }
    }
    EXPECT_NEAR(area, std::abs(polygonArea2D(outline)), 1e-4 * std::abs(polygonArea2D(outline)) + 1e-9)
        << "surface " << r.surface << ": the triangles cover the polygon once";
    for (const auto& [edge, count] : directed) {
      const auto back = directed.find({edge.second, edge.first});
      const glm::dvec2 a(edge.first.first, edge.first.second), b(edge.second.first, edge.second.second);
      if (back != directed.end()) {
        ++interiorEdges;
        EXPECT_EQ(count, back->second) << "surface " << r.surface << " edge (" << a.x << ", " << a.y << ") - (" << b.x << ", " << b.y << ")";
      } else {
        ASSERT_TRUE(onOutline(a, b)) << "surface " << r.surface << ": an edge from (" << a.x << ", " << a.y << ") to ("
                                     << b.x << ", " << b.y << ") inside the polygon has no neighbour across it";
      }
    }
  }
  EXPECT_GT(interiorEdges, mesh.leafNode.size()) << "leaves share their edges";
}

TEST(Relight, CalibratedPhotosTakePhotometricLampsAtTheirFilesFlux) {
  // The sample room's photos are linear radiance in its lamps' own units: calibrated. Each lamp
  // gets a photometric file of Lambertian shape (I = I0 cos gamma, flux pi I0) whose flux is the
  // lamp's true power; with --calibrated-photos the lamps are taken at it (a file gives no colour:
  // grey), without it they are estimated as ever.
  Scene scene = readBundle(kRoom);
  const Scene truth = scene;
  for (auto& p : scene.polygons) p.albedo = glm::dvec3(0.5);
  std::vector<double> power(scene.lamps.size());
  for (size_t l = 0; l < scene.lamps.size(); ++l) {
    const glm::dvec3& r = truth.lamps[l].radiance;
    power[l] = M_PI * (r.x + r.y + r.z) / 3 * polygonArea(scene.polygons[scene.lamps[l].polygon].vertices);
    auto d = std::make_shared<PhotometricDistribution>();
    d->c = {0.0};
    for (double g = 0; g <= 90.0; g += 5.0) {
      d->gamma.push_back(g);
      d->candela.push_back(power[l] / M_PI * std::cos(g * M_PI / 180));
    }
    scene.lamps[l].photometry = d;
    scene.lamps[l].radiance = glm::dvec3(0.0);
  }
  RelightOptions o;
  o.calibratedPhotos = true;
  const RelightData data = preprocessRoom(scene, o);
  for (size_t l = 0; l < scene.lamps.size(); ++l) {
    const glm::dvec3& e = data.lampExitance[l];
    const double area = polygonArea(scene.polygons[scene.lamps[l].polygon].vertices);
    EXPECT_NEAR((e.x + e.y + e.z) / 3 * area, power[l], 0.01 * power[l]) << scene.lamps[l].name;
  }
  // Relit with lamp A off, its old shadow is gone as with the estimates.
  RelightSession s(scene, data);
  s.setLampScale(scene.findLamp("A"), glm::dvec3(0.0));
  s.update();
  EXPECT_TRUE(oldShadowGone(s.render(mainCamera(), RelightMethod::Full)));
}
