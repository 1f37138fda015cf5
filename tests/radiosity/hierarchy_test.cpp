// Physics of the hierarchical solver: energy balance, shadows, cheap lamp edits, seams.
#include <gtest/gtest.h>

#include <array>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <glm/geometric.hpp>
#include <memory>

#include "relume/geometry/camera.h"
#include "relume/geometry/polygon.h"
#include "relume/radiosity/hierarchy.h"
#include "relume/raytrace/ray_scene.h"
#include "relume/relight/solution_render.h"
#include "support/test_rooms.h"

using namespace relume;
using namespace relume::radiosity;
using relume::test::quad;

TEST(Hierarchy, ClosedRoomAbsorbsWhatItEmits) {
  const auto surfaces = test::furnishedRoom();
  HierarchicalRadiosity h(surfaces, Options{});
  h.solve();
  glm::dvec3 emitted(0.0), absorbed(0.0);
  for (size_t i = 0; i < surfaces.size(); ++i) {
    const double A = polygonArea(surfaces[i].vertices);
    emitted += A * surfaces[i].exitance;
    absorbed += A * (glm::dvec3(1.0) - surfaces[i].reflectance) * h.surfaceIrradiance(int(i));
  }
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(absorbed[c], emitted[c], 0.02 * emitted[c]) << "channel " << c;
  // And the solution is not trivially zero or emission-only: walls are lit.
  EXPECT_GT(h.surfaceRadiosity(2).x, 0.05 * emitted.x / 40.0);
}

TEST(Hierarchy, ABrightRoomStopsAsNearItsSolutionAsTheToleranceSays) {
  // In a closed room of albedo 0.9 a Jacobi sweep shrinks the error by some 0.9 only, so when a
  // sweep's step falls to the tolerance the error left is still about ten steps' worth. The solve
  // stops near the solution nonetheless: against the same links solved to 1e-9, every leaf within
  // three times the tolerance (of the mean leaf radiosity). One refinement round, so that both
  // engines refine on emission alone and hold the same links.
  auto surfaces = test::furnishedRoom();
  for (auto& s : surfaces)
    if (s.exitance == glm::dvec3(0.0)) s.reflectance = glm::dvec3(0.9);
  Options o;
  o.maxRefineRounds = 1;
  Options tight = o;
  tight.tolerance = 1e-9;
  tight.maxIterations = 100000;
  HierarchicalRadiosity a(surfaces, o), b(surfaces, tight);
  const SolveStats sa = a.solve(), sb = b.solve();
  ASSERT_EQ(a.links().size(), b.links().size());
  ASSERT_LE(sb.residual, tight.tolerance);
  double worst = 0, sum = 0, area = 0;
  for (size_t i = 0; i < a.nodes().size(); ++i) {
    const auto& n = a.nodes()[i];
    if (n.isCluster() || !n.isLeaf() || surfaces[size_t(n.surface)].exitance != glm::dvec3(0.0)) continue;
    for (int c = 0; c < 3; ++c) worst = std::max(worst, double(std::abs(a.radiosity(int(i))[c] - b.radiosity(int(i))[c])));
    sum += n.area * double(b.radiosity(int(i)).x);
    area += n.area;
  }
  const double mean = sum / area;
  std::printf("albedo 0.9: stopped after %d sweeps, %d to 1e-9; largest leaf error %.2g of the mean radiosity\n", sa.iterations,
              sb.iterations, worst / mean);
  EXPECT_LE(worst, 3 * o.tolerance * mean);
}

