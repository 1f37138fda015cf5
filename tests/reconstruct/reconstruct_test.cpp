// Reconstruction: COLMAP models, triangulation, polygon picking, metric frame, cameras from
// correspondences, HDR merge, checkerboard calibration, and the COLMAP driver's errors.
#include <gtest/gtest.h>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>

#include "relume/geometry/error.h"
#include "relume/reconstruct/colmap_driver.h"
#include "relume/reconstruct/colmap_model.h"
#include "relume/reconstruct/multiview.h"
#include "relume/project/fisheye_lens.h"
#include "relume/reconstruct/photos.h"
#include "relume/reconstruct/polygon_fit.h"
#include "support/error_text.h"
#include "support/checkerboard.h"

namespace fs = std::filesystem;
using namespace relume;
using namespace relume::recon;

namespace {

fs::path tempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("relume_recon_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

using relume::test::errorText;

bool colmapAvailable() {
  try {
    findColmap();
    return true;
  } catch (const Error&) {
    return false;
  }
}

ColmapModel sampleModel() {
  ColmapModel m;
  m.cameras[1] = {1, "SIMPLE_PINHOLE", 640, 480, {500, 320, 240}};
  m.cameras[2] = {2, "PINHOLE", 800, 600, {700, 710, 400, 300}};
  m.cameras[3] = {3, "SIMPLE_RADIAL", 640, 480, {520, 321, 239, -0.05}};
  m.cameras[4] = {4, "RADIAL", 640, 480, {530, 322, 238, -0.08, 0.01}};
  m.cameras[5] = {5, "OPENCV", 1024, 768, {900, 905, 512, 384, -0.1, 0.02, 0.001, -0.002}};
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(-1, 1);
  for (int i = 1; i <= 5; ++i) {
    ColmapImage im;
    im.id = i * 10;
    im.camera = i;
    im.name = "photo" + std::to_string(i) + ".jpg";
    im.q = glm::normalize(glm::dvec4(1 + U(rng), 0.3 * U(rng), 0.3 * U(rng), 0.3 * U(rng)));
    im.t = {U(rng), U(rng), 3 + U(rng)};
    im.points = {{{10.5, 20.25}, 7}, {{100.125, 200.5}, -1}};
    m.images[im.id] = im;
  }
  ColmapPoint p;
  p.id = 7;
  p.xyz = {0.1, -0.2, 2.5};
  p.rgb = {10, 200, 30};
  p.error = 0.42;
  p.track = {{10, 0}, {20, 0}};
  m.points[7] = p;
  return m;
}

void expectSameModel(const ColmapModel& a, const ColmapModel& b) {
  ASSERT_EQ(a.cameras.size(), b.cameras.size());
  for (const auto& [id, c] : a.cameras) {
    const auto& d = b.cameras.at(id);
    EXPECT_EQ(c.model, d.model);
    EXPECT_EQ(c.width, d.width);
    ASSERT_EQ(c.params.size(), d.params.size());
    for (size_t k = 0; k < c.params.size(); ++k) EXPECT_NEAR(c.params[k], d.params[k], 1e-9);
  }
  ASSERT_EQ(a.images.size(), b.images.size());
  for (const auto& [id, im] : a.images) {
    const auto& jm = b.images.at(id);
    EXPECT_EQ(im.name, jm.name);
    EXPECT_EQ(im.camera, jm.camera);
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(im.q[k], jm.q[k], 1e-9);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(im.t[k], jm.t[k], 1e-9);
    ASSERT_EQ(im.points.size(), jm.points.size());
    for (size_t k = 0; k < im.points.size(); ++k) {
      EXPECT_NEAR(im.points[k].xy.x, jm.points[k].xy.x, 1e-9);
      EXPECT_EQ(im.points[k].point3D, jm.points[k].point3D);
    }
  }
  ASSERT_EQ(a.points.size(), b.points.size());
  for (const auto& [id, p] : a.points) {
    const auto& q = b.points.at(id);
    EXPECT_NEAR(glm::length(p.xyz - q.xyz), 0, 1e-9);
    EXPECT_EQ(p.rgb, q.rgb);
    ASSERT_EQ(p.track.size(), q.track.size());
    EXPECT_EQ(p.track[1].image, q.track[1].image);
  }
}

}  // namespace

// ---------------------------------------------------------------- COLMAP models

TEST(ColmapModel, TextRoundTripKeepsEverything) {
  const fs::path d = tempDir("text");
  const ColmapModel m = sampleModel();
  writeColmapText(m, d.string());
  expectSameModel(m, readColmapModel(d.string()));
}

TEST(ColmapModel, BinaryReadMatchesColmapsOwnConversion) {
  if (!colmapAvailable()) GTEST_SKIP() << "colmap is not installed";
  const fs::path d = tempDir("bin");
  const ColmapModel m = sampleModel();
  writeColmapText(m, (d / "txt").string());
  fs::create_directories(d / "bin");
  const std::string cmd = findColmap() + " model_converter --input_path " + (d / "txt").string() + " --output_path " +
                          (d / "bin").string() + " --output_type BIN > /dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  ASSERT_TRUE(fs::exists(d / "bin" / "images.bin"));
  expectSameModel(m, readColmapBinary((d / "bin").string()));
  // A truncated file is reported, naming it.
  fs::resize_file(d / "bin" / "images.bin", fs::file_size(d / "bin" / "images.bin") / 2);
  const std::string e = errorText([&] { readColmapBinary((d / "bin").string()); });
  EXPECT_NE(e.find("images.bin"), std::string::npos) << e;
  EXPECT_NE(e.find("truncated"), std::string::npos) << e;
}

TEST(ColmapModel, UnsupportedCameraModelIsNamed) {
  const fs::path d = tempDir("unsupported");
  std::ofstream(d / "cameras.txt") << "1 FOV 640 480 500 320 240 0.1\n";
  std::ofstream(d / "images.txt") << "";
  const std::string e = errorText([&] { readColmapModel(d.string()); });
  EXPECT_NE(e.find("FOV"), std::string::npos) << e;
  EXPECT_NE(e.find("cameras.txt:1"), std::string::npos) << e;
}

TEST(ColmapModel, DistortionInvertsForEveryModel) {
  const ColmapModel m = sampleModel();
  for (const auto& [id, c] : m.cameras)
    for (double x = -0.5; x <= 0.5; x += 0.1)
      for (double y = -0.4; y <= 0.4; y += 0.1) {
        const glm::dvec2 px = c.distort({x, y});
        const glm::dvec2 back = c.undistort(px);
        EXPECT_NEAR(back.x, x, 1e-9) << c.model;
        EXPECT_NEAR(back.y, y, 1e-9) << c.model;
      }
  // OPENCV's tangential terms move points off the radial line (so they are not ignored).
  const ColmapCamera& cv = m.cameras.at(5);
  const glm::dvec2 p = cv.distort({0.3, 0.3});
  EXPECT_GT(std::abs((p.x - cv.cx()) / cv.fx() - (p.y - cv.cy()) / cv.fy()), 1e-4);
}

TEST(ColmapModel, SimilarityMovesCamerasWithThePoints) {
  ColmapModel m = sampleModel();
  const ColmapImage before = m.images.at(10);
  const Camera cb = m.camera(before);
  glm::dvec2 p0;
  ASSERT_TRUE(cb.project(m.points.at(7).xyz, p0));
  Similarity S;
  S.s = 2.5;
  S.R = glm::dmat3(0, 1, 0, -1, 0, 0, 0, 0, 1);  // 90 degrees about Z
  S.t = {1, 2, 3};
  transformModel(m, S);
  glm::dvec2 p1;
  ASSERT_TRUE(m.camera(m.images.at(10)).project(m.points.at(7).xyz, p1));
  EXPECT_NEAR(glm::length(p1 - p0), 0, 1e-9);
  EXPECT_NEAR(glm::length(m.images.at(10).center() - S.apply(before.center())), 0, 1e-9);
}

// ---------------------------------------------------------------- triangulation

namespace {
struct Rig {
  std::vector<Camera> cams;
  std::vector<glm::dvec3> points;
};
// Three photos of a 1600x1200 camera (60 deg across), 0.8 m apart, 3 m from 100 points on
// 25 quadrilaterals spread over a 2.4 x 1.6 m wall-like patch.
Rig wallRig() {
  Rig r;
  for (int i = 0; i < 3; ++i) r.cams.push_back(Camera::lookAt({-0.8 + 0.8 * i, -3.0, 1.4}, {0, 0, 1.2}, 1600, 1200, 1385));
  for (int q = 0; q < 25; ++q) {
    const glm::dvec3 o(-1.2 + 0.5 * (q % 5), 0.08 * (q % 3), 0.3 + 0.35 * (q / 5));
    r.points.push_back(o);
    r.points.push_back(o + glm::dvec3(0.3, 0, 0));
    r.points.push_back(o + glm::dvec3(0.3, 0, 0.25));
    r.points.push_back(o + glm::dvec3(0, 0, 0.25));
  }
  return r;
}
std::vector<Observation> observe(const Rig& r, const glm::dvec3& X, std::mt19937* rng, double sigma) {
  std::normal_distribution<double> N(0, sigma);
  std::vector<Observation> obs;
  for (const auto& c : r.cams) {
    glm::dvec2 px;
    EXPECT_TRUE(c.project(X, px));
    if (rng) px += glm::dvec2(N(*rng), N(*rng));
    obs.push_back({&c, "photo", px});
  }
  return obs;
}
}  // namespace

TEST(Triangulation, NoiseFreeClicksGiveCornersWithin1mm) {
  const Rig r = wallRig();
  double worst = 0;
  for (const auto& X : r.points) {
    const TriangulatedPoint tp = triangulatePoint(observe(r, X, nullptr, 0), "corner");
    worst = std::max(worst, glm::length(tp.X - X));
    EXPECT_LT(tp.rmsError, 1e-6);
  }
  std::printf("noise-free clicks: largest corner error %.3g m\n", worst);
  EXPECT_LT(worst, 1e-3);
}

TEST(Triangulation, OnePixelClickNoiseAt3mStaysWithin2cm) {
  const Rig r = wallRig();
  std::mt19937 rng(5);
  double worst = 0, rms = 0;
  for (const auto& X : r.points) {
    const TriangulatedPoint tp = triangulatePoint(observe(r, X, &rng, 1.0), "corner");
    worst = std::max(worst, glm::length(tp.X - X));
    rms += tp.rmsError * tp.rmsError;
  }
  std::printf("1 px click noise: largest corner error %.4f m over %zu corners\n", worst, r.points.size());
  EXPECT_LT(worst, 0.02);
  // The reported reprojection error reflects the click noise (2 dof of 6 absorbed by the point).
  EXPECT_GT(std::sqrt(rms / r.points.size()), 0.5);
  EXPECT_LT(std::sqrt(rms / r.points.size()), 1.2);
}

TEST(Triangulation, PointBehindACameraIsNamed) {
  const Camera a = Camera::lookAt({0, 0, 1}, {0, 5, 1}, 640, 480, 500), b = Camera::lookAt({1, 0, 1}, {1, 5, 1}, 640, 480, 500);
  // Rays that diverge: a clicked left of centre, b right of centre; their lines meet behind.
  const std::vector<Observation> obs = {{&a, "left.jpg", {220, 240}}, {&b, "right.jpg", {420, 240}}};
  const std::string e = errorText([&] { triangulatePoint(obs, "point P"); });
  EXPECT_NE(e.find("behind the camera"), std::string::npos) << e;
  EXPECT_NE(e.find("point P"), std::string::npos) << e;
}

TEST(Triangulation, OneClickAndIdenticalRaysAreErrors) {
  const Camera a = Camera::lookAt({0, 0, 1}, {0, 5, 1}, 640, 480, 500);
  EXPECT_NE(errorText([&] { triangulatePoint({{&a, "a", {300, 200}}}, "P"); }).find("two or more"), std::string::npos);
  EXPECT_NE(errorText([&] { triangulatePoint({{&a, "a", {300, 200}}, {&a, "a again", {300, 200}}}, "P"); }).find("same ray"),
            std::string::npos);
}

// ---------------------------------------------------------------- polygons

TEST(PolygonFit, CollinearPointsAreRefused) {
  const std::string e = errorText([] { fitPlane({{0, 0, 0}, {1, 1, 0}, {2, 2, 0}, {3, 3, 0}}, "polygon shelf"); });
  EXPECT_NE(e.find("collinear"), std::string::npos) << e;
  EXPECT_NE(e.find("polygon shelf"), std::string::npos) << e;
}

TEST(PolygonFit, OrdersCornersConvexWithTheNormalTowardsTheCameras) {
  // A floor rectangle picked in scrambled order with an inner point; cameras above it.
  const std::vector<glm::dvec3> pts = {{4, 3, 0.01}, {0, 0, -0.01}, {2, 1.5, 0}, {0, 3, 0.01}, {4, 0, -0.01}};
  const Plane pl = fitPlane(pts, "floor");
  EXPECT_NEAR(std::abs(pl.normal.z), 1.0, 1e-3);
  const auto poly = convexPolygon(pts, pl, {2, 1.5, 1.6}, "floor");
  ASSERT_EQ(poly.size(), 4u);  // the inner point is dropped
  EXPECT_GT(polygonNormal(poly).z, 0.999);
  EXPECT_NEAR(polygonArea(poly), 12.0, 0.05);
  const auto under = convexPolygon(pts, pl, {2, 1.5, -1.0}, "ceiling seen from below");
  EXPECT_LT(polygonNormal(under).z, -0.999);
}

TEST(PolygonFit, RectangleConstraintSquaresANoisyQuad) {
  const std::vector<glm::dvec3> q = {{0.01, 0, 0}, {2.0, -0.01, 0}, {2.01, 1.0, 0}, {-0.01, 1.01, 0}};
  const auto r = rectify(q, "poster");
  for (int i = 0; i < 4; ++i) {
    const glm::dvec3 e1 = r[(i + 1) % 4] - r[i], e2 = r[(i + 2) % 4] - r[(i + 1) % 4];
    EXPECT_NEAR(glm::dot(e1, e2), 0, 1e-9);
    EXPECT_LT(glm::length(r[i] - q[i]), 0.02);
  }
}

TEST(PolygonFit, EditingKeepsIdsStable) {
  PickedPolygons m;
  const glm::dvec3 viewer(0.5, 0.5, 2);
  const int a = m.add("left", "floor", false, {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, viewer);
  const int b = m.add("right", "floor", false, {{1, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}}, viewer);
  const int c = m.add("lamp", "light_A", true, {{0, 0, 2.5}, {0.3, 0, 2.5}, {0.3, 0.3, 2.5}}, viewer);
  EXPECT_EQ(m.get(c).kind, PolygonKind::Light);
  int corner = 0;  // the corner at (0.3, 0, 2.5), wherever the fit put it in the order
  for (int k = 0; k < 3; ++k)
    if (glm::length(m.get(c).vertices[k] - glm::dvec3(0.3, 0, 2.5)) < 1e-9) corner = k;
  m.moveVertex(c, corner, {0.4, -0.05, 2.5});
  EXPECT_NEAR(glm::length(m.get(c).vertices[corner] - glm::dvec3(0.4, -0.05, 2.5)), 0, 1e-9);
  EXPECT_TRUE(m.contains(c));
  m.merge(a, b);
  EXPECT_FALSE(m.contains(b));
  EXPECT_EQ(m.get(a).name, "left");
  EXPECT_NEAR(polygonArea(m.get(a).vertices), 2.0, 1e-9);
  m.remove(c);
  const int d = m.add("wall", "wall", false, {{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}}, {1, 0.5, 0.5});
  EXPECT_NE(d, b);
  EXPECT_NE(d, c);  // ids are never reused
  EXPECT_EQ(m.ids(), (std::vector<int>{a, d}));
  const std::string e = errorText([&] { m.merge(a, d); });
  EXPECT_NE(e.find("not coplanar"), std::string::npos) << e;
}

TEST(PolygonFit, SnapsPolygonsToOneCommonPlane) {
  PickedPolygons m;
  const int a = m.add("wall part 1", "wall", false, {{0, 0.00, 0}, {1, 0.02, 0}, {1, 0.02, 1}, {0, 0.00, 1}}, {0.5, 2, 0.5});
  const int b = m.add("wall part 2", "wall", false, {{1, -0.01, 0}, {2, 0.01, 0}, {2, 0.01, 1}, {1, -0.01, 1}}, {1.5, 2, 0.5});
  m.snapToCommonPlane({a, b});
  std::vector<glm::dvec3> all = m.get(a).vertices;
  all.insert(all.end(), m.get(b).vertices.begin(), m.get(b).vertices.end());
  EXPECT_LT(fitPlane(all, "both").rms, 1e-9);
}

// ---------------------------------------------------------------- metric frame

TEST(MetricFrame, SimilarityFitRecoversAKnownTransform) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> U(-2, 2);
  Similarity S;
  S.s = 0.37;
  S.R = glm::dmat3(glm::dvec3(0.36, 0.48, -0.8), glm::dvec3(-0.8, 0.6, 0), glm::dvec3(0.48, 0.64, 0.6));
  S.t = {0.3, -1, 2};
  std::vector<glm::dvec3> a, b;
  for (int i = 0; i < 10; ++i) {
    a.push_back({U(rng), U(rng), U(rng)});
    b.push_back(S.apply(a.back()));
  }
  const Similarity F = fitSimilarity(a, b);
  EXPECT_NEAR(F.s, S.s, 1e-9);
  for (const auto& p : a) EXPECT_NEAR(glm::length(F.apply(p) - S.apply(p)), 0, 1e-9);
}

TEST(MetricFrame, ScaleAndFloorGiveMetresWithZUp) {
  // A model in an arbitrary frame: the true room under an unknown similarity.
  Similarity hidden;
  hidden.s = 0.2;
  hidden.R = glm::dmat3(glm::dvec3(0, 0, 1), glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0));
  hidden.t = {5, 6, 7};
  const glm::dvec3 f0(0, 0, 0), f1(4, 0, 0), f2(4, 5, 0), camera(2, 2.5, 1.5), top(4, 5, 2.6);
  const Similarity M = metricFrame(hidden.apply(f0), hidden.apply(f1), 4.0,
                                   {hidden.apply(f0), hidden.apply(f1), hidden.apply(f2)}, hidden.apply(camera));
  EXPECT_NEAR(M.apply(hidden.apply(f2)).z, 0, 1e-9);
  EXPECT_NEAR(M.apply(hidden.apply(camera)).z, 1.5, 1e-9);  // above the floor, in metres
  EXPECT_NEAR(M.apply(hidden.apply(top)).z, 2.6, 1e-9);
  EXPECT_NEAR(glm::length(M.apply(hidden.apply(f2)) - M.apply(hidden.apply(f0))), std::sqrt(41.0), 1e-9);
  const std::string e = errorText([&] { metricFrame(f0, f1, 4.0, {f0, f1, {8, 0, 0}}, camera); });
  EXPECT_NE(e.find("collinear"), std::string::npos) << e;
}

