// The interactive relighting phase (Loscos et al. 2000 §4.4-5).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <glm/geometric.hpp>
#include <map>
#include <memory>
#include <numbers>

#include "relight_common.h"
#include "view_cast.h"
#include "relume/geometry/error.h"
#include "relume/image/image.h"
#include "relume/raytrace/outside.h"
#include "relume/raytrace/ray_scene.h"
#include "relume/relight/relighter.h"
#include "relume/relight/solution_render.h"

namespace relume {

using radiosity::HierarchicalRadiosity;
using namespace detail;

VirtualObject boxObject(const std::string& name, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& albedo) {
  const double x0 = a.x, y0 = a.y, z0 = a.z, x1 = b.x, y1 = b.y, z1 = b.z;
  VirtualObject o;
  o.name = name;
  o.albedo = albedo;
  o.polygons = {{{x0, y0, z0}, {x0, y1, z0}, {x1, y1, z0}, {x1, y0, z0}},   // -z
                {{x0, y0, z1}, {x1, y0, z1}, {x1, y1, z1}, {x0, y1, z1}},   // +z
                {{x0, y0, z0}, {x1, y0, z0}, {x1, y0, z1}, {x0, y0, z1}},   // -y
                {{x0, y1, z0}, {x0, y1, z1}, {x1, y1, z1}, {x1, y1, z0}},   // +y
                {{x0, y0, z0}, {x0, y0, z1}, {x0, y1, z1}, {x0, y1, z0}},   // -x
                {{x1, y0, z0}, {x1, y1, z0}, {x1, y1, z1}, {x1, y0, z1}}};  // +x
  return o;
}

VirtualObject meshObject(const std::string& name, const std::vector<std::vector<glm::dvec3>>& faces,
                         const glm::dvec3& albedo) {
  VirtualObject o;
  o.name = name;
  o.albedo = albedo;
  for (const auto& f : faces)
    for (size_t k = 1; k + 1 < f.size(); ++k) {
      std::vector<glm::dvec3> t{f[0], f[k], f[k + 1]};
      if (polygonArea(t) > 1e-10) o.polygons.push_back(std::move(t));
    }
  if (o.polygons.empty()) throw Error("", "virtual object '" + name + "'", "its mesh has no face with an area");
  return o;
}

namespace {
// The bounding box of faces.
void facesBounds(const std::vector<std::vector<glm::dvec3>>& faces, glm::dvec3& lo, glm::dvec3& hi) {
  lo = glm::dvec3(1e300);
  hi = glm::dvec3(-1e300);
  for (const auto& p : faces)
    for (const auto& v : p) {
      lo = glm::min(lo, v);
      hi = glm::max(hi, v);
    }
}
// An object's faces moved 1 mm towards the middle of its bounding box (so that what only touches
// it does not cross it).
std::vector<std::vector<glm::dvec3>> shrunkFaces(const VirtualObject& object) {
  glm::dvec3 lo, hi;
  facesBounds(object.polygons, lo, hi);
  const glm::dvec3 c = 0.5 * (lo + hi);
  std::vector<std::vector<glm::dvec3>> out;
  for (const auto& p : object.polygons) {
    std::vector<glm::dvec3> q;
    for (const auto& v : p) {
      const glm::dvec3 d = c - v;
      const double len = glm::length(d);
      q.push_back(len > 1e-3 ? v + 1e-3 * d / len : c);
    }
    out.push_back(std::move(q));
  }
  return out;
}
// The first polygon one of whose edges crosses something in `rays`, or -1.
int crosses(const RayScene& rays, const std::vector<std::vector<glm::dvec3>>& polys) {
  for (size_t i = 0; i < polys.size(); ++i)
    for (size_t k = 0; k < polys[i].size(); ++k)
      if (rays.occluded(glm::vec3(polys[i][k]), glm::vec3(polys[i][(k + 1) % polys[i].size()]), 0.f)) return int(i);
  return -1;
}
}  // namespace

void checkVirtualObjectsApart(const Scene& scene, const VirtualObject& object, const std::vector<const VirtualObject*>& others) {
  const std::vector<std::vector<glm::dvec3>> mine = shrunkFaces(object);
  glm::dvec3 lo, hi;
  facesBounds(mine, lo, hi);
  std::unique_ptr<RayScene> mineRays;
  for (const VirtualObject* other : others) {
    if (!other || other == &object || other->polygons.empty()) continue;
    const std::vector<std::vector<glm::dvec3>> theirs = shrunkFaces(*other);
    glm::dvec3 olo, ohi;
    facesBounds(theirs, olo, ohi);
    if (glm::any(glm::lessThan(ohi, lo)) || glm::any(glm::lessThan(hi, olo))) continue;  // boxes apart: nothing crosses
    if (!mineRays) mineRays = std::make_unique<RayScene>(mine);
    const RayScene theirRays(theirs);
    if (crosses(theirRays, mine) >= 0 || crosses(*mineRays, theirs) >= 0)
      throw Error(scene.sourceFile, "virtual object '" + object.name + "'", "intersects virtual object '" + other->name + "'");
  }
}

void checkVirtualObject(const Scene& scene, const VirtualObject& object) {
  const std::string what = "virtual object '" + object.name + "'";
  for (double c : {object.albedo.x, object.albedo.y, object.albedo.z})
    if (!(c > 0 && c <= 1)) throw Error(scene.sourceFile, what, "albedo must lie in (0, 1]");
  if (object.polygons.empty()) throw Error(scene.sourceFile, what, "has no polygons");
  if (object.polygons.size() > kMaxObjectFaces)
    throw Error(scene.sourceFile, what,
                "has " + std::to_string(object.polygons.size()) + " faces; a virtual object in the radiosity solution may have up to " +
                    std::to_string(kMaxObjectFaces) + " (simplify the mesh: its faces become elements and links of the solution)");
  for (size_t k = 0; k < object.polygons.size(); ++k)
    if (object.polygons[k].size() < 3 || !(polygonArea(object.polygons[k]) > 1e-8))
      throw Error(scene.sourceFile, what, "polygon " + std::to_string(k) + " has fewer than 3 vertices or no area");
  // The room's bounds: its own polygons', not those outside its windows (a daylight room's ground
  // reaches tens of metres past the walls; an object out there is not in the room).
  glm::dvec3 lo(1e300), hi(-1e300), olo(1e300), ohi(-1e300);
  std::vector<char> outside(scene.polygons.size(), 0);
  for (int i : outsidePolygons(scene)) outside[size_t(i)] = 1;
  for (size_t i = 0; i < scene.polygons.size(); ++i)
    for (const auto& v : scene.polygons[i].vertices) {
      if (outside[i]) continue;
      lo = glm::min(lo, v);
      hi = glm::max(hi, v);
    }
  for (const auto& p : object.polygons)
    for (const auto& v : p) {
      if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
        throw Error(scene.sourceFile, what, "has a vertex that is not a finite number");
      olo = glm::min(olo, v);
      ohi = glm::max(ohi, v);
    }
  // Shrunk by 1 mm towards its centre, no edge of the object may cross a real polygon and no
  // edge of a real polygon may cross the object.
  std::vector<std::vector<glm::dvec3>> room, obj = shrunkFaces(object);
  for (const auto& p : scene.polygons) room.push_back(p.vertices);
  const RayScene roomRays(room), objRays(obj);
  if (crosses(roomRays, obj) >= 0 || crosses(objRays, room) >= 0) {
    // Name the real polygon it cuts.
    for (const auto& p : scene.polygons) {
      const RayScene one({p.vertices});
      if (crosses(one, obj) >= 0 || crosses(objRays, {p.vertices}) >= 0)
        throw Error(scene.sourceFile, what, "intersects polygon '" + p.name + "'");
    }
    throw Error(scene.sourceFile, what, "intersects the room's polygons");
  }
  const double tol = 1e-3;
  if (glm::any(glm::lessThan(olo, lo - tol)) || glm::any(glm::greaterThan(ohi, hi + tol)))
    throw Error(scene.sourceFile, what, "lies (partly) outside the room");
}

struct RelightSession::Impl {
  size_t np = 0;
  std::vector<PolygonTexture> textures;
  std::vector<PolygonKind> kinds;
  std::unique_ptr<HierarchicalRadiosity> h;
  std::vector<int> lampSurfaces, vlampSurfaces;
  std::vector<glm::dvec3> baseExitance, vlampExitance, lampScale;
  ImageRGB glow;
  std::vector<int> glowLamp;
  Camera photoCamera;
  RelightOptions options;                        // the preprocess's (blocked light, element sets)
  Scene scene;                                   // for checking where objects may go
  std::vector<VirtualObject> objects;
  std::vector<std::vector<int>> objectSurfaceIds;  // per object
  std::vector<glm::vec3> D, Borig;
  std::vector<uint8_t> category;  // per node: §4.3's occluded / frontier elements (display only)
  bool dragPreview = false;
  glm::vec3 dragLo{1e30f}, dragHi{-1e30f};  // where the dragged object has been since the preview began
  static constexpr int kPreviewRays = 4;
  std::vector<std::array<glm::vec3, 4>> cD, cBorig, cB;
  double insertSeconds = 0;