namespace {
// Floor 2 x 2 at z=0, a 0.5 x 0.5 lamp at z=2 facing down, a 0.6 x 0.6 occluder at z=1 (facing up),
// all centred on x = y = 1.
std::vector<Surface> occluderScene() {
  std::vector<Surface> s;
  s.push_back({"floor", quad({0, 0, 0}, {2, 0, 0}, {0, 2, 0}), glm::dvec3(0.5), glm::dvec3(0.0)});
  s.push_back({"occluder", quad({0.7, 0.7, 1}, {0.6, 0, 0}, {0, 0.6, 0}), glm::dvec3(0.5), glm::dvec3(0.0)});
  s.push_back({"lamp", quad({0.75, 0.75, 2}, {0, 0.5, 0}, {0.5, 0, 0}), glm::dvec3(0.0), glm::dvec3(10.0)});
  return s;
}

// How many of the lamp's four corners a floor point sees past the occluder (pure geometry).
int cornersSeen(const glm::dvec3& p) {
  int seen = 0;
  for (const glm::dvec3 c : {glm::dvec3(0.75, 0.75, 2), glm::dvec3(1.25, 0.75, 2), glm::dvec3(1.25, 1.25, 2),
                             glm::dvec3(0.75, 1.25, 2)}) {
    const double t = (1.0 - p.z) / (c.z - p.z);  // where the segment crosses z = 1
    const glm::dvec3 q = p + t * (c - p);
    const bool blocked = q.x > 0.7 && q.x < 1.3 && q.y > 0.7 && q.y < 1.3;
    seen += blocked ? 0 : 1;
  }
  return seen;
}
}  // namespace

TEST(Hierarchy, OccluderMakesInvisibleAndPartialElementsWhereGeometrySays) {
  Options o;
  o.oracle = Oracle::BFV;
  o.epsilon = 0.005;
  o.minArea = 1e-3;
  HierarchicalRadiosity h(occluderScene(), o);
  h.solve();
  h.pushLampLinksToLeaves();
  h.iterate();
  const auto& nodes = h.nodes();
  // Per floor leaf: the lamp's links arriving there (or at an ancestor) and their types.
  std::vector<std::vector<VisibilityType>> types(nodes.size());
  for (const auto& l : h.links())
    if (h.sourceIsEmitter(l.source)) types[l.receiver].push_back(l.type);
  int umbra = 0, lit = 0, partial = 0;
  for (size_t n = 0; n < nodes.size(); ++n) {
    const auto& N = nodes[n];
    if (N.isCluster() || !N.isLeaf() || N.surface != 0) continue;
    ASSERT_FALSE(types[n].empty()) << "every floor leaf has its lamp link after pushLampLinksToLeaves";
    int seenMin = 4, seenMax = 0;
    for (const glm::dvec2 uv : {glm::dvec2(N.u0, N.v0), glm::dvec2(N.u1, N.v0), glm::dvec2(N.u1, N.v1),
                                glm::dvec2(N.u0, N.v1)}) {
      const int s = cornersSeen(h.toWorld(0, uv));
      seenMin = std::min(seenMin, s);
      seenMax = std::max(seenMax, s);
    }
    bool anyPartial = false, allInvisible = true, allVisible = true;
    for (auto t : types[n]) {
      anyPartial |= t == VisibilityType::Partial;
      allInvisible &= t == VisibilityType::Invisible;
      allVisible &= t == VisibilityType::Visible;
    }
    if (seenMax == 0) {  // the leaf lies in the umbra: the lamp is hidden from all of it
      EXPECT_TRUE(allInvisible) << "umbra leaf " << n;
      ++umbra;
    } else if (seenMin == 4 &&
               cornersSeen(h.toWorld(0, {0.5 * (N.u0 + N.u1), 0.5 * (N.v0 + N.v1)})) == 4) {
      // The whole leaf sees the whole lamp (corners and centre see all four lamp corners).
      EXPECT_TRUE(allVisible) << "lit leaf " << n;
      ++lit;
    }
    if (anyPartial) ++partial;
  }
  EXPECT_GT(umbra, 0);
  EXPECT_GT(lit, 0);
  EXPECT_GT(partial, 0);

  // And the rendered image shows the shadow: floor under the occluder much darker than the rim.
  Camera cam;
  cam.width = 96;
  cam.height = 96;
  cam.K = glm::dmat3(1.0);
  cam.K[0][0] = cam.K[1][1] = 60.0;
  cam.K[2][0] = cam.K[2][1] = 48.0;
  // Looking straight down from (1, 1, 0.9) -- below the occluder -- so the whole floor is seen.
  cam.R = glm::dmat3(1.0);
  cam.R[1][1] = -1.0;  // rows: x=(1,0,0), y=(0,-1,0), z=(0,0,-1)
  cam.R[2][2] = -1.0;
  const glm::dvec3 eye(1, 1, 0.9);
  cam.t = -(cam.R * eye);
  const ImageRGB img = renderSolution(h, cam);
  glm::dvec2 centre, rim;
  ASSERT_TRUE(cam.project({1.0, 1.0, 0.0}, centre));
  ASSERT_TRUE(cam.project({0.1, 1.0, 0.0}, rim));
  const float dark = img.at(int(centre.x), int(centre.y)).x, bright = img.at(int(rim.x), int(rim.y)).x;
  EXPECT_GT(bright, 0.f);
  EXPECT_LT(dark, 0.25f * bright);
}