// ---------------------------------------------------------------- cameras from clicks

namespace {
// Five photos of a room corner region and 36 clicked points on floor, walls and a table, clicked
// with 0.5 px noise: the true cameras and the tracks.
struct ClickedRoom {
  std::vector<Camera> truth;
  std::vector<glm::dvec3> points;
  std::vector<Track> tracks;
};
ClickedRoom clickedRoom() {
  ClickedRoom r;
  for (int i = 0; i < 5; ++i)
    r.truth.push_back(Camera::lookAt({0.6 + 0.7 * i, 0.5 + 0.3 * (i % 3), 1.4 + 0.15 * (i % 2)}, {2.0 + 0.2 * (i - 2), 4.0, 0.9},
                                     1600, 1200, 1385));
  for (int i = 0; i < 12; ++i) r.points.push_back({0.3 + 0.3 * i, 5.0, 0.2 + 0.18 * i});          // back wall
  for (int i = 0; i < 12; ++i) r.points.push_back({0.4 + 0.28 * i, 3.0 + 0.15 * (i % 4), 0.0});  // floor
  for (int i = 0; i < 12; ++i) r.points.push_back({1.5 + 0.1 * (i % 6), 3.6 + 0.2 * (i / 6), 0.75 + 0.02 * i});  // table
  std::mt19937 rng(21);
  std::normal_distribution<double> N(0, 0.5);
  for (size_t k = 0; k < r.points.size(); ++k) {
    Track t;
    t.name = "p" + std::to_string(k);
    for (int i = 0; i < 5; ++i) {
      glm::dvec2 px;
      if (r.truth[i].project(r.points[k], px) && px.x > 0 && px.y > 0 && px.x < 1600 && px.y < 1200)
        t.clicks.emplace_back(i, px + glm::dvec2(N(rng), N(rng)));
    }
    r.tracks.push_back(t);
  }
  return r;
}
}  // namespace