  std::vector<glm::vec3> cur;
  std::vector<float> seenWeight;  // per node: corner values lean on what the photos show
  std::vector<VirtualLamp> vlamps;  // as they are now
  CornerStencil stencil;            // leaf corners of the current mesh
  // Radiosity is linear in the emittances on a fixed geometry: per emitter (real lamps at their
  // estimate, then virtual lamps at unit radiance) the leaf corner values of its solution alone.
  // A lamp edit is then a weighted sum of these, not radiosity steps. Geometry changes (objects
  // moved, surfaces added) make them stale; they are rebuilt at the next lamp edit.
  std::vector<std::vector<std::array<glm::vec3, 4>>> basis;  // [emitter][leaf of stencil]
  bool basesValid = false, geometryPending = false;
  // After lamp edits by per-lamp sums the engine's own B is not current; refinement needs it.
  bool engineStale = false;
  void syncEngine(Progress& progress) {
    if (!engineStale) return;
    h->iterate(progress);
    engineStale = false;
  }
  // What the display ratio is made of: irradiance on real surfaces (B / D = E / (E + E-bar) there,
  // whatever each element's reflectance, so T_inter's modulation and the display's cancel exactly
  // under the original lighting), radiosity on lamps and virtual surfaces.
  bool byIrradiance(int node) const {
    const int s = h->nodes()[node].surface;
    return s >= 0 && size_t(s) < np && kinds[s] == PolygonKind::Real;
  }
  // Virtual surfaces, and lamps no photo shows (seen from elsewhere), are drawn with their own
  // radiance B / pi rather than a texture.
  bool shownBySolution(int s) const {
    return size_t(s) >= np || (kinds[s] == PolygonKind::Light && !textures[s].photographed());
  }
  glm::vec3 shading(int node) const { return byIrradiance(node) ? h->irradiance(node) : h->radiosity(node); }
  // Seen from the photo's own camera, each lamp's glow follows its lamp (or stays as photographed).
  void addGlow(const Camera& camera, ImageRGB& img, bool original) const {
    const auto& pc = photoCamera;
    if (camera.width != glow.width || camera.height != glow.height || camera.K != pc.K || camera.R != pc.R ||
        camera.t != pc.t || glowLamp.empty())
      return;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        const int l = glowLamp[size_t(y) * img.width + x];
        if (l >= 0) img.set(x, y, img.at(x, y) + glow.at(x, y) * (original ? glm::vec3(1.f) : glm::vec3(lampScale[l])));
      }
  }
  void shadeAll() {
    cur.resize(h->nodes().size());
    for (size_t n = 0; n < cur.size(); ++n) cur[n] = shading(int(n));
  }
  void refreshCorners() {
    shadeAll();
    stencil.apply(cur, cB);
  }
  std::vector<int> emitters() const {
    std::vector<int> e = lampSurfaces;
    e.insert(e.end(), vlampSurfaces.begin(), vlampSurfaces.end());
    return e;
  }
  glm::vec3 emitterScale(size_t e) const {
    return e < lampScale.size() ? glm::vec3(lampScale[e]) : glm::vec3(vlampExitance[e - lampScale.size()] / std::numbers::pi);
  }
  void buildBases(Progress& progress) {
    const auto em = emitters();
    basis.assign(em.size(), {});
    for (size_t e = 0; e < em.size(); ++e) {
      for (size_t k = 0; k < em.size(); ++k) {
        const glm::dvec3 unit = k < lampScale.size() ? baseExitance[k] : glm::dvec3(std::numbers::pi);
        h->setExitance(em[k], k == e ? unit : glm::dvec3(0.0));
      }
      h->iterate(progress);
      shadeAll();
      stencil.applyCompact(cur, basis[e]);
    }
    for (size_t k = 0; k < em.size(); ++k)
      h->setExitance(em[k], k < lampScale.size() ? baseExitance[k] * lampScale[k] : vlampExitance[k - lampScale.size()]);
    h->iterate(progress);  // the engine holds the current solution too
    basesValid = true;
  }
  void combineBases() {
    const auto& leaves = stencil.leaves();
    std::vector<glm::vec3> w(basis.size());
    for (size_t e = 0; e < basis.size(); ++e) w[e] = emitterScale(e);
    cB.resize(std::max(cB.size(), h->nodes().size()));
    tbb::parallel_for(tbb::blocked_range<size_t>(0, leaves.size(), 2048), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i < r.end(); ++i) {
        std::array<glm::vec3, 4> v{glm::vec3(0.f), glm::vec3(0.f), glm::vec3(0.f), glm::vec3(0.f)};
        for (size_t e = 0; e < basis.size(); ++e)
          for (int c = 0; c < 4; ++c) v[c] += w[e] * basis[e][i][c];
        cB[leaves[i]] = v;
      }
    });
  }
  // Per-element reflectance from the reflectance maps, and how much of the element a photo saw.
  void setLeafReflectance(int leaf) {
    const auto& N = h->nodes()[leaf];
    const auto& t = textures[N.surface];
    double seenFraction = 0;
    if (!t.albedo.empty())
      h->setElementReflectance(leaf, glm::dvec3(t.mean(t.albedo, {N.u0, N.v0}, {N.u1, N.v1}, &seenFraction)));
    seenWeight[leaf] = float(seenFraction) + 1e-3f;
  }
  // D and B_orig with the original lighting (§2.4: D is the display factor of the real room),
  // taken before anything virtual adds light: virtual lamps dark, lamps at their estimates, and
  // objects out of the room (far above it; only the links they cross are redone), so the real
  // room's B_orig has no virtual shadows in it; virtual objects then make B < D where they cast
  // shadows. Also §4.3's element sets under that lighting. Everything is put back after; the
  // per-lamp bases are stale.
  void originalLighting(Progress& progress) {
    auto& hr = *h;
    for (size_t k = 0; k < lampSurfaces.size(); ++k) hr.setExitance(lampSurfaces[k], baseExitance[k]);
    for (int s : vlampSurfaces) hr.setExitance(s, glm::dvec3(0.0));
    for (const auto& ids : objectSurfaceIds)
      for (int s : ids) hr.setReflectance(s, glm::dvec3(0.0));
    const glm::dvec3 away(0.0, 0.0, 1000.0);
    for (const auto& ids : objectSurfaceIds) hr.translateSurfaces(ids, away);
    hr.iterate(progress);
    const LinkSums sums = linkSums(hr, options.blockedIndirect);
    const size_t nn = hr.nodes().size();
    D.resize(nn);
    Borig.resize(nn);
    for (size_t n = 0; n < nn; ++n) {
      Borig[n] = shading(int(n));
      D[n] = byIrradiance(int(n)) ? Borig[n] + sums.blocked[n] : Borig[n];
    }
    stencil.apply(D, cD);
    stencil.apply(Borig, cBorig);
    // §4.3's element sets, as the preprocess defines them: occluded (more than occludedFraction
    // of the direct light blocked), and the frontier (unoccluded, seen by the photo, next to an
    // occluded element) where references are looked for.
    category.assign(nn, 0);
    {
      auto grey = [](const glm::vec3& c) { return (double(c.x) + c.y + c.z) / 3; };
      const std::vector<int> leaves = leavesOf(hr, realMask());
      std::vector<uint8_t> occluded(nn, 0), unoccluded(nn, 0);
      for (int n : leaves) {
        const double d = grey(sums.direct[n]), b = grey(sums.directBlocked[n]);
        occluded[n] = d > 0 && b > options.occludedFraction * d;
        unoccluded[n] = b <= 1e-3 * d;
        if (occluded[n]) category[n] = kOccludedElement;
      }
      for (int n : leaves) {
        if (!unoccluded[n] || seenWeight[n] < 0.5f) continue;
        for (int m : neighbours(hr, n))
          if (occluded[m]) {
            category[n] = kFrontierElement;
            break;
          }
      }
    }
    for (const auto& ids : objectSurfaceIds) hr.translateSurfaces(ids, -away);
    for (size_t k = 0; k < lampSurfaces.size(); ++k) hr.setExitance(lampSurfaces[k], baseExitance[k] * lampScale[k]);
    for (size_t k = 0; k < vlampSurfaces.size(); ++k) hr.setExitance(vlampSurfaces[k], vlampExitance[k]);
    for (size_t o = 0; o < objectSurfaceIds.size(); ++o)
      for (int s : objectSurfaceIds[o]) hr.setReflectance(s, objects[o].albedo);
    basesValid = false;
  }
  std::vector<uint8_t> realMask() const {
    std::vector<uint8_t> real(np, 0);
    for (size_t i = 0; i < np; ++i) real[i] = kinds[i] == PolygonKind::Real;
    return real;
  }
  // After surfaces were added (the mesh grew): new elements of real polygons take their
  // reflectance from the maps, and D and B_orig (the original lighting, which nothing virtual
  // changes) from the corner values of the old leaf they were cut from; then new corners.
  void meshGrew(size_t oldNodes) {
    const auto& nodes = h->nodes();
    const size_t nn = nodes.size();
    seenWeight.resize(nn, 1.f);
    category.resize(nn, 0);
    D.resize(nn, glm::vec3(0.f));
    Borig.resize(nn, glm::vec3(0.f));
    std::vector<int> oldLeaf(nn, -1);
    for (size_t n = oldNodes; n < nn; ++n) {
      const auto& N = nodes[n];
      if (N.isCluster() || size_t(N.surface) >= np) continue;
      oldLeaf[n] = size_t(N.parent) < oldNodes ? N.parent : oldLeaf[N.parent];
      if (oldLeaf[n] < 0) continue;
      const auto& P = nodes[oldLeaf[n]];
      const glm::dvec2 uv(0.5 * (double(N.u0) + N.u1), 0.5 * (double(N.v0) + N.v1));
      D[n] = interpolateCorners(P, cD[oldLeaf[n]], uv);
      if (category.size() < nn) category.resize(nn, 0);
      category[n] = category[oldLeaf[n]];
      Borig[n] = interpolateCorners(P, cBorig[oldLeaf[n]], uv);
      if (kinds[N.surface] == PolygonKind::Real && N.isLeaf()) setLeafReflectance(int(n));
    }
    stencil = CornerStencil(*h, &seenWeight);
    stencil.apply(D, cD);
    stencil.apply(Borig, cBorig);
    basesValid = false;
    geometryPending = true;
  }
};

