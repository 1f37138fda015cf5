// Image fans and image-based objects (Dinh, Metoyer, Turk): meshes read, fans rendered, written
// and read back (bad files refused with the file named), and the object drawn from its fan held
// against a reference renderer that ray-casts the mesh itself (exact normals, the same lamps with
// shadow rays, the same indirect light) — shading and shadows.
#include <gtest/gtest.h>

#include <QByteArray>
#include <zlib.h>

#include <algorithm>
#include <bit>
#include <random>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <numbers>

#include "relume/geometry/error.h"
#include "relume/ibr/fan.h"
#include "relume/ibr/ibr_object.h"
#include "relume/ibr/mesh.h"
#include "relume/ibr/relit_objects.h"
#include "relume/image/image.h"
#include "relume/radiosity/form_factor.h"
#include "relume/radiosity/hierarchy.h"
#include "relume/raytrace/ray_scene.h"
#include "support/error_text.h"
#include "support/test_rooms.h"

using namespace relume;
using namespace relume::ibr;

namespace {

// A smooth bumpy blob standing on z = 0 (radius about r), its colour varying with height.
Mesh blob(int nu = 160, int nv = 80, double r = 0.3, double bump = 0.1) {
  Mesh m = bumpyBall(nu, nv, r, bump);
  m.name = "blob";
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k)
      m.cornerColours.push_back(glm::vec3(0.7f, 0.45f + 0.25f * std::sin(8.f * m.positions[t[k]].z), 0.3f));
  return m;
}

// A closed 4 x 4 x 2.8 m room (normals inward), walls of three colours, and small lamps.
std::vector<radiosity::Surface> room(const std::vector<std::vector<glm::dvec3>>& lamps, glm::dvec3 exitance) {
  const double W = 4, D = 4, H = 2.8;
  std::vector<radiosity::Surface> s;
  auto add = [&](const char* name, std::vector<glm::dvec3> v, glm::dvec3 rho) { s.push_back({name, v, rho, glm::dvec3(0.0)}); };
  add("floor", test::quad({0, 0, 0}, {W, 0, 0}, {0, D, 0}), glm::dvec3(0.5));
  add("ceiling", test::quad({0, 0, H}, {0, D, 0}, {W, 0, 0}), glm::dvec3(0.7));
  add("wall_x0", test::quad({0, 0, 0}, {0, D, 0}, {0, 0, H}), glm::dvec3(0.7, 0.3, 0.3));
  add("wall_x1", test::quad({W, 0, 0}, {0, 0, H}, {0, D, 0}), glm::dvec3(0.3, 0.6, 0.3));
  add("wall_y0", test::quad({0, 0, 0}, {0, 0, H}, {W, 0, 0}), glm::dvec3(0.6));
  add("wall_y1", test::quad({0, D, 0}, {W, 0, 0}, {0, 0, H}), glm::dvec3(0.6));
  for (size_t i = 0; i < lamps.size(); ++i) s.push_back({"lamp" + std::to_string(i), lamps[i], glm::dvec3(0.0), exitance});
  return s;
}

// A square lamp of side `side` at `c` facing `n` (one of +-x, +-y, -z).
std::vector<glm::dvec3> lampAt(glm::dvec3 c, glm::dvec3 n, double side) {
  glm::dvec3 u = std::abs(n.z) > 0.5 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 0, 1);
  glm::dvec3 v = glm::cross(n, u);
  u = glm::cross(v, n);
  return test::quad(c - 0.5 * side * (u + v), u * side, v * side);
}

FanOptions testFan(std::vector<double> rings, bool dither, int size = 192) {
  FanOptions o;
  o.viewsPerRing = 96;
  o.size = size;
  o.ringElevations = std::move(rings);
  o.dither = dither;
  return o;
}

// The reference: the placed mesh ray-cast, per pixel albedo / pi x (direct light of each lamp with
// a shadow ray past the mesh and the room + the indirect irradiance from the same SH).
ImageRGB reference(const Mesh& m, const ImageFan& fan, const Placement& place, const ObjectLighting& light,
                   const radiosity::HierarchicalRadiosity& h, const Camera& cam, std::vector<uint8_t>& hitMask) {
  std::vector<glm::vec3> world;
  for (const auto& p : m.positions) world.push_back(glm::vec3(place.toWorld(fan, glm::dvec3(p))));
  const RayScene mesh(std::span<const glm::vec3>(world), std::span<const glm::uvec3>(m.triangles));
  ImageRGB img(cam.width, cam.height);
  hitMask.assign(size_t(cam.width) * cam.height, 0);
  const glm::dvec3 eye = cam.center();
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      const glm::dvec3 d = cam.rayDirection(x + 0.5, y + 0.5);
      const RayHit hit = mesh.intersect(Ray{glm::vec3(eye), glm::vec3(d), 0.f, 1e30f});
      if (hit.polygon < 0) continue;
      hitMask[size_t(y) * cam.width + x] = 1;
      const size_t t = size_t(hit.triangle);
      const float u = hit.barycentric.x, v = hit.barycentric.y, a = 1 - u - v;
      glm::dvec3 n = place.toWorldDirection(glm::dvec3(glm::normalize(
          a * m.cornerNormals[3 * t] + u * m.cornerNormals[3 * t + 1] + v * m.cornerNormals[3 * t + 2])));
      const glm::dvec3 albedo(a * m.cornerColours[3 * t] + u * m.cornerColours[3 * t + 1] + v * m.cornerColours[3 * t + 2]);
      const glm::dvec3 p = eye + double(hit.t) * d;
      glm::dvec3 e = radiosity::shIrradiance(light.indirect, n);
      for (const auto& l : light.lamps) {
        const glm::dvec3 toL = l.position - p;
        const double dist = glm::length(toL);
        const glm::dvec3 w = toL / dist;
        glm::dvec3 ln(0.0);
        for (size_t i = 1; i + 1 < l.polygon.size(); ++i) ln += glm::cross(l.polygon[i] - l.polygon[0], l.polygon[i + 1] - l.polygon[0]);
        const double area = 0.5 * glm::length(ln);
        const double cosL = std::max(0.0, -glm::dot(glm::normalize(ln), w));
        const double cosP = std::max(0.0, glm::dot(n, w));
        if (cosL <= 0 || cosP <= 0) continue;
        const glm::vec3 from(p + 1e-4 * n);
        if (mesh.occluded(from, glm::vec3(l.position)) || h.rayScene().occluded(from, glm::vec3(l.position))) continue;
        e += l.exitance / std::numbers::pi * area * cosL * cosP / (dist * dist);
      }
      img.set(x, y, glm::vec3(albedo / std::numbers::pi * e));
    }
  return img;
}