TEST(Hierarchy, LampEditResolvesWithoutRefinementOrRays) {
  auto surfaces = test::furnishedRoom();
  const int lamp = int(surfaces.size()) - 1;
  HierarchicalRadiosity h(surfaces, Options{});
  h.solve();
  const size_t links = h.links().size(), nodes = h.nodes().size();
  const uint64_t rays = h.totals().rays;
  const glm::dvec3 before = h.surfaceRadiosity(0);
  h.setExitance(lamp, 2.0 * surfaces[lamp].exitance);
  h.iterate();
  EXPECT_EQ(h.links().size(), links);
  EXPECT_EQ(h.nodes().size(), nodes);
  EXPECT_EQ(h.totals().rays, rays);
  // Radiosity is linear in the emission: doubling the only lamp doubles every surface.
  const glm::dvec3 after = h.surfaceRadiosity(0);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(after[c], 2.0 * before[c], 0.002 * before[c]);
  h.setExitance(lamp, glm::dvec3(0.0));
  h.iterate();
  EXPECT_NEAR(h.surfaceRadiosity(0).x, 0.0, 1e-6);
}

TEST(Hierarchy, LinksCrossingBoxFindsTheShaftsItBlocks) {
  HierarchicalRadiosity h(occluderScene(), Options{});
  h.solve();
  const auto& links = h.links();
  // A small box in mid-air right between lamp and floor centre.
  const auto hit = h.linksCrossingBox({0.95, 0.95, 1.45}, {1.05, 1.05, 1.55});
  ASSERT_FALSE(hit.empty());
  for (int i : hit) {
    // Every link it reports has bounds on both sides of z = 1.5 or touching the box's column.
    const auto& R = h.nodes()[links[i].receiver];
    const auto& S = h.nodes()[links[i].source];
    EXPECT_LE(std::min(R.bmin.z, S.bmin.z), 1.55f);
    EXPECT_GE(std::max(R.bmax.z, S.bmax.z), 1.45f);
  }
  // A box far outside the scene crosses nothing.
  EXPECT_TRUE(h.linksCrossingBox({5, 5, 5}, {6, 6, 6}).empty());
  // Every lamp -> floor-centre link is among those found.
  for (size_t i = 0; i < links.size(); ++i) {
    const auto& R = h.nodes()[links[i].receiver];
    if (!h.sourceIsEmitter(links[i].source) || R.isCluster() || R.surface != 0) continue;
    if (R.bmin.x <= 1.0f && R.bmax.x >= 1.0f && R.bmin.y <= 1.0f && R.bmax.y >= 1.0f)
      EXPECT_NE(std::find(hit.begin(), hit.end(), int(i)), hit.end()) << "link " << i;
  }
}

namespace {
// Point to a parallel, coaxial rectangle 2a x 2b at distance c (four corner rectangles; Howell's
// catalogue, configuration A-3 for one corner).
double pointToCentredRectangle(double a, double b, double c) {
  const double A = a / c, B = b / c;
  const double qa = std::sqrt(1 + A * A), qb = std::sqrt(1 + B * B);
  return 4.0 / (2.0 * M_PI) * (A / qa * std::atan(B / qa) + B / qb * std::atan(A / qb));
}
}  // namespace