RelightSession::RelightSession(const Scene& scene, const RelightData& data, std::vector<VirtualLamp> virtualLamps,
                               std::vector<VirtualObject> objects, Progress& progress, SessionMesh mesh)
    : impl_(std::make_unique<Impl>()) {
  auto& im = *impl_;
  im.np = scene.polygons.size();
  if (data.textures.size() != im.np || data.lampExitance.size() != scene.lamps.size())
    throw Error(scene.sourceFile, "relighting data", "does not match the room (re-run relume preprocess)");
  im.textures = data.textures;
  for (const auto& p : scene.polygons) im.kinds.push_back(p.kind);
  std::vector<uint8_t> real(im.np, 0), seen(im.np, 0);
  std::vector<glm::dvec3> refl(im.np, glm::dvec3(0.0));
  for (size_t i = 0; i < im.np; ++i) {
    real[i] = scene.polygons[i].kind == PolygonKind::Real;
    const auto& t = im.textures[i];
    seen[i] = t.photographed();
    if (real[i] && !t.albedo.empty()) refl[i] = glm::dvec3(t.mean(t.albedo, t.origin, t.uvOf(t.width, t.height)));
  }
  auto surfaces = engineSurfaces(scene, refl, data.lampExitance);
  for (const auto& l : scene.lamps) im.lampSurfaces.push_back(l.polygon);
  im.baseExitance = data.lampExitance;
  im.options = data.options;
  im.lampScale.assign(scene.lamps.size(), glm::dvec3(1.0));
  im.glow = data.glow;
  im.glowLamp = data.glowLamp;
  if (const Photo* ph = scene.findPhoto(data.photo)) im.photoCamera = ph->camera;
  im.vlamps = virtualLamps;
  for (const auto& v : virtualLamps) {
    if (v.polygon.size() < 3) throw Error(scene.sourceFile, "virtual lamp '" + v.name + "'", "needs a polygon of 3 or more vertices");
    for (double c : {v.radiance.x, v.radiance.y, v.radiance.z})
      if (!(c >= 0) || !std::isfinite(c)) throw Error(scene.sourceFile, "virtual lamp '" + v.name + "'", "radiance must be finite and >= 0");
    radiosity::Surface s;
    s.name = v.name;
    s.vertices = v.polygon;
    s.exitance = std::numbers::pi * v.radiance;
    s.twoSided = v.twoSided;
    s.photometry = v.photometry;
    im.vlampSurfaces.push_back(int(surfaces.size()));
    im.vlampExitance.push_back(s.exitance);
    surfaces.push_back(s);
  }
  std::vector<std::pair<int, glm::dvec3>> objectSurfaces;
  im.scene = scene;
  im.objects = objects;
  for (const auto& o : objects) {
    checkVirtualObject(scene, o);
    {
      std::vector<const VirtualObject*> before;
      for (const auto& e : objects) {
        if (&e == &o) break;
        before.push_back(&e);
      }
      checkVirtualObjectsApart(scene, o, before);
    }
    im.objectSurfaceIds.emplace_back();
    for (size_t k = 0; k < o.polygons.size(); ++k) {
      im.objectSurfaceIds.back().push_back(int(surfaces.size()));
      radiosity::Surface s;
      s.name = o.name + "_" + std::to_string(k);
      s.vertices = o.polygons[k];
      s.reflectance = o.albedo;
      objectSurfaces.emplace_back(int(surfaces.size()), o.albedo);
      surfaces.push_back(s);
    }
  }
  radiosity::Options eo = data.options.engine;
  if (mesh == SessionMesh::Interactive) {
    eo.oracle = radiosity::Oracle::BFV;
    eo.epsilon = data.options.interactiveEpsilon;
  }
  im.h = std::make_unique<HierarchicalRadiosity>(std::move(surfaces), eo);
  auto& h = *im.h;
  {
    ProgressScope scope(progress, 0.0, 0.5);
    h.solve(scope);
    h.pushLampLinksToLeaves(scope);
  }
  if (mesh == SessionMesh::Refined) {
    ProgressScope scope(progress, 0.5, 0.8);
    textureRefine(h, im.textures, im.lampSurfaces, real, data.colourScale, data.options, nullptr, scope);
  }
  if (!im.vlampSurfaces.empty()) {
    // §4.5: links from a virtual lamp forced onto the polygons the photos show.
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<int> receivers;
    for (size_t i = 0; i < im.np; ++i)
      if (seen[i]) receivers.push_back(int(i));
    for (const auto& [s, a] : objectSurfaces) receivers.push_back(s);
    h.forceRefine(receivers, im.vlampSurfaces, progress);
    h.pushLampLinksToLeaves(progress);
    h.iterate(progress);
    im.insertSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  // Per-element reflectance from the reflectance maps.
  im.seenWeight.assign(h.nodes().size(), 1.f);
  for (int leaf : leavesOf(h, real)) im.setLeafReflectance(leaf);
  im.stencil = CornerStencil(h, &im.seenWeight);
  im.originalLighting(progress);
  im.buildBases(progress);
  im.combineBases();
  progress.report(1.0, "relighting session ready");
}

RelightSession::~RelightSession() = default;

void RelightSession::setReflectanceMaps(const std::vector<PolygonTexture>& textures, Progress& progress) {
  auto& im = *impl_;
  if (textures.size() != im.np)
    throw Error(im.scene.sourceFile, "reflectance maps", "do not match the room (one texture per polygon)");
  im.textures = textures;
  for (int leaf : leavesOf(*im.h, im.realMask())) im.setLeafReflectance(leaf);
  im.originalLighting(progress);
  im.geometryPending = false;
  update(progress);
}

const HierarchicalRadiosity& RelightSession::engine() const { return *impl_->h; }
HierarchicalRadiosity& RelightSession::engine() { return *impl_->h; }
double RelightSession::insertSeconds() const { return impl_->insertSeconds; }
void RelightSession::syncEngine(Progress& progress) { impl_->syncEngine(progress); }
glm::vec3 RelightSession::displayFactor(int node) const {
  const auto& D = impl_->D;
  return node >= 0 && size_t(node) < D.size() ? D[size_t(node)] : glm::vec3(0.f);
}
glm::vec3 RelightSession::originalShading(int node) const {
  const auto& B = impl_->Borig;
  return node >= 0 && size_t(node) < B.size() ? B[size_t(node)] : glm::vec3(0.f);
}
glm::vec3 RelightSession::shading(int node) const { return impl_->shading(node); }
const PolygonTexture& RelightSession::texture(int polygon) const { return impl_->textures.at(size_t(polygon)); }
size_t RelightSession::realPolygonCount() const { return impl_->np; }

void RelightSession::setLampScale(int lamp, const glm::dvec3& scale) {
  impl_->h->setExitance(impl_->lampSurfaces.at(lamp), impl_->baseExitance.at(lamp) * scale);
  impl_->lampScale.at(lamp) = scale;
}

void RelightSession::setVirtualLampRadiance(int lamp, const glm::dvec3& radiance) {
  auto& im = *impl_;
  for (double c : {radiance.x, radiance.y, radiance.z})
    if (!(c >= 0) || !std::isfinite(c))
      throw Error(im.scene.sourceFile, "virtual lamp '" + im.vlamps.at(lamp).name + "'", "radiance must be finite and >= 0");
  im.vlampExitance.at(lamp) = std::numbers::pi * radiance;
  im.vlamps.at(lamp).radiance = radiance;
  im.h->setExitance(im.vlampSurfaces.at(lamp), im.vlampExitance[lamp]);
}

namespace {
void checkVirtualLamp(const Scene& scene, const VirtualLamp& lamp) {
  const std::string what = "virtual lamp '" + lamp.name + "'";
  if (lamp.polygon.size() < 3) throw Error(scene.sourceFile, what, "needs a polygon of 3 or more vertices");
  for (const auto& v : lamp.polygon)
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
      throw Error(scene.sourceFile, what, "has a vertex that is not a finite number");
  if (!(polygonArea(lamp.polygon) > 1e-8)) throw Error(scene.sourceFile, what, "has no area");
  for (double c : {lamp.radiance.x, lamp.radiance.y, lamp.radiance.z})
    if (!(c >= 0) || !std::isfinite(c)) throw Error(scene.sourceFile, what, "radiance must be finite and >= 0");
}
}  // namespace

void RelightSession::replaceVirtualLamp(int lamp, const VirtualLamp& replacement, Progress& progress) {
  auto& im = *impl_;
  const size_t i = size_t(lamp);
  if (i >= im.vlamps.size()) throw Error(im.scene.sourceFile, "virtual lamp " + std::to_string(lamp), "does not exist");
  checkVirtualLamp(im.scene, replacement);  // before anything changes
  removeVirtualLamp(lamp, progress);
  addVirtualLamp(replacement, progress);
  // Back to its place in the list.
  const auto at = std::ptrdiff_t(i);
  std::rotate(im.vlamps.begin() + at, im.vlamps.end() - 1, im.vlamps.end());
  std::rotate(im.vlampSurfaces.begin() + at, im.vlampSurfaces.end() - 1, im.vlampSurfaces.end());
  std::rotate(im.vlampExitance.begin() + at, im.vlampExitance.end() - 1, im.vlampExitance.end());
  im.basesValid = false;
}

int RelightSession::addVirtualLamp(const VirtualLamp& lamp, Progress& progress) {
  auto& im = *impl_;
  checkVirtualLamp(im.scene, lamp);
  const auto t0 = std::chrono::steady_clock::now();
  im.syncEngine(progress);
  const size_t oldNodes = im.h->nodes().size();
  radiosity::Surface s;
  s.name = lamp.name;
  s.vertices = lamp.polygon;
  s.exitance = std::numbers::pi * lamp.radiance;
  s.twoSided = lamp.twoSided;
  s.photometry = lamp.photometry;
  const int id = im.h->addSurfaces({s}, progress).at(0);
  im.vlampSurfaces.push_back(id);
  im.vlampExitance.push_back(s.exitance);
  im.vlamps.push_back(lamp);
  im.meshGrew(oldNodes);
  update(progress);
  im.insertSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return int(im.vlamps.size()) - 1;
}

size_t RelightSession::moveVirtualLamp(int lamp, const glm::dvec3& offset, Progress& progress) {
  auto& im = *impl_;
  VirtualLamp& v = im.vlamps.at(size_t(lamp));
  const size_t n = im.h->translateSurfaces({im.vlampSurfaces[size_t(lamp)]}, offset);
  for (auto& p : v.polygon) p += offset;
  im.basesValid = false;
  im.geometryPending = true;
  update(progress);
  return n;
}

void RelightSession::removeVirtualLamp(int lamp, Progress& progress) {
  auto& im = *impl_;
  const size_t i = size_t(lamp);
  im.h->removeSurfaces({im.vlampSurfaces.at(i)});
  im.vlampSurfaces.erase(im.vlampSurfaces.begin() + std::ptrdiff_t(i));
  im.vlampExitance.erase(im.vlampExitance.begin() + std::ptrdiff_t(i));
  im.vlamps.erase(im.vlamps.begin() + std::ptrdiff_t(i));
  im.basesValid = false;
  im.geometryPending = true;
  update(progress);
}

size_t RelightSession::virtualLampCount() const { return impl_->vlamps.size(); }
const VirtualLamp& RelightSession::virtualLamp(int lamp) const { return impl_->vlamps.at(size_t(lamp)); }
int RelightSession::virtualLampSurface(int lamp) const { return impl_->vlampSurfaces.at(size_t(lamp)); }

int RelightSession::addObject(const VirtualObject& object, Progress& progress) {
  auto& im = *impl_;
  checkVirtualObject(im.scene, object);
  {
    std::vector<const VirtualObject*> others;
    for (const auto& e : im.objects) others.push_back(&e);
    checkVirtualObjectsApart(im.scene, object, others);
  }
  im.syncEngine(progress);
  const size_t oldNodes = im.h->nodes().size();
  std::vector<radiosity::Surface> faces;
  for (size_t k = 0; k < object.polygons.size(); ++k) {
    radiosity::Surface s;
    s.name = object.name + "_" + std::to_string(k);
    s.vertices = object.polygons[k];
    s.reflectance = object.albedo;
    faces.push_back(s);
  }
  im.objectSurfaceIds.push_back(im.h->addSurfaces(faces, progress));
  im.objects.push_back(object);
  im.meshGrew(oldNodes);
  update(progress);
  return int(im.objects.size()) - 1;
}

size_t RelightSession::moveObject(int object, const glm::dvec3& offset, Progress& progress) {
  return moveObject(object, offset, 0.0, progress);
}

size_t RelightSession::moveObject(int object, const glm::dvec3& offset, double turnRadians, Progress& progress) {
  return moveObjectAbout(object, offset, turnRadians, objectCentre(impl_->objects.at(size_t(object))), progress);
}

size_t RelightSession::moveObjectAbout(int object, const glm::dvec3& offset, double turnRadians, const glm::dvec3& pivot,
                                       Progress& progress) {
  auto& im = *impl_;
  VirtualObject moved = im.objects.at(size_t(object));
  const double c = std::cos(turnRadians), sn = std::sin(turnRadians);
  const glm::dmat3 rot(glm::dvec3(c, sn, 0), glm::dvec3(-sn, c, 0), glm::dvec3(0, 0, 1));  // about +z
  for (auto& p : moved.polygons)
    for (auto& v : p) v = rot * (v - pivot) + pivot + offset;
  checkVirtualObject(im.scene, moved);
  {
    std::vector<const VirtualObject*> others;
    for (size_t k = 0; k < im.objects.size(); ++k)
      if (int(k) != object) others.push_back(&im.objects[k]);
    checkVirtualObjectsApart(im.scene, moved, others);
  }
  if (im.dragPreview) {  // every place the object passes through is settled at the end
    for (const VirtualObject* o : {&im.objects[size_t(object)], &moved})
      for (const auto& p : o->polygons)
        for (const auto& v : p) {
          im.dragLo = glm::min(im.dragLo, glm::vec3(v));
          im.dragHi = glm::max(im.dragHi, glm::vec3(v));
        }
  }
  const size_t n = im.h->moveSurfaces(im.objectSurfaceIds[size_t(object)], rot, pivot, offset,
                                      im.dragPreview ? Impl::kPreviewRays : 0);
  im.objects[size_t(object)] = moved;
  im.basesValid = false;
  im.geometryPending = true;
  update(progress);
  return n;
}

void RelightSession::setDragPreview(bool on) {
  impl_->dragPreview = on;
  if (on) {
    impl_->dragLo = glm::vec3(1e30f);
    impl_->dragHi = glm::vec3(-1e30f);
  }
}

size_t RelightSession::settleObject(int object, Progress& progress) {
  auto& im = *impl_;
  im.dragPreview = false;
  glm::vec3 lo = im.dragLo, hi = im.dragHi;
  for (const auto& p : im.objects.at(size_t(object)).polygons)
    for (const auto& v : p) {
      lo = glm::min(lo, glm::vec3(v));
      hi = glm::max(hi, glm::vec3(v));
    }
  im.dragLo = glm::vec3(1e30f);
  im.dragHi = glm::vec3(-1e30f);
  const size_t n = im.h->refreshLinks(im.objectSurfaceIds.at(size_t(object)), lo, hi);
  im.basesValid = false;
  im.geometryPending = true;
  update(progress);
  return n;
}

void RelightSession::removeObject(int object, Progress& progress) {
  auto& im = *impl_;
  const size_t i = size_t(object);
  im.h->removeSurfaces(im.objectSurfaceIds.at(i));
  im.objectSurfaceIds.erase(im.objectSurfaceIds.begin() + std::ptrdiff_t(i));
  im.objects.erase(im.objects.begin() + std::ptrdiff_t(i));
  im.basesValid = false;
  im.geometryPending = true;
  update(progress);
}

size_t RelightSession::objectCount() const { return impl_->objects.size(); }
const VirtualObject& RelightSession::object(int object) const { return impl_->objects.at(size_t(object)); }
const std::vector<int>& RelightSession::objectSurfaces(int object) const { return impl_->objectSurfaceIds.at(size_t(object)); }

glm::dvec3 objectCentre(const VirtualObject& object) {
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const auto& p : object.polygons)
    for (const auto& v : p) {
      lo = glm::min(lo, v);
      hi = glm::max(hi, v);
    }
  return 0.5 * (lo + hi);
}

