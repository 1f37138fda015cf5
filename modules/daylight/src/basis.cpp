#include "relume/daylight/basis.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>
#include <numbers>
#include <stdexcept>
#include <string>

#include "relume/geometry/binary.h"
#include "relume/geometry/error.h"
#include "relume/geometry/polygon.h"
#include "relume/geometry/scene.h"
#include "relume/radiosity/form_factor.h"
#include "relume/radiosity/hierarchy.h"
#include "relume/raytrace/outside.h"

namespace relume::daylight {

namespace {
constexpr double kPi = std::numbers::pi;

double seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Every direction within `half` of `axis` below the horizon (the margin as coneInsideCell's).
bool coneBelowHorizon(const glm::dvec3& axis, double half) {
  return std::asin(std::clamp(glm::normalize(axis).z, -1.0, 1.0)) + half < -1e-9;
}

// Region k of the sky at unit radiance.
std::shared_ptr<radiosity::DistantLight> regionLight(const SkyRegions& regions, int k, double pieceDeg) {
  auto light = std::make_shared<radiosity::DistantLight>();
  light->pieceDeg = pieceDeg;
  light->radiance = [&regions, k](const glm::dvec3& d) { return regions.regionOf(d) == k ? 1.0 : 0.0; };
  const SkyRegions::Cell cell = regions.cell(k);
  light->mayShine = [cell](const glm::dvec3& axis, double half) { return coneMeetsCell(axis, half, cell); };
  light->uniform = [cell](const glm::dvec3& axis, double half) { return coneInsideCell(axis, half, cell); };
  return light;
}

std::shared_ptr<radiosity::DistantLight> groundLight(double pieceDeg) {
  auto light = std::make_shared<radiosity::DistantLight>();
  light->pieceDeg = pieceDeg;
  light->radiance = [](const glm::dvec3& d) { return d.z < 0 ? 1.0 : 0.0; };
  light->mayShine = [](const glm::dvec3& axis, double half) { return std::asin(std::clamp(axis.z, -1.0, 1.0)) - half < 0; };
  light->uniform = coneBelowHorizon;
  return light;
}
}  // namespace

bool coneMeetsCell(const glm::dvec3& axis, double halfAngle, const SkyRegions::Cell& cell) {
  if (halfAngle >= kPi) return true;
  const glm::dvec3 u = glm::normalize(axis);
  const double e = std::asin(std::clamp(u.z, -1.0, 1.0));
  // The elevation difference bounds the angle between two directions from below.
  if (e + halfAngle < cell.elev0 || e - halfAngle > cell.elev1) return false;
  if (cell.azim1 - cell.azim0 >= 2 * kPi - 1e-9) return true;
  double a = std::atan2(u.y, u.x);
  if (a < 0) a += 2 * kPi;
  // Circular distance from a to [azim0, azim1].
  double da = 0;
  if (a < cell.azim0 || a > cell.azim1) {
    auto wrap = [](double x) { return std::fmod(std::fmod(x, 2 * kPi) + 2 * kPi, 2 * kPi); };
    da = std::min(wrap(cell.azim0 - a), wrap(a - cell.azim1));
  }
  if (da <= 0) return true;
  // Two directions at elevations of cosine >= r, da apart in azimuth, lie at least a chord of
  // 2 r sin(da / 2) apart (their horizontal parts alone do).
  const double r = std::min(std::cos(e), std::cos(std::max(std::abs(cell.elev0), std::abs(cell.elev1))));
  const double chord = 2.0 * std::max(0.0, r) * std::sin(std::min(da, kPi) / 2);
  return 2.0 * std::asin(std::clamp(chord / 2, 0.0, 1.0)) <= halfAngle;
}

bool coneInsideCell(const glm::dvec3& axis, double halfAngle, const SkyRegions::Cell& cell) {
  constexpr double kMargin = 1e-9;  // radians: regionOf's rounding at a cell's edge is far below it
  if (!(halfAngle >= 0) || halfAngle >= kPi / 2) return false;
  const glm::dvec3 u = glm::normalize(axis);
  const double e = std::asin(std::clamp(u.z, -1.0, 1.0));
  if (!std::isfinite(e)) return false;
  // Every direction in the cone has an elevation within halfAngle of the axis's.
  if (e - halfAngle < cell.elev0 + kMargin) return false;
  const bool wholeCircle = cell.azim1 - cell.azim0 >= 2 * kPi - 1e-9;
  const bool reachesTheZenith = cell.elev1 >= kPi / 2 - 1e-12;
  // A cell that is a whole cap around the zenith holds every direction above its lower edge.
  if (wholeCircle && reachesTheZenith) return true;
  if (e + halfAngle > cell.elev1 - kMargin) return false;
  if (wholeCircle) return true;
  // The cone clear of the zenith (e + halfAngle < pi/2, so cos e > sin halfAngle): its
  // directions' azimuths lie within asin(sin halfAngle / cos e) of the axis's.
  if (e + halfAngle > kPi / 2 - kMargin) return false;
  const double spread = std::asin(std::min(1.0, std::sin(halfAngle) / std::cos(e)));
  double a = std::atan2(u.y, u.x);
  if (a < 0) a += 2 * kPi;
  return a - spread > cell.azim0 + kMargin && a + spread < cell.azim1 - kMargin;
}

DaylightBasis::DaylightBasis(const Scene& scene, const SkyRadiance& refineFor, const BasisOptions& options,
                             Progress& progress)
    : regions_(options.regions), options_(options) {
  setUp(scene, refineFor);
  auto t0 = std::chrono::steady_clock::now();
  {
    Progress stage(progress, 0.0, 0.3);
    stage.report(0, "refining the links for the sky");
    engine_->solve(stage);
  }
  refineSeconds_ = seconds(t0);
  Progress stage(progress, 0.3, 1.0);
  solveBases(stage);
  progress.report(1.0, "daylight basis solved");
}

void DaylightBasis::setUp(const Scene& scene, const SkyRadiance& refineFor) {
  const BasisOptions& options = options_;
  if (refineFor.region.size() != size_t(regions_.size()))
    throw Error(scene.sourceFile, "daylight", "the sky was averaged over " + std::to_string(refineFor.region.size()) +
                                                  " regions, the basis has " + std::to_string(regions_.size()));
  for (size_t i = 0; i < scene.polygons.size(); ++i) {
    const Polygon& p = scene.polygons[i];
    if (p.kind != PolygonKind::Window) continue;
    if (p.vertices.size() < 3 || !(polygonArea(p.vertices) > 0))
      throw Error(scene.sourceFile, "polygon '" + p.name + "'", "a window with no area");
    windows_.push_back(int(i));
  }
  if (windows_.empty())
    throw Error(scene.sourceFile, "daylight", "the room has no window (a polygon of kind \"window\"): no daylight enters it");
  // Outside polygons: beyond some window's plane.
  double groundArea = 0;
  glm::dvec3 groundAlbedo(0.0);
  outside_ = outsidePolygons(scene);
  for (int i : outside_) {
    const Polygon& p = scene.polygons[size_t(i)];
    if (p.kind == PolygonKind::Real && polygonNormal(p.vertices).z > 0.9) {
      const double a = polygonArea(p.vertices);
      groundArea += a;
      groundAlbedo += a * p.albedo;
    }
  }
  // A window must face into the room: some of the room's polygons lie in front of it.
  for (int w : windows_) {
    const Polygon& win = scene.polygons[size_t(w)];
    const glm::dvec3 n = polygonNormal(win.vertices), c = polygonCentroid(win.vertices);
    bool inFront = false;
    for (size_t i = 0; i < scene.polygons.size() && !inFront; ++i) {
      if (int(i) == w || std::find(outside_.begin(), outside_.end(), int(i)) != outside_.end()) continue;
      for (const auto& v : scene.polygons[i].vertices) inFront = inFront || glm::dot(v - c, n) > 0.05;
    }
    if (!inFront)
      throw Error(scene.sourceFile, "polygon '" + win.name + "'",
                  "the window faces away from the room (its vertices must run counter-clockwise seen from inside)");
    // In a wall: some real polygon in its plane, facing the same way, touching it.
    glm::dvec3 lo(1e300), hi(-1e300);
    for (const auto& v : win.vertices) lo = glm::min(lo, v), hi = glm::max(hi, v);
    bool inWall = false;
    for (const auto& p : scene.polygons) {
      if (p.kind != PolygonKind::Real || p.vertices.size() < 3 || glm::dot(polygonNormal(p.vertices), n) < 0.99) continue;
      glm::dvec3 plo(1e300), phi(-1e300);
      bool coplanar = true;
      for (const auto& v : p.vertices) {
        plo = glm::min(plo, v), phi = glm::max(phi, v);
        coplanar = coplanar && std::abs(glm::dot(v - c, n)) < 0.01;
      }
      const bool touching = glm::all(glm::lessThanEqual(plo, hi + 0.01)) && glm::all(glm::greaterThanEqual(phi, lo - 0.01));
      inWall = inWall || (coplanar && touching);
    }
    if (!inWall)
      throw Error(scene.sourceFile, "polygon '" + win.name + "'",
                  "the window is not in a wall: no wall polygon lies in its plane beside it");
  }
  groundReflectance_ = groundArea > 0 ? luminance(groundAlbedo / groundArea) : options.groundReflectance;

  std::vector<radiosity::Surface> surfaces = radiosity::surfacesFromScene(scene);
  for (auto& s : surfaces) s.exitance = glm::dvec3(0.0);  // lamps dark: each is its own term
  // The sky the links are refined for, as one luminance per direction plus its sun.
  auto refineLight = std::make_shared<radiosity::DistantLight>();
  refineLight->pieceDeg = options.pieceDeg;
  {
    std::vector<double> lum(refineFor.region.size());
    for (size_t k = 0; k < lum.size(); ++k) lum[k] = luminance(refineFor.region[k]);
    const double ground = luminance(groundRadiance(refineFor));
    // Never dark: a link is kept only where some light passes, and every basis (the ground's,
    // another sky's sun) needs the links from the windows to whatever they can light.
    double mean = ground;
    for (double l : lum) mean += l / double(lum.size());
    const double floor = 1e-3 * (mean > 0 ? mean : 1.0);
    const SkyRegions* regions = &regions_;
    refineLight->radiance = [lum, ground, regions, floor](const glm::dvec3& d) {
      const int k = regions->regionOf(d);
      return std::max(floor, k < 0 ? ground : lum[size_t(k)]);
    };
    // Alike across a piece seen within one region, or below the horizon throughout.
    refineLight->uniform = [regions](const glm::dvec3& axis, double half) {
      if (coneBelowHorizon(axis, half)) return true;
      const int k = regions->regionOf(axis);
      return k >= 0 && coneInsideCell(axis, half, regions->cell(k));
    };
    if (refineFor.sun.found)
      refineLight->beams.push_back({glm::normalize(refineFor.sun.direction), luminance(refineFor.sun.irradiance)});
  }
  for (size_t i = 0; i < scene.polygons.size(); ++i) lamp_.push_back(scene.polygons[i].kind == PolygonKind::Light || scene.lampOfPolygon(int(i)) >= 0);
  for (const auto& l : scene.lamps) {
    if (l.polygon < 0 || size_t(l.polygon) >= scene.polygons.size())
      throw Error(scene.sourceFile, "lamp " + l.name, "names no polygon of the room");
    lampSurface_.push_back(l.polygon);
  }
  sceneLamps_ = int(lampSurface_.size());
  lampExitance_.assign(lampSurface_.size(), glm::dvec3(0.0));
  lampSolution_.resize(lampSurface_.size());
  for (int w : windows_) {
    surfaces[size_t(w)].opening = true;
    surfaces[size_t(w)].exitance = glm::dvec3(kPi);
    surfaces[size_t(w)].distant = refineLight;
  }
  refineLight_ = refineLight;
  const radiosity::Options engineOptions = [&] {
    radiosity::Options o = options.engine ? *options.engine : radiosity::Options{};
    o.oracle = radiosity::Oracle::BF;  // (see BasisOptions::engine)
    return o;
  }();
  engine_ = std::make_unique<radiosity::HierarchicalRadiosity>(std::move(surfaces), engineOptions);
  engine_->removeSurfaces(outside_);
  sceneSurfaces_ = engine_->surfaces().size();
}

namespace {
constexpr char kBasisMagic[8] = {'R', 'L', 'D', 'Y', 'B', 'A', 'S', '1'};
constexpr size_t kMaxSolutions = 4096;
}  // namespace

void DaylightBasis::write(ByteWriter& out) const {
  if (undo_ || lampSurface_.size() != size_t(sceneLamps_) || engine_->surfaces().size() != sceneSurfaces_)
    throw Error("", "daylight basis", "cannot be kept while virtual objects or lamps are in it");
  out.raw(kBasisMagic, 8);
  out.u32(uint32_t(regions_.size()));
  out.f64(options_.pieceDeg);
  out.f64(groundReflectance_);
  out.f64(refineSeconds_);
  out.f64(secondsPerBasis_);
  engine_->writeState(out);
  const size_t nodes = engine_->nodes().size();
  out.u64(bases_.size());
  for (const auto& b : bases_) out.array(b);
  out.u32(haveSun_ ? 1u : 0u);
  for (int k = 0; k < 3; ++k) out.f64(sunDirection_[k]);
  out.array(haveSun_ ? sun_ : std::vector<glm::vec3>{});
  out.array(haveSun_ ? sunDirect_ : std::vector<glm::vec3>{});
  out.u64(lampSolution_.size());
  for (const auto& l : lampSolution_) out.array(l.size() == nodes ? l : std::vector<glm::vec3>{});
}

DaylightBasis::DaylightBasis(const Scene& scene, const SkyRadiance& refineFor, const BasisOptions& options, ByteReader& in)
    : regions_(options.regions), options_(options) {
  const char* part = "daylight basis";
  in.need(8, part);
  if (std::memcmp(in.bytes().data() + in.pos, kBasisMagic, 8) != 0) in.fail(part, "is not a kept daylight basis");
  in.pos += 8;
  if (in.u32(part) != uint32_t(regions_.size()))
    in.fail(part, "was solved for another number of sky regions (solve it again)");
  if (in.f64(part) != options_.pieceDeg) in.fail(part, "was solved with other window pieces (solve it again)");
  setUp(scene, refineFor);
  if (in.f64(part) != groundReflectance_) in.fail(part, "was solved for another ground albedo (solve it again)");
  refineSeconds_ = in.f64(part);
  secondsPerBasis_ = in.f64(part);
  engine_->readState(in);  // checks the room's polygons, reflectances and engine options
  const size_t nodes = engine_->nodes().size();
  auto solution = [&](bool mayBeEmpty) {
    auto v = in.array<glm::vec3>(part, nodes);
    if (v.size() != nodes && !(mayBeEmpty && v.empty())) in.fail(part, "a solution does not cover the hierarchy (damaged)");
    return v;
  };
  const uint64_t nb = in.u64(part);
  if (nb != uint64_t(regions_.size() + 1)) in.fail(part, "holds another number of basis solutions than the regions need (damaged)");
  for (uint64_t k = 0; k < nb; ++k) bases_.push_back(solution(false));
  const uint32_t sun = in.u32(part);
  if (sun > 1) in.fail(part, "is damaged (the sun's flag)");
  for (int k = 0; k < 3; ++k) sunDirection_[k] = in.f64(part);
  sun_ = solution(sun == 0);
  sunDirect_ = solution(sun == 0);
  haveSun_ = sun == 1;
  if (haveSun_ && std::abs(glm::length(sunDirection_) - 1) > 1e-6) in.fail(part, "is damaged (the sun's direction)");
  const uint64_t nl = in.u64(part);
  if (nl != lampSolution_.size()) in.fail(part, "was solved for another number of lamps (solve it again)");
  if (nl > kMaxSolutions) in.fail(part, "is damaged");
  for (auto& l : lampSolution_) l = solution(true);
  ++revision_;
}

void DaylightBasis::solveBases(Progress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  const int n = regions_.size() + 1;
  std::vector<std::vector<glm::vec3>> bases;
  bases.reserve(size_t(n));
  for (int k = 0; k < n; ++k) {
    Progress stage(progress, double(k) / n, double(k + 1) / n);
    stage.report(0, k < regions_.size() ? "basis solution " + std::to_string(k + 1) + " of " + std::to_string(n) +
                                              " (sky region " + std::to_string(k + 1) + ")"
                                        : "basis solution " + std::to_string(n) + " of " + std::to_string(n) + " (the ground)");
    bases.push_back(solveFor(k < regions_.size() ? regionLight(regions_, k, options_.pieceDeg) : groundLight(options_.pieceDeg),
                             stage));
  }
  bases_ = std::move(bases);
  ++revision_;
  haveSun_ = false;  // solved again on demand, on the links as they are now
  for (auto& l : lampSolution_) l.clear();  // so are the lamps'
  secondsPerBasis_ = seconds(t0) / n;
}

void DaylightBasis::extendToNodes() {
  // New elements (refinement appends children after their parents) hold their parent's values
  // until solved again.
  const auto& nodes = engine_->nodes();
  auto extend = [&](std::vector<glm::vec3>& v) {
    if (v.empty()) return;
    for (size_t i = v.size(); i < nodes.size(); ++i) v.push_back(v[size_t(nodes[i].parent)]);
  };
  for (auto& b : bases_) extend(b);
  extend(sun_);
  extend(sunDirect_);
  for (auto& l : lampSolution_) extend(l);
}

bool DaylightBasis::anyLampOn() const {
  for (const auto& e : lampExitance_)
    if (e != glm::dvec3(0.0)) return true;
  return false;
}

int DaylightBasis::lampOfSurface(int surface) const {
  for (size_t l = 0; l < lampSurface_.size(); ++l)
    if (lampSurface_[l] == surface) return int(l);
  return -1;
}

void DaylightBasis::setLampExitance(int lamp, const glm::dvec3& exitance) {
  if (lamp < 0 || size_t(lamp) >= lampExitance_.size()) throw Error("", "lamp", "no lamp " + std::to_string(lamp + 1) + " in the room");
  for (int c = 0; c < 3; ++c)
    if (!(exitance[c] >= 0) || !std::isfinite(exitance[c]))
      throw Error("", "lamp", "exitance must be finite and >= 0");
  if (exitance == lampExitance_[size_t(lamp)]) return;
  lampExitance_[size_t(lamp)] = exitance;
  ++revision_;  // what is made from the combination is made again
}

const std::vector<glm::vec3>& DaylightBasis::lampSolution(int lamp, Progress& progress) {
  if (lamp < 0 || size_t(lamp) >= lampSolution_.size()) throw Error("", "lamp", "no lamp " + std::to_string(lamp + 1) + " in the room");
  auto& out = lampSolution_[size_t(lamp)];
  if (!out.empty()) return out;
  const int s = lampSurface_[size_t(lamp)];
  const double lampArea = polygonArea(engine_->surfaces()[size_t(s)].vertices);
  if (!(lampArea > 0)) throw Error("", "lamp", "lamp " + std::to_string(lamp + 1) + "'s polygon has no area");
  // The links refined for this lamp: the refinement threshold is relative to the emitted power,
  // so the lamp is refined at a thousand times the power the windows would let in under a sky of
  // unit radiance (the faint sky through them, kept so that no link another solution needs is
  // dropped, is a thousandth of that again); the threshold's scale is put back after, so that
  // objects added later are refined as before.
  double windowArea = 0;
  for (int w : windows_) windowArea += polygonArea(engine_->surfaces()[size_t(w)].vertices);
  const double faces = engine_->surfaces()[size_t(s)].twoSided ? 2.0 : 1.0;
  auto faint = std::make_shared<radiosity::DistantLight>();
  faint->pieceDeg = options_.pieceDeg;
  faint->radiance = [](const glm::dvec3&) { return 1e-3; };
  faint->uniform = [](const glm::dvec3&, double) { return true; };
  auto dark = std::make_shared<radiosity::DistantLight>();
  dark->radiance = [](const glm::dvec3&) { return 0.0; };
  dark->mayShine = [](const glm::dvec3&, double) { return false; };
  const double scale = engine_->refinementScale();
  try {
    {
      for (int w : windows_) engine_->setDistantLight(w, faint);
      engine_->setExitance(s, glm::dvec3(1e3 * kPi * windowArea / (faces * lampArea)));
      Progress stage(progress, 0.0, 0.8);
      stage.report(0, "refining the links for lamp " + std::to_string(lamp + 1));
      engine_->solve(stage);
      extendToNodes();
    }
    engine_->setExitance(s, glm::dvec3(1.0));
    Progress stage(progress, 0.8, 1.0);
    std::vector<glm::vec3> b = solveFor(dark, stage);
    engine_->setExitance(s, glm::dvec3(0.0));
    engine_->setRefinementScale(scale);
    out = std::move(b);
  } catch (...) {
    engine_->setExitance(s, glm::dvec3(0.0));  // dark again in every other solution
    engine_->setRefinementScale(scale);
    throw;
  }
  ++revision_;
  return out;
}

std::vector<int> DaylightBasis::addObjects(const std::vector<Polygon>& polygons, Progress& progress) {
  return addObjects(polygons, {}, progress);
}

struct DaylightBasis::Undo {
  std::vector<int> surfaces;  // what the add put in
  std::shared_ptr<const radiosity::HierarchicalRadiosity::State> engine;
  std::vector<std::vector<glm::vec3>> bases, lampSolution;
  std::vector<glm::vec3> sun, sunDirect;
  glm::dvec3 sunDirection{0.0};
  bool haveSun = false;
  std::vector<bool> lamp;
  std::vector<int> lampSurface;
  double secondsPerBasis = 0;
};

void DaylightBasis::putBack(Undo&& u) {
  engine_->restoreState(*u.engine);
  bases_ = std::move(u.bases);
  sun_ = std::move(u.sun);
  sunDirect_ = std::move(u.sunDirect);
  sunDirection_ = u.sunDirection;
  haveSun_ = u.haveSun;
  lamp_ = std::move(u.lamp);
  lampSurface_ = std::move(u.lampSurface);
  lampSolution_ = std::move(u.lampSolution);
  lampExitance_.resize(lampSurface_.size());  // the lamps there before shine as they were set since
  secondsPerBasis_ = u.secondsPerBasis;
  ++revision_;
}

std::vector<int> DaylightBasis::addObjects(const std::vector<Polygon>& polygons, const std::vector<BasisLamp>& lamps,
                                           Progress& progress) {
  for (const auto& l : lamps) {
    if (l.polygon.size() < 3 || !(polygonArea(l.polygon) > 1e-12))
      throw Error("", "virtual lamp " + l.name, "its polygon has no area");
    for (int c = 0; c < 3; ++c)
      if (!(l.exitance[c] >= 0) || !std::isfinite(l.exitance[c]))
        throw Error("", "virtual lamp " + l.name, "its exitance must be finite and >= 0");
  }
  auto undo = std::make_shared<Undo>(Undo{{}, engine_->saveState(), bases_, lampSolution_, sun_, sunDirect_, sunDirection_,
                                          haveSun_, lamp_, lampSurface_, secondsPerBasis_});
  haveSun_ = false;
  std::vector<radiosity::Surface> add;
  for (const auto& p : polygons) {
    radiosity::Surface s;
    s.name = p.name;
    s.vertices = p.vertices;
    s.reflectance = p.albedo;
    add.push_back(std::move(s));
  }
  for (const auto& l : lamps) {  // dark in every basis (reflectance 0): each lamp is its own term
    radiosity::Surface s;
    s.name = l.name;
    s.vertices = l.polygon;
    s.twoSided = l.twoSided;
    add.push_back(std::move(s));
  }
  std::vector<int> ids;
  {
    // Their links are refined under the sky the hierarchy was refined for (never dark anywhere).
    for (int w : windows_) engine_->setDistantLight(w, refineLight_);
    Progress stage(progress, 0.0, 0.3);
    try {
      ids = engine_->addSurfaces(add, stage);
    } catch (...) {  // a Cancel while their links were refined: all as it was
      putBack(std::move(*undo));
      throw;
    }
  }
  undo->surfaces = ids;
  lamp_.resize(engine_->surfaces().size(), false);
  for (size_t k = 0; k < lamps.size(); ++k) {
    const int s = ids[polygons.size() + k];
    lamp_[size_t(s)] = true;
    lampSurface_.push_back(s);
    lampExitance_.push_back(lamps[k].exitance);
    lampSolution_.emplace_back();
  }
  try {
    Progress stage(progress, 0.3, 1.0);
    solveBases(stage);
  } catch (...) {  // a Cancel: the objects go again, and the bases are those without them
    putBack(std::move(*undo));
    throw;
  }
  if (!ids.empty()) undo_ = std::move(undo);  // (an earlier add's surfaces are then removed by solving again)
  return ids;
}

void DaylightBasis::removeObjects(const std::vector<int>& surfaces, Progress& progress) {
  if (undo_ && undo_->surfaces == surfaces) {
    const std::shared_ptr<Undo> u = std::move(undo_);
    putBack(std::move(*u));
    return;
  }
  undo_.reset();  // what was saved after these were added holds them
  haveSun_ = false;
  for (size_t l = lampSurface_.size(); l-- > size_t(sceneLamps_);)
    if (std::find(surfaces.begin(), surfaces.end(), lampSurface_[l]) != surfaces.end()) {
      lamp_[size_t(lampSurface_[l])] = false;
      lampSurface_.erase(lampSurface_.begin() + std::ptrdiff_t(l));
      lampExitance_.erase(lampExitance_.begin() + std::ptrdiff_t(l));
      lampSolution_.erase(lampSolution_.begin() + std::ptrdiff_t(l));
    }
  engine_->removeSurfaces(surfaces);
  solveBases(progress);
}

DaylightBasis::~DaylightBasis() = default;

std::vector<glm::vec3> DaylightBasis::solveFor(std::shared_ptr<const radiosity::DistantLight> light, Progress& progress) {
  for (int w : windows_) engine_->setDistantLight(w, light);
  engine_->clearSolution();  // from emission, not from the last basis's solution
  engine_->iterate(progress);
  std::vector<glm::vec3> b(engine_->nodes().size());
  for (size_t i = 0; i < b.size(); ++i) b[i] = engine_->radiosity(int(i));
  return b;
}

const std::vector<glm::vec3>& DaylightBasis::sunSolution(const glm::dvec3& direction, Progress& progress) {
  const glm::dvec3 d = glm::normalize(direction);
  if (haveSun_ && glm::dot(d, sunDirection_) > 1 - 1e-12) return sun_;
  haveSun_ = false;  // until this one is solved (a Cancel midway leaves no stale sun behind)
  auto light = std::make_shared<radiosity::DistantLight>();
  light->beams.push_back({d, 1.0});
  // The links refined for this sun's patch (its edges as sharp as the elements allow), with a
  // faint sky beside it so that no link another basis needs is dropped; the bases solved before
  // hold their values on the new elements (an element's radiosity is its parent's until solved).
  {
    auto refine = std::make_shared<radiosity::DistantLight>(*light);
    refine->pieceDeg = options_.pieceDeg;
    refine->radiance = [](const glm::dvec3&) { return 1e-3; };
    refine->uniform = [](const glm::dvec3&, double) { return true; };
    for (int w : windows_) engine_->setDistantLight(w, refine);
    Progress stage(progress, 0.0, 0.8);
    stage.report(0, "refining the links for the sun");
    engine_->solve(stage);
    extendToNodes();
  }
  Progress stage(progress, 0.8, 1.0);
  sun_ = solveFor(light, stage);
  // The beam's own share: E = F V B_window over the links from the windows (B = pi per unit).
  const auto& nodes = engine_->nodes();
  sunDirect_.assign(nodes.size(), glm::vec3(0.f));
  for (const auto& l : engine_->links()) {
    const int src = nodes[size_t(l.source)].surface;
    if (src >= 0 && std::find(windows_.begin(), windows_.end(), src) != windows_.end())
      sunDirect_[size_t(l.receiver)] += glm::vec3(float(kPi) * l.formFactor * l.visibility);
  }
  for (size_t n = 1; n < nodes.size(); ++n)  // parents come before their children
    if (nodes[n].parent >= 0) sunDirect_[n] += sunDirect_[size_t(nodes[n].parent)];
  sunDirection_ = d;
  haveSun_ = true;
  ++revision_;
  return sun_;
}

glm::dvec3 DaylightBasis::groundRadiance(const SkyRadiance& sky) const {
  // The horizontal plane's projected solid angle per region, integrated once (the constructor
  // asks first, so no two threads fill it at once).
  if (horizontal_.empty()) {
    SkyRadiance unit;
    unit.region.assign(size_t(regions_.size()), glm::dvec3(0.0));
    horizontal_.resize(size_t(regions_.size()));
    for (int k = 0; k < regions_.size(); ++k) {
      unit.region[size_t(k)] = glm::dvec3(1.0);
      horizontal_[size_t(k)] = planeIrradiance(regions_, unit, {0, 0, 1}).x;
      unit.region[size_t(k)] = glm::dvec3(0.0);
    }
  }
  glm::dvec3 e(0.0);
  for (int k = 0; k < regions_.size(); ++k) e += horizontal_[size_t(k)] * sky.region[size_t(k)];
  if (sky.sun.found) e += sky.sun.irradiance * std::max(0.0, glm::normalize(sky.sun.direction).z);
  return groundReflectance_ * e / kPi;
}

std::vector<glm::vec3> DaylightBasis::combine(const SkyRadiance& sky, Progress& progress) {
  if (sky.region.size() != size_t(regions_.size()))
    throw Error("", "sky", "averaged over " + std::to_string(sky.region.size()) + " regions, the basis has " +
                               std::to_string(regions_.size()));
  // The sun first: its links may refine the hierarchy, and every basis then covers the new elements.
  const bool sun = sky.sun.found && sky.sun.direction.z > 0;
  if (sun) sunSolution(sky.sun.direction, progress);
  for (size_t l = 0; l < lampExitance_.size(); ++l)
    if (lampExitance_[l] != glm::dvec3(0.0)) lampSolution(int(l), progress);
  extendToNodes();
  // The weights and their solutions, then one pass over the nodes in parallel chunks.
  std::vector<const glm::vec3*> src;
  std::vector<glm::vec3> w;
  auto term = [&](const std::vector<glm::vec3>& basis, const glm::dvec3& weight) {
    if (weight == glm::dvec3(0.0)) return;
    src.push_back(basis.data());
    w.emplace_back(weight);
  };
  for (int k = 0; k < regions_.size(); ++k) term(bases_[size_t(k)], sky.region[size_t(k)]);
  term(bases_.back(), groundRadiance(sky));
  if (sun) term(sun_, sky.sun.irradiance);
  for (size_t l = 0; l < lampExitance_.size(); ++l)
    if (lampExitance_[l] != glm::dvec3(0.0)) term(lampSolution_[l], lampExitance_[l]);
  std::vector<glm::vec3> b(engine_->nodes().size(), glm::vec3(0.f));
  tbb::parallel_for(tbb::blocked_range<size_t>(0, b.size(), 2048), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t t = 0; t < src.size(); ++t) {
      const glm::vec3 wt = w[t];
      const glm::vec3* s = src[t];
      for (size_t i = r.begin(); i < r.end(); ++i) b[i] += wt * s[i];
    }
  });
  return b;
}

