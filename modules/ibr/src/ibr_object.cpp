#include "relume/ibr/ibr_object.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <numbers>

#include "relume/geometry/polygon.h"
#include "relume/image/image.h"
#include "relume/radiosity/form_factor.h"
#include "relume/radiosity/hierarchy.h"
#include "relume/raytrace/ray_scene.h"

namespace relume::ibr {

namespace {

glm::dvec3 bottomCentre(const ImageFan& fan) {
  return glm::dvec3(0.5 * (fan.boundsMin.x + fan.boundsMax.x), 0.5 * (fan.boundsMin.y + fan.boundsMax.y), fan.boundsMin.z);
}

glm::dvec3 turn(const glm::dvec3& d, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return glm::dvec3(c * d.x - s * d.y, s * d.x + c * d.y, d.z);
}

// Points spread over a convex polygon, with weights (their share of its area) summing to 1: in
// each triangle of its fan, the centres of the n (n + 1) / 2 upright triangles of its n-fold
// subdivision.
std::vector<std::pair<glm::dvec3, double>> pointsOn(const std::vector<glm::dvec3>& poly, int n) {
  std::vector<std::pair<glm::dvec3, double>> out;
  const double area = polygonArea(poly);
  for (size_t t = 1; t + 1 < poly.size(); ++t) {
    const glm::dvec3 a = poly[t] - poly[0], b = poly[t + 1] - poly[0];
    const double share = area > 0 ? 0.5 * glm::length(glm::cross(a, b)) / area : 1.0 / double(poly.size() - 2);
    const double each = share / (n * (n + 1) / 2);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n - i; ++j) out.push_back({poly[0] + (i + 1.0 / 3.0) / n * a + (j + 1.0 / 3.0) / n * b, each});
  }
  return out;
}

// The view frame `ax` (ImageFan::axes): code normal -> object direction.
glm::dvec3 fromView(const ImageFan::Axes& ax, const glm::vec3& n) {
  return double(n.x) * ax.right + double(n.y) * ax.up + double(n.z) * ax.toCamera;
}

// A stored (sRGB) albedo byte, linear: looked up (the shading loop reads three per fan texel).
float decode(uint8_t s) {
  static const std::array<float, 256> linear = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[size_t(i)] = srgbToLinear(float(i) / 255.f);
    return t;
  }();
  return linear[s];
}

}  // namespace

glm::dvec3 Placement::toWorld(const ImageFan& fan, const glm::dvec3& p) const {
  return position + scale * turn(p - bottomCentre(fan), yaw);
}
glm::dvec3 Placement::toObject(const ImageFan& fan, const glm::dvec3& w) const {
  return bottomCentre(fan) + turn(w - position, -yaw) / scale;
}
glm::dvec3 Placement::toWorldDirection(const glm::dvec3& d) const { return turn(d, yaw); }
glm::dvec3 Placement::toObjectDirection(const glm::dvec3& d) const { return turn(d, -yaw); }

glm::dvec3 ObjectLamp::intensityTowards(const glm::dvec3& p) const {
  const glm::dvec3 to = p - position;
  const double d = glm::length(to);
  if (!(d > 0) || polygon.size() < 3) return glm::dvec3(0.0);
  const double cosT = glm::dot(polygonNormal(polygon), to / d);
  double shape;
  if (photometry) shape = radiosity::EmitterShape(polygon, twoSided, photometry).weight(p) * std::abs(cosT);
  else shape = (twoSided || cosT > 0) ? std::abs(cosT) : 0.0;
  return exitance / std::numbers::pi * polygonArea(polygon) * shape * visible;
}

ObjectLighting lightingAt(const radiosity::HierarchicalRadiosity& h, const glm::dvec3& c, int shRays) {
  ObjectLighting out;
  out.centre = c;
  out.indirect = radiosity::incidentRadiance(h, c, false, shRays);
  const auto& surfaces = h.surfaces();
  for (size_t s = 0; s < surfaces.size(); ++s) {
    const auto& surf = surfaces[s];
    if (surf.vertices.size() < 3 || glm::dot(surf.exitance, surf.exitance) <= 0) continue;
    ObjectLamp l;
    l.surface = int(s);
    l.polygon = surf.vertices;
    l.exitance = surf.exitance;
    l.twoSided = surf.twoSided;
    l.photometry = surf.photometry;
    l.position = polygonCentroid(surf.vertices);
    const glm::dvec3 toObj = c - l.position;
    const double d = glm::length(toObj);
    if (!(d > 0)) continue;
    const double cosT = glm::dot(polygonNormal(surf.vertices), toObj / d);
    // The share of the lamp the centre sees (points over its area, lifted off it so that it does
    // not hide itself).
    const glm::dvec3 lift = (cosT >= 0 ? 1.0 : -1.0) * 1e-4 * polygonNormal(surf.vertices);
    l.visible = 0;
    for (const auto& [p, w] : pointsOn(surf.vertices, 4))
      if (!h.rayScene().occluded(glm::vec3(c), glm::vec3(p + lift))) l.visible += w;
    l.intensity = l.intensityTowards(c);
    out.lamps.push_back(std::move(l));
  }
  return out;
}

LampTables lampTables(const ImageFan& fan, int view, const Placement& place, const ObjectLamp& lamp, int cells) {
  const FanView& v = fan.view(view);
  const bool cached = cells == kTableCells;
  LampTables out;
  out.cells = cells;
  out.table.resize(size_t(cells) * cells);
  const auto& normals = byteToNormal();
  const ImageFan::Axes ax = fan.axes(view);
  const glm::dvec3 r = ax.right, u = ax.up, d = ax.toCamera;
  for (int cy = 0; cy < cells; ++cy)
    for (int cx = 0; cx < cells; ++cx) {
      const double depth = cached ? double(v.cellDepth[size_t(cy) * cells + cx]) : fan.radius;
      const double x = (cx + 0.5) / cells * fan.size, y = (cy + 0.5) / cells * fan.size;
      const glm::dvec3 p = place.toWorld(fan, fan.pointAt(ax, x, y, depth));
      const glm::dvec3 toLamp = lamp.position - p;
      const double dist = glm::length(toLamp);
      const glm::dvec3 w = place.toObjectDirection(toLamp / dist);
      const glm::dvec3 lv(glm::dot(w, r), glm::dot(w, u), glm::dot(w, d));
      const glm::dvec3 i = lamp.intensityTowards(p);
      LightTable& t = out.table[size_t(cy) * cells + cx];
      for (int k = 0; k < kNormalCodes; ++k)
        t[size_t(k)] = glm::vec3(i * std::max(0.0, glm::dot(glm::dvec3(normals[size_t(k)]), lv)));
    }
  return out;
}

