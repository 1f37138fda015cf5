// Photo textures: texels the main photo does not show come from the other photos at the main
// photo's exposure, whatever exposure those photos were taken at.
#include <gtest/gtest.h>

#include <QDir>
#include <QFile>
#include <QTemporaryDir>
#include <cmath>

#include "relume/image/image.h"
#include "relume/project/room_io.h"
#include "relume/raytrace/ray_scene.h"
#include "relume/relight/texture.h"

using namespace relume;

namespace {
const QString kRoom = QStringLiteral(RELUME_SOURCE_DIR) + "/resources/sample_room";

std::vector<PolygonTexture> texturesOf(const Scene& scene, DewarpStats& stats) {
  std::vector<std::vector<glm::dvec3>> polys;
  for (const auto& p : scene.polygons) polys.push_back(p.vertices);
  const RayScene rays(polys);
  const int main = int(scene.findPhoto(scene.mainPhoto) - scene.photos.data());
  return dewarpPhotos(scene, rays, main, &stats);
}
}  // namespace

TEST(Textures, TexelsFromAnotherPhotoTakeThatPhotosExposureIntoAccount) {
  // The sample room with every photo but the main one taken one stop brighter (its radiance x 2).
  QTemporaryDir tmp;
  ASSERT_TRUE(tmp.isValid());
  const QString copy = tmp.path() + "/room";
  ASSERT_TRUE(QDir().mkpath(copy + "/photos"));
  for (const char* f : {"scene.json", "geometry.obj"}) ASSERT_TRUE(QFile::copy(kRoom + "/" + f, copy + "/" + f));
  const Scene original = readBundle(kRoom.toStdString());
  for (const auto& ph : original.photos)
    for (const std::string& rel : {ph.file, ph.hdr}) {
      if (rel.empty()) continue;
      const QString src = kRoom + "/" + QString::fromStdString(rel), dst = copy + "/" + QString::fromStdString(rel);
      if (ph.name != original.mainPhoto && isRadianceFile(rel)) {
        ImageRGB img = readImageLinear(src.toStdString());
        for (float& v : img.pixels) v *= 2.f;
        writeImage(dst.toStdString(), img);
      } else {
        ASSERT_TRUE(QFile::copy(src, dst));
      }
    }
  const Scene brighter = readBundle(copy.toStdString());
  DewarpStats a, b;
  const auto ta = texturesOf(original, a), tb = texturesOf(brighter, b);
  ASSERT_GT(a.fromOther, 1000u) << "the main photo must leave texels for the others to fill";
  EXPECT_EQ(a.fromOther, b.fromOther);
  ASSERT_EQ(b.exposureScale.size(), a.exposureScale.size());
  for (size_t k = 0; k < b.exposureScale.size(); ++k) {
    // The sample room's photos share one exposure; the brighter ones are found to be twice it.
    EXPECT_NEAR(a.exposureScale[k], 1.0, 0.03) << "photo " << k;
    EXPECT_NEAR(b.exposureScale[k], 0.5, 0.015) << "photo " << k;
    EXPECT_GE(b.exposureOverlap[k], 64u);
  }
  // The texels filled from the other photos are the same either way (within 1 %).
  double diff = 0, sum = 0;
  for (size_t p = 0; p < ta.size(); ++p)
    for (size_t i = 0; i < ta[p].original.size(); ++i) {
      if (!fromOtherPhoto(ta[p].source[i])) continue;
      EXPECT_EQ(tb[p].source[i], ta[p].source[i]);
      for (int c = 0; c < 3; ++c) {
        diff += std::abs(double(ta[p].original[i][c]) - tb[p].original[i][c]);
        sum += ta[p].original[i][c];
      }
    }
  EXPECT_LT(diff / sum, 0.01);
}

TEST(Textures, TexelsPhotographedAtAPolygonsOutlineAreMarkedSoAndLeftOutOfItsMean) {
  // Cycles' pixel filter mixes the neighbours into a pixel at a polygon's outline in the photo. On
  // the flat-albedo sample room the table top's 4 cm side strip is mostly outline, the floor
  // hardly; a polygon's photographed mean is taken over the texels away from its outline.
  const Scene scene = readBundle(RELUME_SOURCE_DIR "/resources/sample_room_flat");
  DewarpStats stats;
  const auto tex = texturesOf(scene, stats);
  struct Count {
    size_t photographed = 0, outline = 0;
    glm::dvec3 insideMean{0.0};
  };
  auto count = [&](const std::string& name) {
    Count c;
    for (size_t p = 0; p < scene.polygons.size(); ++p) {
      if (scene.polygons[p].name != name) continue;
      const auto& t = tex[p];
      for (size_t i = 0; i < t.source.size(); ++i) {
        if (!fromPhoto(t.source[i])) continue;
        ++c.photographed;
        if (photographedInside(t.source[i]))
          c.insideMean += glm::dvec3(t.original[i]);
        else
          ++c.outline;
      }
      if (c.photographed > c.outline) c.insideMean /= double(c.photographed - c.outline);
      std::printf("  %s: %zu photographed texels, %.1f %% on its outline\n", name.c_str(), c.photographed,
                  100.0 * double(c.outline) / double(std::max<size_t>(1, c.photographed)));
    }
    return c;
  };
  const Count floor = count("floor"), strip = count("table_top_left");
  ASSERT_GT(floor.photographed, 10000u);
  ASSERT_GT(strip.photographed, 0u);
  EXPECT_LT(double(floor.outline), 0.1 * double(floor.photographed));  // (its outline runs round the table legs and the box too)
  EXPECT_GT(double(strip.outline), 0.5 * double(strip.photographed));
  for (size_t p = 0; p < scene.polygons.size(); ++p)
    if (scene.polygons[p].name == "floor") {
      size_t n = 0;
      const glm::dvec3 m = tex[p].photographedMean(tex[p].original, &n);
      EXPECT_EQ(n, floor.photographed - floor.outline);
      EXPECT_NEAR(m.y, floor.insideMean.y, 1e-9 + 1e-9 * floor.insideMean.y);
    }
}