TEST(Hierarchy, ATwoSidedLampLightsBothHalfSpacesByTheAnalyticFormFactor) {
  // A 0.5 m square lamp 0.3 m below a ceiling and 1 m above a floor, nothing else: the element of
  // each surface straight above / below its centre receives E x F(point -> square) from the face
  // towards it; a one-sided lamp (facing down) leaves the ceiling dark. (Reflectances of 1 %, and
  // a threshold low enough that the oracle still refines: interreflection below 0.1 %.)
  for (bool twoSided : {true, false}) {
    std::vector<Surface> s;
    s.push_back({"floor", quad({-1, -1, 0}, {2, 0, 0}, {0, 2, 0}), glm::dvec3(0.01), glm::dvec3(0.0)});
    s.push_back({"ceiling", quad({-1, -1, 1.3}, {0, 2, 0}, {2, 0, 0}), glm::dvec3(0.01), glm::dvec3(0.0)});
    s.push_back({"lamp", quad({-0.25, -0.25, 1.0}, {0, 0.5, 0}, {0.5, 0, 0}), glm::dvec3(0.0), glm::dvec3(10.0), twoSided});
    Options o;
    o.minArea = 5e-4;
    o.epsilon = 3e-5;
    HierarchicalRadiosity h(s, o);
    h.solve();
    h.pushLampLinksToLeaves();
    h.iterate();
    const double below = h.irradiance(h.findLeaf(0, h.toUV(0, {0, 0, 0})))[0];
    const double above = h.irradiance(h.findLeaf(1, h.toUV(1, {0, 0, 1.3})))[0];
    EXPECT_NEAR(below, 10.0 * pointToCentredRectangle(0.25, 0.25, 1.0), 0.03 * 10.0 * pointToCentredRectangle(0.25, 0.25, 1.0));
    if (twoSided)
      EXPECT_NEAR(above, 10.0 * pointToCentredRectangle(0.25, 0.25, 0.3), 0.03 * 10.0 * pointToCentredRectangle(0.25, 0.25, 0.3));
    else
      EXPECT_LT(above, 0.01 * 10.0 * pointToCentredRectangle(0.25, 0.25, 0.3));  // interreflection only
  }
}

TEST(Hierarchy, ATwoSidedLampIsItsTwoFacesBackToBack) {
  // Hung 0.4 m below the ceiling of a closed room: a two-sided lamp gives the room what a lamp
  // facing down plus one facing up give (superposition; its own back face blocks none of its
  // light), and everything, the lamp's two faces included, absorbs both faces' power. The room's
  // own ceiling lamp is off (it absorbs what reaches its front, as a lamp polygon does).
  const double ls = 0.3;
  auto solve = [&](bool twoSided, bool up, double& room, double& all) {
    auto surfaces = test::furnishedRoom(3.0, 3.5, 2.5, glm::dvec3(0.0));
    auto q = quad({0.5, 2.5, 2.1}, {0, ls, 0}, {ls, 0, 0});  // facing down
    if (up) q = std::vector<glm::dvec3>(q.rbegin(), q.rend());
    surfaces.push_back({"lamp2", q, glm::dvec3(0.0), glm::dvec3(50.0), twoSided});
    auto h = std::make_unique<HierarchicalRadiosity>(surfaces, Options{});
    h->solve();
    room = all = 0;
    for (size_t i = 0; i < surfaces.size(); ++i) {
      const double a = polygonArea(surfaces[i].vertices) * (1.0 - surfaces[i].reflectance.x) * h->surfaceIrradiance(int(i)).x;
      all += a;
      if (i + 1 < surfaces.size()) room += a;
    }
    return h;
  };
  double both = 0, down = 0, up = 0, bothAll = 0, unused = 0;
  const auto h = solve(true, false, both, bothAll);
  solve(false, false, down, unused);
  solve(false, true, up, unused);
  std::printf("room's absorbed power: two-sided %.4f, down + up %.4f; with the lamp's own %.4f of %.4f emitted\n", both,
              down + up, bothAll, 2 * ls * ls * 50.0);
  EXPECT_NEAR(both, down + up, 0.01 * both);
  // Energy: within 2 % (the lamp receives on both faces; a one-sided lamp's back receives
  // nothing, and the up-facing face alone, 0.4 m from the ceiling, is 4.7 % short so).
  EXPECT_NEAR(bothAll, 2 * ls * ls * 50.0, 0.02 * 2 * ls * ls * 50.0);
  // The ceiling right above it is lit directly (and at least by that).
  const int ceiling = 1;
  EXPECT_GT(h->irradiance(h->findLeaf(ceiling, h->toUV(ceiling, {0.65, 2.65, 2.5})))[0],
            50.0 * pointToCentredRectangle(0.15, 0.15, 0.4));
}