LightTable indirectTable(const ImageFan& fan, int view, const Placement& place, const radiosity::SH9& sh) {
  const auto& normals = byteToNormal();
  const ImageFan::Axes ax = fan.axes(view);
  LightTable t;
  for (int k = 0; k < kNormalCodes; ++k)
    // (Nine coefficients ring: towards what a strong source leaves dark the sum can dip below zero,
    // which drew a vase's rim in the complement of the wall's colour; no light is negative.)
    t[size_t(k)] = glm::vec3(glm::max(radiosity::shIrradiance(sh, place.toWorldDirection(fromView(ax, normals[size_t(k)]))),
                                      glm::dvec3(0.0)));
  return t;
}

std::vector<LightTable> indirectTables(const ImageFan& fan, int view, const Placement& place,
                                       const std::function<radiosity::SH9(const glm::dvec3&)>& indirectAt) {
  const FanView& v = fan.view(view);
  const ImageFan::Axes ax = fan.axes(view);
  std::vector<LightTable> out;
  out.reserve(size_t(kTableCells) * kTableCells);
  for (int cy = 0; cy < kTableCells; ++cy)
    for (int cx = 0; cx < kTableCells; ++cx) {
      const double x = (cx + 0.5) / kTableCells * fan.size, y = (cy + 0.5) / kTableCells * fan.size;
      const double depth = double(v.cellDepth[size_t(cy) * kTableCells + cx]);
      out.push_back(indirectTable(fan, view, place, indirectAt(place.toWorld(fan, fan.pointAt(ax, x, y, depth)))));
    }
  return out;
}

std::array<int, kDrawnViews> viewsToward(const ImageFan& fan, const Placement& place, const glm::dvec3& eye) {
  std::array<int, kDrawnViews> views{-1, -1, -1};
  const glm::dvec3 toEye = eye - place.toWorld(fan, fan.centre);
  const double dist = glm::length(toEye);
  if (!(dist > fan.radius * place.scale)) return views;  // the eye is inside the object's sphere
  const glm::dvec3 vObj = place.toObjectDirection(toEye / dist);
  views[0] = fan.nearestView(vObj);
  const int ring0 = views[0] / std::max(1, fan.viewsPerRing);
  double best1 = -2, best2 = -2;
  const std::vector<int> around = fan.viewsAround(vObj);  // every view that can be first or second
  for (int k : around) {
    if (k == views[0]) continue;
    const double c = glm::dot(fan.toCamera(k), vObj);
    if (c > best1) {
      best1 = c;
      views[1] = k;
    }
  }
  for (int k : around) {
    if (k == views[0] || k == views[1] || k / std::max(1, fan.viewsPerRing) == ring0) continue;
    const double c = glm::dot(fan.toCamera(k), vObj);
    if (c > best2) {
      best2 = c;
      views[2] = k;
    }
  }
  return views;
}

int lampView(const ImageFan& fan, const Placement& place, const glm::dvec3& lampPosition) {
  const glm::dvec3 to = lampPosition - place.toWorld(fan, fan.centre);
  const double d = glm::length(to);
  return fan.nearestView(d > 0 ? place.toObjectDirection(to / d) : glm::dvec3(0, 0, 1));
}

std::vector<glm::vec3> viewTables(const ImageFan& fan, int view, const Placement& place, const ObjectLighting& light) {
  std::vector<glm::vec3> rows;
  rows.reserve(size_t(kNormalCodes) * (1 + light.lamps.size() * kTableCells * kTableCells));
  const std::vector<LightTable> ind = light.indirectAt ? indirectTables(fan, view, place, light.indirectAt)
                                                      : std::vector<LightTable>{indirectTable(fan, view, place, light.indirect)};
  for (const auto& t : ind) rows.insert(rows.end(), t.begin(), t.end());
  for (const auto& lamp : light.lamps)
    for (const auto& t : lampTables(fan, view, place, lamp).table) rows.insert(rows.end(), t.begin(), t.end());
  return rows;
}