std::vector<glm::vec3> DaylightBasis::irradiance(const SkyRadiance& sky, bool directSun, Progress& progress) {
  std::vector<glm::vec3> e = combine(sky, progress);
  extendToNodes();
  const bool sun = sky.sun.found && sky.sun.direction.z > 0;
  const glm::vec3 sunE(sky.sun.irradiance);
  for (size_t n = 0; n < e.size(); ++n) {
    const glm::vec3& rho = engine_->reflectanceOf(int(n));
    for (int c = 0; c < 3; ++c) e[n][c] = rho[c] > 0 ? e[n][c] / rho[c] : 0.f;
    if (sun && !directSun) e[n] = glm::max(e[n] - sunE * sunDirect_[n], glm::vec3(0.f));
  }
  return e;
}

glm::dvec3 DaylightBasis::surfaceMean(const std::vector<glm::vec3>& b, int surface) const {
  const auto& nodes = engine_->nodes();
  const auto& children = engine_->children();
  if (b.size() < nodes.size())  // a solution from before the hierarchy was refined further
    throw std::invalid_argument("surfaceMean: a solution of " + std::to_string(b.size()) + " nodes for a hierarchy of " +
                                std::to_string(nodes.size()));
  glm::dvec3 sum(0.0);
  double area = 0;
  std::vector<int> stack{engine_->surfaceRoot(surface)};
  while (!stack.empty()) {
    const int n = stack.back();
    stack.pop_back();
    if (n < 0) continue;
    const auto& N = nodes[size_t(n)];
    if (N.isLeaf()) {
      sum += double(N.area) * glm::dvec3(b[size_t(n)]);
      area += N.area;
      continue;
    }
    for (int i = 0; i < N.childCount; ++i) stack.push_back(children[size_t(N.childBegin + i)]);
  }
  return area > 0 ? sum / area : glm::dvec3(0.0);
}

}  // namespace relume::daylight