// PSNR over the pixels both images cover fully (and their 3 x 3 neighbours), after a 3 x 3 box
// filter, the peak the reference's brightest value there.
double maskedPsnr(const ImageRGB& a, const ImageRGB& ref, const std::vector<uint8_t>& mask) {
  const int w = ref.width, hgt = ref.height;
  double peak = 0, se = 0;
  size_t n = 0;
  for (int y = 1; y + 1 < hgt; ++y)
    for (int x = 1; x + 1 < w; ++x) {
      bool inside = true;
      glm::dvec3 sa(0.0), sr(0.0);
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          inside = inside && mask[size_t(y + dy) * w + x + dx];
          sa += glm::dvec3(a.at(x + dx, y + dy));
          sr += glm::dvec3(ref.at(x + dx, y + dy));
        }
      if (!inside) continue;
      sa /= 9.0;
      sr /= 9.0;
      for (int c = 0; c < 3; ++c) {
        se += (sa[c] - sr[c]) * (sa[c] - sr[c]);
        peak = std::max(peak, sr[c]);
      }
      n += 3;
    }
  EXPECT_GT(n, 3000u) << "too few object pixels to compare";
  return 10 * std::log10(peak * peak / (se / double(n)));
}

struct Scenario {
  const char* name;
  glm::dvec3 lampCentre, lampNormal;
};

}  // namespace