void keepDisplayLamps(ObjectLighting& light, const ImageFan& fan, const Placement& place, size_t most) {
  auto& lamps = light.lamps;
  const glm::dvec3 c = place.toWorld(fan, fan.centre);
  auto strength = [&](const ObjectLamp& l) {
    const glm::dvec3 d = l.position - c;
    return (l.intensity.x + l.intensity.y + l.intensity.z) / std::max(glm::dot(d, d), 1e-12);
  };
  std::erase_if(lamps, [&](const ObjectLamp& l) { return !(strength(l) > 0); });
  std::stable_sort(lamps.begin(), lamps.end(), [&](const ObjectLamp& a, const ObjectLamp& b) { return strength(a) > strength(b); });
  if (lamps.size() > most) lamps.resize(most);
  std::vector<std::pair<int, size_t>> byView;
  for (size_t l = 0; l < lamps.size(); ++l) byView.emplace_back(lampView(fan, place, lamps[l].position), l);
  std::stable_sort(byView.begin(), byView.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<ObjectLamp> ordered;
  ordered.reserve(lamps.size());
  for (const auto& [view, l] : byView) ordered.push_back(std::move(lamps[l]));
  lamps = std::move(ordered);
}

DrawnTables drawnTables(const ImageFan& fan, const Placement& place, const ObjectLighting& light, const glm::dvec3& eye) {
  DrawnTables out;
  out.views = viewsToward(fan, place, eye);
  out.indirectRows = indirectRows(light);
  int n = 0;
  for (int j = 0; j < kDrawnViews && out.views[size_t(j)] >= 0; ++j, ++n) {
    const auto t = viewTables(fan, out.views[size_t(j)], place, light);
    out.rows.insert(out.rows.end(), t.begin(), t.end());
  }
  out.rowsPerView = n ? int(out.rows.size() / size_t(kNormalCodes) / size_t(n)) : 0;
  return out;
}

std::vector<ShadowCaster> shadowCasters(const ImageFan& fan, const Placement& place, const ObjectLighting& light) {
  std::vector<ShadowCaster> out;
  const glm::dvec3 cw = place.toWorld(fan, fan.centre);
  const double rs = fan.radius * place.scale;
  for (size_t l = 0; l < light.lamps.size(); ++l) {
    const ObjectLamp& lamp = light.lamps[l];
    if (glm::dot(lamp.exitance, lamp.exitance) <= 0) continue;
    const glm::dvec3 toLamp = lamp.position - cw;
    const double d = glm::length(toLamp);
    if (!(d > rs)) continue;  // a lamp inside the object's sphere: no silhouette to cast
    ShadowCaster c;
    c.lamp = l;
    c.view = fan.nearestView(place.toObjectDirection(toLamp / d));
    c.right = place.toWorldDirection(fan.right(c.view));
    c.up = place.toWorldDirection(fan.up(c.view));
    c.toCamera = place.toWorldDirection(fan.toCamera(c.view));
    c.samples = pointsOn(lamp.polygon, 3);
    for (const auto& v : lamp.polygon) c.lampRadius = std::max(c.lampRadius, glm::length(v - lamp.position));
    const double reach = rs + c.lampRadius;
    if (d > reach * 1.0001) {
      const double sinT = reach / d;
      c.cone = true;
      c.apex = lamp.position;
      c.axis = -toLamp / d;
      c.cos2 = (1.0 - sinT * sinT) * (1.0 - 1e-4);  // a hair wider than exact
      c.nearSide = d - reach - 1e-3;
    }
    out.push_back(std::move(c));
  }
  return out;
}

namespace {
// RoomView::tiles from the view's points.
void roomTiles(RoomView& v) {
  constexpr int T = RoomView::kRoomTile;
  const int tilesX = v.tilesX(), tilesY = v.tilesY();
  v.tiles.assign(size_t(tilesX) * size_t(tilesY), glm::dvec4(0.0, 0.0, 0.0, -1.0));
  tbb::parallel_for(tbb::blocked_range<int>(0, tilesX * tilesY, 16), [&](const tbb::blocked_range<int>& r) {
    for (int tile = r.begin(); tile < r.end(); ++tile) {
      const int tx0 = (tile % tilesX) * T, ty0 = (tile / tilesX) * T;
      const int tx1 = std::min(v.width, tx0 + T), ty1 = std::min(v.height, ty0 + T);
      glm::dvec3 lo(1e300), hi(-1e300);
      for (int y = ty0; y < ty1; ++y)
        for (int x = tx0; x < tx1; ++x) {
          const size_t pi = size_t(y) * size_t(v.width) + size_t(x);
          if (v.surface[pi] < 0) continue;
          lo = glm::min(lo, glm::dvec3(v.point[pi]));
          hi = glm::max(hi, glm::dvec3(v.point[pi]));
        }
      if (lo.x <= hi.x) v.tiles[size_t(tile)] = glm::dvec4(0.5 * (lo + hi), 0.5 * glm::length(hi - lo) + 1e-6);
    }
  });
}
}  // namespace

bool blockedBetween(const RayScene& room, const RayScene* occluders, const glm::dvec3& a, const glm::dvec3& b,
                    float endEpsilon) {
  return room.occluded(glm::vec3(a), glm::vec3(b), endEpsilon) ||
         (occluders && occluders->occluded(glm::vec3(a), glm::vec3(b), endEpsilon));
}

RoomView roomView(const radiosity::HierarchicalRadiosity& h, const Camera& cam, const RayScene* occluders) {
  RoomView v;
  v.width = cam.width;
  v.height = cam.height;
  const size_t n = size_t(cam.width) * cam.height;
  v.depth.assign(n, std::numeric_limits<float>::infinity());
  v.point.assign(n, glm::vec3(0.f));
  v.normal.assign(n, glm::vec3(0.f));
  v.surface.assign(n, -1);
  const glm::dvec3 eye = cam.center();
  std::vector<glm::dvec3> normals;  // per surface, once
  for (const auto& surf : h.surfaces()) normals.push_back(surf.vertices.size() >= 3 ? polygonNormal(surf.vertices) : glm::dvec3(0.0));
  tbb::parallel_for(tbb::blocked_range<int>(0, cam.height, 8), [&](const tbb::blocked_range<int>& rows) {
    std::vector<Ray> rays(size_t(cam.width));
    std::vector<RayHit> hits(rays.size()), other(occluders ? rays.size() : 0);
    for (int y = rows.begin(); y < rows.end(); ++y) {
      for (int x = 0; x < cam.width; ++x) rays[size_t(x)] = Ray{glm::vec3(eye), glm::vec3(cam.rayDirection(x + 0.5, y + 0.5)), 0.f, 1e30f};
      h.rayScene().intersect(rays, hits);
      if (occluders) occluders->intersect(rays, other);
      for (int x = 0; x < cam.width; ++x) {
        const size_t i = size_t(y) * cam.width + x;
        if (occluders && other[size_t(x)].polygon >= 0 && (hits[size_t(x)].polygon < 0 || other[size_t(x)].t < hits[size_t(x)].t)) {
          v.depth[i] = other[size_t(x)].t;  // an occluder beside the room: depth only
          v.point[i] = other[size_t(x)].point;
          v.normal[i] = other[size_t(x)].geometricNormal;
          continue;
        }
        const RayHit& hit = hits[size_t(x)];
        if (hit.polygon < 0) continue;
        v.depth[i] = hit.t;
        v.point[i] = hit.point;
        const glm::dvec3& nrm = normals[size_t(hit.polygon)];
        v.normal[i] = glm::vec3(nrm);
        if (glm::dot(glm::dvec3(rays[size_t(x)].direction), nrm) < 0) v.surface[i] = hit.polygon;
      }
    }
  });
  roomTiles(v);
  return v;
}

namespace {

struct ViewHit {
  double t = 0;      // along the ray
  size_t texel = 0;  // the fan pixel it meets
};

// A ray (object frame, o + t d) met with view k's depth image, a height field over the view's
// image square: marched in steps of half a fan pixel, the crossing refined by bisection. The fan
// image's pixels then stand where the object's surface is, not on a flat billboard: seen from
// close by, a viewer's ray meets the surface point it would meet on the object itself (as far as
// view k saw it). A crossing where the ray ends up well behind the surface (more than a few
// pixels' depth) is no crossing of it but of the "curtain" a height field hangs behind every
// depth edge: the ray passes behind a part view k saw in front of what the ray really meets, so
// view k cannot tell (Hidden), and the next view is asked.
enum class March { Miss, Hit, Hidden };
constexpr double kCurtainPixels = 1.5;  // how far behind the surface (in fan pixels) a ray may end up

March marchView(const ImageFan& fan, const FanView& v, const ImageFan::Axes& ax, const glm::dvec3& o, const glm::dvec3& d,
               ViewHit& hit) {
  const double R = fan.radius;
  const int S = fan.size;
  const glm::dvec3 q = o - fan.centre, r = ax.right, u = ax.up, c = ax.toCamera;
  const double p0[3] = {glm::dot(q, r), glm::dot(q, u), R - glm::dot(q, c)};
  const double dv[3] = {glm::dot(d, r), glm::dot(d, u), -glm::dot(d, c)};
  const double lo[3] = {-R, -R, 0.0}, hi[3] = {R, R, 2.0 * R};
  double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    if (std::abs(dv[a]) < 1e-15) {
      if (p0[a] < lo[a] || p0[a] > hi[a]) return March::Miss;
      continue;
    }
    double ta = (lo[a] - p0[a]) / dv[a], tb = (hi[a] - p0[a]) / dv[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (!(t0 < t1)) return March::Miss;
  const double px = S / (2.0 * R);
  auto surfaceAt = [&](double t, size_t& ti) {
    const int x = std::clamp(int(std::floor((p0[0] + t * dv[0] + R) * px)), 0, S - 1);
    const int y = std::clamp(int(std::floor((R - (p0[1] + t * dv[1])) * px)), 0, S - 1);
    ti = size_t(y) * S + x;
    return v.alpha[ti] ? fan.depthMetres(v.depth[ti]) : std::numeric_limits<double>::infinity();
  };
  const double across = std::hypot(dv[0], dv[1]) * (t1 - t0) * px;
  const int steps = std::max(1, int(std::ceil(2.0 * across)));
  // Empty space is skipped a block at a time (FanView::nearBlock): where the ray crosses a block
  // wholly in front of the block's nearest surface, every step inside it would find the ray in
  // front, so the march jumps to the first step at the block's far edge (the steps, and so the
  // crossing found, are the same as without the skip).
  const int blocks = (S + kNearBlock - 1) / kNearBlock;
  const bool skip = v.nearBlock.size() == size_t(blocks) * size_t(blocks);
  const double margin = 1e-6 * R;  // the blocks' depths are single precision
  auto blockExit = [&](double t, int& block) {  // the ray's t where it leaves the block holding t
    double exit = t1;
    int b[2];
    for (int a = 0; a < 2; ++a) {
      const double pix = a == 0 ? (p0[0] + t * dv[0] + R) * px : (R - (p0[1] + t * dv[1])) * px;
      const int cell = std::clamp(int(std::floor(pix)), 0, S - 1) / kNearBlock;
      b[a] = cell;
      const double slope = (a == 0 ? dv[0] : -dv[1]) * px;  // pixels per unit t
      if (std::abs(slope) < 1e-15) continue;
      const double edge = slope > 0 ? double((cell + 1) * kNearBlock) : double(cell * kNearBlock);
      exit = std::min(exit, t + (edge - pix) / slope);
    }
    block = b[1] * blocks + b[0];
    return exit;
  };
  double prev = t0;
  double unskippedTo = -std::numeric_limits<double>::infinity();  // a block found not skippable ends here
  for (int i = 0; i <= steps; ++i) {
    const double t = t0 + (t1 - t0) * i / steps;
    if (skip && t >= unskippedTo) {
      int block;
      const double exit = blockExit(t, block);
      unskippedTo = exit;  // not asked again before the exit unless the block is skipped
      const double deepest = std::max(p0[2] + t * dv[2], p0[2] + exit * dv[2]);
      if (deepest < double(v.nearBlock[size_t(block)]) - margin) {
        // Every step before the exit is in front; the last of them is checked to lie in the
        // block (rounding at its edge), else the one before it, else no skip.
        const double lastD = std::floor((exit - t0) / (t1 - t0) * steps - 1e-9);
        int last = lastD >= double(i) ? int(std::min(lastD, double(steps))) : i - 1;
        for (int tries = 0; last >= i && tries < 2; ++tries) {
          int at;
          blockExit(t0 + (t1 - t0) * last / steps, at);
          if (at == block) break;
          last = tries == 0 ? last - 1 : i - 1;
        }
        if (last >= i) {
          prev = t0 + (t1 - t0) * last / steps;
          i = last;
          unskippedTo = -std::numeric_limits<double>::infinity();
          continue;
        }
      }
    }
    size_t ti;
    if (p0[2] + t * dv[2] < surfaceAt(t, ti)) {
      prev = t;
      continue;
    }
    double a = prev, b = t;  // in front at a (unless i == 0), behind at b
    for (int it = 0; i > 0 && it < 10; ++it) {
      const double m = 0.5 * (a + b);
      size_t tm;
      (p0[2] + m * dv[2] < surfaceAt(m, tm) ? a : b) = m;
    }
    const double behind = p0[2] + b * dv[2] - surfaceAt(b, hit.texel);
    hit.t = b;
    return behind > kCurtainPixels / px ? March::Hidden : March::Hit;
  }
  return March::Miss;
}

// How much of a lamp reaches the object's point p (object frame) past the object itself: p
// against the depth of the fan image nearest the lamp's direction, 3 x 3 pixels around p's own
// (percentage-closer), p lit where it is no deeper than the surface there by more than a bias:
// two pixels (the lamp's offset from the view's direction), and as much as the surface's depth
// changes across the kernel's reach (about two pixels from p) where it is turned away from the
// view — `cosToView`, its normal's cosine with the view's direction. Without the slope, a face
// the lamp grazes shadowed itself in rows (a box's side under a low sun lost a quarter of its light).
double selfShadow(const ImageFan& fan, const FanView& v, const ImageFan::Axes& ax, const glm::dvec3& p, double cosToView) {
  const double R = fan.radius;
  const int S = fan.size;
  const glm::dvec3 q = p - fan.centre;
  const double px = S / (2.0 * R);
  const double x = (glm::dot(q, ax.right) + R) * px, y = (R - glm::dot(q, ax.up)) * px;
  const double depth = R - glm::dot(q, ax.toCamera);
  const double c = std::clamp(cosToView, 0.12, 1.0);  // beyond tan 8 the map cannot tell
  const double bias = (2.0 + 2.2 * std::sqrt(1.0 - c * c) / c) / px;
  const int ix = int(std::floor(x)), iy = int(std::floor(y));
  int lit = 0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int xx = ix + dx, yy = iy + dy;
      if (xx < 0 || yy < 0 || xx >= S || yy >= S) {
        ++lit;
        continue;
      }
      const size_t i = size_t(yy) * S + xx;
      lit += (!v.alpha[i] || depth <= fan.depthMetres(v.depth[i]) + bias) ? 1 : 0;
    }
  return lit / 9.0;
}

}  // namespace

DrawStats drawObject(const ImageFan& fan, const Placement& place, const ObjectLighting& light, const Camera& cam,
                     const RoomView& room, ImageRGB& image, std::vector<uint8_t>* mask) {
  DrawStats st;
  const glm::dvec3 eye = cam.center();
  const glm::dvec3 cw = place.toWorld(fan, fan.centre);
  const glm::dvec3 toEye = eye - cw;
  const double dist = glm::length(toEye);
  const double rs = fan.radius * place.scale;
  if (!(dist > rs)) return st;  // the camera is inside the object's sphere
  // The two fan images nearest the viewer's direction: the nearest drawn, the next where the
  // nearest did not see the surface the ray meets.
  const std::array<int, kDrawnViews> views = viewsToward(fan, place, eye);
  st.view = views[0];
  int nViews = 1;  // a fan of one view has no second, one ring no third
  while (nViews < kDrawnViews && views[size_t(nViews)] >= 0) ++nViews;
  // Its bounds on screen: the bounding sphere's cube.
  int ix0 = 0, iy0 = 0, ix1 = cam.width - 1, iy1 = cam.height - 1;
  {
    double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
    bool all = true;
    for (int c = 0; c < 8 && all; ++c) {
      glm::dvec2 p;
      all = cam.project(cw + rs * glm::dvec3(c & 1 ? 1 : -1, c & 2 ? 1 : -1, c & 4 ? 1 : -1), p);
      x0 = std::min(x0, p.x);
      x1 = std::max(x1, p.x);
      y0 = std::min(y0, p.y);
      y1 = std::max(y1, p.y);
    }
    if (all) {
      ix0 = std::max(ix0, int(std::floor(x0)));
      ix1 = std::min(ix1, int(std::ceil(x1)));
      iy0 = std::max(iy0, int(std::floor(y0)));
      iy1 = std::min(iy1, int(std::ceil(y1)));
    }
  }
  if (ix0 > ix1 || iy0 > iy1) return st;
  // The tables of both views (§3: recomputed per frame from the lights).
  struct Lit {
    std::vector<LampTables> lamps;
    std::vector<LightTable> indirect;  // one, or per table cell (ObjectLighting::indirectAt)
    const FanView* view;
    ImageFan::Axes axes;
  } lit[kDrawnViews];
  struct Shadow {  // a lamp's fan image, as a shadow map of the object on itself
    glm::dvec3 position;
    ImageFan::Axes axes;
    const FanView* image;
    size_t lamp;  // in light.lamps
  };
  std::vector<Shadow> lamps;
  for (int j = 0; j < nViews; ++j) {
    lit[j].indirect = light.indirectAt ? indirectTables(fan, views[j], place, light.indirectAt)
                                       : std::vector<LightTable>{indirectTable(fan, views[j], place, light.indirect)};
    lit[j].view = &fan.view(views[j]);
    lit[j].axes = fan.axes(views[j]);
  }
  for (size_t li = 0; li < light.lamps.size(); ++li) {
    const ObjectLamp& lamp = light.lamps[li];
    if (glm::dot(lamp.intensity, lamp.intensity) <= 0 && lamp.visible <= 0) continue;
    for (int j = 0; j < nViews; ++j) lit[j].lamps.push_back(lampTables(fan, views[j], place, lamp));
    const int kl = lampView(fan, place, lamp.position);
    lamps.push_back({lamp.position, fan.axes(kl), &fan.view(kl), li});
  }
  const glm::dvec3 eyeObj = place.toObject(fan, eye);
  const double cosYaw = std::cos(place.yaw) / place.scale, sinYaw = std::sin(place.yaw) / place.scale;
  const int S = fan.size;
  // Fan pixels per screen pixel at the object's distance (1 to 4 across).
  const double texel = 2.0 * rs / S, pixel = dist / std::max(cam.fx(), 1e-9);
  const int foot = std::clamp(int(std::lround(pixel / texel)), 1, 4);
  // Every point the march can hit lies within the fan's sphere widened by three of its pixels (a
  // pixel's square about the surface point it saw, its diagonal, and the march's curtain tolerance
  // of one and a half pixels): a ray that misses that sphere meets none.
  const double reach = rs * (1.0 + 6.0 / S), reach2 = reach * reach;
  std::atomic<size_t> drawn{0};
  tbb::parallel_for(tbb::blocked_range<int>(iy0, iy1 + 1, 4), [&](const tbb::blocked_range<int>& rows) {
    size_t count = 0;
    std::vector<double> falloff(lamps.size());
    for (int y = rows.begin(); y < rows.end(); ++y)
      for (int x = ix0; x <= ix1; ++x) {
        const glm::dvec3 r = cam.rayDirection(x + 0.5, y + 0.5);
        if (dist > reach) {
          const double along = glm::dot(toEye, r);  // toEye = eye - centre; r unit
          if (along > 0 || dist * dist - along * along > reach2) continue;
        }
        const glm::dvec3 dObj(cosYaw * r.x + sinYaw * r.y, -sinYaw * r.x + cosYaw * r.y, r.z / place.scale);  // t stays the world distance
        // The first view that sees what the ray meets. A ray that stays in front of a view's depth
        // all the way misses the object (every point of it lies at or behind that depth); one that
        // passes behind some surface there is asked of the next view; one that every view sees
        // passing behind a surface goes past the object too: it ran behind the edge of a
        // silhouette (drawing those hits hung translucent sheets beside a vase's neck).
        ViewHit hit;
        int j = 0;
        March m = March::Miss;
        while (j < nViews && (m = marchView(fan, *lit[j].view, lit[j].axes, eyeObj, dObj, hit)) == March::Hidden) ++j;
        if (m != March::Hit) continue;
        const size_t pi = size_t(y) * cam.width + x;
        if (double(room.depth[pi]) < hit.t - 1e-4) continue;  // the room is nearer
        const FanView& v = *lit[j].view;
        if (!v.alpha[hit.texel] || v.code[hit.texel] == kNoNormal) continue;
        const glm::dvec3 pWorld = eye + hit.t * r;
        const glm::dvec3 pObj = eyeObj + hit.t * dObj;
        // Per lamp: its falloff from this point and the object's own shadow here.
        const glm::dvec3 nObj = fromView(lit[j].axes, byteToNormal()[v.code[hit.texel]]);
        for (size_t l = 0; l < lamps.size(); ++l) {
          const glm::dvec3 dl = lamps[l].position - pWorld;
          falloff[l] = selfShadow(fan, *lamps[l].image, lamps[l].axes, pObj, glm::dot(nObj, lamps[l].axes.toCamera)) /
                       std::max(glm::dot(dl, dl), 1e-8);
          if (light.lamps[lamps[l].lamp].perPoint && light.roomLets && falloff[l] > 0)
            falloff[l] *= light.roomLets(lamps[l].lamp, pWorld);
        }
        // The four nearest cells' tables, bilinearly.
        const int tx = int(hit.texel % size_t(S)), ty = int(hit.texel / size_t(S));
        const double gx = std::clamp((tx + 0.5) * kTableCells / S - 0.5, 0.0, kTableCells - 1.0);
        const double gy = std::clamp((ty + 0.5) * kTableCells / S - 0.5, 0.0, kTableCells - 1.0);
        const int cx = std::min(int(gx), kTableCells - 2), cy = std::min(int(gy), kTableCells - 2);
        const double fx = gx - cx, fy = gy - cy;
        const size_t c00 = size_t(cy) * kTableCells + cx;
        const float w[4] = {float((1 - fx) * (1 - fy)), float(fx * (1 - fy)), float((1 - fx) * fy), float(fx * fy)};
        const size_t cell[4] = {c00, c00 + 1, c00 + kTableCells, c00 + kTableCells + 1};
        // The pixel's footprint in the fan image: its texels shaded and averaged (a dithered
        // normal image is meant to be averaged; point sampling it where the fan is finer than
        // the screen only aliases the dither).
        glm::dvec3 sum(0.0);
        double alphaSum = 0;
        for (int oy = -foot / 2; oy < foot - foot / 2; ++oy)
          for (int ox = -foot / 2; ox < foot - foot / 2; ++ox) {
            const int xx = tx + ox, yy = ty + oy;
            if (xx < 0 || yy < 0 || xx >= S || yy >= S) continue;
            const size_t ti = size_t(yy) * S + xx;
            const uint8_t code = v.code[ti];
            if (!v.alpha[ti] || code == kNoNormal) continue;
            // (Single precision: the tables are.)
            const auto& ind = lit[j].indirect;
            glm::vec3 e = ind.size() == 1 ? ind[0][code]
                                          : w[0] * ind[cell[0]][code] + w[1] * ind[cell[1]][code] +
                                                w[2] * ind[cell[2]][code] + w[3] * ind[cell[3]][code];
            for (size_t l = 0; l < lamps.size(); ++l) {
              const auto& t = lit[j].lamps[l].table;
              e += float(falloff[l]) * (w[0] * t[cell[0]][code] + w[1] * t[cell[1]][code] + w[2] * t[cell[2]][code] +
                                        w[3] * t[cell[3]][code]);
            }
            const glm::vec3 albedo(decode(v.colour[3 * ti]), decode(v.colour[3 * ti + 1]), decode(v.colour[3 * ti + 2]));
            const double a = v.alpha[ti] / 255.0;
            sum += a / std::numbers::pi * glm::dvec3(albedo * e);
            alphaSum += a;
          }
        if (!(alphaSum > 0)) continue;
        const double al = alphaSum / (foot * foot);
        const glm::dvec3 radiance = sum / alphaSum;
        const glm::dvec3 under(image.at(x, y));
        image.set(x, y, glm::vec3(al * radiance + (1.0 - al) * under));
        if (mask) (*mask)[pi] = std::max((*mask)[pi], uint8_t(std::lround(255 * al)));
        ++count;
      }
    drawn += count;
  });
  st.objectPixels = drawn.load();
  return st;
}

ObjectShadows::ObjectShadows(const ImageFan& fan, const Placement& place, const ObjectLighting& light, bool cull)
    : fan_(&fan), place_(place), light_(&light), centre_(place.toWorld(fan, fan.centre)), radius_(fan.radius * place.scale),
      cull_(cull), casters_(shadowCasters(fan, place, light)) {
  for (const auto& c : casters_) {
    const ObjectLamp& lamp = light.lamps[c.lamp];
    shapes_.emplace_back(lamp.polygon, lamp.twoSided, lamp.photometry);
    silhouettes_.push_back(&fan.view(c.view));
    std::vector<glm::dvec3>& pts = inFrame_.emplace_back();
    auto inFrame = [&](const glm::dvec3& w) {
      const glm::dvec3 q = w - centre_;
      return glm::dvec3(glm::dot(q, c.right), glm::dot(q, c.up), glm::dot(q, c.toCamera));
    };
    for (const auto& sample : c.samples) pts.push_back(inFrame(sample.first));
    // The silhouette's pixel box, in metres on the view's plane (taken reads pixel
    // (int(fx), int(fy)) at fx = r * toPixel + S / 2, fy = S / 2 - u * toPixel).
    Reach& r = reach_.emplace_back();
    r.lampCentre = inFrame(lamp.position);
    const FanView& v = fan.view(c.view);
    const int S = fan.size;
    int x0 = S, y0 = S, x1 = -1, y1 = -1;
    for (int y = 0; y < S; ++y)
      for (int x = 0; x < S; ++x)
        if (v.alpha[size_t(y) * S + x]) {
          x0 = std::min(x0, x), x1 = std::max(x1, x);
          y0 = std::min(y0, y), y1 = std::max(y1, y);
        }
    if (x1 >= 0) {
      const double toPixel = 0.5 * S / radius_;
      r.lo = glm::dvec2((x0 - 0.5 * S) / toPixel, (0.5 * S - (y1 + 1)) / toPixel);
      r.hi = glm::dvec2((x1 + 1 - 0.5 * S) / toPixel, (0.5 * S - y0) / toPixel);
    }
  }
}

namespace {

// Whether some line from a point x to a point within rho of a lamp's centre p may cross a
// caster's view plane inside [lo, hi] (all in the caster's frame, p in front of the plane:
// p.z - rho > 0), for x anywhere in the box [xlo, xhi]. Behind the plane at depth a = -x.z, the
// line to a lamp point q at height b crosses it at (b x + a q) / (a + b): increasing in x and q,
// and monotonic in a and in b for the others fixed, so its extremes over the boxes lie at their
// corners (exact: no point is passed over that some lamp point would find blocked).
bool mayCross(const glm::dvec3& xlo, const glm::dvec3& xhi, const glm::dvec3& p, double rho, const glm::dvec2& lo,
              const glm::dvec2& hi) {
  if (lo.x > hi.x) return false;  // no silhouette
  // On the lamp's side of the plane (a <= 0) no line crosses it before the lamp.
  if (!(xlo.z < 0)) return false;
  const double a[2] = {std::max(0.0, -xhi.z), -xlo.z};
  const double b[2] = {p.z - rho, p.z + rho};
  double inv[2][2];
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) inv[i][j] = 1.0 / (a[i] + b[j]);
  for (int axis = 0; axis < 2; ++axis) {
    double cmin = std::numeric_limits<double>::infinity(), cmax = -cmin;
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) {
        cmin = std::min(cmin, (b[j] * xlo[axis] + a[i] * (p[axis] - rho)) * inv[i][j]);
        cmax = std::max(cmax, (b[j] * xhi[axis] + a[i] * (p[axis] + rho)) * inv[i][j]);
      }
    if (cmax < lo[axis] || cmin > hi[axis]) return false;
  }
  return true;
}

}  // namespace