TEST(Hierarchy, ALampCloseBelowALargeCeilingLightsIt) {
  // A 25 cm lamp facing up 2 cm and 10 cm below a 4 x 4 m ceiling: nearly all its power reaches
  // the ceiling (F > 0.99), although the ceiling's first quadrature points all lie far from it
  // (the oracle must not take their near-zero spread for an accurate link).
  for (double gap : {0.1, 0.02}) {
    std::vector<Surface> s;
    s.push_back({"ceiling", quad({-2, -2, 1.0 + gap}, {0, 4, 0}, {4, 0, 0}), glm::dvec3(0.01), glm::dvec3(0.0)});
    s.push_back({"lamp", quad({-0.125, -0.125, 1.0}, {0.25, 0, 0}, {0, 0.25, 0}), glm::dvec3(0.0), glm::dvec3(10.0)});
    HierarchicalRadiosity h(s, Options{});
    h.solve();
    const double received = h.surfaceIrradiance(0).x * 16.0, emitted = 10.0 * 0.0625;
    EXPECT_GT(received, 0.99 * emitted) << "gap " << gap;
    EXPECT_LT(received, 1.005 * emitted) << "gap " << gap;
  }
}


namespace {
// An empty closed room 3 x 3.5 x 2.5 m (ceiling 0.8, walls 0.6, floor 0.3, grey) with one 25 cm
// lamp facing down 2 cm below the ceiling, one- or two-sided.
std::vector<Surface> roomWithLampBelowCeiling(bool twoSided) {
  const double W = 3.0, D = 3.5, H = 2.5, a = 0.25;
  std::vector<Surface> s;
  s.push_back({"floor", quad({0, 0, 0}, {W, 0, 0}, {0, D, 0}), glm::dvec3(0.3), glm::dvec3(0.0)});
  s.push_back({"ceiling", quad({0, 0, H}, {0, D, 0}, {W, 0, 0}), glm::dvec3(0.8), glm::dvec3(0.0)});
  s.push_back({"wall_x0", quad({0, 0, 0}, {0, D, 0}, {0, 0, H}), glm::dvec3(0.6), glm::dvec3(0.0)});
  s.push_back({"wall_x1", quad({W, 0, 0}, {0, 0, H}, {0, D, 0}), glm::dvec3(0.6), glm::dvec3(0.0)});
  s.push_back({"wall_y0", quad({0, 0, 0}, {0, 0, H}, {W, 0, 0}), glm::dvec3(0.6), glm::dvec3(0.0)});
  s.push_back({"wall_y1", quad({0, D, 0}, {W, 0, 0}, {0, 0, H}), glm::dvec3(0.6), glm::dvec3(0.0)});
  Surface lamp{"lamp", quad({1.1, 1.6, H - 0.02}, {0, a, 0}, {a, 0, 0}), glm::dvec3(0.0), glm::dvec3(10.0)};
  lamp.twoSided = twoSided;
  s.push_back(lamp);
  return s;
}

// The regions of roomWithLampBelowCeiling that a near-field error shows in: the ceiling within
// 0.5 m of the lamp's centre (the ring its upper face lights), the rest of the ceiling, the walls,
// the floor.
enum Region { kRing, kCeilingRest, kWalls, kFloor, kRegions };
const char* const kRegionName[kRegions] = {"ceiling ring", "ceiling rest", "walls", "floor"};
int regionOf(int surface, const glm::dvec3& p) {
  if (surface == 0) return kFloor;
  if (surface == 1) return glm::length(glm::dvec2(p.x - 1.225, p.y - 1.725)) < 0.5 ? kRing : kCeilingRest;
  return kWalls;
}

// Share of the emitted power that each region of the room absorbs (the rest falls back on the
// lamp, which reflects nothing), by light tracing with Embree: an estimate independent of the
// engine's meshing, links and visibility sampling.
std::array<double, kRegions> regionSharesByLightTracing(const std::vector<Surface>& s, int lamp, int photons,
                                                        uint64_t seed = 0x2545F4914F6CDD1Dull) {
  std::vector<std::vector<glm::dvec3>> polys;
  for (const auto& x : s) polys.push_back(x.vertices);
  const RayScene scene(polys);
  uint64_t state = seed;
  auto uniform = [&state] {
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return double(state >> 11) * (1.0 / 9007199254740992.0);
  };
  auto cosineAbout = [&](const glm::dvec3& n) {
    const glm::dvec3 t = glm::normalize(std::abs(n.x) < 0.9 ? glm::cross(n, glm::dvec3(1, 0, 0)) : glm::cross(n, glm::dvec3(0, 1, 0)));
    const glm::dvec3 b = glm::cross(n, t);
    const double u1 = uniform(), phi = 2 * 3.14159265358979 * uniform(), r = std::sqrt(u1);
    return r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(1 - u1) * n;
  };
  const auto& L = s[size_t(lamp)].vertices;
  const glm::dvec3 lampNormal = glm::normalize(glm::cross(L[1] - L[0], L[3] - L[0]));
  std::array<double, kRegions> out{};
  for (int k = 0; k < photons; ++k) {
    const glm::dvec3 p = L[0] + uniform() * (L[1] - L[0]) + uniform() * (L[3] - L[0]);
    const glm::dvec3 n = (s[size_t(lamp)].twoSided && uniform() < 0.5) ? -lampNormal : lampNormal;
    glm::dvec3 o = p + 1e-5 * n, d = cosineAbout(n);
    for (;;) {
      const RayHit hit = scene.intersect(Ray{glm::vec3(o), glm::vec3(d)});
      if (hit.polygon < 0 || hit.polygon == lamp) break;  // (a closed room: every ray hits something)
      // Absorbed with probability 1 - rho, else reflected whole (unbiased, few bounces).
      if (uniform() >= s[size_t(hit.polygon)].reflectance.x) {
        out[size_t(regionOf(hit.polygon, glm::dvec3(hit.point)))] += 1.0 / photons;
        break;
      }
      glm::dvec3 m = glm::normalize(glm::dvec3(hit.geometricNormal));
      if (glm::dot(m, d) > 0) m = -m;
      o = glm::dvec3(hit.point) + 1e-5 * m;
      d = cosineAbout(m);
    }
  }
  return out;
}

// The whole room's share (the first seed this test was written with).
double roomShareByLightTracing(const std::vector<Surface>& s, int lamp, int photons) {
  double room = 0;
  for (const double r : regionSharesByLightTracing(s, lamp, photons, 0x9E3779B97F4A7C15ull)) room += r;
  return room;
}

double roomShareByEngine(const std::vector<Surface>& s, int lamp) {
  HierarchicalRadiosity h(s, Options{});
  h.solve();
  double absorbed = 0;
  for (size_t i = 0; i < s.size(); ++i)
    if (int(i) != lamp) absorbed += polygonArea(s[i].vertices) * (1 - s[i].reflectance.x) * h.surfaceIrradiance(int(i)).x;
  const auto& l = s[size_t(lamp)];
  return absorbed / (polygonArea(l.vertices) * l.exitance.x * (l.twoSided ? 2 : 1));
}
}  // namespace