TEST(ImageFan, MeshesAreReadFromObjAndPlyAndBadOnesRefusedWithTheFileNamed) {
  const auto dir = std::filesystem::temp_directory_path() / "relume_ibr_mesh";
  std::filesystem::create_directories(dir);
  {
    std::ofstream(dir / "m.mtl") << "newmtl green\nKd 0.1 0.6 0.2\n";
    std::ofstream(dir / "m.obj") << "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nusemtl green\nf 1//1 2//1 3//1 4//1\n";
  }
  const Mesh obj = readMesh((dir / "m.obj").string());
  ASSERT_EQ(obj.triangles.size(), 2u);
  EXPECT_NEAR(obj.triangleAlbedo[0].g, 0.6f, 1e-6f);
  ASSERT_EQ(obj.cornerNormals.size(), 6u);
  EXPECT_NEAR(obj.cornerNormals[0].z, 1.f, 1e-6f);
  // The same quad as ASCII and as binary PLY, with 8-bit (sRGB) vertex colours.
  const std::string header = "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                             "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                             "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  {
    std::ofstream(dir / "a.ply") << "ply\nformat ascii 1.0\n" << header
                                 << "0 0 0 255 128 0\n1 0 0 255 128 0\n1 1 0 255 128 0\n0 1 0 255 128 0\n4 0 1 2 3\n";
    std::ofstream b(dir / "b.ply", std::ios::binary);
    b << "ply\nformat binary_little_endian 1.0\n" << header;
    const float xyz[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    for (const auto& p : xyz) {
      b.write(reinterpret_cast<const char*>(p), 12);
      const unsigned char c[3] = {255, 128, 0};
      b.write(reinterpret_cast<const char*>(c), 3);
    }
    const unsigned char n = 4;
    b.write(reinterpret_cast<const char*>(&n), 1);
    for (int32_t i : {0, 1, 2, 3}) b.write(reinterpret_cast<const char*>(&i), 4);
  }
  const Mesh a = readMesh((dir / "a.ply").string()), b = readMesh((dir / "b.ply").string());
  ASSERT_EQ(a.triangles.size(), 2u);
  EXPECT_EQ(a.triangles, b.triangles);
  EXPECT_EQ(a.positions, b.positions);
  ASSERT_EQ(a.cornerColours.size(), 6u);
  EXPECT_NEAR(a.cornerColours[0].r, 1.f, 1e-6f);
  EXPECT_NEAR(a.cornerColours[0].g, 0.2158f, 1e-3f);  // sRGB 128 in linear light
  EXPECT_EQ(a.cornerColours, b.cornerColours);
  // The same quad as glTF 2.0 (+Y up: its y becomes z), a translated node, a red material; as
  // .gltf with a base64 buffer and as .glb with a binary chunk.
  {
    std::string buf;
    auto put = [&](const void* p, size_t n) { buf.append(static_cast<const char*>(p), n); };
    const float pos[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    const float nrm[4][3] = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    const uint16_t idx[6] = {0, 1, 2, 0, 2, 3};
    put(pos, sizeof pos);
    put(nrm, sizeof nrm);
    put(idx, sizeof idx);
    auto json = [&](const std::string& buffer) {
      return std::string(R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],)"
                         R"("nodes":[{"mesh":0,"translation":[0,0,-2]}],)"
                         R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,"NORMAL":1},"indices":2,"material":0}]}],)"
                         R"("materials":[{"pbrMetallicRoughness":{"baseColorFactor":[0.9,0.1,0.05,1]}}],)"
                         R"("accessors":[{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3"},)"
                         R"({"bufferView":1,"componentType":5126,"count":4,"type":"VEC3"},)"
                         R"({"bufferView":2,"componentType":5123,"count":6,"type":"SCALAR"}],)"
                         R"("bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},{"buffer":0,"byteOffset":48,"byteLength":48},)"
                         R"({"buffer":0,"byteOffset":96,"byteLength":12}],)"
                         R"("buffers":[{"byteLength":108)") + buffer + "}]}";
    };
    const QByteArray b64 = QByteArray(buf.data(), qsizetype(buf.size())).toBase64();
    std::ofstream(dir / "q.gltf") << json(R"(,"uri":"data:application/octet-stream;base64,)" + b64.toStdString() + "\"");
    std::string chunk = json("");
    while (chunk.size() % 4) chunk += ' ';
    std::string bin = buf;
    while (bin.size() % 4) bin += '\0';
    std::string glb = "glTF";
    auto u32 = [](std::string& s, uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); };
    u32(glb, 2);
    u32(glb, uint32_t(12 + 8 + chunk.size() + 8 + bin.size()));
    u32(glb, uint32_t(chunk.size()));
    u32(glb, 0x4E4F534A);
    glb += chunk;
    u32(glb, uint32_t(bin.size()));
    u32(glb, 0x004E4942);
    glb += bin;
    std::ofstream(dir / "q.glb", std::ios::binary) << glb;
    const Mesh g = readMesh((dir / "q.gltf").string()), gb = readMesh((dir / "q.glb").string());
    ASSERT_EQ(g.triangles.size(), 2u);
    EXPECT_EQ(g.positions, gb.positions);
    EXPECT_EQ(g.cornerNormals, gb.cornerNormals);
    // glTF (1, 1, 0) + (0, 0, -2) = (1, 1, -2), +Y up -> (1, 2, 1) with +Z up.
    EXPECT_NEAR(glm::length(g.positions[2] - glm::vec3(1, 2, 1)), 0.f, 1e-6f);
    EXPECT_NEAR(glm::length(g.cornerNormals[0] - glm::vec3(0, -1, 0)), 0.f, 1e-6f);
    EXPECT_NEAR(g.triangleAlbedo[1].r, 0.9f, 1e-6f);
    // Cut short: refused, naming the file.
    std::ofstream(dir / "cut.glb", std::ios::binary) << glb.substr(0, glb.size() - 20);
    const std::string e = test::errorText([&] { readMesh((dir / "cut.glb").string()); });
    EXPECT_NE(e.find("cut.glb"), std::string::npos) << e;
    EXPECT_NE(e.find("truncated"), std::string::npos) << e;
  }
  // Bad meshes: each refused, naming the file and what is wrong.
  struct Bad {
    const char* file;
    std::string text, says;
  };
  const Bad bad[] = {{"empty.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no faces"},
                     {"nan.obj", "v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "not a finite number"},
                     {"index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "does not exist"},
                     {"flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n", "zero area"},
                     {"short.ply", "ply\nformat ascii 1.0\n" + header + "0 0 0 1 1 1\n", "ends before"},
                     {"nohead.ply", "ply\nformat ascii 1.0\nelement vertex 3\n", "end_header"},
                     {"mesh.stl", "solid x\n", "not a mesh Relume reads"}};
  for (const auto& x : bad) {
    std::ofstream(dir / x.file) << x.text;
    const std::string path = (dir / x.file).string();
    const std::string e = test::errorText([&] { readMesh(path); });
    EXPECT_NE(e.find(path), std::string::npos) << e;
    EXPECT_NE(e.find(x.says), std::string::npos) << x.file << ": " << e;
  }
  std::filesystem::remove_all(dir);
}

TEST(ImageFan, ViewsHoldTheObjectsCoverageDepthNormalsAndColour) {
  // A sphere of radius 0.3 standing on the floor: seen from any view, a disc of radius 0.3 whose
  // centre pixel lies 0.3 in front of the sphere's centre and faces the viewer.
  Mesh m = blob(96, 48, 0.3, 0.0);
  const auto fan = buildFan(m, testFan({15, 45}, true, 96));
  EXPECT_EQ(fan->viewCount(), 192);
  EXPECT_NEAR(fan->radius, 0.3, 0.002);
  EXPECT_NEAR(fan->centre.z, 0.3, 1e-3);
  for (int k : {0, 37, 96 + 50}) {
    const FanView& v = fan->view(k);
    double covered = 0;
    for (uint8_t a : v.alpha) covered += a / 255.0;
    const double expected = std::numbers::pi * 0.25 * 96 * 96 * (0.3 / fan->radius) * (0.3 / fan->radius);
    EXPECT_NEAR(covered / expected, 1.0, 0.02) << "view " << k;
    const size_t c = size_t(48) * 96 + 48;
    EXPECT_NEAR(fan->depthMetres(v.depth[c]), fan->radius - 0.3, 0.01);
    EXPECT_GT(byteToNormal()[v.code[c]].z, 0.99f);
    // The point at the centre pixel lies on the sphere, towards the view's camera.
    const glm::dvec3 p = fan->pointAt(k, 48.5, 48.5, fan->depthMetres(v.depth[c]));
    EXPECT_NEAR(glm::length(p - fan->centre), 0.3, 0.01);
    EXPECT_GT(glm::dot(p - fan->centre, fan->toCamera(k)), 0.29);
    // Colour: the blob's albedo at that height, sRGB-encoded.
    EXPECT_NEAR(srgbToLinear(v.colour[3 * c] / 255.f), 0.7f, 0.01f);
  }
}

TEST(ImageFan, FilesRoundTripAndTruncatedOrForeignOrDamagedFilesAreRefused) {
  const auto fan = buildFan(blob(48, 24), testFan({30}, true, 32));
  const auto bytes = fanBytes(*fan);
  const auto back = parseFan(bytes, "x.fan");
  ASSERT_EQ(back->viewCount(), fan->viewCount());
  EXPECT_EQ(back->radius, fan->radius);
  EXPECT_EQ(back->boundsMin, fan->boundsMin);
  EXPECT_EQ(back->ringElevations, fan->ringElevations);
  for (int k = 0; k < fan->viewCount(); k += 7) {
    EXPECT_EQ(back->view(k).code, fan->view(k).code);
    EXPECT_EQ(back->view(k).depth, fan->view(k).depth);
    EXPECT_EQ(back->view(k).alpha, fan->view(k).alpha);
    EXPECT_EQ(back->view(k).colour, fan->view(k).colour);
  }
  const auto dir = std::filesystem::temp_directory_path() / "relume_ibr_fan";
  std::filesystem::create_directories(dir);
  writeFan(*fan, (dir / "ok.fan").string());
  EXPECT_EQ(readFan((dir / "ok.fan").string())->viewCount(), fan->viewCount());
  EXPECT_FALSE(std::filesystem::exists(dir / "ok.fan.part"));
  auto refused = [&](std::vector<uint8_t> b, const std::string& says) {
    std::ofstream((dir / "bad.fan"), std::ios::binary).write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size()));
    const std::string e = test::errorText([&] { readFan((dir / "bad.fan").string()); });
    EXPECT_NE(e.find((dir / "bad.fan").string()), std::string::npos) << e;
    EXPECT_NE(e.find(says), std::string::npos) << e;
  };
  for (size_t cut : {size_t(5), size_t(40), bytes.size() / 2, bytes.size() - 2})
    refused(std::vector<uint8_t>(bytes.begin(), bytes.begin() + long(cut)), cut < 8 ? "not an image fan" : "truncated");
  auto other = bytes;
  other[8] = 2;  // a fan of version 2, intact (its checksum made anew)
  const uint32_t crc = uint32_t(crc32_z(0L, other.data(), other.size() - 4));
  for (int k = 0; k < 4; ++k) other[other.size() - 4 + size_t(k)] = uint8_t(crc >> (8 * k));
  refused(other, "version 2");
  other[8] = 3;  // ... and one whose version byte was damaged
  refused(other, "damaged");
  auto damaged = bytes;
  damaged[bytes.size() / 2] ^= 0x40;
  refused(damaged, "damaged");
  refused(std::vector<uint8_t>{'P', 'K', 3, 4, 0, 0, 0, 0, 0, 0}, "not an image fan");
  std::filesystem::remove_all(dir);
  // A fan of one view draws (with no second view to fall back on); a view that does not exist is
  // an error, not a crash.
  const auto one = buildFan(blob(48, 24), [] {
    FanOptions o = testFan({30}, true, 32);
    o.viewsPerRing = 1;
    return o;
  }());
  radiosity::HierarchicalRadiosity h(room({lampAt({2.0, 2.0, 2.79}, {0, 0, -1}, 0.3)}, glm::dvec3(30.0)));
  h.solve();
  Placement place;
  place.position = glm::dvec3(2.0, 2.0, 0.0);
  const Camera cam = Camera::lookAt(glm::dvec3(3.5, 2.0, 1.2), glm::dvec3(2.0, 2.0, 0.3), 160, 120, 150);
  ImageRGB img(cam.width, cam.height);
  EXPECT_GT(drawObject(*one, place, lightingAt(h, place.toWorld(*one, one->centre), 256), cam, roomView(h, cam), img).objectPixels, 100u);
  EXPECT_NE(test::errorText([&] { one->view(1); }).find("no such view"), std::string::npos);
}