glm::dvec3 RelightSession::lampScale(int lamp) const { return impl_->lampScale.at(lamp); }
size_t RelightSession::lampCount() const { return impl_->lampScale.size(); }
const Camera& RelightSession::photoCamera() const { return impl_->photoCamera; }

namespace {

// Inserts into each leaf piece's outline the vertices of other pieces of the same polygon that
// lie inside one of its axis-aligned edges (T-junctions). Leaf boundaries come from the same
// splits of a common ancestor, so a shared boundary line has bit-identical coordinates on both
// sides (where a slanted outline crosses it, the two clipped points may differ in the last bits:
// a sliver, not a crack).
void removeTJunctions(std::vector<std::vector<glm::dvec2>>& pieces) {
  std::map<double, std::vector<double>> onU, onV;  // x = u: the v of every vertex; y = v: the u
  for (const auto& piece : pieces)
    for (const auto& p : piece) {
      onU[p.x].push_back(p.y);
      onV[p.y].push_back(p.x);
    }
  for (auto* m : {&onU, &onV})
    for (auto& [key, list] : *m) {
      std::sort(list.begin(), list.end());
      list.erase(std::unique(list.begin(), list.end()), list.end());
    }
  for (auto& piece : pieces) {
    std::vector<glm::dvec2> out;
    out.reserve(piece.size() + 4);
    for (size_t i = 0; i < piece.size(); ++i) {
      const glm::dvec2 a = piece[i], b = piece[(i + 1) % piece.size()];
      out.push_back(a);
      const int axis = a.x == b.x ? 0 : a.y == b.y ? 1 : -1;  // the coordinate the edge keeps
      if (axis < 0) continue;
      const auto& m = axis == 0 ? onU : onV;
      const auto it = m.find(a[axis]);
      if (it == m.end()) continue;
      const double from = a[1 - axis], to = b[1 - axis];
      const auto& list = it->second;
      auto emit = [&](double t) {
        glm::dvec2 q;
        q[axis] = a[axis];
        q[1 - axis] = t;
        out.push_back(q);
      };
      if (from < to) {
        for (auto k = std::upper_bound(list.begin(), list.end(), from); k != list.end() && *k < to; ++k) emit(*k);
      } else {
        auto k = std::lower_bound(list.begin(), list.end(), from);
        while (k != list.begin() && *(k - 1) > to) emit(*--k);
      }
    }
    piece = std::move(out);
  }
}

// Makes the pieces of one polygon agree to the last bit: coordinates within 1 µm of each other
// become one value (the same boundary clipped on its two sides, or a leaf rectangle kept in
// single precision against a corner in double), and a corner that then repeats is dropped.
void snapPieces(std::vector<std::vector<glm::dvec2>>& pieces, std::vector<int>& leafOf) {
  constexpr double tol = 1e-6;
  for (int axis = 0; axis < 2; ++axis) {
    std::vector<double> values;
    for (const auto& piece : pieces)
      for (const auto& p : piece) values.push_back(p[axis]);
    std::sort(values.begin(), values.end());
    std::vector<double> canonical;  // the first value of each run of values closer than tol
    for (double v : values)
      if (canonical.empty() || v - canonical.back() > tol) canonical.push_back(v);
    for (auto& piece : pieces)
      for (auto& p : piece) {
        auto it = std::upper_bound(canonical.begin(), canonical.end(), p[axis]);
        p[axis] = *std::prev(it);
      }
  }
  for (auto& piece : pieces) {
    std::vector<glm::dvec2> distinct;
    for (const auto& p : piece)
      if (distinct.empty() || p != distinct.back()) distinct.push_back(p);
    while (distinct.size() > 1 && distinct.front() == distinct.back()) distinct.pop_back();
    piece = std::move(distinct);
  }
  size_t kept = 0;
  for (size_t k = 0; k < pieces.size(); ++k)
    if (pieces[k].size() >= 3 && polygonArea2D(pieces[k]) > 0) {
      if (kept != k) {
        pieces[kept] = std::move(pieces[k]);
        leafOf[kept] = leafOf[k];
      }
      ++kept;
    }
  pieces.resize(kept);
  leafOf.resize(kept);
}

}  // namespace