ObjectShadows::Casters ObjectShadows::castersNear(const glm::dvec3& centre, double radius) const {
  Casters out = 0;
  for (size_t ci = 0; ci < casters_.size(); ++ci) {
    const Casters bit = Casters(1) << std::min<size_t>(ci, 63);  // the 64th on share the last bit
    if (!cull_) {
      out |= bit;
      continue;
    }
    const ShadowCaster& c = casters_[ci];
    if (c.cone) {
      const glm::dvec3 v = centre - c.apex;
      const double len = glm::length(v), d = glm::dot(v, c.axis);
      if (len > radius) {
        if (d + radius < c.nearSide) continue;
        // Outside the cone widened by the sphere's angle: the angle to the axis beyond the cone's
        // half angle plus the sphere's, compared by cosines (cos(h + b), both in [0, pi / 2]; this
        // runs for every tile of the image). The margin keeps it on the safe side of rounding.
        const double cosH = std::sqrt(std::clamp(c.cos2, 0.0, 1.0)), sinH = std::sqrt(1.0 - cosH * cosH);
        const double sinB = std::min(1.0, radius / len), cosB = std::sqrt(1.0 - sinB * sinB);
        if (d / len < cosH * cosB - sinH * sinB - 1e-6) continue;
      }
    }
    const Reach& re = reach_[ci];
    if (re.lampCentre.z - c.lampRadius > 0) {
      const glm::dvec3 q = centre - centre_;
      const glm::dvec3 x(glm::dot(q, c.right), glm::dot(q, c.up), glm::dot(q, c.toCamera));
      if (!mayCross(x - radius, x + radius, re.lampCentre, c.lampRadius, re.lo, re.hi)) continue;
    }
    out |= bit;
  }
  return out;
}