TEST(MetricFrame, UpFromTheCamerasIgnoresTheirPitch) {
  // Five photos around a room, each pitched down 25 degrees, none rolled: up is +z exactly, where
  // the mean of the photos' up directions leans 25 degrees.
  ColmapModel m;
  const double pitch = 25 * std::numbers::pi / 180;
  for (int k = 0; k < 5; ++k) {
    const double a = 0.3 + 1.1 * k;
    const glm::dvec3 f(std::cos(a), std::sin(a), 0), down(0, 0, -1), x(std::sin(a), -std::cos(a), 0);
    const glm::dvec3 z = std::cos(pitch) * f + std::sin(pitch) * down, y = glm::cross(z, x);
    ColmapImage im;
    im.id = k + 1;
    im.setRotation(glm::transpose(glm::dmat3(x, y, z)));
    m.images[im.id] = im;
  }
  EXPECT_LT(glm::length(estimateUp(m) - glm::dvec3(0, 0, 1)), 1e-6);
  // In any frame: the same model turned by a rotation gives the turned up.
  Similarity S;
  S.R = glm::dmat3(glm::dvec3(0.36, 0.48, -0.8), glm::dvec3(-0.8, 0.6, 0), glm::dvec3(0.48, 0.64, 0.6));
  transformModel(m, S);
  EXPECT_LT(glm::length(estimateUp(m) - S.R * glm::dvec3(0, 0, 1)), 1e-6);
  // The sample room's cameras (metric, +z up): within 2 degrees.
  const ColmapModel room = readColmapModel(std::string(RELUME_SOURCE_DIR) + "/resources/sample_room/colmap");
  const double deg = std::acos(std::clamp(estimateUp(room).z, -1.0, 1.0)) * 180 / std::numbers::pi;
  std::printf("sample room: up from the cameras %.2f degrees from +z\n", deg);
  EXPECT_LT(deg, 2.0);
}

TEST(Correspondences, CamerasFromThirtyClicksMatchTheTruth) {
  const ClickedRoom room = clickedRoom();
  const std::vector<Camera>& truth = room.truth;
  const std::vector<glm::dvec3>& pts = room.points;
  const std::vector<Track>& tracks = room.tracks;
  std::vector<Camera> intr = truth;
  const CameraSolution sol = solveCameras(intr, {"a", "b", "c", "d", "e"}, tracks);
  std::vector<glm::dvec3> est, tru;
  for (int i = 0; i < 5; ++i) {
    ASSERT_TRUE(sol.posed[i]) << "photo " << i;
    est.push_back(sol.cameras[i].center());
    tru.push_back(truth[i].center());
  }
  const CenterAlignment a = alignCenters(est, tru);
  std::printf("cameras from 36 clicked points: largest centre error %.4f m, rms %.3f px\n", a.max, sol.rmsError);
  EXPECT_LT(a.max, 0.01) << "camera centres after the similarity fit";
  EXPECT_LT(sol.rmsError, 1.0);
  // Points land within a centimetre or two after the same similarity.
  double worst = 0;
  for (size_t k = 0; k < pts.size(); ++k)
    if (sol.triangulated[k]) worst = std::max(worst, glm::length(a.S.apply(sol.points[k].X) - pts[k]));
  EXPECT_LT(worst, 0.02);
}