DisplayMesh RelightSession::displayMesh() const {
  const auto& im = *impl_;
  const auto& h = *im.h;
  const auto& nodes = h.nodes();
  const size_t ns = h.surfaces().size();
  std::vector<std::vector<int>> leaves(ns);
  for (size_t n = 0; n < nodes.size(); ++n)
    if (!nodes[n].isCluster() && nodes[n].isLeaf()) leaves[nodes[n].surface].push_back(int(n));
  DisplayMesh mesh;
  mesh.realPolygons = im.np;
  std::vector<std::vector<glm::dvec2>> pieces;
  std::vector<int> pieceLeaf;
  for (size_t s = 0; s < ns; ++s) {
    const auto& surf = h.surfaces()[s];
    std::vector<glm::dvec2> outline;
    for (const auto& v : surf.vertices) outline.push_back(h.toUV(int(s), v));
    if (polygonArea2D(outline) < 0) std::reverse(outline.begin(), outline.end());
    DisplayMesh::Range range;
    range.surface = int(s);
    range.kind = im.shownBySolution(int(s))               ? DisplaySurfaceKind::Virtual
                 : im.kinds[s] == PolygonKind::Window ? DisplaySurfaceKind::Window
                                                       : DisplaySurfaceKind::Textured;
    range.normal = glm::vec3(polygonNormal(surf.vertices));
    range.first = mesh.indices.size();
    pieces.clear();
    pieceLeaf.clear();
    for (int leaf : leaves[s]) {
      const auto& L = nodes[leaf];
      auto piece = clipToRect(outline, {L.u0, L.v0}, {L.u1, L.v1});
      if (piece.size() < 3 || polygonArea2D(piece) <= 0) continue;
      pieces.push_back(std::move(piece));
      pieceLeaf.push_back(leaf);
    }
    snapPieces(pieces, pieceLeaf);
    std::vector<glm::dvec2> centres(pieces.size());  // before the T-vertices are added
    std::vector<size_t> corners(pieces.size());
    for (size_t k = 0; k < pieces.size(); ++k) {
      for (const auto& p : pieces[k]) centres[k] += p;
      centres[k] /= double(pieces[k].size());
      corners[k] = pieces[k].size();
    }
    removeTJunctions(pieces);
    for (size_t k = 0; k < pieces.size(); ++k) {
      const auto& L = nodes[pieceLeaf[k]];
      const int32_t index = int32_t(mesh.leafNode.size());
      mesh.leafNode.push_back(pieceLeaf[k]);
      mesh.leafRect.emplace_back(L.u0, L.v0, L.u1, L.v1);
      auto vertex = [&](const glm::dvec2& uv) {
        mesh.vertices.push_back({glm::vec3(h.toWorld(int(s), uv)), glm::vec2(uv), index});
      };
      const auto first = uint32_t(mesh.vertices.size());
      const auto n = uint32_t(pieces[k].size());
      if (n == corners[k] && n <= 4) {  // a triangle, or a quadrilateral as two (llvmpipe pays per triangle)
        for (const auto& p : pieces[k]) vertex(p);
        for (uint32_t i = 1; i + 1 < n; ++i) mesh.indices.insert(mesh.indices.end(), {first, first + i, first + i + 1});
      } else {  // with T-vertices: a fan around the centre, no sliver triangles
        vertex(centres[k]);
        for (const auto& p : pieces[k]) vertex(p);
        for (uint32_t i = 0; i < n; ++i) mesh.indices.insert(mesh.indices.end(), {first, first + 1 + i, first + 1 + (i + 1) % n});
      }
    }
    range.count = mesh.indices.size() - range.first;
    if (range.count > 0) mesh.ranges.push_back(range);
  }
  return mesh;
}