TEST(ImageBasedObject, ShadedLikeTheMeshItselfUnderThreeLampPlacements) {
  // The issue's measure: from a view halfway between two fan images, >= 28 dB on the object's
  // pixels after a 3 x 3 box filter. (Dithering against plain coding, where coding is the only
  // error, is in normal_code_test.cpp.)
  const Mesh m = blob();
  const auto fan = buildFan(m, testFan({15, 45, 75}, true));
  Placement place;  // turned and scaled, as a user places it
  place.position = glm::dvec3(2.0, 2.0, 0.0);
  place.yaw = 0.3;
  place.scale = 1.3;
  const glm::dvec3 c = place.toWorld(*fan, fan->centre);
  // Halfway between views 10 and 11 of the 45 deg ring (azimuth in the object's frame).
  const double az = (10.5 * 2 * std::numbers::pi / 96) + place.yaw, el = std::numbers::pi / 4;
  const glm::dvec3 eye = c + 2.0 * glm::dvec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  const Camera cam = Camera::lookAt(eye, c, 320, 240, 300);
  const Scenario scenarios[] = {{"ceiling, behind left", {1.0, 1.2, 2.79}, {0, 0, -1}},
                                {"ceiling, front right", {3.3, 2.9, 2.79}, {0, 0, -1}},
                                {"wall lamp, low", {0.01, 2.5, 1.2}, {1, 0, 0}}};
  for (const auto& s : scenarios) {
    radiosity::HierarchicalRadiosity h(room({lampAt(s.lampCentre, s.lampNormal, 0.3)}, glm::dvec3(40.0, 36.0, 30.0)));
    h.solve();
    const ObjectLighting light = lightingAt(h, c);
    ASSERT_EQ(light.lamps.size(), 1u);
    std::vector<uint8_t> hit;
    const ImageRGB ref = reference(m, *fan, place, light, h, cam, hit);
    ImageRGB img(cam.width, cam.height);
    std::vector<uint8_t> mask(hit.size(), 0);
    const DrawStats st = drawObject(*fan, place, light, cam, roomView(h, cam), img, &mask);
    EXPECT_GT(st.objectPixels, 5000u);
    std::vector<uint8_t> both(hit.size());
    for (size_t i = 0; i < both.size(); ++i) both[i] = hit[i] && mask[i] == 255;
    const double psnr = maskedPsnr(img, ref, both);
    if (const char* dump = std::getenv("RELUME_TEST_DUMP")) {
      writeImage(std::string(dump) + "/" + s.name + ".ibr.exr", img);
      writeImage(std::string(dump) + "/" + s.name + ".reference.exr", ref);
    }
    std::printf("%s: %.2f dB (3x3 box filter, object pixels)\n", s.name, psnr);
    EXPECT_GE(psnr, 28.0) << s.name;
  }
}