// A click 40 px off (a mis-click): the robust loss keeps the cameras where the other clicks put
// them, and the bundle adjustment names it as beyond the robust scale.
TEST(Correspondences, AMisclickDoesNotBendTheCameras) {
  ClickedRoom room = clickedRoom();
  const std::vector<Camera>& truth = room.truth;
  std::vector<Track>& tracks = room.tracks;
  // Point 30 clicked 40 px to the right in its third photo.
  ASSERT_GE(tracks[30].clicks.size(), 3u);
  tracks[30].clicks[2].second.x += 40.0;
  const CameraSolution sol = solveCameras(truth, {"a", "b", "c", "d", "e"}, tracks);
  std::vector<glm::dvec3> est, tru;
  for (int i = 0; i < 5; ++i) {
    ASSERT_TRUE(sol.posed[i]);
    est.push_back(sol.cameras[i].center());
    tru.push_back(truth[i].center());
  }
  const CenterAlignment a = alignCenters(est, tru);
  std::printf("with one click 40 px off: largest centre error %.4f m, %zu click(s) flagged\n", a.max, sol.bundle.beyondRobust);
  EXPECT_LT(a.max, 0.01);
  EXPECT_GE(sol.bundle.beyondRobust, 1u);
  EXPECT_LE(sol.bundle.beyondRobust, 3u);
}

// Bundle adjustment from a perturbed start: 8 cameras, 100 points, 0.5 px noise. It comes back to
// the truth (up to the noise), the fixed camera does not move, and the held scale stays.
TEST(Bundle, PerturbedCamerasAndPointsReturnToTheTruth) {
  std::mt19937 rng(5);
  std::normal_distribution<double> N(0, 1);
  std::vector<Camera> truth;
  for (int i = 0; i < 8; ++i)
    truth.push_back(Camera::lookAt({0.5 + 0.5 * i, 0.4 + 0.2 * (i % 3), 1.3 + 0.1 * (i % 2)}, {2.2, 4.0, 1.0}, 1600, 1200, 1400));
  std::vector<glm::dvec3> X;
  for (int k = 0; k < 100; ++k) X.push_back({0.5 + 3.0 * (k % 10) / 9.0, 3.5 + 1.5 * ((k / 10) % 2), 0.1 + 2.2 * (k / 10) / 9.0});
  std::vector<BundleObservation> obs;
  for (int i = 0; i < 8; ++i)
    for (int k = 0; k < 100; ++k) {
      glm::dvec2 px;
      if (truth[i].project(X[k], px) && px.x > 0 && px.y > 0 && px.x < 1600 && px.y < 1200)
        obs.push_back({i, k, px + 0.5 * glm::dvec2(N(rng), N(rng))});
    }
  std::vector<Camera> cams = truth;
  std::vector<glm::dvec3> pts = X;
  for (int i = 2; i < 8; ++i) {
    cams[i].t += 0.03 * glm::dvec3(N(rng), N(rng), N(rng));
    const double a = 0.01;
    glm::dmat3 Rx(1.0);
    Rx[1][1] = Rx[2][2] = std::cos(a);
    Rx[1][2] = std::sin(a);
    Rx[2][1] = -std::sin(a);
    cams[i].R = Rx * cams[i].R;
  }
  for (auto& p : pts) p += 0.02 * glm::dvec3(N(rng), N(rng), N(rng));
  const glm::dvec3 heldT = cams[1].t;
  const BundleReport r = bundleAdjust(cams, pts, obs, {0}, 1);
  std::vector<glm::dvec3> est, tru;
  for (int i = 0; i < 8; ++i) est.push_back(cams[i].center()), tru.push_back(truth[i].center());
  const CenterAlignment a = alignCenters(est, tru);
  double worst = 0;
  for (int k = 0; k < 100; ++k) worst = std::max(worst, glm::length(a.S.apply(pts[k]) - X[k]));
  std::printf("bundle adjustment: rms %.2f -> %.3f px in %d iterations; centres within %.4f m, points within %.4f m\n",
              r.initialRms, r.rms, r.iterations, a.max, worst);
  EXPECT_TRUE(r.converged);
  EXPECT_GT(r.initialRms, 5.0);
  EXPECT_LT(r.rms, 0.6);
  EXPECT_LT(a.max, 0.005);
  EXPECT_LT(worst, 0.01);
  EXPECT_EQ(cams[0].t, truth[0].t) << "the fixed camera stays";
  EXPECT_EQ(cams[0].R, truth[0].R);
  int largest = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(heldT[k]) > std::abs(heldT[largest])) largest = k;
  EXPECT_EQ(cams[1].t[largest], heldT[largest]) << "the scale gauge stays";
  EXPECT_THROW(bundleAdjust(cams, pts, obs, {}), Error) << "no gauge";
}

TEST(Correspondences, RelativePoseNeedsEightClicks) {
  const std::string e = errorText([] { relativePose({{1, 1}, {2, 2}}, {{1, 1}, {2, 2}}, glm::dmat3(1.0), glm::dmat3(1.0)); });
  EXPECT_NE(e.find("8 or more"), std::string::npos) << e;
}

// ---------------------------------------------------------------- HDR