std::vector<glm::vec4> RelightSession::displayCorners(const DisplayMesh& mesh) const {
  const auto& im = *impl_;
  std::vector<glm::vec4> out(mesh.leafNode.size() * kDisplayCornerTexels);
  for (size_t i = 0; i < mesh.leafNode.size(); ++i) {
    const int leaf = mesh.leafNode[i];
    glm::vec4* o = &out[i * kDisplayCornerTexels];
    for (int c = 0; c < 4; ++c) {
      o[c] = glm::vec4(im.cB.at(leaf)[c], 1.f);
      o[4 + c] = glm::vec4(im.cD.at(leaf)[c], c == 0 && size_t(leaf) < im.category.size() ? float(im.category[leaf]) : 1.f);
      o[8 + c] = glm::vec4(im.cBorig.at(leaf)[c], 1.f);
    }
  }
  return out;
}

std::vector<float> RelightSession::displayVertexLight(const DisplayMesh& mesh) const {
  const auto& im = *impl_;
  const auto& nodes = im.h->nodes();
  std::vector<float> out(mesh.vertices.size() * kDisplayVertexLight);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, mesh.vertices.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t v = r.begin(); v < r.end(); ++v) {
      const auto& vertex = mesh.vertices[v];
      const int leaf = mesh.leafNode.at(size_t(vertex.leaf));
      const auto& L = nodes[leaf];
      const glm::dvec2 uv(vertex.uv);
      const glm::vec3 values[3] = {interpolateCorners(L, im.cB.at(leaf), uv), interpolateCorners(L, im.cD.at(leaf), uv),
                                   interpolateCorners(L, im.cBorig.at(leaf), uv)};
      float* o = &out[v * kDisplayVertexLight];
      for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 3; ++c) o[3 * k + c] = values[k][c];
    }
  });
  return out;
}