TEST(ImageBasedObject, ShadowsOnTheFloorAndAWallMatchTheMeshsOwnShadow) {
  // A small lamp (its shadow hard but for the lamp's size) within 10 deg of a ring's elevation:
  // the strip of the fan seen from the lamp, met by each pixel's line to the lamp, against shadow
  // rays to the lamp's centre past the mesh itself. Intersection over union >= 0.8 on each surface.
  const Mesh m = blob();
  const auto fan = buildFan(m, testFan({15, 45}, true));
  struct Case {
    const char* name;
    glm::dvec3 object;
    double elevationDeg, azimuthDeg, distance;
    const char* surface;
  };
  const Case cases[] = {{"floor", {2.0, 2.0, 0.0}, 50, 200, 1.7, "floor"},
                        {"wall", {2.0, 0.75, 0.0}, 20, 95, 1.8, "wall_y0"}};
  for (const auto& cs : cases) {
    Placement place;
    place.position = cs.object;
    const glm::dvec3 c = place.toWorld(*fan, fan->centre);
    const double el = cs.elevationDeg * std::numbers::pi / 180, az = cs.azimuthDeg * std::numbers::pi / 180;
    const glm::dvec3 toLamp(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    const glm::dvec3 lampC = c + cs.distance * toLamp;
    radiosity::HierarchicalRadiosity h(room({lampAt(lampC, -toLamp, 0.05)}, glm::dvec3(200.0)));
    h.solve();
    const ObjectLighting light = lightingAt(h, c);
    const Camera cam = Camera::lookAt(glm::dvec3(2.0, 3.9, 2.6), c - glm::dvec3(0, 0.6, 0.3), 320, 240, 220);
    const RoomView rv = roomView(h, cam);
    ImageRGB img(cam.width, cam.height);
    std::fill(img.pixels.begin(), img.pixels.end(), 1.f);
    // The display's irradiance: the lamp's own direct light, so that a fully blocked pixel goes black.
    const radiosity::EmitterShape shape(false);
    const auto& lampPoly = h.surfaces().back().vertices;
    const IrradianceAt irradiance = [&](int surface, const glm::dvec3& x) {
      const auto& v = h.surfaces()[size_t(surface)].vertices;
      const glm::dvec3 n = glm::normalize(glm::cross(v[1] - v[0], v[2] - v[0]));
      return radiosity::emitterFormFactor(x, n, lampPoly, shape) * h.surfaces().back().exitance;
    };
    drawShadows(*fan, place, light, h, cam, rv, irradiance, img);
    std::vector<glm::vec3> world;
    for (const auto& p : m.positions) world.push_back(glm::vec3(place.toWorld(*fan, glm::dvec3(p))));
    const RayScene mesh(std::span<const glm::vec3>(world), std::span<const glm::uvec3>(m.triangles));
    int target = -1;
    for (size_t i = 0; i < h.surfaces().size(); ++i)
      if (h.surfaces()[i].name == cs.surface) target = int(i);
    size_t inter = 0, uni = 0, truth = 0;
    for (size_t i = 0; i < rv.surface.size(); ++i) {
      if (rv.surface[i] != target) continue;
      const bool ibr = img.pixels[3 * i + 1] < 0.5f;
      const bool ref = mesh.occluded(rv.point[i] + 1e-4f * rv.normal[i], glm::vec3(lampC));
      inter += ibr && ref;
      uni += ibr || ref;
      truth += ref;
    }
    const double iou = uni ? double(inter) / double(uni) : 0.0;
    std::printf("shadow on the %s: %zu pixels in the mesh's shadow, intersection over union %.3f\n", cs.name, truth, iou);
    EXPECT_GT(truth, 500u) << cs.name;
    EXPECT_GE(iou, 0.8) << cs.name;
  }
}

TEST(ImageBasedObject, ADimmedLampCastsAShadowAsMuchLighterAndALampSwitchedOffNone) {
  // Two lamps on either side of the object; the display's pixels are the room's radiance B / pi and
  // its irradiance B / rho, as the relit photo's are proportional to its irradiance. The darkening
  // lamp 0's shadow adds (all pixels' sum) halves when lamp 0 is dimmed to half, and is gone when
  // it is off; lamp 1's shadow stays.
  const Mesh m = blob(64, 32);
  const auto fan = buildFan(m, testFan({15, 45, 75}, true, 96));
  Placement place;
  place.position = glm::dvec3(2.0, 2.0, 0.0);
  const glm::dvec3 c = place.toWorld(*fan, fan->centre);
  radiosity::HierarchicalRadiosity h(room({lampAt({1.0, 2.0, 2.79}, {0, 0, -1}, 0.2), lampAt({3.0, 2.2, 2.79}, {0, 0, -1}, 0.2)},
                                          glm::dvec3(30.0)));
  h.solve();
  const int lamp0 = int(h.surfaces().size()) - 2;
  const Camera cam = Camera::lookAt(glm::dvec3(2.0, 3.9, 2.6), glm::dvec3(2.0, 1.6, 0.0), 320, 240, 220);
  const RoomView rv = roomView(h, cam);
  auto darkening = [&](double scale0) {
    h.setExitance(lamp0, glm::dvec3(30.0 * scale0));
    h.iterate();
    ImageRGB img(cam.width, cam.height);
    for (size_t i = 0; i < rv.surface.size(); ++i)
      if (rv.surface[i] >= 0) {
        const int leaf = h.findLeaf(rv.surface[i], h.toUV(rv.surface[i], glm::dvec3(rv.point[i])));
        img.set(int(i % size_t(cam.width)), int(i / size_t(cam.width)), h.radiosity(leaf) / float(std::numbers::pi));
      }
    const ImageRGB before = img;
    const IrradianceAt irradiance = [&](int surface, const glm::dvec3& x) {
      const glm::dvec3 b(h.radiosity(h.findLeaf(surface, h.toUV(surface, x))));
      return b / h.surfaces()[size_t(surface)].reflectance;
    };
    drawShadows(*fan, place, lightingAt(h, c, 256), h, cam, rv, irradiance, img);
    double sum = 0;
    for (size_t i = 0; i < img.pixels.size(); ++i) sum += before.pixels[i] - img.pixels[i];
    return sum;
  };
  const double full = darkening(1.0), half = darkening(0.5), off = darkening(0.0);
  std::printf("darkening: lamp 0 full %.4f, half %.4f, off (lamp 1's shadow alone) %.4f\n", full, half, off);
  EXPECT_GT(off, 0.0);              // lamp 1 still casts its shadow
  EXPECT_GT(full - off, 0.2 * off);  // lamp 0's shadow is there
  EXPECT_NEAR((half - off) / (full - off), 0.5, 0.05);
}

TEST(ImageBasedObject, TheLampsPassedOverNearAPointTakeNothingThere) {
  // The shadow passes skip the lamps whose lines from a point (or from anywhere in a tile) cannot
  // meet the object's silhouette (ObjectShadows::castersNear, and the same tests inside taken).
  // Exact, not a guess: at every pixel of the room, the light taken off with that culling is the
  // light taken off with every lamp's lines all tried — for a large lamp, a small one, and one
  // beside the object (its plane cuts the lamp: nothing passed over), per point and per tile.
  const Mesh m = blob(64, 32);
  const auto fan = buildFan(m, testFan({15, 45, 75}, true, 96));
  Placement place;
  place.position = glm::dvec3(2.0, 2.0, 0.0);
  place.yaw = 0.4;
  const glm::dvec3 c = place.toWorld(*fan, fan->centre);
  radiosity::HierarchicalRadiosity h(room({lampAt({1.2, 1.9, 2.79}, {0, 0, -1}, 0.6), lampAt({3.0, 2.4, 2.79}, {0, 0, -1}, 0.1),
                                           lampAt({2.6, 2.0, 0.2}, {-1, 0, 0}, 0.2)},
                                          glm::dvec3(30.0)));
  h.solve();
  const ObjectLighting light = lightingAt(h, c);
  const ObjectShadows shadows(*fan, place, light), exhaustive(*fan, place, light, false);
  const Camera cam = Camera::lookAt(glm::dvec3(2.0, 3.9, 2.6), glm::dvec3(2.0, 1.6, 0.0), 240, 180, 165);
  const RoomView rv = roomView(h, cam);
  size_t asked = 0, passedOver = 0, shadowed = 0, differ = 0;
  for (int ty = 0; ty < cam.height; ty += 8)
    for (int tx = 0; tx < cam.width; tx += 8) {
      glm::dvec3 lo(1e300), hi(-1e300);
      for (int y = ty; y < std::min(ty + 8, cam.height); ++y)
        for (int x = tx; x < std::min(tx + 8, cam.width); ++x)
          if (rv.surface[size_t(y) * cam.width + x] >= 0) {
            lo = glm::min(lo, glm::dvec3(rv.point[size_t(y) * cam.width + x]));
            hi = glm::max(hi, glm::dvec3(rv.point[size_t(y) * cam.width + x]));
          }
      if (lo.x > hi.x) continue;
      const auto tile = shadows.castersNear(0.5 * (lo + hi), 0.5 * glm::length(hi - lo) + 1e-6);
      for (int y = ty; y < std::min(ty + 8, cam.height); ++y)
        for (int x = tx; x < std::min(tx + 8, cam.width); ++x) {
          const size_t i = size_t(y) * cam.width + x;
          if (rv.surface[i] < 0) continue;
          const glm::dvec3 X(rv.point[i]), n(rv.normal[i]);
          const glm::dvec3 all = exhaustive.taken(h, rv.surface[i], X, n);
          const auto point = shadows.castersNear(X, 0.0);
          ++asked;
          passedOver += std::popcount(exhaustive.castersNear(X, 0.0) & ~point);
          shadowed += all != glm::dvec3(0.0);
          differ += shadows.taken(h, rv.surface[i], X, n) != all;
          differ += shadows.taken(h, rv.surface[i], X, n, point) != all;
          differ += shadows.taken(h, rv.surface[i], X, n, tile) != all;
        }
    }
  std::printf("%zu points: %zu lamp-point pairs passed over, %zu points shadowed, %zu differ\n", asked, passedOver, shadowed,
              differ);
  EXPECT_EQ(differ, 0u);
  EXPECT_GT(shadowed, 1000u);
  EXPECT_GT(passedOver, asked);  // most pairs are passed over: the test asks something
}

TEST(ImageBasedObject, ShadowMapsOverTheSurfacesShowWhatThePerPixelShadowsShow) {
  // What the viewport multiplies the room by (ibr::shadowMaps, 1.5 cm texels over each surface's
  // plane, any camera) against the CPU renderer's per-pixel shadows (drawShadows, one object after
  // the other), seen through one camera: two objects, two lamps, their shadows overlapping.
  const Mesh m = blob(64, 32);
  const std::shared_ptr<const ImageFan> fan = buildFan(m, testFan({15, 45, 75}, true, 96));
  radiosity::HierarchicalRadiosity h(room({lampAt({1.0, 2.0, 2.79}, {0, 0, -1}, 0.2), lampAt({3.0, 2.2, 2.79}, {0, 0, -1}, 0.2)},
                                          glm::dvec3(30.0)));
  h.solve();
  std::vector<ImageObject> objects(2);
  objects[0].name = "a";
  objects[0].place.position = glm::dvec3(1.8, 2.0, 0.0);
  objects[1].name = "b";
  objects[1].place.position = glm::dvec3(2.3, 2.1, 0.0);
  objects[1].place.yaw = 0.6;
  std::vector<ObjectLighting> lights;
  for (auto& o : objects) {
    o.fan = fan;
    lights.push_back(lightingAt(h, o.place.toWorld(*fan, fan->centre), 256));
  }
  const Camera cam = Camera::lookAt(glm::dvec3(2.0, 3.9, 2.6), glm::dvec3(2.0, 1.6, 0.0), 320, 240, 220);
  const RoomView rv = roomView(h, cam);
  const IrradianceAt irradiance = [&](int surface, const glm::dvec3& x) {
    return glm::dvec3(h.irradiance(h.findLeaf(surface, h.toUV(surface, x))));
  };
  ImageRGB perPixel(cam.width, cam.height);
  for (auto& p : perPixel.pixels) p = 1.f;
  for (size_t i = 0; i < objects.size(); ++i) drawShadows(*fan, objects[i].place, lights[i], h, cam, rv, irradiance, perPixel);
  const auto maps = shadowMaps(h, objects, lights);
  ASSERT_FALSE(maps.empty());
  // The maps looked up at each pixel's point, bilinearly as the display does.
  auto mapped = [&](int surface, const glm::dvec3& x) {
    for (const auto& mp : maps) {
      if (mp.surface != surface) continue;
      const glm::dvec2 t = (h.toUV(surface, x) - mp.origin) / mp.texel - 0.5;
      const int x0 = std::clamp(int(std::floor(t.x)), 0, mp.width - 1), y0 = std::clamp(int(std::floor(t.y)), 0, mp.height - 1);
      const int x1 = std::min(x0 + 1, mp.width - 1), y1 = std::min(y0 + 1, mp.height - 1);
      const double fx = std::clamp(t.x - x0, 0.0, 1.0), fy = std::clamp(t.y - y0, 0.0, 1.0);
      auto at = [&](int xx, int yy) { return double(mp.keep[size_t(yy) * mp.width + xx].y); };
      return (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x1, y0)) + fy * ((1 - fx) * at(x0, y1) + fx * at(x1, y1));
    }
    return 1.0;
  };
  double diff = 0, darkPixel = 0, darkMap = 0;
  size_t n = 0, shadowed = 0;
  for (size_t i = 0; i < rv.surface.size(); ++i) {
    if (rv.surface[i] < 0) continue;
    const double a = perPixel.pixels[3 * i + 1], b = mapped(rv.surface[i], glm::dvec3(rv.point[i]));
    diff += std::abs(a - b);
    darkPixel += 1 - a;
    darkMap += 1 - b;
    shadowed += a < 0.97;
    ++n;
  }
  std::printf("shadow maps vs per-pixel shadows: mean |keep difference| %.4f over %zu pixels (%zu in shadow); light "
              "taken off, maps / per pixel %.3f\n",
              diff / double(n), n, shadowed, darkMap / darkPixel);
  EXPECT_GT(shadowed, 1000u);
  EXPECT_LT(diff / double(n), 0.005);
  EXPECT_NEAR(darkMap / darkPixel, 1.0, 0.03);
  // Made one object at a time and multiplied (what the viewport does when one object moves): the
  // same maps as made together.
  const auto a = shadowMaps(h, {objects[0]}, {lights[0]}), b = shadowMaps(h, {objects[1]}, {lights[1]});
  const auto both = multiplyShadowMaps({&a, &b});
  ASSERT_EQ(both.size(), maps.size());
  double worst = 0;
  for (size_t k = 0; k < maps.size(); ++k) {
    ASSERT_EQ(both[k].surface, maps[k].surface);
    ASSERT_EQ(both[k].width, maps[k].width);
    ASSERT_EQ(both[k].height, maps[k].height);
    EXPECT_LT(glm::length(both[k].origin - maps[k].origin), 1e-9);
    for (size_t t = 0; t < maps[k].keep.size(); ++t)
      worst = std::max(worst, double(glm::length(both[k].keep[t] - maps[k].keep[t])));
  }
  EXPECT_LT(worst, 1e-5);
}