TEST(Hdr, EvStepsFollowTheFStopTable) {
  EXPECT_DOUBLE_EQ(exposureFromEv(0, 0.1), 0.1);
  EXPECT_DOUBLE_EQ(exposureFromEv(-2, 0.1), 0.025);
  EXPECT_NEAR(exposureFromEv(1.5, 1), 2 * std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(exposureFromEv(-0.5, 1), 1 / std::sqrt(2.0), 1e-12);
}

TEST(Hdr, MergedBracketRecoversRadianceRatiosWithin5Percent) {
  // A radiance image spanning 1:2000 and a camera response that is not a power law.
  const int w = 96, h = 64;
  std::vector<double> E(w * h);
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> U(0, 1);
  for (int i = 0; i < w * h; ++i) E[i] = std::exp(std::log(0.0005) * (1 - (i % w) / double(w - 1)) + 0.2 * U(rng));
  auto response = [](double x) {  // film-like S curve on log exposure
    const double v = std::log10(std::max(x, 1e-9));
    return 255.0 / (1 + std::exp(-2.2 * (v + 1.0)));
  };
  // Two stops apart, covering the scene: every pixel is well exposed in at least one image.
  const std::vector<double> times = {1.0 / 64, 1.0 / 16, 1.0 / 4, 1.0, 4.0, 16.0, 64.0};
  std::vector<Image8> bracket;
  for (double t : times) {
    Image8 im;
    im.width = w;
    im.height = h;
    im.pixels.resize(size_t(w) * h * 3);
    for (int i = 0; i < w * h; ++i)
      for (int c = 0; c < 3; ++c) {
        const double tint = 1.0 + 0.2 * c;
        im.pixels[3 * i + c] = (unsigned char)std::clamp(std::lround(response(E[i] * tint * t)), 0L, 255L);
      }
    bracket.push_back(im);
  }
  const HdrResult r = mergeBracket(bracket, times, {"1", "2", "3", "4", "5", "6", "7"}, silentProgress());
  // One scale per channel (radiance is relative); then every pixel's ratio to the truth.
  for (int c = 0; c < 3; ++c) {
    std::vector<double> ratio;
    for (int i = 0; i < w * h; ++i) ratio.push_back(r.radiance.pixels[3 * i + c] / (E[i] * (1.0 + 0.2 * c)));
    std::vector<double> sorted = ratio;
    std::sort(sorted.begin(), sorted.end());
    const double scale = sorted[sorted.size() / 2];
    double worst = 0;
    for (double q : ratio) worst = std::max(worst, std::abs(q / scale - 1));
    std::printf("HDR merge, channel %d: largest radiance-ratio error %.2f %%\n", c, 100 * worst);
    EXPECT_LT(worst, 0.05) << "channel " << c;
  }
}

TEST(Hdr, UnreadableAndMismatchedExposuresAreNamed) {
  const fs::path d = tempDir("hdr");
  Image8 a;
  a.width = 32, a.height = 24;
  a.pixels.assign(32 * 24 * 3, 100);
  writeImage8((d / "a.png").string(), a);
  Image8 b = a;
  b.width = 16;
  b.pixels.resize(16 * 24 * 3);
  writeImage8((d / "b.png").string(), b);
  std::string e = errorText([&] { mergeBracket({(d / "a.png").string(), (d / "b.png").string()}, {0.1, 0.4}, silentProgress()); });
  EXPECT_NE(e.find("b.png"), std::string::npos) << e;
  // A truncated file.
  fs::copy_file(d / "a.png", d / "cut.png");
  fs::resize_file(d / "cut.png", fs::file_size(d / "cut.png") / 3);
  e = errorText([&] { mergeBracket({(d / "a.png").string(), (d / "cut.png").string()}, {0.1, 0.4}, silentProgress()); });
  EXPECT_NE(e.find("cut.png"), std::string::npos) << e;
  // No exposure data at all.
  e = errorText([&] { mergeBracket({(d / "a.png").string(), (d / "a.png").string()}, {}, silentProgress()); });
  EXPECT_NE(e.find("exposure"), std::string::npos) << e;
}

// ---------------------------------------------------------------- calibration


TEST(Calibration, CheckerboardPhotosGiveTheIntrinsics) {
  const fs::path d = tempDir("calib");
  const int cols = 9, rows = 6;
  const double sq = 0.025, k1 = -0.12;
  std::vector<std::string> files;
  const glm::dvec3 centre(4 * sq, 2.5 * sq, 0);
  const glm::dvec3 eyes[] = {{0.0, -0.1, -0.45}, {0.25, 0.1, -0.4}, {-0.1, 0.25, -0.42}, {0.3, -0.15, -0.5},
                             {-0.15, -0.2, -0.38}, {0.1, 0.3, -0.5}, {0.35, 0.2, -0.35}, {-0.2, 0.05, -0.45}};
  int i = 0;
  for (const auto& e : eyes) {
    Camera cam = Camera::lookAt(centre + e, centre, 640, 480, 600);
    const std::string f = (d / ("board" + std::to_string(i++) + ".png")).string();
    writeImage8(f, test::renderCheckerboard(cam, k1, cols, rows, sq));
    files.push_back(f);
  }
  const Intrinsics in = calibrateCheckerboard(files, cols, rows, sq, silentProgress());
  std::printf("calibration: fx %.2f fy %.2f cx %.2f cy %.2f k1 %.4f rms %.3f px (true 600, 600, 320, 240, %.2f)\n", in.fx,
              in.fy, in.cx, in.cy, in.k1, in.rms, k1);
  EXPECT_EQ(in.used.size(), files.size());
  EXPECT_NEAR(in.fx, 600, 6);
  EXPECT_NEAR(in.fy, 600, 6);
  EXPECT_NEAR(in.cx, 320, 4);
  EXPECT_NEAR(in.cy, 240, 4);
  EXPECT_NEAR(in.k1, k1, 0.03);
  EXPECT_LT(in.rms, 0.5);
}

TEST(Calibration, FisheyeCheckerboardPhotosGiveTheLensAnglesBack) {
  // Photos of the board through a 190-degree-class fisheye (OpenCV's model with distortion), the
  // board seen on the axis and towards the image's edges; the calibrated lens must give back the
  // angle from the axis of every image radius the views covered.
  const fs::path d = tempDir("fisheye_calib");
  const int cols = 9, rows = 6;
  const double sq = 0.025, f = 190, cx = 322.4, cy = 238.1;
  const double k[4] = {0.02, -0.015, 0.003, -0.0004};
  const glm::dvec3 centre(4 * sq, 2.5 * sq, 0);
  std::vector<std::string> files;
  int i = 0;
  // Twelve views from in front of the board (z < 0), 22-30 cm from its centre and seen from up to
  // 25 degrees off its normal, the optical axis turned away from the board by 0, 20 or 38 degrees
  // in twelve directions: the board lands on the axis and out to about 60 degrees from it.
  for (int v = 0; v < 12; ++v) {
    const double alpha = (v == 0 ? 0.0 : v < 5 ? 20.0 : 38.0) * M_PI / 180, phi = v * 137.5 * M_PI / 180;
    const double beta = (v % 3) * 12.5 * M_PI / 180, psi = v * 73.0 * M_PI / 180, dist = 0.22 + 0.08 * (v % 2);
    const glm::dvec3 eye = centre + dist * glm::dvec3(std::sin(beta) * std::cos(psi), std::sin(beta) * std::sin(psi), -std::cos(beta));
    const glm::dvec3 toBoard = glm::normalize(centre - eye);
    const glm::dvec3 side = glm::normalize(glm::cross(toBoard, glm::dvec3(std::cos(phi), std::sin(phi), 0.0)));
    const glm::dvec3 z = glm::normalize(std::cos(alpha) * toBoard + std::sin(alpha) * glm::cross(side, toBoard));
    const glm::dvec3 down = glm::normalize(glm::dvec3(0, 1, 0) - z * z.y), xAxis = glm::cross(down, z);
    Camera cam;
    cam.width = 640, cam.height = 480;
    cam.R = glm::transpose(glm::dmat3(xAxis, down, z));  // rows: the camera's axes in the world
    cam.t = -(cam.R * eye);
    const std::string file = (d / ("fisheye" + std::to_string(i++) + ".png")).string();
    writeImage8(file, test::renderFisheyeCheckerboard(cam, f, cx, cy, k, cols, rows, sq));
    files.push_back(file);
  }
  const FisheyeCalibration cal = calibrateFisheyeCheckerboard(files, cols, rows, sq, silentProgress());
  const FisheyeLens& in = cal.lens;
  std::printf("fisheye calibration: fx %.2f fy %.2f cx %.2f cy %.2f k %.4f %.4f %.4f %.4f rms %.3f px, %zu of %zu photos\n",
              in.fx, in.fy, in.cx, in.cy, in.k[0], in.k[1], in.k[2], in.k[3], in.rms, cal.used.size(), files.size());
  ASSERT_GE(cal.used.size(), 8u) << "the board must be found in most photos";
  EXPECT_LT(in.rms, 0.3);
  EXPECT_NEAR(in.fx, f, 0.01 * f);
  EXPECT_NEAR(in.fy, f, 0.01 * f);
  EXPECT_NEAR(in.cx, cx, 1.5);
  EXPECT_NEAR(in.cy, cy, 1.5);
  // The angle at each image radius out to 60 degrees from the axis.
  auto thetaD = [](const double (&kk)[4], double t) {
    const double t2 = t * t;
    return t * (1 + t2 * (kk[0] + t2 * (kk[1] + t2 * (kk[2] + t2 * kk[3]))));
  };
  const double reach = 60 * M_PI / 180;
  double worst = 0;
  for (double t = 0.01; t <= reach; t += 0.01) {
    const double rTrue = f * thetaD(k, t);
    // the calibrated lens's angle at that radius (bisection on its own model)
    double lo = 0, hi = M_PI;
    for (int it = 0; it < 60; ++it) (in.fx * thetaD(in.k, 0.5 * (lo + hi)) < rTrue ? lo : hi) = 0.5 * (lo + hi);
    worst = std::max(worst, std::abs(0.5 * (lo + hi) - t));
  }
  std::printf("fisheye calibration: worst angle error up to 60 degrees from the axis %.3f degrees\n", worst * 180 / M_PI);
  EXPECT_LT(worst * 180 / M_PI, 0.2);
  // Kept as JSON and read back (the lens `relume sky --lens` reads).
  const std::string json = (d / "lens.json").string();
  FisheyeLens withCircle = in;
  withCircle.circleX = 320, withCircle.circleY = 240, withCircle.circleRadius = 231.5;
  writeFisheyeLens(withCircle, json);
  const FisheyeLens back = readFisheyeLens(json);
  EXPECT_DOUBLE_EQ(back.fx, in.fx);
  EXPECT_DOUBLE_EQ(back.k[3], in.k[3]);
  EXPECT_DOUBLE_EQ(back.circleRadius, 231.5);
  // A pinhole calibration is not a fisheye lens: refused naming the file and the field.
  Intrinsics pin;
  pin.width = 640, pin.height = 480, pin.fx = pin.fy = 500, pin.cx = 320, pin.cy = 240;
  writeIntrinsics(pin, json);
  const std::string e = errorText([&] { readFisheyeLens(json); });
  EXPECT_NE(e.find("lens.json"), std::string::npos) << e;
  EXPECT_NE(e.find("OPENCV_FISHEYE"), std::string::npos) << e;
}

TEST(Calibration, NoCheckerboardIsAClearError) {
  const fs::path d = tempDir("nocalib");
  Image8 blank;
  blank.width = 320, blank.height = 240;
  blank.pixels.assign(320 * 240 * 3, 128);
  std::vector<std::string> files;
  for (int i = 0; i < 3; ++i) {
    files.push_back((d / ("wall" + std::to_string(i) + ".png")).string());
    writeImage8(files.back(), blank);
  }
  const std::string e = errorText([&] { calibrateCheckerboard(files, 9, 6, 0.025, silentProgress()); });
  EXPECT_NE(e.find("checkerboard"), std::string::npos) << e;
  EXPECT_NE(e.find("wall0.png"), std::string::npos) << e;
}

// ---------------------------------------------------------------- COLMAP driver

namespace {
// A folder with two flat grey photos a.png and b.png.
fs::path twoFlatPhotos(const std::string& name) {
  const fs::path d = tempDir(name);
  Image8 a;
  a.width = 64, a.height = 48;
  a.pixels.assign(64 * 48 * 3, 90);
  writeImage8((d / "a.png").string(), a);
  writeImage8((d / "b.png").string(), a);
  return d;
}
}  // namespace

TEST(ColmapDriver, MissingColmapSaysHowToInstallIt) {
  const fs::path d = twoFlatPhotos("nocolmap");
  ColmapOptions o;
  o.executable = "relume-no-such-colmap";
  const std::string e = errorText([&] { runColmap(d.string(), (d / "ws").string(), o, silentProgress()); });
  EXPECT_NE(e.find("not installed"), std::string::npos) << e;
  EXPECT_NE(e.find("apt-get install colmap"), std::string::npos) << e;
}

TEST(ColmapDriver, TruncatedPhotoIsNamedBeforeColmapRuns) {
  const fs::path d = twoFlatPhotos("truncated");
  fs::resize_file(d / "b.png", fs::file_size(d / "b.png") / 2);
  const std::string e = errorText([&] { runColmap(d.string(), (d / "ws").string(), {}, silentProgress()); });
  EXPECT_NE(e.find("b.png"), std::string::npos) << e;
}

TEST(ColmapDriver, FewerThanTwoRegisteredPhotosNamesThem) {
  if (!colmapAvailable()) GTEST_SKIP() << "colmap is not installed";
  const fs::path d = tempDir("unrelated");
  std::mt19937 rng(1);
  for (const char* n : {"noise1.png", "noise2.png", "noise3.png"}) {
    Image8 a;
    a.width = 160, a.height = 120;
    a.pixels.resize(160 * 120 * 3);
    for (auto& p : a.pixels) p = (unsigned char)(rng() % 256);
    writeImage8((d / n).string(), a);
  }
  const std::string e = errorText([&] { runColmap(d.string(), (d / "ws").string(), {}, silentProgress()); });
  EXPECT_NE(e.find("fewer than 2"), std::string::npos) << e;
  EXPECT_NE(e.find("noise2.png"), std::string::npos) << e;
  EXPECT_FALSE(fs::exists(d / "ws" / "sparse" / "cameras.txt"));
}

// ---------------------------------------------------------------- match proposals

#include "relume/project/room_io.h"
#include "relume/reconstruct/clicks.h"
#include "relume/reconstruct/matching.h"

TEST(MatchProposals, EpipolarSearchFindsTheClickedPointInAnotherPhoto) {
  // The corners of the sample room's clicks that the main photo shows: where are they in the
  // other photos that show them? (The clicks mark the truth, to the pixel.)
  const std::string dir = std::string(RELUME_SOURCE_DIR) + "/resources/sample_room";
  const Scene room = loadRoom(dir);
  const Clicks clicks = readClicks(dir + "/clicks.json");
  const Photo* a = room.findPhoto("main");
  ASSERT_NE(a, nullptr);
  const Image8 ia = readImage8(dir + "/" + a->file);
  std::map<std::string, Image8> others;
  int tried = 0, found = 0, foundTop3 = 0, foundFree = 0;
  std::vector<double> epipolarMs;
  for (const auto& [name, pt] : clicks.points) {
    glm::dvec2 pa(-1);
    for (const auto& [photo, px] : pt.clicks)
      if (photo == "main") pa = px;
    if (pa.x < 10 || pa.y < 10 || pa.x > ia.width - 10 || pa.y > ia.height - 10) continue;
    for (const auto& [photo, pb] : pt.clicks) {
      if (photo == "main") continue;
      const Photo* b = room.findPhoto(photo);
      if (!others.count(photo)) others[photo] = readImage8(dir + "/" + b->file);
      ++tried;
      const auto t0 = std::chrono::steady_clock::now();
      const auto m = proposeMatches(ia, pa, others[photo], &a->camera, &b->camera, 3, 7, glm::dvec3(0, 0, 1));  // metric: +z up
      epipolarMs.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      found += !m.empty() && glm::length(m[0].pixel - pb) <= 2;
      bool inTop = false;
      for (const auto& q : m) inTop = inTop || glm::length(q.pixel - pb) <= 2;
      foundTop3 += inTop;
      bool any = false;
      for (const auto& q : proposeMatches(ia, pa, others[photo], nullptr, nullptr)) any = any || glm::length(q.pixel - pb) <= 2;
      foundFree += any;
    }
  }
  std::sort(epipolarMs.begin(), epipolarMs.end());
  std::printf("match proposals: %d of %d best on the epipolar line, %d among its 3; %d among 3 without cameras; "
              "%.1f ms per photo (median, 640 x 480)\n",
              found, tried, foundTop3, foundFree, epipolarMs.empty() ? 0.0 : epipolarMs[epipolarMs.size() / 2]);
  ASSERT_GE(tried, 10);
  // Measured with a fronto-parallel sweep only: 66 of 139 (47 %) best, 72 among three; with the
  // horizontal and vertical plane hypotheses: 93 (67 %), 105. Corners on occluding edges look
  // different from each side, which no patch comparison fully follows.
  EXPECT_GE(found, 0.6 * tried) << "best epipolar proposal within 2 px";
  EXPECT_GE(foundTop3, found);
  EXPECT_GT(found, 2 * foundFree) << "knowing the cameras (plane sweep on the epipolar line) helps";
}


TEST(MatchProposals, AllPhotosAtOnceAndThePlanesOfPolygonsAlreadyBuilt) {
  // Every clicked corner of the sample room that the main photo shows, its proposals in the other
  // photos that show it: one photo at a time; in all six photos at once (a depth is scored in
  // every photo); and at once with the planes of the polygons built from the other points (as a
  // user models the room polygon by polygon: the corner itself is left out of every fit).
  const std::string dir = std::string(RELUME_SOURCE_DIR) + "/resources/sample_room";
  const Scene room = loadRoom(dir);
  const Clicks clicks = readClicks(dir + "/clicks.json");
  std::map<std::string, glm::dvec3> positions;
  for (const auto& [name, pt] : clicks.points) {
    std::vector<Observation> obs;
    for (const auto& [photo, px] : pt.clicks) obs.push_back({&room.findPhoto(photo)->camera, photo, px});
    if (obs.size() >= 2) positions[name] = triangulatePoint(obs, name).X;
  }
  const Photo* a = room.findPhoto("main");
  const MatchImage ia = prepareForMatching(readImage8(dir + "/" + a->file));
  std::vector<std::string> names;
  std::vector<MatchImage> images;
  for (const auto& p : room.photos)
    if (p.name != "main") {
      names.push_back(p.name);
      images.push_back(prepareForMatching(readImage8(dir + "/" + p.file)));
    }
  std::vector<const MatchImage*> others;
  std::vector<const Camera*> cams;
  for (size_t j = 0; j < names.size(); ++j) {
    others.push_back(&images[j]);
    cams.push_back(&room.findPhoto(names[j])->camera);
  }
  int tried = 0, single = 0, together = 0, withPlanes = 0;
  for (const auto& [name, pt] : clicks.points) {
    glm::dvec2 pa(-1);
    for (const auto& [photo, px] : pt.clicks)
      if (photo == "main") pa = px;
    if (pa.x < 10 || pa.y < 10 || pa.x > ia.width - 10 || pa.y > ia.height - 10) continue;
    const auto all = proposeMatchesInPhotos(ia, pa, a->camera, others, cams, 3, 7, glm::dvec3(0, 0, 1));
    const auto allPlanes =
        proposeMatchesInPhotos(ia, pa, a->camera, others, cams, 3, 7, glm::dvec3(0, 0, 1), polygonPlanes(clicks, positions, name));
    for (const auto& [photo, pb] : pt.clicks) {
      if (photo == "main") continue;
      const size_t j = size_t(std::find(names.begin(), names.end(), photo) - names.begin());
      ASSERT_LT(j, names.size());
      ++tried;
      const auto m = proposeMatches(ia, pa, images[j], &a->camera, cams[j], 3, 7, glm::dvec3(0, 0, 1));
      auto hit = [&](const std::vector<MatchProposal>& v) { return !v.empty() && glm::length(v[0].pixel - pb) <= 2; };
      single += hit(m);
      together += hit(all[j]);
      withPlanes += hit(allPlanes[j]);
      if (getenv("DEBUG_PROPOSALS") && !hit(allPlanes[j]))
        std::printf("miss %s in %s: %.1f px\n", name.c_str(), photo.c_str(), allPlanes[j].empty() ? -1.0 : glm::length(allPlanes[j][0].pixel - pb));
    }
  }
  std::printf("match proposals, best within 2 px: %d of %d one photo at a time, %d in all photos at once, %d also on the "
              "planes of built polygons\n", single, tried, together, withPlanes);
  ASSERT_GE(tried, 10);
  EXPECT_GE(together, single);
  EXPECT_GE(withPlanes, 0.7 * tried);
}

TEST(MatchProposals, LargePhotosAreSweptCoarseAndRefinedAtFullSize) {
  // The sample room's photos at 4x (2560 x 1920, bilinear): proposals are swept on the 640 x 480
  // level and refined at full size; they land within 8 px (2 px at the original size) about as
  // often as on the originals, and at the full size's precision.
  const std::string dir = std::string(RELUME_SOURCE_DIR) + "/resources/sample_room";
  const Scene room = loadRoom(dir);
  const Clicks clicks = readClicks(dir + "/clicks.json");
  auto upscale = [](const Image8& in, int k) { return resizeImage8(in, in.width * k, in.height * k); };
  const int k = 4;
  auto scaledCamera = [&](Camera c) {
    c.K[0][0] *= k, c.K[1][1] *= k, c.K[2][0] *= k, c.K[2][1] *= k;
    c.width *= k, c.height *= k;
    return c;
  };
  const Photo* a = room.findPhoto("main");
  const MatchImage ia = prepareForMatching(upscale(readImage8(dir + "/" + a->file), k));
  ASSERT_EQ(ia.levels.size(), 3u);  // 2560, 1280, 640 across
  const Camera ca = scaledCamera(a->camera);
  std::map<std::string, MatchImage> others;
  int tried = 0, found = 0;
  std::vector<double> ms, err;
  for (const auto& [name, pt] : clicks.points) {
    glm::dvec2 pa(-1);
    for (const auto& [photo, px] : pt.clicks)
      if (photo == "main") pa = px;
    if (pa.x < 10 || pa.y < 10 || pa.x > 630 || pa.y > 470) continue;
    for (const auto& [photo, pb] : pt.clicks) {
      if (photo == "main") continue;
      const Photo* b = room.findPhoto(photo);
      if (!others.count(photo)) others[photo] = prepareForMatching(upscale(readImage8(dir + "/" + b->file), k));
      const Camera cb = scaledCamera(b->camera);
      ++tried;
      const auto t0 = std::chrono::steady_clock::now();
      const auto m = proposeMatches(ia, pa * double(k), others[photo], &ca, &cb, 3, 7 * k, glm::dvec3(0, 0, 1));
      ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      if (!m.empty() && glm::length(m[0].pixel - pb * double(k)) <= 2 * k) {
        ++found;
        err.push_back(glm::length(m[0].pixel - pb * double(k)));
      }
    }
  }
  std::sort(ms.begin(), ms.end());
  std::sort(err.begin(), err.end());
  std::printf("match proposals at 2560 x 1920: %d of %d best within 8 px (median distance %.2f px); %.1f ms per photo (median)\n",
              found, tried, err.empty() ? 0.0 : err[err.size() / 2], ms.empty() ? 0.0 : ms[ms.size() / 2]);
  ASSERT_GE(tried, 10);
  EXPECT_GE(found, 0.6 * tried);
}

TEST(MatchProposals, LensDistortionIsTakenOutOfThePhotos) {
  // The sample room photographed through a barrel-distorting lens (COLMAP's SIMPLE_RADIAL, k =
  // -0.2): prepared with their camera, the photos are swept as pinholes and the proposals come back
  // in the distorted photo, as often on the corners as without a lens; taken as pinholes, they
  // are not.
  const std::string dir = std::string(RELUME_SOURCE_DIR) + "/resources/sample_room";
  const Scene room = loadRoom(dir);
  const Clicks clicks = readClicks(dir + "/clicks.json");
  auto lens = [](const Camera& c) {
    ColmapCamera l;
    l.model = "SIMPLE_RADIAL";
    l.width = c.width, l.height = c.height;
    l.params = {c.fx(), c.cx(), c.cy(), -0.2};
    return l;
  };
  auto through = [](const Image8& in, const ColmapCamera& l) {  // what the lens makes of a pinhole photo
    Image8 out = in;
    for (int y = 0; y < in.height; ++y)
      for (int x = 0; x < in.width; ++x) {
        const glm::dvec2 p = pinholePixel(l, glm::dvec2(x + 0.5, y + 0.5)) - 0.5;
        const int x0 = std::clamp(int(std::floor(p.x)), 0, in.width - 2), y0 = std::clamp(int(std::floor(p.y)), 0, in.height - 2);
        const double fx = std::clamp(p.x - x0, 0.0, 1.0), fy = std::clamp(p.y - y0, 0.0, 1.0);
        for (int c = 0; c < 3; ++c) {
          auto at = [&](int xx, int yy) { return double(in.pixels[(size_t(yy) * in.width + xx) * 3 + c]); };
          out.pixels[(size_t(y) * in.width + x) * 3 + c] = (unsigned char)std::lround(
              (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x0 + 1, y0)) + fy * ((1 - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1)));
        }
      }
    return out;
  };
  const Photo* a = room.findPhoto("main");
  const ColmapCamera la = lens(a->camera);
  const Image8 da = through(readImage8(dir + "/" + a->file), la);
  const MatchImage undistortedA = prepareForMatching(da, la), rawA = prepareForMatching(da);
  std::map<std::string, std::pair<MatchImage, MatchImage>> others;
  int tried = 0, found = 0, foundRaw = 0;
  for (const auto& [name, pt] : clicks.points) {
    glm::dvec2 pa(-1);
    for (const auto& [photo, px] : pt.clicks)
      if (photo == "main") pa = distortedPixel(la, px);
    if (pa.x < 10 || pa.y < 10 || pa.x > 630 || pa.y > 470) continue;
    for (const auto& [photo, px] : pt.clicks) {
      if (photo == "main") continue;
      const Photo* b = room.findPhoto(photo);
      const ColmapCamera lb = lens(b->camera);
      if (!others.count(photo)) {
        const Image8 db = through(readImage8(dir + "/" + b->file), lb);
        others.emplace(photo, std::make_pair(prepareForMatching(db, lb), prepareForMatching(db)));
      }
      const glm::dvec2 pb = distortedPixel(lb, px);
      if (pb.x < 0 || pb.y < 0 || pb.x > 640 || pb.y > 480) continue;
      ++tried;
      const auto m = proposeMatches(undistortedA, pinholePixel(la, pa), others.at(photo).first, &a->camera, &b->camera, 3, 7,
                                    glm::dvec3(0, 0, 1));
      found += !m.empty() && glm::length(distortedPixel(lb, m[0].pixel) - pb) <= 2;
      const auto r = proposeMatches(rawA, pa, others.at(photo).second, &a->camera, &b->camera, 3, 7, glm::dvec3(0, 0, 1));
      foundRaw += !r.empty() && glm::length(r[0].pixel - pb) <= 2;
    }
  }
  std::printf("match proposals through a lens (k = -0.2): %d of %d best within 2 px with the distortion taken out, %d taken "
              "as pinholes\n", found, tried, foundRaw);
  ASSERT_GE(tried, 10);
  EXPECT_GE(found, 0.6 * tried);
  EXPECT_GT(found, foundRaw + tried / 10);
}