glm::dvec3 ObjectShadows::taken(const radiosity::HierarchicalRadiosity& h, int surface, const glm::dvec3& X,
                                const glm::dvec3& n, Casters casters, glm::dvec3* perPoint) const {
  const ImageFan& fan = *fan_;
  const int S = fan.size;
  const glm::dvec3 cw = centre_;
  const double rs = radius_;
  glm::dvec3 out(0.0);
  std::vector<int8_t> beside;  // (with occluders beside the room: per lamp line)
  for (size_t ci = 0; ci < casters_.size(); ++ci) {
    if (!(casters >> std::min<size_t>(ci, 63) & 1)) continue;
    const ShadowCaster& lv = casters_[ci];
    const ObjectLamp& lamp = light_->lamps[lv.lamp];
    if (surface == lamp.surface) continue;
    // Nothing to hide unless the line to the lamp's centre passes within the object's sphere
    // widened by the lamp's own radius (every line to a point of the lamp lies within that radius
    // of it): X inside the cone from the lamp's centre around that sphere, and beyond its near
    // side. (Single precision: it only picks the points tested exactly.)
    if (cull_ && lv.cone) {
      const glm::vec3 v = glm::vec3(X) - glm::vec3(lv.apex);
      const float d = glm::dot(v, glm::vec3(lv.axis));
      if (d < float(lv.nearSide) || d * d < float(lv.cos2) * glm::dot(v, v)) continue;
    }
    const FanView& silhouette = *silhouettes_[ci];
    // The lamp's points (a soft shadow: the share of its area the silhouette hides). The line
    // X -> P meets the plane of the view through the centre at the share u of the way; there the
    // silhouette is read. (Coordinates in the view's frame about the centre: linear along the line.)
    const glm::dvec3 x = X - cw;
    const double xr = glm::dot(x, lv.right), xu = glm::dot(x, lv.up), xt = glm::dot(x, lv.toCamera);
    // First whether any of those lines can cross the silhouette's box at all (exact: no point
    // is passed over that some lamp point would find blocked).
    const Reach& re = reach_[ci];
    const glm::dvec3 xf(xr, xu, xt);
    if (cull_ && re.lampCentre.z - lv.lampRadius > 0 && !mayCross(xf, xf, re.lampCentre, lv.lampRadius, re.lo, re.hi))
      continue;
    const double toPixel = 0.5 * S / rs;
    double blocked = 0, blockedAny = 0;  // (blocked: of the lines no occluder beside the room blocks)
    const glm::dvec3 from = X + 1e-4 * n;
    // Whether an occluder beside the room blocks line k, each line asked once (-1: not yet).
    if (light_->occluders) beside.assign(lv.samples.size(), -1);
    auto occludedBeside = [&](size_t k) {
      if (beside[k] < 0) {
        const glm::dvec3& P = lv.samples[k].first;
        beside[k] = light_->occluders->occluded(glm::vec3(from), glm::vec3(P),
                                                float(std::min(1e-4, 2e-4 / std::max(glm::length(P - from), 1e-9))));
      }
      return beside[k] != 0;
    };
    // Per lamp point P, in that frame (no division but u's, no square root): the tests that
    // reject most lines first.
    const double x2 = xr * xr + xu * xu + xt * xt, rs2 = rs * rs;
    for (size_t k = 0; k < lv.samples.size(); ++k) {
      const glm::dvec3& pt = inFrame_[ci][k];  // (right, up, toCamera)
      const double sr = pt.x - xr, su = pt.y - xu, st = pt.z - xt;
      // The crossing u = -xt / st of the plane must lie strictly between X and P.
      if (std::abs(st) < 1e-12 || !(st > 0 ? (xt < 0 && -xt < st) : (xt > 0 && xt < -st))) continue;
      const double u = -xt / st;
      const double fx = (xr + u * sr) * toPixel + 0.5 * S, fy = 0.5 * S - (xu + u * su) * toPixel;
      if (!(fx >= 0 && fy >= 0 && fx < S && fy < S)) continue;
      const int tx = int(fx), ty = int(fy);
      const size_t ti = size_t(ty) * S + tx;
      if (!silhouette.alpha[ti]) continue;
      // The segment X -> P must pass within the object's sphere: its nearest point to the centre
      // is X (dot <= 0), P (dot >= len2) or between, at squared distance x2 - dot^2 / len2.
      const double len2 = sr * sr + su * su + st * st;
      const double dot = -(xr * sr + xu * su + xt * st);
      if (dot <= 0 ? x2 > rs2 : dot >= len2 ? glm::dot(pt, pt) > rs2 : x2 * len2 - dot * dot > rs2 * len2) continue;
      // The silhouette's point must lie between X and the lamp (not behind X): its offset from X,
      // projected on the segment's direction, more than a millimetre.
      const double a = ((tx + 0.5) / S * 2.0 - 1.0) * fan.radius, b = (1.0 - (ty + 0.5) / S * 2.0) * fan.radius;
      const double c = fan.radius - fan.depthMetres(silhouette.depth[ti]);
      const double along = (place_.scale * a - xr) * sr + (place_.scale * b - xu) * su + (place_.scale * c - xt) * st;
      if (along <= 0 || along * along <= 1e-6 * len2) continue;
      // A line an occluder beside the room (a daylight render's box) blocks already brought no
      // light here: the object takes none off it.
      const double share = lv.samples[k].second * (silhouette.alpha[ti] / 255.0);
      blockedAny += share;
      if (light_->occluders && occludedBeside(k)) continue;
      blocked += share;
    }
    if (!(blockedAny > 0)) continue;
    // A lamp seen per point whose light the display gives (perPoint asked): the share blocked —
    // with occluders beside the room, of the lines they leave (the display's light there is what
    // they left): the share of what is left that the object hides. Where they leave no line but
    // the display still showed some of the lamp (its own edge of their shadow), as if they were not there.
    if (perPoint && lamp.perPoint) {
      if (!light_->occluders) {
        *perPoint += glm::dvec3(blocked);
        continue;
      }
      double left = 0;
      for (size_t k = 0; k < lv.samples.size(); ++k)
        if (!occludedBeside(k)) left += lv.samples[k].second;
      *perPoint += glm::dvec3(left > 1e-3 ? std::min(1.0, blocked / left) : blockedAny);
      continue;
    }
    if (!(blocked > 0)) continue;
    // The lamp's direct irradiance at X, as far as the room lets it through (a lamp seen per
    // point: as the lighting says; else the line to its centre, its ends' margin a fifth of a
    // millimetre however far the lamp).
    const glm::dvec3 lift = X + 1e-4 * n;
    double through = 1.0;
    if (lamp.perPoint && light_->roomLets) {
      through = light_->roomLets(lv.lamp, lift);
    } else {
      const double len = glm::length(lamp.position - lift);
      if (blockedBetween(h.rayScene(), light_->occluders, lift, lamp.position, float(std::min(1e-4, 2e-4 / std::max(len, 1e-9)))))
        continue;
    }
    if (!(through > 0)) continue;
    const double f = radiosity::emitterFormFactor(X, n, lamp.polygon, shapes_[ci]);
    if (!(f > 0)) continue;
    out += blocked * through * f * lamp.exitance;
  }
  return out;
}