radiosity::SolveStats RelightSession::update(Progress& progress) {
  auto& im = *impl_;
  if (im.geometryPending) {  // radiosity steps on the changed geometry; the bases wait
    const auto st = im.h->iterate(progress);
    im.refreshCorners();
    im.geometryPending = false;
    return st;
  }
  if (!im.basesValid) im.buildBases(progress);
  im.combineBases();
  im.engineStale = true;
  return {};
}


ImageRGB RelightSession::render(const Camera& camera, RelightMethod method, Progress& progress) const {
  const auto& im = *impl_;
  const auto& h = *im.h;
  const float invPi = float(1.0 / std::numbers::pi);
  const auto& den = method == RelightMethod::Full ? im.cD : im.cBorig;
  ImageRGB img = castView(h, camera, progress, [&](int s, int leaf, glm::dvec2 uv) {
    const auto& L = h.nodes()[leaf];
    const glm::vec3 b = interpolateCorners(L, im.cB[leaf], uv);
    if (im.shownBySolution(s)) return b * invPi;  // virtual, or a lamp no photo shows: its radiance
    const auto& t = im.textures[s];
    const bool useFinal = method == RelightMethod::Full && !t.unoccluded.empty();
    const glm::vec3 tex = t.sample(useFinal ? t.unoccluded : t.original, uv);
    if (im.kinds[s] == PolygonKind::Window) return tex;
    const glm::vec3 d = interpolateCorners(L, den[leaf], uv);
    glm::vec3 ratio;
    for (int c = 0; c < 3; ++c) ratio[c] = d[c] > 1e-12f ? b[c] / d[c] : 1.f;
    return tex * ratio;
  });
  im.addGlow(camera, img, false);
  return img;
}

ImageRGB RelightSession::renderUnoccluded(const Camera& camera) const {
  const auto& im = *impl_;
  ImageRGB img = castView(*im.h, camera, silentProgress(), [&](int s, int, glm::dvec2 uv) {
    if (size_t(s) >= im.np) return glm::vec3(0.f);
    const auto& t = im.textures[s];
    return t.sample(t.unoccluded.empty() ? t.original : t.unoccluded, uv);
  });
  im.addGlow(camera, img, true);
  return img;
}

}  // namespace relume