// ---------------------------------------------------------------- photo import

TEST(PhotoImport, ExifBracketsAreGroupedAndMergedPerViewpoint) {
  const fs::path in = tempDir("brackets"), out = in / "merged";
  // Two viewpoints: a bracket with exposure times, a bracket with EV steps only (Appendix B), and
  // one photo without EXIF. A scene of two patches 16x apart in radiance.
  auto shot = [](double e) {
    Image8 im;
    im.width = 64, im.height = 48;
    im.pixels.resize(64 * 48 * 3);
    for (int y = 0; y < 48; ++y)
      for (int x = 0; x < 64; ++x) {
        const double radiance = (x < 32 ? 0.02 : 0.32) * (1 + 0.3 * y / 47.0);
        const double v = 255 * std::pow(std::min(1.0, radiance * e), 1 / 2.2);
        for (int c = 0; c < 3; ++c) im.pixels[(y * 64 + x) * 3 + c] = (unsigned char)std::lround(v);
      }
    return im;
  };
  const double times[] = {0.25, 1.0, 4.0};
  for (int i = 0; i < 3; ++i) {
    PhotoInfo exif;
    exif.exposureTime = times[i];
    exif.focal35mm = 28;
    exif.make = "Relume", exif.model = "Test";
    // (TIFF: OpenImageIO 2.4 writes a fractional ExposureTime into JPEG EXIF as infinity.)
    writeImage8((in / ("a" + std::to_string(i) + ".tif")).string(), shot(times[i]), exifMetadata(exif));
    PhotoInfo ev;
    ev.hasExposureBias = true;
    ev.exposureBias = 2.0 * (i - 1);
    ev.make = "Relume", ev.model = "Test";
    writeImage8((in / ("b" + std::to_string(i) + ".jpg")).string(), shot(exposureFromEv(ev.exposureBias)), exifMetadata(ev));
  }
  writeImage8((in / "c.png").string(), shot(1.0));
  const PhotoInfo a1 = readPhotoInfo((in / "a0.tif").string());
  EXPECT_NEAR(a1.exposureTime, 0.25, 1e-6);
  EXPECT_NEAR(a1.focalPixels(), 28.0 / 36.0 * 64, 1e-6);
  EXPECT_TRUE(readPhotoInfo((in / "b0.jpg").string()).hasExposureBias);
  const auto groups = mergeBracketFolder(in.string(), out.string(), silentProgress());
  ASSERT_EQ(groups.size(), 3u);
  EXPECT_EQ(groups[0].size(), 3u);
  EXPECT_EQ(groups[1].size(), 3u);
  EXPECT_EQ(groups[2].size(), 1u);
  // One photo per viewpoint: the middle exposures, and a radiance image per bracket whose patch
  // ratio is the scene's (16), within JPEG's and the response fit's error.
  EXPECT_TRUE(fs::exists(out / "a1.tif") && fs::exists(out / "b1.jpg") && fs::exists(out / "c.png"));
  for (const char* exr : {"a1.exr", "b1.exr"}) {
    ASSERT_TRUE(fs::exists(out / exr)) << exr;
    const ImageRGB r = readImageLinear((out / exr).string());
    const double dark = r.at(16, 24).y, bright = r.at(48, 24).y;
    EXPECT_NEAR(bright / dark, 16.0, 16.0 * 0.1) << exr;
  }
  EXPECT_FALSE(fs::exists(out / "c.exr"));
}