TEST(Hierarchy, LightThatATwoSidedLampSendsToTheCeilingMostlyFallsBackOnIt) {
  // A two-sided lamp 2 cm below a ceiling lights the ceiling above it brightly; most of that light
  // falls back on the lamp (which reflects nothing), and only what leaves through the 2 cm gap
  // reaches the room. Before the oracle opened links from such bright patches, their light left
  // with the mean radiosity of a larger ceiling element that the lamp hides only in part: the
  // upper face added 0.54 of its power to the room where light tracing gives 0.37 (now 0.41), and
  // the room absorbed 0.77 of all the light emitted (light tracing 0.68, now 0.70).
  const int lamp = 6;
  const auto one = roomWithLampBelowCeiling(false), two = roomWithLampBelowCeiling(true);
  const double mcOne = roomShareByLightTracing(one, lamp, 200000), mcTwo = roomShareByLightTracing(two, lamp, 200000);
  const double hrOne = roomShareByEngine(one, lamp), hrTwo = roomShareByEngine(two, lamp);
  // What the upper face adds to the room, per unit of the lower face's power.
  const double mcUpper = 2 * mcTwo - mcOne, hrUpper = 2 * hrTwo - hrOne;
  std::printf("room's share of the emitted power: one-sided engine %.4f, light tracing %.4f; two-sided %.4f, %.4f; "
              "upper face's light reaching the room %.3f, %.3f\n",
              hrOne, mcOne, hrTwo, mcTwo, hrUpper, mcUpper);
  EXPECT_NEAR(hrOne, mcOne, 0.015);
  EXPECT_NEAR(hrTwo, mcTwo, 0.03);
  EXPECT_NEAR(hrUpper, mcUpper, 0.06);
}

