#include "relight_common.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "relume/geometry/polygon.h"
#include "relume/geometry/scene.h"
#include "relume/raytrace/ray_scene.h"

namespace relume::detail {

LinkSums linkSums(const HierarchicalRadiosity& h, bool indirect) {
  const auto& nodes = h.nodes();
  const size_t n = nodes.size();
  LinkSums s;
  s.blocked.assign(n, glm::vec3(0.f));
  s.direct.assign(n, glm::vec3(0.f));
  s.directBlocked.assign(n, glm::vec3(0.f));
  for (const auto& l : h.links()) {
    if (l.receiver == l.source || l.formFactor <= 0.f) continue;
    const glm::vec3 b = h.radiosity(l.source);
    const glm::vec3 lost = l.formFactor * (1.f - l.visibility) * b;
    const bool emitter = h.sourceIsEmitter(l.source);
    if (emitter) {
      s.direct[l.receiver] += l.formFactor * b;
      s.directBlocked[l.receiver] += lost;
    }
    if (emitter || indirect) s.blocked[l.receiver] += lost;
  }
  for (size_t i = 1; i < n; ++i) {  // parents precede children
    const int p = nodes[i].parent;
    s.blocked[i] += s.blocked[p];
    s.direct[i] += s.direct[p];
    s.directBlocked[i] += s.directBlocked[p];
  }
  s.unoccluded.resize(n);
  for (size_t i = 0; i < n; ++i) s.unoccluded[i] = h.irradiance(int(i)) + s.blocked[i];
  return s;
}

namespace {
// A fixed 2-D low-discrepancy point (R2 sequence) in [0,1)^2.
glm::dvec2 r2(int i) {
  const double g = 1.32471795724474602596;
  return {std::fmod(0.5 + i / g, 1.0), std::fmod(0.5 + i / (g * g), 1.0)};
}
constexpr int kLampPoints = 16, kReceiverPoints = 16, kPairsPerPoint = 2;
}  // namespace

LampVisibility::LampVisibility(const HierarchicalRadiosity& h, std::vector<int> lampSurfaces)
    : h_(h), lamps_(std::move(lampSurfaces)) {
  for (int s : lamps_) {
    const auto& v = h.surfaces()[s].vertices;
    const PlaneFrame f = PlaneFrame::of(v);
    std::vector<glm::dvec2> uv;
    glm::dvec2 lo(1e300), hi(-1e300);
    for (const auto& p : v) {
      uv.push_back(f.toUV(p));
      lo = glm::min(lo, uv.back());
      hi = glm::max(hi, uv.back());
    }
    std::vector<glm::dvec3> pts;
    for (int i = 0; int(pts.size()) < kLampPoints && i < 4000; ++i) {
      const glm::dvec2 q = lo + r2(i) * (hi - lo);
      if (insideConvex2D(uv, q)) pts.push_back(f.toWorld(q));
    }
    if (pts.empty()) pts.push_back(polygonCentroid(v));
    points_.push_back(std::move(pts));
    normals_.push_back(f.normal);
  }
}

std::vector<float> LampVisibility::at(int surface, const glm::vec4& rect) const {
  const auto& verts = h_.surfaces()[surface].vertices;
  const glm::dvec3 n = glm::normalize(polygonNormal(verts));
  // Receiver points inside the element (its rectangle clipped to the polygon).
  std::vector<glm::dvec2> uvPoly;
  for (const auto& v : verts) uvPoly.push_back(h_.toUV(surface, v));
  std::vector<glm::dvec3> recv;
  for (int i = 0; int(recv.size()) < kReceiverPoints && i < 8 * kReceiverPoints; ++i) {
    const glm::dvec2 q = r2(i + 7);
    const glm::dvec2 uv(rect.x + q.x * (rect.z - rect.x), rect.y + q.y * (rect.w - rect.y));
    if (insideConvex2D(uvPoly, uv, 1e-9)) recv.push_back(h_.toWorld(surface, uv));
  }
  if (recv.empty()) recv.push_back(h_.toWorld(surface, {0.5 * (rect.x + rect.z), 0.5 * (rect.y + rect.w)}));
  std::vector<Segment> segs;
  std::vector<int> owner;
  for (size_t l = 0; l < lamps_.size(); ++l) {
    const auto& lp = points_[l];
    for (size_t i = 0; i < recv.size(); ++i) {
      const glm::dvec3& p = recv[i];
      for (int k = 0; k < kPairsPerPoint; ++k) {
        const glm::dvec3& a = lp[(i * kPairsPerPoint + k) % lp.size()];
        const glm::dvec3 d = a - p;
        // A two-sided lamp, or one with a photometric distribution, lights both half-spaces of its plane.
        const auto& lamp = h_.surfaces()[lamps_[l]];
        const bool behind = lamp.twoSided || lamp.photometry;
        if (glm::dot(d, n) <= 0 || (!behind && glm::dot(d, normals_[l]) >= 0)) continue;
        segs.push_back({glm::vec3(p), glm::vec3(a)});
        owner.push_back(int(l));
      }
    }
  }
  std::vector<uint8_t> blocked(segs.size(), 0);
  h_.rayScene().occluded(segs, blocked, 1e-4f);
  std::vector<float> seen(lamps_.size(), 0.f), total(lamps_.size(), 0.f);
  for (size_t i = 0; i < segs.size(); ++i) {
    total[owner[i]] += 1.f;
    if (!blocked[i]) seen[owner[i]] += 1.f;
  }
  std::vector<float> v(lamps_.size(), 1.f);
  for (size_t l = 0; l < lamps_.size(); ++l)
    if (total[l] > 0) v[l] = seen[l] / total[l];
  return v;
}

std::vector<int> neighbours(const HierarchicalRadiosity& h, int leaf) {
  const auto& nodes = h.nodes();
  const auto& N = nodes[leaf];
  const auto& root = nodes[h.surfaceRoot(N.surface)];
  const double du = N.u1 - N.u0, dv = N.v1 - N.v0, eps = 1e-4 * (du + dv);
  std::vector<int> out;
  for (double f : {0.25, 0.5, 0.75}) {
    const glm::dvec2 probes[4] = {{N.u0 - eps, N.v0 + f * dv},
                                  {N.u1 + eps, N.v0 + f * dv},
                                  {N.u0 + f * du, N.v0 - eps},
                                  {N.u0 + f * du, N.v1 + eps}};
    for (const auto& p : probes) {
      if (p.x < root.u0 || p.x > root.u1 || p.y < root.v0 || p.y > root.v1) continue;
      const int m = h.findLeaf(N.surface, p);
      if (m == leaf || !nodes[m].isLeaf()) continue;
      const auto& M = nodes[m];
      if (p.x < M.u0 || p.x > M.u1 || p.y < M.v0 || p.y > M.v1) continue;
      if (std::find(out.begin(), out.end(), m) == out.end()) out.push_back(m);
    }
  }
  return out;
}

std::vector<int> leavesOf(const HierarchicalRadiosity& h, const std::vector<uint8_t>& surfaceMask) {
  std::vector<int> out;
  const auto& nodes = h.nodes();
  for (size_t i = 0; i < nodes.size(); ++i)
    if (!nodes[i].isCluster() && nodes[i].isLeaf() && size_t(nodes[i].surface) < surfaceMask.size() &&
        surfaceMask[nodes[i].surface])
      out.push_back(int(i));
  return out;
}

glm::vec4 rectOf(const HierarchicalRadiosity::Node& n) { return {n.u0, n.v0, n.u1, n.v1}; }

void textureRefine(HierarchicalRadiosity& h, const std::vector<PolygonTexture>& textures,
                   const std::vector<int>& lampSurfaces, const std::vector<uint8_t>& mask, double colourScale,
                   const RelightOptions& o, RelightEstimates* est, Progress& progress) {
  if (lampSurfaces.empty()) return;
  const LampVisibility lampVis(h, lampSurfaces);
  const size_t nl = lampSurfaces.size();
  struct Info {
    bool ready = false;
    glm::dvec3 lab{0.0};
    double seen = 0;
    std::vector<float> vis;
  };
  std::vector<Info> info;
  auto compute = [&](const std::vector<int>& ids) {
    info.resize(h.nodes().size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, ids.size(), 16), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t k = r.begin(); k < r.end(); ++k) {
        const int i = ids[k];
        Info& in = info[i];
        if (in.ready) continue;
        const auto& N = h.nodes()[i];
        const auto& t = textures[N.surface];
        const glm::vec3 m = t.mean(t.original, {N.u0, N.v0}, {N.u1, N.v1}, &in.seen);
        in.lab = linearRgbToLab(glm::dvec3(m) * colourScale);
        in.vis = lampVis.at(N.surface, rectOf(N));
        in.ready = true;
      }
    });
  };
  auto visDiff = [&](const std::vector<float>& a, const std::vector<float>& b) {
    float d = 0;
    for (size_t l = 0; l < nl; ++l) d = std::max(d, std::abs(a[l] - b[l]));
    return d;
  };
  std::vector<int> work;
  for (int i : leavesOf(h, mask)) work.push_back(i);
  size_t subdivided = 0, cancelled = 0;
  if (est) est->leavesBeforeTextureRefinement = work.size();
  for (int pass = 0; pass < o.textureRefineLevels && !work.empty(); ++pass) {
    progress.report(double(pass) / o.textureRefineLevels,
                    "texture-based refinement, pass " + std::to_string(pass + 1) + " (" + std::to_string(work.size()) + " elements)");
    std::vector<int> all = work;
    std::vector<std::vector<int>> nb(work.size());
    for (size_t k = 0; k < work.size(); ++k) {
      nb[k] = neighbours(h, work[k]);
      all.insert(all.end(), nb[k].begin(), nb[k].end());
    }
    std::sort(all.begin(), all.end());
    all.erase(std::unique(all.begin(), all.end()), all.end());
    compute(all);
    // Decide, then test the would-be children: a split that changes no visibility is cancelled.
    std::vector<uint8_t> decision(work.size(), 0);  // 1 split, 2 cancelled
    tbb::parallel_for(tbb::blocked_range<size_t>(0, work.size(), 16), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t k = r.begin(); k < r.end(); ++k) {
        const int i = work[k];
        const Info& a = info[i];
        if (a.seen < 0.5) continue;  // the photo does not show it: no colour evidence
        const auto& N = h.nodes()[i];
        const double rectArea = double(N.u1 - N.u0) * double(N.v1 - N.v0);
        const auto rects = h.splitRects(i);
        if (rectArea / double(rects.size()) < o.textureMinArea) continue;
        bool want = false;
        for (float v : a.vis) want = want || (v > 0.f && v < 1.f);  // PARTIAL
        for (int n : nb[k]) {
          if (want) break;
          const Info& b = info[n];
          if (b.seen < 0.5) continue;
          const bool sameColour = glm::length(a.lab - b.lab) < o.colourThreshold;
          const bool sameVis = visDiff(a.vis, b.vis) < o.visibilityThreshold;
          want = sameColour != sameVis;
        }
        if (!want) continue;
        bool change = false;
        std::vector<std::vector<float>> kids;
        for (const auto& rc : rects) kids.push_back(lampVis.at(N.surface, rc));
        for (const auto& kv : kids) change = change || visDiff(kv, a.vis) >= 0.5 * o.visibilityThreshold;
        for (size_t x = 0; x < kids.size() && !change; ++x)
          for (size_t y = x + 1; y < kids.size(); ++y) change = change || visDiff(kids[x], kids[y]) > 0.f;
        decision[k] = change ? 1 : 2;
      }
    });
    std::vector<int> split;
    for (size_t k = 0; k < work.size(); ++k) {
      if (decision[k] == 1) split.push_back(work[k]);
      cancelled += decision[k] == 2;
    }
    if (split.empty()) break;
    subdivided += split.size();
    h.subdivideElements(split);
    h.pushLampLinksToLeaves(progress);
    work.clear();
    for (int i : split) {
      const auto& N = h.nodes()[i];
      for (int c = 0; c < N.childCount; ++c) work.push_back(h.children()[N.childBegin + c]);
    }
  }
  if (est) {
    est->texturesSubdivided = subdivided;
    est->subdivisionsCancelled = cancelled;
    est->leavesAfter = leavesOf(h, mask).size();
  }
}

std::vector<radiosity::Surface> engineSurfaces(const Scene& scene, const std::vector<glm::dvec3>& reflectance,
                                               const std::vector<glm::dvec3>& lampExitance) {
  std::vector<radiosity::Surface> out;
  for (size_t i = 0; i < scene.polygons.size(); ++i) {
    const auto& p = scene.polygons[i];
    radiosity::Surface s;
    s.name = p.name;
    s.vertices = p.vertices;
    if (p.kind == PolygonKind::Real || p.kind == PolygonKind::Virtual) s.reflectance = reflectance[i];
    out.push_back(s);
  }
  for (size_t l = 0; l < scene.lamps.size(); ++l) {
    out[scene.lamps[l].polygon].exitance = lampExitance[l];
    out[scene.lamps[l].polygon].twoSided = scene.lamps[l].twoSided;
    out[scene.lamps[l].polygon].photometry = scene.lamps[l].photometry;
  }
  return out;
}

}  // namespace relume::detail