// The views searched for the nearest and the next nearest (a handful per ring instead of every
// view): the same answers as searching every view, for any direction, with rings above and below
// the horizon, few or many views per ring, and directions straight up or down.
TEST(ImageFan, TheViewsNearADirectionAreFoundAsAnExhaustiveSearchFindsThem) {
  struct Layout {
    int perRing;
    std::vector<double> rings;
  };
  const std::vector<Layout> layouts = {{96, {15, 45, 75}}, {5, {0}}, {7, {-30, 10, 60, 89}}, {3, {20, 50}}, {64, {-80, 0, 80}}};
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  for (const auto& layout : layouts) {
    ImageFan fan;
    fan.size = 8;
    fan.viewsPerRing = layout.perRing;
    fan.ringElevations = layout.rings;
    // (Straight up with a negative zero across, nearly straight up, and no direction at all too.)
    std::vector<glm::dvec3> dirs = {{0, 0, 1},   {0, 0, -1},           {1, 0, 0},
                                    {-1, 0, 0},  {0, -1, 0},           {-0.0, 0.0, 1},
                                    {-0.0, -0.0, -1}, {1e-13, -1e-13, 1}, {std::nan(""), 0, 1}};
    for (int i = 0; i < 20000; ++i) dirs.push_back(glm::normalize(glm::dvec3(g(rng), g(rng), g(rng))));
    for (const auto& d : dirs) {
      // Exhaustively: the first of the largest dot products, then the first of the rest.
      int best = 0, second = -1;
      for (int k = 1; k < fan.viewCount(); ++k)
        if (glm::dot(fan.toCamera(k), d) > glm::dot(fan.toCamera(best), d)) best = k;
      for (int k = 0; k < fan.viewCount(); ++k)
        if (k != best && (second < 0 || glm::dot(fan.toCamera(k), d) > glm::dot(fan.toCamera(second), d))) second = k;
      ASSERT_EQ(fan.nearestView(d), best) << layout.perRing << " per ring, d = " << d.x << ", " << d.y << ", " << d.z;
      const std::vector<int> around = fan.viewsAround(d);
      ASSERT_TRUE(std::is_sorted(around.begin(), around.end()));
      EXPECT_NE(std::find(around.begin(), around.end(), second), around.end())
          << layout.perRing << " per ring: the next nearest view " << second << " is not searched";
    }
  }
}