std::vector<char> emittingSurfaces(const radiosity::HierarchicalRadiosity& h) {
  std::vector<char> emitters(h.surfaces().size(), 0);
  for (size_t i = 0; i < emitters.size(); ++i)
    emitters[i] = glm::dot(h.surfaces()[i].exitance, h.surfaces()[i].exitance) > 0 || h.surfaces()[i].photometry != nullptr;
  return emitters;
}

DrawStats drawShadows(const ImageFan& fan, const Placement& place, const ObjectLighting& light,
                      const radiosity::HierarchicalRadiosity& h, const Camera& cam, const RoomView& room,
                      const IrradianceAt& irradiance, ImageRGB& image, const ImageRGB* perPointCap) {
  DrawStats st;
  if (perPointCap && (perPointCap->width != cam.width || perPointCap->height != cam.height)) perPointCap = nullptr;
  const ObjectShadows shadows(fan, place, light);
  if (shadows.empty()) return st;
  const std::vector<char> emitters = emittingSurfaces(h);
  std::atomic<size_t> shaded{0};
  // In tiles of 8 x 8 pixels: a tile whose points all lie out of every lamp's reach (the sphere
  // around them, kept with the room view; ObjectShadows::castersNear) is passed over whole, and
  // the others ask only the lamps that may shadow some of it.
  RoomView tiled;
  const RoomView* tiles = &room;
  if (room.width != cam.width || room.height != cam.height ||
      room.tiles.size() != size_t(room.tilesX()) * size_t(room.tilesY())) {  // made by hand, not by roomView
    tiled = room;
    tiled.width = cam.width;
    tiled.height = cam.height;
    roomTiles(tiled);
    tiles = &tiled;
  }
  constexpr int kTile = RoomView::kRoomTile;
  const int tilesX = tiles->tilesX(), tilesY = tiles->tilesY();
  tbb::parallel_for(tbb::blocked_range<int>(0, tilesX * tilesY, 4), [&](const tbb::blocked_range<int>& range) {
    size_t count = 0;
    for (int tile = range.begin(); tile < range.end(); ++tile) {
      const int tx0 = (tile % tilesX) * kTile, ty0 = (tile / tilesX) * kTile;
      const int tx1 = std::min(cam.width, tx0 + kTile), ty1 = std::min(cam.height, ty0 + kTile);
      const glm::dvec4& sphere = tiles->tiles[size_t(tile)];
      if (sphere.w < 0) continue;
      const ObjectShadows::Casters near = shadows.castersNear(glm::dvec3(sphere), sphere.w);
      if (!near) continue;
      for (int y = ty0; y < ty1; ++y)
        for (int x = tx0; x < tx1; ++x) {
        const size_t pi = size_t(y) * cam.width + x;
        const int surface = room.surface[pi];
        // Lamps keep their glow: a shadow falls on what reflects.
        if (surface < 0 || emitters[size_t(surface)]) continue;
        const glm::dvec3 X(room.point[pi]);
        glm::dvec3 perPoint(0.0);
        glm::dvec3 taken = shadows.taken(h, surface, X, glm::dvec3(room.normal[pi]), near, perPointCap ? &perPoint : nullptr);
        if (perPointCap) taken += glm::min(perPoint, glm::dvec3(1.0)) * glm::dvec3(perPointCap->at(x, y));
        if (taken == glm::dvec3(0.0)) continue;
        const glm::dvec3 total = irradiance(surface, X);
        glm::dvec3 keep;
        for (int c = 0; c < 3; ++c) keep[c] = total[c] > 0 ? std::clamp(1.0 - taken[c] / total[c], 0.0, 1.0) : 1.0;
        image.set(x, y, glm::vec3(glm::dvec3(image.at(x, y)) * keep));
        ++count;
      }
    }
    shaded += count;
  });
  st.shadowPixels = shaded.load();
  return st;
}

}  // namespace relume::ibr