namespace {
// The engine's absorbed power per region over the emitted power: each leaf's area x (1 - rho) x
// irradiance, split over the regions by an 8 x 8 grid of points on the leaf.
std::array<double, kRegions> regionSharesByEngine(const std::vector<Surface>& s, int lamp) {
  HierarchicalRadiosity h(s, Options{});
  h.solve();
  std::array<double, kRegions> out{};
  const auto& nodes = h.nodes();
  for (size_t i = 0; i < nodes.size(); ++i) {
    const auto& n = nodes[i];
    if (n.isCluster() || !n.isLeaf() || n.surface == lamp) continue;
    const double absorbed = (1 - s[size_t(n.surface)].reflectance.x) * h.irradiance(int(i)).x;
    // (A leaf on a polygon's edge reaches past it, but its points all fall in one region.)
    const glm::dvec3 a = h.toWorld(n.surface, {n.u0, n.v0}), b = h.toWorld(n.surface, {n.u1, n.v0}),
                     c = h.toWorld(n.surface, {n.u0, n.v1});
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) {
        const glm::dvec3 q = a + (x + 0.5) / 8 * (b - a) + (y + 0.5) / 8 * (c - a);
        out[size_t(regionOf(n.surface, q))] += absorbed * n.area / 64.0;
      }
  }
  const auto& l = s[size_t(lamp)];
  for (auto& v : out) v /= polygonArea(l.vertices) * l.exitance.x * (l.twoSided ? 2 : 1);
  return out;
}
}  // namespace

TEST(Hierarchy, ALampCloseBelowTheCeilingLightsEachRegionAsLightTracingSays) {
  // The two-sided lamp 2 cm below the ceiling, region by region: the ring its upper face lights,
  // the rest of the ceiling, the walls, the floor; the one-sided lamp beside it. A near-field
  // error (the ring's light falling back on the lamp, or leaving through the gap) shows in the ring
  // first. Light tracing's own noise at 400 000 photons is below 0.002 per region.
  const int lamp = 6;
  for (const bool twoSided : {false, true}) {
    const auto room = roomWithLampBelowCeiling(twoSided);
    const auto mc = regionSharesByLightTracing(room, lamp, 400000);
    const auto hr = regionSharesByEngine(room, lamp);
    for (int r = 0; r < kRegions; ++r) {
      std::printf("%s lamp, %-12s absorbed share: engine %.4f, light tracing %.4f (%+.1f %%)\n", twoSided ? "two-sided" : "one-sided",
                  kRegionName[r], hr[size_t(r)], mc[size_t(r)], 100 * (hr[size_t(r)] / mc[size_t(r)] - 1));
      // Before the BFV oracle and the near field's finer elements the two-sided lamp's walls were
      // +2.2 % and its floor +3.3 %: the ring's own share was right, but more of its light passed
      // the lamp than does (a partly hidden link kept its unoccluded factor x its mean visibility,
      // and elements wider than the 2 cm gap carried the bright patch past the lamp's outline).
      // Now every region within 1.5 % (the one-sided lamp's ring, a share of 0.004, is within the
      // absolute term: light tracing's own noise there is 2.6 %).
      EXPECT_NEAR(hr[size_t(r)], mc[size_t(r)], 0.015 * mc[size_t(r)] + 0.0005)
          << (twoSided ? "two-sided" : "one-sided") << " lamp, " << kRegionName[r];
    }
  }
}