// intrinsics.json (relume calibrate) and workspace.json (relume reconstruct) name what is wrong.
TEST(WorkspaceFiles, MalformedIntrinsicsAndWorkspaceDescriptionsAreNamed) {
  const std::string good = R"({"width": 640, "height": 480, "fx": 500, "fy": 501, "cx": 320, "cy": 240, "k1": -0.1})";
  const relume::recon::Intrinsics in = relume::recon::parseIntrinsics(good, "i.json");
  EXPECT_EQ(in.width, 640);
  EXPECT_DOUBLE_EQ(in.k1, -0.1);
  EXPECT_DOUBLE_EQ(in.k2, 0.0);
  // What parsing `json` with `parse` throws ("no error" when it throws nothing).
  auto errorOf = [](auto parse, const std::string& json, const char* name) {
    try {
      parse(json, name);
    } catch (const relume::Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  auto intrinsicsError = [&](const std::string& json) { return errorOf(relume::recon::parseIntrinsics, json, "i.json"); };
  EXPECT_NE(intrinsicsError("{\"width\": 640").find("i.json: is not JSON"), std::string::npos);
  EXPECT_NE(intrinsicsError(R"({"width": 0, "height": 480, "fx": 1, "fy": 1, "cx": 0, "cy": 0})").find("i.json: width: must be a whole number"),
            std::string::npos);
  EXPECT_NE(intrinsicsError(R"({"width": 640, "height": 480, "fx": "500", "fy": 1, "cx": 0, "cy": 0})").find("i.json: fx: must be a number"),
            std::string::npos);
  EXPECT_NE(intrinsicsError(R"({"width": 640, "height": 480, "fx": -5, "fy": 1, "cx": 0, "cy": 0})").find("fx, fy: must be positive"),
            std::string::npos);
  const relume::recon::WorkspaceInfo w =
      relume::recon::parseWorkspaceInfo(R"({"photos": "/data/room", "registered": ["a", "b"], "points": 12, "metric": true})", "w.json");
  EXPECT_EQ(w.photos, "/data/room");
  EXPECT_EQ(w.registered.size(), 2u);
  EXPECT_TRUE(w.metric);
  auto workspaceError = [&](const std::string& json) { return errorOf(relume::recon::parseWorkspaceInfo, json, "w.json"); };
  EXPECT_NE(workspaceError("[1, 2").find("w.json: is not JSON"), std::string::npos);
  EXPECT_NE(workspaceError(R"({"photos": 3})").find("w.json: photos: must be the photos folder"), std::string::npos);
  EXPECT_NE(workspaceError(R"({"registered": "a"})").find("w.json: registered: must be a list of photo names"), std::string::npos);
  EXPECT_NE(workspaceError(R"({"metric": "yes"})").find("w.json: metric: must be true or false"), std::string::npos);
  EXPECT_NE(workspaceError(R"({"points": -4})").find("w.json: points: must be a whole number"), std::string::npos);
}