TEST(Hierarchy, ATwoSidedLampReceivesOnBothFacesSoTheRoomsEnergyCloses) {
  // The lamp 2 cm below the ceiling lights the ceiling above it, and most of that light falls back
  // on the lamp's upper face: the lamp absorbs it there (it reflects nothing). Every surface's
  // absorbed power, the lamp's both faces included, adds up to the power emitted.
  for (const bool twoSided : {false, true}) {
    const auto room = roomWithLampBelowCeiling(twoSided);
    HierarchicalRadiosity h(room, Options{});
    h.solve();
    double absorbed = 0, onLamp = 0;
    for (size_t i = 0; i < room.size(); ++i) {
      const double a = polygonArea(room[i].vertices) * (1 - room[i].reflectance.x) * h.surfaceIrradiance(int(i)).x;
      absorbed += a;
      if (i == 6) onLamp = a;
    }
    const auto& l = room[6];
    const double emitted = polygonArea(l.vertices) * l.exitance.x * (l.twoSided ? 2 : 1);
    std::printf("%s lamp: absorbed %.4f of the emitted power, %.4f of it by the lamp\n", twoSided ? "two-sided" : "one-sided",
                absorbed / emitted, onLamp / emitted);
    EXPECT_NEAR(absorbed, emitted, 0.015 * emitted) << (twoSided ? "two-sided" : "one-sided");
    // (Light tracing's share that falls back on the lamp: 0.0017 one-sided, 0.315 two-sided.)
    if (twoSided) EXPECT_GT(onLamp, 0.25 * emitted);
  }
}

TEST(Hierarchy, ASavedStateComesBackExactlyAfterSurfacesWereAddedRefinedAndSolved) {
  // A virtual box added for a while (its links refined, visibility redone where it crosses, the
  // room solved with it), then the saved state put back: every element, link and radiosity as it
  // was, bit for bit, and the ray scene is the room's again (the box no longer blocks). Removing
  // the box instead leaves its elements behind and changes the solution by the solve's tolerance.
  HierarchicalRadiosity h(occluderScene(), Options{});
  h.solve();
  const size_t nodes = h.nodes().size(), links = h.links().size(), surfaces = h.surfaces().size();
  std::vector<glm::vec3> before(nodes), irradiance(nodes);
  for (size_t i = 0; i < nodes; ++i) {
    before[i] = h.radiosity(int(i));
    irradiance[i] = h.irradiance(int(i));
  }
  const double eRef = h.refinementScale();
  const auto saved = h.saveState();
  // A box on the floor beside the occluder's shadow.
  std::vector<Surface> box;
  const glm::dvec3 lo(1.4, 0.2, 0.0), hi(1.7, 0.5, 0.3);
  box.push_back({"top", quad({lo.x, lo.y, hi.z}, {hi.x - lo.x, 0, 0}, {0, hi.y - lo.y, 0}), glm::dvec3(0.7), glm::dvec3(0.0)});
  box.push_back({"side", quad({lo.x, lo.y, lo.z}, {0, 0, hi.z - lo.z}, {hi.x - lo.x, 0, 0}), glm::dvec3(0.7), glm::dvec3(0.0)});
  const std::vector<int> ids = h.addSurfaces(box);
  h.solve();
  ASSERT_GT(h.nodes().size(), nodes);
  auto blockedThroughTop = [&] {  // a ray down through the box's top
    const RayHit hit = h.rayScene().intersect(Ray{glm::vec3(1.55f, 0.35f, 1.5f), glm::vec3(0.f, 0.f, -1.f), 0.f, 1e30f});
    return hit.polygon;
  };
  EXPECT_EQ(blockedThroughTop(), ids[0]);
  h.restoreState(*saved);
  EXPECT_EQ(h.nodes().size(), nodes);
  EXPECT_EQ(h.links().size(), links);
  EXPECT_EQ(h.surfaces().size(), surfaces);
  EXPECT_EQ(h.refinementScale(), eRef);
  size_t differ = 0;
  for (size_t i = 0; i < nodes; ++i) differ += h.radiosity(int(i)) != before[i] || h.irradiance(int(i)) != irradiance[i];
  EXPECT_EQ(differ, 0u);
  EXPECT_EQ(blockedThroughTop(), 0);  // the floor again
  // And it goes on as the room it was: solving again changes nothing beyond the tolerance.
  h.solve();
  for (size_t i = 0; i < nodes; ++i)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(h.radiosity(int(i))[c], before[i][c], 1e-3f * (before[i][c] + 1e-3f)) << i;
  // Removing instead of restoring leaves the box's elements in the arrays (never reclaimed).
  const std::vector<int> again = h.addSurfaces(box);
  h.removeSurfaces(again);
  EXPECT_GT(h.nodes().size(), nodes);
}
