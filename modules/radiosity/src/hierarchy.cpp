#include "relume/radiosity/hierarchy.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <glm/geometric.hpp>
#include <numbers>
#include <numeric>
#include <random>
#include <stdexcept>

#include "relume/geometry/binary.h"
#include "relume/geometry/polygon.h"
#include "relume/geometry/scene.h"
#include "relume/radiosity/form_factor.h"
#include "relume/raytrace/ray_scene.h"

namespace relume::radiosity {

namespace {
constexpr double kPi = std::numbers::pi;
constexpr float kUnknownVisibility = -1.f;
constexpr float kNormalOffset = 1e-4f;  // m: sample points lifted off their surface

float maxc(const glm::vec3& v) { return std::max(v.x, std::max(v.y, v.z)); }

// SplitMix64: a small, good, deterministic generator per link.
struct Rng {
  uint64_t s;
  explicit Rng(uint64_t seed) : s(seed) {}
  uint64_t next() {
    uint64_t z = (s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return double(next() >> 11) * (1.0 / 9007199254740992.0); }
};

// Visits every node of the subtree below `root` (root included).
template <class F>
void forSubtree(const std::vector<HierarchicalRadiosity::Node>& nodes, const std::vector<int32_t>& children,
                int root, F&& f) {
  std::vector<int> stack{root};
  while (!stack.empty()) {
    const int n = stack.back();
    stack.pop_back();
    f(n);
    for (int i = 0; i < nodes[n].childCount; ++i) stack.push_back(children[nodes[n].childBegin + i]);
  }
}

// `poly` clipped to the convex polygon `clip` (counter-clockwise), Sutherland-Hodgman.
std::vector<glm::dvec2> clipConvex2D(std::vector<glm::dvec2> poly, const std::vector<glm::dvec2>& clip) {
  for (size_t e = 0; e < clip.size() && !poly.empty(); ++e) {
    const glm::dvec2 a = clip[e], b = clip[(e + 1) % clip.size()];
    auto side = [&](const glm::dvec2& p) { return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x); };
    std::vector<glm::dvec2> out;
    for (size_t i = 0; i < poly.size(); ++i) {
      const glm::dvec2 p = poly[i], q = poly[(i + 1) % poly.size()];
      const double sp = side(p), sq = side(q);
      if (sp >= 0) out.push_back(p);
      if ((sp >= 0) != (sq >= 0)) out.push_back(p + (q - p) * (sp / (sp - sq)));
    }
    poly = std::move(out);
  }
  return poly;
}

// The polygons that stop light: every surface but the openings (left empty, so indices hold).
std::vector<std::vector<glm::dvec3>> occluders(const std::vector<Surface>& surfaces) {
  std::vector<std::vector<glm::dvec3>> polys;
  polys.reserve(surfaces.size());
  for (const auto& s : surfaces) polys.push_back(s.opening ? std::vector<glm::dvec3>{} : s.vertices);
  return polys;
}

template <class F>
void forLeaves(const std::vector<HierarchicalRadiosity::Node>& nodes, const std::vector<int32_t>& children,
               int root, F&& f) {
  forSubtree(nodes, children, root, [&](int n) {
    if (nodes[n].isLeaf()) f(n);
  });
}
}  // namespace

std::vector<Surface> surfacesFromScene(const Scene& scene) {
  std::vector<Surface> out;
  out.reserve(scene.polygons.size());
  for (size_t i = 0; i < scene.polygons.size(); ++i) {
    const Polygon& p = scene.polygons[i];
    Surface s;
    s.name = p.name;
    s.vertices = p.vertices;
    const int lamp = scene.lampOfPolygon(int(i));
    if (p.kind == PolygonKind::Light || lamp >= 0) {
      s.reflectance = glm::dvec3(0.0);  // lamp polygons reflect nothing
      if (lamp >= 0) {
        s.exitance = kPi * scene.lamps[lamp].radiance;
        s.twoSided = scene.lamps[lamp].twoSided;
        s.photometry = scene.lamps[lamp].photometry;
      }
    } else if (p.kind == PolygonKind::Window) {
      s.reflectance = glm::dvec3(0.0);  // an opening absorbs everything that leaves the room
    } else {
      s.reflectance = p.albedo;
    }
    out.push_back(std::move(s));
  }
  return out;
}

struct HierarchicalRadiosity::Impl {
  std::shared_ptr<RayScene> rays;  // replaced whole when surfaces change (a saved state keeps its own)
  std::vector<PlaneFrame> frames;
  std::vector<std::vector<glm::dvec2>> uvPolys;
  std::vector<std::vector<double>> fanCdf;  // cumulative triangle-fan areas per surface
  std::vector<EmitterShape> shapes;          // per surface: how it emits (if it does)
  std::vector<double> surfaceArea;
  std::vector<int32_t> perm, posInPerm;      // cluster surface order
  std::vector<int32_t> rangeBegin, rangeCount;  // per node (clusters)
  std::vector<glm::vec3> rho, emit;          // per node (leaves use them)
  std::vector<float> rhoMax;                 // per node: max reflectance below it
  std::vector<uint8_t> emitterOnly;          // per node: every surface below emits
  // Gather arrays, sorted by receiver (struct of arrays).
  std::vector<int32_t> gRecv, gSrc;
  std::vector<float> gK;
  std::vector<size_t> gChunk;  // chunk starts at receiver boundaries, for a parallel gather
  bool gatherDirty = true;
  double eRef = 1.0;  // mean first-bounce irradiance
  // Per surface (once setDistantLight was called): whether the V of its links was taken along a
  // single beam (the next light then takes V again). Kept with the state: an engine read back
  // from bytes has its openings' lights set afresh, and must still know how their V was taken.
  std::vector<uint8_t> beamVisibility;
  std::vector<float> pullAccumulator;  // scratch of pushPull()
  uint64_t raysAtStart = 0;
  double lastSeconds = 0;
  int lastIterations = 0;
};

// ----------------------------------------------------------------------------------------------
// Construction: surface frames, the cluster hierarchy, surface root elements.

struct Builder {
  HierarchicalRadiosity& h;
  HierarchicalRadiosity::Impl& im;

  int newNode(const HierarchicalRadiosity::Node& n) {
    h.nodes_.push_back(n);
    im.rangeBegin.push_back(0);
    im.rangeCount.push_back(0);
    im.rho.emplace_back(0.f);
    im.emit.emplace_back(0.f);
    im.rhoMax.push_back(0.f);
    im.emitterOnly.push_back(0);
    return int(h.nodes_.size()) - 1;
  }

  int surfaceRootNode(int s, int parent) {
    HierarchicalRadiosity::Node n;
    n.parent = parent;
    n.surface = s;
    n.level = parent >= 0 ? h.nodes_[parent].level + 1 : 0;
    glm::dvec2 lo(1e300), hi(-1e300);
    for (const auto& q : im.uvPolys[s]) {
      lo = glm::min(lo, q);
      hi = glm::max(hi, q);
    }
    n.u0 = float(lo.x);
    n.v0 = float(lo.y);
    n.u1 = float(hi.x);
    n.v1 = float(hi.y);
    setElementGeometry(n, im.uvPolys[s], s);
    const int id = newNode(n);
    const Surface& surf = h.surfaces_[s];
    im.rho[id] = glm::vec3(surf.reflectance);
    im.emit[id] = glm::vec3(surf.exitance);
    im.rhoMax[id] = maxc(im.rho[id]);
    im.emitterOnly[id] = maxc(im.emit[id]) > 0.f ? 1 : 0;
    h.surfaceRoot_[s] = id;
    return id;
  }

  void setElementGeometry(HierarchicalRadiosity::Node& n, const std::vector<glm::dvec2>& uvPoly, int s) {
    const PlaneFrame& f = im.frames[s];
    n.area = float(std::abs(polygonArea2D(uvPoly)));
    const glm::dvec3 c = f.toWorld(polygonCentroid2D(uvPoly));
    n.center = glm::vec3(c);
    glm::dvec3 lo(1e300), hi(-1e300);
    double r = 0;
    for (const auto& q : uvPoly) {
      const glm::dvec3 w = f.toWorld(q);
      lo = glm::min(lo, w);
      hi = glm::max(hi, w);
      r = std::max(r, glm::length(w - c));
    }
    n.bmin = glm::vec3(lo);
    n.bmax = glm::vec3(hi);
    n.radius = float(r);
  }

  int buildCluster(int begin, int end, int parent) {
    HierarchicalRadiosity::Node n;
    n.parent = parent;
    n.level = parent >= 0 ? h.nodes_[parent].level + 1 : 0;
    const int id = newNode(n);
    im.rangeBegin[id] = begin;
    im.rangeCount[id] = end - begin;
    std::vector<int> kids;
    const int count = end - begin;
    if (count <= 2) {
      const int cb = int(h.children_.size());
      h.children_.resize(cb + count);
      h.nodes_[id].childBegin = cb;
      h.nodes_[id].childCount = count;
      for (int i = 0; i < count; ++i) h.children_[cb + i] = surfaceRootNode(im.perm[begin + i], id);
    } else {
      // Median split along the longest axis of the surface centroids.
      glm::vec3 lo(1e30f), hi(-1e30f);
      auto centroid = [&](int s) { return glm::vec3(polygonCentroid(h.surfaces_[s].vertices)); };
      for (int i = begin; i < end; ++i) {
        const glm::vec3 c = centroid(im.perm[i]);
        lo = glm::min(lo, c);
        hi = glm::max(hi, c);
      }
      const glm::vec3 ext = hi - lo;
      const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
      const int mid = begin + count / 2;
      std::nth_element(im.perm.begin() + begin, im.perm.begin() + mid, im.perm.begin() + end,
                       [&](int a, int b) { return centroid(a)[axis] < centroid(b)[axis]; });
      const int cb = int(h.children_.size());
      h.children_.resize(cb + 2);
      h.nodes_[id].childBegin = cb;
      h.nodes_[id].childCount = 2;
      const int c0 = buildCluster(begin, mid, id);
      h.children_[cb] = c0;
      const int c1 = buildCluster(mid, end, id);
      h.children_[cb + 1] = c1;
    }
    // Bounds, area, centre (area-weighted), flags from the children.
    auto& me = h.nodes_[id];
    glm::vec3 lo(1e30f), hi(-1e30f), c(0.f);
    float area = 0.f, rmax = 0.f;
    bool allEmit = true;
    for (int k = 0; k < me.childCount; ++k) {
      const auto& ch = h.nodes_[h.children_[me.childBegin + k]];
      lo = glm::min(lo, ch.bmin);
      hi = glm::max(hi, ch.bmax);
      c += ch.center * ch.area;
      area += ch.area;
      rmax = std::max(rmax, im.rhoMax[h.children_[me.childBegin + k]]);
      allEmit = allEmit && im.emitterOnly[h.children_[me.childBegin + k]];
    }
    me.bmin = lo;
    me.bmax = hi;
    me.area = area;
    me.center = area > 0 ? c / area : 0.5f * (lo + hi);
    float r = 0.f;
    for (const glm::vec3 corner : {glm::vec3(lo.x, lo.y, lo.z), glm::vec3(hi.x, lo.y, lo.z),
                                   glm::vec3(lo.x, hi.y, lo.z), glm::vec3(hi.x, hi.y, lo.z),
                                   glm::vec3(lo.x, lo.y, hi.z), glm::vec3(hi.x, lo.y, hi.z),
                                   glm::vec3(lo.x, hi.y, hi.z), glm::vec3(hi.x, hi.y, hi.z)})
      r = std::max(r, glm::length(corner - me.center));
    me.radius = r;
    im.rhoMax[id] = rmax;
    im.emitterOnly[id] = allEmit ? 1 : 0;
    return id;
  }

  // Quadtree split of an element (binary along the long side when it is more than twice as long).
  void subdivide(int id) {
    if (h.nodes_[id].subdivided || h.nodes_[id].isCluster()) return;
    h.nodes_[id].subdivided = true;
    const auto n = h.nodes_[id];
    const int s = n.surface;
    std::vector<HierarchicalRadiosity::Node> kids;
    for (const glm::vec4& r : h.splitRects(id)) {
        HierarchicalRadiosity::Node c;
        c.parent = id;
        c.surface = s;
        c.level = n.level + 1;
        c.u0 = r.x;
        c.v0 = r.y;
        c.u1 = r.z;
        c.v1 = r.w;
        const auto clipped = clipToRect(im.uvPolys[s], {c.u0, c.v0}, {c.u1, c.v1});
        if (clipped.size() < 3) continue;
        setElementGeometry(c, clipped, s);
        if (c.area <= 1e-9f * n.area) continue;
        kids.push_back(c);
      }
    const int cb = int(h.children_.size());
    for (auto& c : kids) {
      const int cid = newNode(c);
      im.rho[cid] = im.rho[id];
      im.emit[cid] = im.emit[id];
      im.rhoMax[cid] = im.rhoMax[id];
      im.emitterOnly[cid] = im.emitterOnly[id];
      h.children_.push_back(cid);
      h.B_.push_back(h.B_[id]);
      h.E_.emplace_back(0.f);
      h.Edown_.push_back(h.Edown_[id]);
    }
    h.nodes_[id].childBegin = cb;
    h.nodes_[id].childCount = int(kids.size());
  }
};

HierarchicalRadiosity::HierarchicalRadiosity(std::vector<Surface> surfaces, Options options)
    : impl_(std::make_unique<Impl>()), surfaces_(std::move(surfaces)), options_(options) {
  const size_t ns = surfaces_.size();
  impl_->rays = std::make_shared<RayScene>(occluders(surfaces_));
  impl_->frames.resize(ns);
  impl_->uvPolys.resize(ns);
  impl_->fanCdf.resize(ns);
  impl_->surfaceArea.resize(ns);
  for (size_t s = 0; s < ns; ++s) {
    const auto& v = surfaces_[s].vertices;
    impl_->shapes.emplace_back(v, surfaces_[s].twoSided, surfaces_[s].photometry, surfaces_[s].distant);
    impl_->frames[s] = PlaneFrame::of(v);
    for (const auto& q : v) impl_->uvPolys[s].push_back(impl_->frames[s].toUV(q));
    double acc = 0;
    for (size_t i = 1; i + 1 < v.size(); ++i) {
      acc += 0.5 * glm::length(glm::cross(v[i] - v[0], v[i + 1] - v[0]));
      impl_->fanCdf[s].push_back(acc);
    }
    impl_->surfaceArea[s] = acc;
  }
  surfaceRoot_.assign(ns, -1);
  impl_->perm.resize(ns);
  std::iota(impl_->perm.begin(), impl_->perm.end(), 0);
  Builder b{*this, *impl_};
  b.buildCluster(0, int(ns), -1);
  impl_->posInPerm.resize(ns);
  for (size_t i = 0; i < ns; ++i) impl_->posInPerm[impl_->perm[i]] = int(i);
  B_.assign(nodes_.size(), glm::vec3(0.f));
  E_.assign(nodes_.size(), glm::vec3(0.f));
  Edown_.assign(nodes_.size(), glm::vec3(0.f));
  // The root cluster linked to itself.
  links_.push_back(Link{0, 0, 0.f, 1.f, 0.f, VisibilityType::Visible});
}

HierarchicalRadiosity::~HierarchicalRadiosity() = default;

struct HierarchicalRadiosity::State {
  Impl impl;  // its ray scene shared, never changed in place
  std::vector<Surface> surfaces;
  std::vector<Node> nodes;
  std::vector<int32_t> children, surfaceRoot;
  std::vector<Link> links;
  std::vector<glm::vec3> B, E, Edown;
};

std::shared_ptr<const HierarchicalRadiosity::State> HierarchicalRadiosity::saveState() const {
  return std::make_shared<const State>(State{*impl_, surfaces_, nodes_, children_, surfaceRoot_, links_, B_, E_, Edown_});
}

void HierarchicalRadiosity::restoreState(const State& state) {
  *impl_ = state.impl;  // (the ray counts are the saved scene's: the rays cast on other scenes since are not)
  surfaces_ = state.surfaces;
  nodes_ = state.nodes;
  children_ = state.children;
  surfaceRoot_ = state.surfaceRoot;
  links_ = state.links;
  B_ = state.B;
  E_ = state.E;
  Edown_ = state.Edown;
}

namespace {
// FNV-1a over the surfaces and options an engine was made from: a kept state is read back only
// into an engine made the same way.
struct Fingerprint {
  uint64_t h = 1469598103934665603ull;
  void bytes(const void* p, size_t n) {
    for (size_t i = 0; i < n; ++i) h = (h ^ static_cast<const uint8_t*>(p)[i]) * 1099511628211ull;
  }
  void f64(double v) { bytes(&v, 8); }
  void i64(int64_t v) { bytes(&v, 8); }
  void vec(const glm::dvec3& v) { f64(v.x), f64(v.y), f64(v.z); }
};
uint64_t engineFingerprint(const std::vector<Surface>& surfaces, const Options& o) {
  Fingerprint f;
  f.i64(int64_t(surfaces.size()));
  for (const Surface& s : surfaces) {
    f.i64(int64_t(s.vertices.size()));
    for (const auto& v : s.vertices) f.vec(v);
    f.vec(s.reflectance);
    f.vec(s.exitance);
    f.i64(int64_t(s.twoSided) | int64_t(s.opening) << 1 | int64_t(s.photometry != nullptr) << 2 |
          int64_t(s.distant != nullptr) << 3);
    if (s.photometry) {  // its shape, not only that it has one: another file gives other links
      const PhotometricDistribution& d = *s.photometry;
      f.i64(int64_t(d.symmetry));
      for (const auto* a : {&d.c, &d.gamma, &d.candela}) {
        f.i64(int64_t(a->size()));
        for (double v : *a) f.f64(v);
      }
    }
  }
  f.i64(int64_t(o.oracle));
  f.f64(o.epsilon);
  f.f64(o.minArea);
  f.i64(o.visibilityRays);
  f.i64(o.quadratureOrder);
  f.f64(o.tolerance);
  f.i64(o.maxIterations);
  f.i64(o.maxRefineRounds);
  f.i64(o.seed);
  return f.h;
}
constexpr uint32_t kStateVersion = 1;
// Elements and links field by field (no padding bytes on disk): 81 and 21 bytes.
constexpr size_t kNodeBytes = 5 * 4 + 6 * 4 + 9 * 4 + 1, kLinkBytes = 2 * 4 + 3 * 4 + 1;
template <class T>
void put(uint8_t*& p, const T& v) {
  std::memcpy(p, &v, sizeof(T));
  p += sizeof(T);
}
template <class T>
T take(const uint8_t*& p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  p += sizeof(T);
  return v;
}
// A count, then `bytes` per record as `encode` lays it out (and `decode` reads it back).
template <class T, class Encode>
void writeRecords(ByteWriter& out, const std::vector<T>& records, size_t bytes, Encode encode) {
  std::vector<uint8_t> b(records.size() * bytes);
  uint8_t* p = b.data();
  for (const T& r : records) encode(p, r);
  out.u64(records.size());
  out.raw(b.data(), b.size());
}
template <class T, class Decode>
std::vector<T> readRecords(ByteReader& in, const char* part, const char* what, size_t max, size_t bytes, Decode decode) {
  const uint64_t count = in.u64(part);
  if (count > max) in.fail(part, std::string("holds more ") + what + " than it can (damaged)");
  in.need(size_t(count) * bytes, part);
  const uint8_t* p = in.bytes().data() + in.pos;
  std::vector<T> records(static_cast<size_t>(count));
  for (T& r : records) decode(p, r);
  in.pos += size_t(count) * bytes;
  return records;
}
// A hierarchy of more elements than this is not one Relume made (about 40 GB of links).
constexpr size_t kMaxStateNodes = size_t(1) << 28, kMaxStateLinks = size_t(1) << 31;
}  // namespace

void HierarchicalRadiosity::writeState(ByteWriter& out) const {
  out.u32(kStateVersion);
  out.u32(uint32_t(kNodeBytes));
  out.u32(uint32_t(kLinkBytes));
  out.u64(engineFingerprint(surfaces_, options_));
  out.f64(impl_->eRef);
  writeRecords(out, nodes_, kNodeBytes, [](uint8_t*& p, const Node& n) {
    for (int32_t v : {n.parent, n.childBegin, n.childCount, n.surface, n.level}) put(p, v);
    for (float v : {n.u0, n.v0, n.u1, n.v1, n.area, n.radius}) put(p, v);
    for (const glm::vec3* v : {&n.center, &n.bmin, &n.bmax}) put(p, v->x), put(p, v->y), put(p, v->z);
    put(p, uint8_t(n.subdivided ? 1 : 0));
  });
  out.array(children_);
  out.array(surfaceRoot_);
  writeRecords(out, links_, kLinkBytes, [](uint8_t*& p, const Link& l) {
    put(p, l.receiver), put(p, l.source);
    put(p, l.formFactor), put(p, l.visibility), put(p, l.variation);
    put(p, uint8_t(l.type));
  });
  out.array(B_);
  out.array(E_);
  out.array(Edown_);
  const Impl& im = *impl_;
  out.array(im.perm);
  out.array(im.posInPerm);
  out.array(im.rangeBegin);
  out.array(im.rangeCount);
  out.array(im.rho);
  out.array(im.emit);
  out.array(im.rhoMax);
  out.array(im.emitterOnly);
  std::vector<uint8_t> beam(surfaces_.size());
  for (size_t s = 0; s < beam.size(); ++s)
    beam[s] = s < im.beamVisibility.size() ? im.beamVisibility[s]
                                           : uint8_t(surfaces_[s].distant && !surfaces_[s].distant->radiance &&
                                                     surfaces_[s].distant->beams.size() == 1);
  out.array(beam);
}

void HierarchicalRadiosity::readState(ByteReader& in) {
  const char* part = "radiosity hierarchy";
  if (in.u32(part) != kStateVersion) in.fail(part, "was written by another version of Relume (solve it again)");
  if (in.u32(part) != kNodeBytes || in.u32(part) != kLinkBytes)
    in.fail(part, "was written by a build of Relume with another memory layout (solve it again)");
  if (in.u64(part) != engineFingerprint(surfaces_, options_))
    in.fail(part, "was solved for other polygons, reflectances, lamp distributions or engine options than the room's now (solve it "
            "again)");
  const double eRef = in.f64(part);
  if (!(eRef > 0)) in.fail(part, "is damaged (the refinement scale)");
  auto nodes = readRecords<Node>(in, part, "elements", kMaxStateNodes, kNodeBytes, [&](const uint8_t*& p, Node& n) {
    n.parent = take<int32_t>(p), n.childBegin = take<int32_t>(p), n.childCount = take<int32_t>(p);
    n.surface = take<int32_t>(p), n.level = take<int32_t>(p);
    n.u0 = take<float>(p), n.v0 = take<float>(p), n.u1 = take<float>(p), n.v1 = take<float>(p);
    n.area = take<float>(p), n.radius = take<float>(p);
    for (glm::vec3* v : {&n.center, &n.bmin, &n.bmax}) v->x = take<float>(p), v->y = take<float>(p), v->z = take<float>(p);
    const uint8_t sub = take<uint8_t>(p);
    if (sub > 1) in.fail(part, "is damaged (an element's flag)");
    n.subdivided = sub != 0;
  });
  auto children = in.array<int32_t>(part, kMaxStateNodes);
  auto surfaceRoot = in.array<int32_t>(part, surfaces_.size());
  auto links = readRecords<Link>(in, part, "links", kMaxStateLinks, kLinkBytes, [&](const uint8_t*& p, Link& l) {
    l.receiver = take<int32_t>(p), l.source = take<int32_t>(p);
    l.formFactor = take<float>(p), l.visibility = take<float>(p), l.variation = take<float>(p);
    const uint8_t type = take<uint8_t>(p);
    if (type > uint8_t(VisibilityType::Partial) || !std::isfinite(l.formFactor) || !std::isfinite(l.visibility))
      in.fail(part, "a link is damaged");
    l.type = VisibilityType(type);
  });
  auto B = in.array<glm::vec3>(part, kMaxStateNodes), E = in.array<glm::vec3>(part, kMaxStateNodes),
       Edown = in.array<glm::vec3>(part, kMaxStateNodes);
  auto perm = in.array<int32_t>(part, surfaces_.size()), posInPerm = in.array<int32_t>(part, surfaces_.size());
  auto rangeBegin = in.array<int32_t>(part, kMaxStateNodes), rangeCount = in.array<int32_t>(part, kMaxStateNodes);
  auto rho = in.array<glm::vec3>(part, kMaxStateNodes), emit = in.array<glm::vec3>(part, kMaxStateNodes);
  auto rhoMax = in.array<float>(part, kMaxStateNodes);
  auto emitterOnly = in.array<uint8_t>(part, kMaxStateNodes);
  auto beamVisibility = in.array<uint8_t>(part, surfaces_.size());
  // Every index in range, so that a damaged file can never make the engine read out of bounds.
  const size_t n = nodes.size(), ns = surfaces_.size();
  const bool sizes = n > 0 && B.size() == n && E.size() == n && Edown.size() == n && rangeBegin.size() == n &&
                     rangeCount.size() == n && rho.size() == n && emit.size() == n && rhoMax.size() == n &&
                     emitterOnly.size() == n && surfaceRoot.size() == ns && perm.size() == ns && posInPerm.size() == ns &&
                     beamVisibility.size() == ns;
  if (!sizes) in.fail(part, "its arrays do not agree in size (damaged)");
  auto within = [](int64_t v, int64_t lo, int64_t hi) { return v >= lo && v < hi; };
  for (size_t i = 0; i < n; ++i) {
    const Node& nd = nodes[i];
    // The root cluster alone has no parent, and parents come before their children.
    const bool ok = (i == 0 ? nd.parent == -1 : within(nd.parent, 0, int64_t(i))) && nd.childCount >= 0 && nd.childBegin >= 0 &&
                    int64_t(nd.childBegin) + nd.childCount <= int64_t(children.size()) && within(nd.surface, -1, int64_t(ns)) &&
                    rangeBegin[i] >= 0 && rangeCount[i] >= 0 && int64_t(rangeBegin[i]) + rangeCount[i] <= int64_t(ns);
    if (!ok) in.fail(part, "element " + std::to_string(i) + " is damaged (an index out of range)");
  }
  for (size_t i = 0; i < n; ++i)  // each child names this node its parent; an element's are on its surface
    for (int32_t k = 0; k < nodes[i].childCount; ++k) {
      const int32_t c = children[size_t(nodes[i].childBegin + k)];
      if (!within(c, 1, int64_t(n)) || nodes[size_t(c)].parent != int32_t(i) ||
          (nodes[i].surface >= 0 && nodes[size_t(c)].surface != nodes[i].surface))
        in.fail(part, "the element tree is damaged (a child out of place)");
    }
  for (size_t s = 0; s < ns; ++s)
    if (!within(surfaceRoot[s], 1, int64_t(n)) || nodes[size_t(surfaceRoot[s])].surface != int32_t(s) ||
        !within(perm[s], 0, int64_t(ns)) || !within(posInPerm[s], 0, int64_t(ns)))
      in.fail(part, "the surfaces' elements are damaged (an index out of range)");
  for (const Link& l : links)
    if (!within(l.receiver, 0, int64_t(n)) || !within(l.source, 0, int64_t(n)))
      in.fail(part, "a link is damaged (an element out of range)");
  Impl& im = *impl_;
  im.eRef = eRef;
  im.perm = std::move(perm);
  im.posInPerm = std::move(posInPerm);
  im.rangeBegin = std::move(rangeBegin);
  im.rangeCount = std::move(rangeCount);
  im.rho = std::move(rho);
  im.emit = std::move(emit);
  im.rhoMax = std::move(rhoMax);
  im.emitterOnly = std::move(emitterOnly);
  im.beamVisibility = std::move(beamVisibility);
  im.gatherDirty = true;
  nodes_ = std::move(nodes);
  children_ = std::move(children);
  surfaceRoot_ = std::move(surfaceRoot);
  links_ = std::move(links);
  B_ = std::move(B);
  E_ = std::move(E);
  Edown_ = std::move(Edown);
}

const RayScene& HierarchicalRadiosity::rayScene() const { return *impl_->rays; }
double HierarchicalRadiosity::refinementScale() const { return impl_->eRef; }
void HierarchicalRadiosity::setRefinementScale(double eRef) {
  if (eRef > 0 && std::isfinite(eRef)) impl_->eRef = eRef;
}

bool HierarchicalRadiosity::isEmitter(int surface) const {
  return std::max({surfaces_[surface].exitance.x, surfaces_[surface].exitance.y,
                   surfaces_[surface].exitance.z}) > 0.0;
}

bool HierarchicalRadiosity::sourceIsEmitter(int node) const { return impl_->emitterOnly[node] != 0; }

glm::dvec2 HierarchicalRadiosity::toUV(int surface, const glm::dvec3& p) const {
  return impl_->frames[surface].toUV(p);
}

glm::dvec3 HierarchicalRadiosity::toWorld(int surface, glm::dvec2 uv) const {
  return impl_->frames[surface].toWorld(uv);
}

// ----------------------------------------------------------------------------------------------
// Kernels, sampling, visibility

namespace {

// Gauss-Legendre rules on [0,1] for orders 1..8, computed once.
const std::pair<std::vector<double>, std::vector<double>>& gaussRule(int order) {
  static const auto rules = [] {
    std::array<std::pair<std::vector<double>, std::vector<double>>, 9> r;
    for (int k = 1; k <= 8; ++k) gaussLegendre01(k, r[k].first, r[k].second);
    return r;
  }();
  return rules[std::clamp(order, 1, 8)];
}

struct Kernel {
  const HierarchicalRadiosity& h;
  const HierarchicalRadiosity::Impl& im;
  const std::vector<HierarchicalRadiosity::Node>& nodes;
  int order;

  std::vector<glm::dvec3> worldPolygon(int id) const {
    const auto& n = nodes[id];
    const auto clipped = clipToRect(im.uvPolys[n.surface], {n.u0, n.v0}, {n.u1, n.v1});
    std::vector<glm::dvec3> w;
    w.reserve(clipped.size());
    for (const auto& q : clipped) w.push_back(im.frames[n.surface].toWorld(q));
    return w;
  }

  // Quadrature points of an element (inside its polygon) with weights summing to 1. Near
  // sources (closer than about their sizes, such as the wall across a room edge) get a finer rule:
  // the point kernel peaks at a shared edge and a coarse rule would lose that exchange.
  void quadrature(int id, std::vector<glm::dvec3>& pts, std::vector<double>& wts, int near = -1) const {
    const auto& n = nodes[id];
    int q = order;
    if (near >= 0) {
      const auto& s = nodes[near];
      if (glm::length(n.center - s.center) < 1.5f * (n.radius + s.radius)) q = std::max(order, 6);
    }
    const auto& [x, w] = gaussRule(q);
    pts.clear();
    wts.clear();
    double sum = 0;
    const auto& uvp = im.uvPolys[n.surface];
    for (size_t i = 0; i < x.size(); ++i)
      for (size_t j = 0; j < x.size(); ++j) {
        const glm::dvec2 uv(n.u0 + x[i] * (n.u1 - n.u0), n.v0 + x[j] * (n.v1 - n.v0));
        if (!insideConvex2D(uvp, uv, 1e-9)) continue;
        pts.push_back(im.frames[n.surface].toWorld(uv));
        wts.push_back(w[i] * w[j]);
        sum += w[i] * w[j];
      }
    if (pts.empty()) {
      pts.push_back(glm::dvec3(n.center));
      wts.push_back(1.0);
      return;
    }
    for (auto& v : wts) v /= sum;
  }

  // Is the node's bounding box entirely behind the plane (p, n)?
  static bool behind(const HierarchicalRadiosity::Node& b, const glm::dvec3& p, const glm::dvec3& n) {
    for (int k = 0; k < 8; ++k) {
      const glm::dvec3 c((k & 1) ? b.bmax.x : b.bmin.x, (k & 2) ? b.bmax.y : b.bmin.y,
                         (k & 4) ? b.bmax.z : b.bmin.z);
      if (glm::dot(c - p, n) > 1e-9) return false;
    }
    return true;
  }

  // E_receiver += F * B_source (unoccluded); `variation` gets the kernel's spread over the receiver.
  double formFactor(int r, int s, float& variation) const {
    const auto& R = nodes[r];
    const auto& S = nodes[s];
    variation = 0.f;
    if (!R.isCluster() && !S.isCluster()) {
      if (R.surface == S.surface) return 0.0;  // planar polygons do not see themselves
      const PlaneFrame& fr = im.frames[R.surface];
      const PlaneFrame& fs = im.frames[S.surface];
      const EmitterShape& shape = im.shapes[S.surface];
      // A panel that emits from both faces (a two-sided lamp) hangs in the room and receives on
      // both: what reaches its back is absorbed there (lamps reflect nothing; a reflectance would
      // send the two faces' light out of both).
      const bool twoFaced = im.shapes[R.surface].emitsBehind();
      const glm::dvec3 r0 = fr.toWorld({R.u0, R.v0});
      if ((behind(S, r0, fr.normal) && (!twoFaced || behind(S, r0, -fr.normal))) ||
          (behind(R, fs.toWorld({S.u0, S.v0}), fs.normal) &&
           (!shape.emitsBehind() || behind(R, fs.toWorld({S.u0, S.v0}), -fs.normal))))
        return 0.0;
      const auto src = worldPolygon(s);
      std::vector<glm::dvec3> pts;
      std::vector<double> wts;
      quadrature(r, pts, wts, s);
      double f = 0, fmin = 1e300, fmax = 0;
      auto pointFactor = [&](const glm::dvec3& x, const glm::dvec3& n) {
        return shape.distant ? radiosity::distantFormFactor(x, n, src, *shape.distant, false) : emitterFormFactor(x, n, src, shape);
      };
      for (size_t i = 0; i < pts.size(); ++i) {
        const double fi = pointFactor(pts[i], fr.normal) + (twoFaced ? pointFactor(pts[i], -fr.normal) : 0.0);
        f += wts[i] * fi;
        fmin = std::min(fmin, fi);
        fmax = std::max(fmax, fi);
      }
      variation = float(pts.size() > 1 ? fmax - fmin : f);
      // A source close in front of a large receiver (a lamp 2 cm below a ceiling) lights a patch
      // the receiver's points can miss altogether: then the kernel's peak (straight above the
      // source) bounds the error, so that the oracle refines the receiver there.
      const glm::dvec3 sc(S.center);
      const double dPlane = glm::dot(sc - fr.toWorld({R.u0, R.v0}), fr.normal);
      if (dPlane > 1e-6 && dPlane < 0.5 * R.radius) {
        const glm::dvec2 uv = fr.toUV(sc);
        const double m = S.radius;
        if (uv.x > R.u0 - m && uv.x < R.u1 + m && uv.y > R.v0 - m && uv.y < R.v1 + m)
          variation = std::max(variation, float(std::min(shape.peak, shape.peak * S.area / (kPi * dPlane * dPlane))));
      }
      // A beam through an opening lights the opening's outline cast along it onto the receiver's
      // plane: its share of the element's area, exactly (the points above would quantise the edges).
      // Where the outline crosses the element, the beam's whole kernel is the oracle's error.
      if (shape.distant)
        for (const auto& beam : shape.distant->beams) {
          const double c = twoFaced ? std::abs(glm::dot(fr.normal, beam.direction)) : glm::dot(fr.normal, beam.direction);
          if (!(c > 0) || !(beam.irradiance > 0) || glm::dot(beam.direction, fs.normal) >= 0) continue;
          const glm::dvec3 o = fr.toWorld({R.u0, R.v0});
          std::vector<glm::dvec2> cast;
          const double cn = glm::dot(fr.normal, beam.direction);  // (signed: the cast along the beam onto the plane)
          for (const auto& v : src) cast.push_back(fr.toUV(v - beam.direction * (glm::dot(fr.normal, v - o) / cn)));
          if (polygonArea2D(cast) < 0) std::reverse(cast.begin(), cast.end());
          cast = clipToRect(cast, {R.u0, R.v0}, {R.u1, R.v1});
          cast = clipConvex2D(cast, im.uvPolys[R.surface]);
          const double share = std::clamp(std::abs(polygonArea2D(cast)) / std::max(1e-300, double(R.area)), 0.0, 1.0);
          const double k = beam.irradiance * c / kPi;
          f += share * k;
          if (share > 1e-6 && share < 1 - 1e-6) variation = std::max(variation, float(k));
        }
      return f;
    }
    // With a cluster at either end the kernel is an isotropic estimate; the oracle gets its bound
    // with every cosine taken as 1 (a surface in the cluster may face the other end squarely).
    double f = 0, bound = 0;
    if (!R.isCluster()) {  // element <- cluster (isotropic source: intensity = power / 4 pi)
      const PlaneFrame& fr = im.frames[R.surface];
      const bool twoFaced = im.shapes[R.surface].emitsBehind();
      if (!twoFaced && behind(S, glm::dvec3(R.center), fr.normal)) return 0.0;
      std::vector<glm::dvec3> pts;
      std::vector<double> wts;
      quadrature(r, pts, wts);
      for (size_t i = 0; i < pts.size(); ++i) {
        const glm::dvec3 d = glm::dvec3(S.center) - pts[i];
        const double d2 = glm::dot(d, d);
        const double cos = glm::dot(d, fr.normal) / std::sqrt(d2), cr = twoFaced ? std::abs(cos) : std::max(0.0, cos);
        f += wts[i] * S.area * cr / (4.0 * kPi * d2);
        bound = std::max(bound, S.area / (kPi * d2));
      }
    } else if (!S.isCluster() && im.shapes[S.surface].distant) {  // cluster <- opening
      // An isotropic receiver gathers a quarter of the radiance over the solid angle.
      const glm::dvec3 rc(R.center);
      f = 0.25 * distantSolidAngleFactor(rc, worldPolygon(s), *im.shapes[S.surface].distant);
      bound = 4.0 * f;
    } else if (!S.isCluster()) {  // cluster <- element (isotropic receiver: mean cosine 1/4)
      const PlaneFrame& fs = im.frames[S.surface];
      const EmitterShape& shape = im.shapes[S.surface];
      if (!shape.emitsBehind() && behind(R, glm::dvec3(S.center), fs.normal)) return 0.0;
      const glm::dvec3 d = glm::dvec3(R.center) - glm::dvec3(S.center);
      const double d2 = glm::dot(d, d);
      const double c = glm::dot(d, fs.normal) / std::sqrt(d2);
      const double cs = (shape.emitsBehind() ? std::abs(c) : std::max(0.0, c)) * shape.weight(glm::dvec3(R.center));
      f = S.area * cs / (4.0 * kPi * d2);
      // A photometric source may send up to `peak` times a Lambertian face's light to any part of
      // the cluster, not only towards its centre.
      bound = S.area * (shape.photometry ? std::max(cs, shape.peak) : cs) / (kPi * d2);
    } else {
      const glm::dvec3 d = glm::dvec3(R.center) - glm::dvec3(S.center);
      f = S.area / (16.0 * kPi * glm::dot(d, d));
      bound = S.area / (kPi * glm::dot(d, d));
    }
    variation = float(bound);
    return f;
  }

  // N stratified, jittered sample points on a node's surfaces (lifted off them along the normal).
  // `surfaces` (when given): each point's surface (-1 for a cluster's centre).
  void samplePoints(int id, int count, Rng& rng, std::vector<glm::vec3>& out, std::vector<glm::vec3>& normals,
                    std::vector<int>* surfaces = nullptr) const {
    out.clear();
    normals.clear();
    if (surfaces) surfaces->clear();
    const auto& n = nodes[id];
    const int g = std::max(1, int(std::ceil(std::sqrt(double(count)))));
    // Strata visited in a random order so that the pairing of two nodes' points decorrelates.
    thread_local std::vector<int> strata;
    strata.resize(size_t(g) * g);
    std::iota(strata.begin(), strata.end(), 0);
    for (size_t i = strata.size(); i > 1; --i) std::swap(strata[i - 1], strata[rng.next() % i]);
    // An element whose rectangle lies inside its (convex) polygon needs no test per point.
    const bool wholeRect = !n.isCluster() && rectInsidePolygon(n);
    // A cluster's surfaces by area: their running sum, once (a cluster of a mesh holds thousands).
    thread_local std::vector<double> running;
    thread_local std::vector<int> runningSurface;
    double total = 0;
    if (n.isCluster()) {
      running.clear();
      runningSurface.clear();
      const int begin = im.rangeBegin[id], cnt = im.rangeCount[id];
      for (int i = 0; i < cnt; ++i) {
        const int c = im.perm[begin + i];
        if (im.surfaceArea[c] <= 0) continue;  // removed surfaces (no area) are never chosen
        total += im.surfaceArea[c];
        running.push_back(total);
        runningSurface.push_back(c);
      }
    }
    for (int k = 0; k < count; ++k) {
      const int st = strata[k % strata.size()];
      const double a = (st % g + rng.uniform()) / g, b = (st / g + rng.uniform()) / g;
      if (!n.isCluster()) {
        out.push_back(pointOnElement(id, a, b, rng, wholeRect));
        normals.push_back(glm::vec3(im.frames[n.surface].normal));
        if (surfaces) surfaces->push_back(n.surface);
      } else {
        // Surface chosen by area with the first coordinate, point on it with the second + fresh.
        int s = -1;
        if (!running.empty()) {
          const size_t i = size_t(std::upper_bound(running.begin(), running.end(), a * total) - running.begin());
          s = runningSurface[std::min(i, running.size() - 1)];
        }
        if (s < 0) {
          out.push_back(n.center);
          normals.emplace_back(0.f, 0.f, 1.f);
          if (surfaces) surfaces->push_back(-1);
          continue;
        }
        out.push_back(pointOnSurface(s, b, rng.uniform()));
        normals.push_back(glm::vec3(im.frames[s].normal));
        if (surfaces) surfaces->push_back(s);
      }
    }
  }

  bool rectInsidePolygon(const HierarchicalRadiosity::Node& n) const {
    // The far corners as pointOnElement reaches them (u0 + the float width), which may round past u1.
    const auto& uvp = im.uvPolys[n.surface];
    const double u0 = n.u0, v0 = n.v0, u1 = u0 + double(n.u1 - n.u0), v1 = v0 + double(n.v1 - n.v0);
    return insideConvex2D(uvp, {u0, v0}, 1e-9) && insideConvex2D(uvp, {u1, v0}, 1e-9) &&
           insideConvex2D(uvp, {u1, v1}, 1e-9) && insideConvex2D(uvp, {u0, v1}, 1e-9);
  }

  // `wholeRect`: the element's rectangle lies inside its polygon (rectInsidePolygon).
  glm::vec3 pointOnElement(int id, double a, double b, Rng& rng, bool wholeRect) const {
    const auto& n = nodes[id];
    const auto& uvp = im.uvPolys[n.surface];
    glm::dvec2 uv(n.u0 + a * (n.u1 - n.u0), n.v0 + b * (n.v1 - n.v0));
    bool inside = wholeRect || insideConvex2D(uvp, uv, 1e-9);
    for (int tries = 0; tries < 8 && !inside; ++tries) {
      uv = {n.u0 + rng.uniform() * (n.u1 - n.u0), n.v0 + rng.uniform() * (n.v1 - n.v0)};
      inside = insideConvex2D(uvp, uv, 1e-9);
    }
    if (!inside) uv = im.frames[n.surface].toUV(glm::dvec3(n.center));
    const PlaneFrame& f = im.frames[n.surface];
    return glm::vec3(f.toWorld(uv) + f.normal * double(kNormalOffset));
  }

  glm::vec3 pointOnSurface(int s, double a, double b) const {
    const auto& v = h.surfaces()[s].vertices;
    const auto& cdf = im.fanCdf[s];
    double t = a * cdf.back();
    size_t tri = std::lower_bound(cdf.begin(), cdf.end(), t) - cdf.begin();
    tri = std::min(tri, cdf.size() - 1);
    const double lo = tri ? cdf[tri - 1] : 0.0;
    double u = (t - lo) / std::max(1e-300, cdf[tri] - lo), w = b;
    if (u + w > 1) {
      u = 1 - u;
      w = 1 - w;
    }
    const glm::dvec3 p = v[0] + u * (v[tri + 1] - v[0]) + w * (v[tri + 2] - v[0]);
    return glm::vec3(p + im.frames[s].normal * double(kNormalOffset));
  }

  // A sample point on a surface that receives or emits on both faces (a two-sided lamp), moved to
  // its back face when `towards` (the other end's direction) lies behind its front.
  void toFacingSide(int surface, const glm::vec3& towards, glm::vec3& p, glm::vec3& n) const {
    if (surface < 0 || !im.shapes[size_t(surface)].emitsBehind() || glm::dot(towards, n) > 0.f) return;
    p -= 2.f * kNormalOffset * n;
    n = -n;
  }

  // A parallel beam through an opening's element s: the fraction of r's sample points, among those
  // whose ray towards the source crosses s, that nothing blocks on the way to it.
  float beamVisibility(int r, int s, int rays, Rng& rng) const {
    thread_local std::vector<glm::vec3> a, na, fa, fb;
    thread_local std::vector<int> sa;
    samplePoints(r, rays, rng, a, na, &sa);
    const auto& S = nodes[s];
    const glm::dvec3 d = im.shapes[S.surface].distant->beams[0].direction;
    const PlaneFrame& f = im.frames[S.surface];
    const auto& uvp = im.uvPolys[S.surface];
    fa.clear();
    fb.clear();
    for (size_t i = 0; i < a.size(); ++i) {
      toFacingSide(sa[i], glm::vec3(d), a[i], na[i]);  // (a two-faced receiver's back towards the beam)
      const glm::dvec3 p(a[i]);
      if (glm::dot(glm::dvec3(na[i]), d) <= 0.0 || glm::dot(d, f.normal) >= 0.0) continue;
      const double t = glm::dot(f.normal, f.toWorld({S.u0, S.v0}) - p) / glm::dot(d, f.normal);
      if (!(t > 0)) continue;
      const glm::dvec3 x = p + t * d;
      const glm::dvec2 uv = f.toUV(x);
      if (uv.x < S.u0 || uv.x > S.u1 || uv.y < S.v0 || uv.y > S.v1 || !insideConvex2D(uvp, uv, 1e-9)) continue;
      fa.push_back(a[i]);
      fb.push_back(glm::vec3(x));
    }
    if (fa.empty()) return 1.f;
    return im.rays->visibility(fa, fb, 1e-5f);
  }

  // Fraction of unblocked ray pairs among the pairs whose ends face each other: a pair with an
  // end behind the other's surface carries no light, which the form factor already accounts for
  // (it is clipped to each point's hemisphere), so counting it as blocked would darken twice.
  float visibility(int r, int s, int rays, uint32_t seed) const {
    Rng rng((uint64_t(uint32_t(r)) << 32 | uint32_t(s)) * 0x2545F4914F6CDD1Dull + seed);
    thread_local std::vector<glm::vec3> a, b, na, nb, fa, fb;
    thread_local std::vector<int> sb;
    const auto& S = nodes[s];
    if (!S.isCluster() && im.shapes[S.surface].distant && !im.shapes[S.surface].distant->radiance &&
        im.shapes[S.surface].distant->beams.size() == 1)
      return beamVisibility(r, s, rays, rng);
    thread_local std::vector<int> sa;
    samplePoints(r, rays, rng, a, na, &sa);
    samplePoints(s, rays, rng, b, nb, &sb);
    fa.clear();
    fb.clear();
    for (size_t i = 0; i < a.size(); ++i) {
      // Either end on a two-faced surface with the other end behind it: its back face's point.
      toFacingSide(sa[i], b[i] - a[i], a[i], na[i]);
      toFacingSide(sb[i], a[i] - b[i], b[i], nb[i]);
      const glm::vec3 d = b[i] - a[i];
      if (glm::dot(d, na[i]) > 0.f && glm::dot(d, nb[i]) < 0.f) {
        fa.push_back(a[i]);
        fb.push_back(b[i]);
      }
    }
    if (fa.empty()) return 1.f;  // no facing pair: the form factor is (nearly) zero anyway
    return im.rays->visibility(fa, fb, 1e-5f);
  }
};

VisibilityType classify(float v) {
  return v >= 1.f ? VisibilityType::Visible : (v <= 0.f ? VisibilityType::Invisible : VisibilityType::Partial);
}

}  // namespace

// ----------------------------------------------------------------------------------------------
// Refinement

enum class Open { None, Receiver, Source };

struct RefineContext {
  HierarchicalRadiosity& h;
  HierarchicalRadiosity::Impl& im;
  bool useOracle = true;
  std::function<Open(const HierarchicalRadiosity::Link&)> force;
  size_t keep = 0;  // links_[0, keep) are kept as they are, unexamined
};

namespace {

bool canSubdivide(const HierarchicalRadiosity::Node& n, double minArea) {
  if (n.isCluster()) return true;
  if (n.subdivided) return n.childCount > 0;
  const double rectArea = double(n.u1 - n.u0) * double(n.v1 - n.v0);
  const float du = n.u1 - n.u0, dv = n.v1 - n.v0;
  const int parts = (dv > 2 * du || du > 2 * dv) ? 2 : 4;
  return rectArea / parts >= minArea;
}

}  // namespace

// Refines links_ breadth-first; returns whether any link was replaced.
bool refineLinks(RefineContext& ctx, Progress& progress) {
  auto& h = ctx.h;
  auto& im = ctx.im;
  const Options& opt = h.options_;
  Builder builder{h, im};
  const double threshold = opt.epsilon * im.eRef;
  // Clusters holding a lamp with a photometric distribution or an opening's distant light: their
  // isotropic estimate cannot stand for a beam, so links from them are always opened (down to
  // the emitter's own elements).
  std::vector<uint8_t> beamBelow(h.nodes_.size(), 0);
  for (size_t n = h.nodes_.size(); n-- > 1;) {
    const auto& N = h.nodes_[n];
    if (!N.isCluster() && (im.shapes[N.surface].photometry || im.shapes[N.surface].distant) &&
        h.isEmitter(N.surface))
      beamBelow[n] = 1;
    if (beamBelow[n] && N.parent >= 0) beamBelow[N.parent] = 1;
  }
  // Per node the largest reflected radiosity of any element below it. A link carries its source's
  // mean radiosity with one visibility; where a small, very bright patch sits in a larger source
  // (the ceiling 2 cm above a two-sided lamp, most of whose light falls back on the lamp) the mean
  // hides it, and light that the lamp stops would reach the room. The oracle bounds such a link's
  // error with the brightest patch, and opens the source.
  std::vector<float> reflMax(h.nodes_.size(), 0.f);
  for (size_t n = h.nodes_.size(); n-- > 0;) {
    const auto& N = h.nodes_[n];
    if (N.isLeaf() && !N.isCluster()) reflMax[n] = std::max(reflMax[n], maxc(glm::max(h.B_[n] - im.emit[n], glm::vec3(0.f))));
    if (N.parent >= 0) reflMax[size_t(N.parent)] = std::max(reflMax[size_t(N.parent)], reflMax[n]);
  }
  // The smallest element a link may cut its receiver into. Within a lamp's near field (a ceiling
  // 2 cm above a two-sided lamp) the light it receives falls from the lamp's full exitance to a
  // fraction across a few times that distance at the lamp's outline; an element wider than that
  // carries its mean past the outline, where the light it sends on is not stopped by the lamp. So
  // near an emitter an element may be cut down to the square of its centre's distance from the
  // emitter element's bounding box (no finer than a sixteenth of minArea).
  auto receiverMinArea = [&](const HierarchicalRadiosity::Node& R, const HierarchicalRadiosity::Node& S) {
    if (R.isCluster() || S.isCluster() || !h.isEmitter(S.surface) || im.shapes[S.surface].distant) return opt.minArea;
    const glm::dvec3 c(R.center), gap = glm::max(glm::dvec3(S.bmin) - c, glm::max(c - glm::dvec3(S.bmax), glm::dvec3(0.0)));
    const double d2 = glm::dot(gap, gap);  // from R's centre to S's bounding box
    return std::clamp(d2, opt.minArea / 16, opt.minArea);
  };
  bool changed = false;
  std::vector<HierarchicalRadiosity::Link> frontier, next, finals;
  const size_t keep = std::min(ctx.keep, h.links_.size());
  finals.assign(h.links_.begin(), h.links_.begin() + std::ptrdiff_t(keep));
  frontier.assign(h.links_.begin() + std::ptrdiff_t(keep), h.links_.end());
  // links_ stays as it was until the end: a Cancel (or any error) midway leaves the old links.
  auto computeVisibility = [&](std::vector<HierarchicalRadiosity::Link>& ls) {
    Kernel k{h, im, h.nodes_, opt.quadratureOrder};
    tbb::parallel_for(tbb::blocked_range<size_t>(0, ls.size(), 16), [&](const tbb::blocked_range<size_t>& rg) {
      progress.poll();  // many links take seconds: answer Cancel between chunks
      for (size_t i = rg.begin(); i < rg.end(); ++i) {
        auto& l = ls[i];
        if (l.visibility != kUnknownVisibility || l.receiver == l.source) continue;
        l.visibility = k.visibility(l.receiver, l.source, opt.visibilityRays, opt.seed);
        l.type = classify(l.visibility);
      }
    });
  };
  int pass = 0;
  while (!frontier.empty()) {
    progress.report(std::min(0.9, 0.1 * pass), "refining links (" + std::to_string(frontier.size()) +
                                                  " to examine, " + std::to_string(finals.size()) + " kept)");
    if (opt.oracle == Oracle::BFV) computeVisibility(frontier);
    next.clear();
    for (const auto& l : frontier) {
      const auto& R = h.nodes_[l.receiver];
      const auto& S = h.nodes_[l.source];
      if (l.receiver == l.source) {
        changed = true;
        if (!R.isCluster()) continue;
        const int cb = R.childBegin, cc = R.childCount;
        for (int i = 0; i < cc; ++i)
          for (int j = 0; j < cc; ++j) {
            const int a = h.children_[cb + i], b = h.children_[cb + j];
            next.push_back({a, b, 0.f, kUnknownVisibility, 0.f, VisibilityType::Visible});
          }
        continue;
      }
      Open open = ctx.force ? ctx.force(l) : Open::None;
      if (open == Open::None && ctx.useOracle) {
        const bool clusterEnd = R.isCluster() || S.isCluster();
        const float dist = glm::length(R.center - S.center);
        // An opening's light is directional: no isotropic cluster stands for it at either end.
        const bool overlap = (clusterEnd && dist < R.radius + S.radius) || (S.isCluster() && beamBelow[l.source]) ||
                             (R.isCluster() && !S.isCluster() && im.shapes[S.surface].distant);
        double kernelError = l.variation;
        if (opt.oracle == Oracle::BFV)
          kernelError = l.type == VisibilityType::Partial ? l.formFactor : l.visibility * l.variation;
        // (Nodes made during this pass are leaves whose brightest patch is their own.)
        const double bMean = maxc(h.B_[l.source]);
        const double bPeak = size_t(l.source) < reflMax.size() ? std::max(bMean, double(reflMax[size_t(l.source)])) : bMean;
        // A source whose brightest patch outshines its mean by far (and is already cut into
        // pieces) is the error's cause: it is opened, not the receiver; how much of the patch's
        // light gets through is unknown at this level, so the whole factor bounds the error.
        const bool hotSource = !S.isLeaf() && bPeak > 1.5 * bMean && !S.isCluster();
        if (hotSource) kernelError = std::max(kernelError, double(l.formFactor));
        // A two-faced lamp reflects nothing, but what it receives is what it absorbs (the light
        // falling back on it from the ceiling 2 cm above): while it shines, its links are refined
        // as a white receiver's, so that the room's energy closes (a dark one, as the daylight
        // basis keeps its lamps, is not worth the links).
        const bool absorber = !R.isCluster() && im.shapes[R.surface].emitsBehind() && h.isEmitter(R.surface);
        const double err = double(absorber ? 1.f : im.rhoMax[l.receiver]) * bPeak * kernelError;
        if (overlap || err > threshold) {
          const bool rOk = canSubdivide(R, receiverMinArea(R, S)), sOk = canSubdivide(S, opt.minArea);
          // A cluster end is opened first: its isotropic estimate is the error being bounded, and
          // splitting the other end instead would only spread that error over many small links.
          // Between two elements (or two clusters) the larger is subdivided.
          if (R.isCluster() != S.isCluster()) open = R.isCluster() ? Open::Receiver : Open::Source;
          else if (hotSource && 4.0 * S.area >= R.area) open = Open::Source;
          else if (rOk && (!sOk || R.area >= S.area)) open = Open::Receiver;
          else if (sOk) open = Open::Source;
        }
      }
      if (open == Open::None) {
        finals.push_back(l);
        continue;
      }
      const int node = open == Open::Receiver ? l.receiver : l.source;
      if (!h.nodes_[node].isCluster()) builder.subdivide(node);
      const auto& N = h.nodes_[node];
      if (N.childCount == 0) {
        finals.push_back(l);
        continue;
      }
      changed = true;
      for (int i = 0; i < N.childCount; ++i) {
        const int c = h.children_[N.childBegin + i];
        if (open == Open::Receiver) next.push_back({c, l.source, 0.f, kUnknownVisibility, 0.f, VisibilityType::Visible});
        else next.push_back({l.receiver, c, 0.f, kUnknownVisibility, 0.f, VisibilityType::Visible});
      }
    }
    // Form factors of the new links (parallel; nodes are not modified here); drop empty ones.
    {
      Kernel k{h, im, h.nodes_, opt.quadratureOrder};
      tbb::parallel_for(tbb::blocked_range<size_t>(0, next.size(), 64), [&](const tbb::blocked_range<size_t>& rg) {
        for (size_t i = rg.begin(); i < rg.end(); ++i)
          if (next[i].receiver != next[i].source)
            next[i].formFactor = float(k.formFactor(next[i].receiver, next[i].source, next[i].variation));
      });
    }
    frontier.clear();
    // A link is dropped only when no light can pass (both factor and bound are zero): an isotropic
    // cluster estimate may be zero (its centre behind the receiver) while part of it is in front.
    for (const auto& l : next)
      if (l.receiver == l.source || l.formFactor > 0.f || l.variation > 0.f) frontier.push_back(l);
    ++pass;
  }
  computeVisibility(finals);
  h.links_ = std::move(finals);
  im.gatherDirty = true;
  return changed;
}

// ----------------------------------------------------------------------------------------------
// Gather, push-pull, iteration

namespace {
void buildGather(const std::vector<HierarchicalRadiosity::Link>& links, HierarchicalRadiosity::Impl& im) {
  // Grouped by receiver with a counting sort (links in their own order within a receiver):
  // linear in the links, so a geometry edit does not pay for a comparison sort of them all.
  const size_t nn = im.rho.size();
  std::vector<uint32_t> start(nn + 1, 0);
  for (const auto& l : links)
    if (l.formFactor * l.visibility > 0.f) ++start[size_t(l.receiver) + 1];
  for (size_t i = 0; i < nn; ++i) start[i + 1] += start[i];
  const size_t total = start[nn];
  im.gRecv.assign(total, 0);
  im.gSrc.assign(total, 0);
  im.gK.assign(total, 0.f);
  for (const auto& l : links) {
    const float k = l.formFactor * l.visibility;
    if (k <= 0.f) continue;
    const uint32_t p = start[size_t(l.receiver)]++;
    im.gRecv[p] = l.receiver;
    im.gSrc[p] = l.source;
    im.gK[p] = k;
  }
  im.gChunk.clear();
  const size_t n = im.gRecv.size(), step = std::max<size_t>(4096, n / 64);
  for (size_t i = 0; i < n;) {
    im.gChunk.push_back(i);
    size_t j = std::min(n, i + step);
    while (j < n && im.gRecv[j] == im.gRecv[j - 1]) ++j;  // a receiver's links stay in one chunk
    i = j;
  }
  im.gChunk.push_back(n);
  im.gatherDirty = false;
}
}  // namespace

// Push the gathered irradiance E_ down, set the leaves' radiosity, pull it up area-weighted.
// Returns max |dB| on leaves over the mean radiosity of non-emitting leaves.
double HierarchicalRadiosity::pushPull() {
  auto& im = *impl_;
  const size_t nn = nodes_.size();
  std::vector<float>& acc = im.pullAccumulator;
  acc.assign(nn * 3, 0.f);
  double maxDelta = 0, sumB = 0, sumA = 0;
  Edown_[0] = E_[0];
  for (size_t n = 1; n < nn; ++n) Edown_[n] = Edown_[nodes_[n].parent] + E_[n];
  for (size_t n = nn; n-- > 0;) {
    const Node& N = nodes_[n];
    glm::vec3 b;
    if (N.isLeaf()) {
      b = im.emit[n] + im.rho[n] * Edown_[n];
      maxDelta = std::max(maxDelta, double(maxc(glm::abs(b - B_[n]))));
      if (maxc(im.emit[n]) <= 0.f) {
        sumB += double(maxc(b)) * N.area;
        sumA += N.area;
      }
    } else {
      b = N.area > 0 ? glm::vec3(acc[3 * n], acc[3 * n + 1], acc[3 * n + 2]) / N.area : glm::vec3(0.f);
    }
    B_[n] = b;
    if (N.parent >= 0) {
      // A cluster's radiosity is its power over its area: a two-sided emitter gives it both faces'.
      const float w = N.surface >= 0 && nodes_[N.parent].isCluster() ? float(impl_->shapes[N.surface].faces()) : 1.f;
      float* a = &acc[3 * size_t(N.parent)];
      a[0] += w * N.area * b.x;
      a[1] += w * N.area * b.y;
      a[2] += w * N.area * b.z;
    }
  }
  const double mean = sumA > 0 ? sumB / sumA : 0.0;
  return mean > 0 ? maxDelta / mean : (maxDelta > 0 ? 1.0 : 0.0);
}

void HierarchicalRadiosity::clearSolution() {
  std::fill(E_.begin(), E_.end(), glm::vec3(0.f));
  std::fill(B_.begin(), B_.end(), glm::vec3(0.f));
  pushPull();
}

SolveStats HierarchicalRadiosity::iterate(Progress& progress) {
  auto& im = *impl_;
  const auto t0 = std::chrono::steady_clock::now();
  if (im.gatherDirty) buildGather(links_, im);
  const size_t nn = nodes_.size();
  B_.resize(nn);
  E_.resize(nn);
  Edown_.resize(nn);
  SolveStats st;
  // Jacobi's error shrinks per sweep by the largest eigenvalue lambda of the sweep's operator
  // (rho F, per colour channel); in a bright room lambda is near 1 (0.96 at rho 0.98: some 160
  // sweeps to the tolerance) and the error left when the steps are small is step x lambda /
  // (1 - lambda). Once the last steps are parallel (one mode left) and shrink at a steady rate,
  // that remainder is added at once (Lyusternik's extrapolation); the sweeps after it go on from
  // there, and a stop is decided only on a plain sweep's step.
  std::vector<glm::vec3> before(nn), last(nn, glm::vec3(0.f));  // B before a sweep; the last sweep's change
  glm::dvec3 lastRate(-1.0);
  glm::ivec3 plainSteps(0);  // per channel: sweeps since the start or its last extrapolation
  for (int it = 0; it < options_.maxIterations; ++it) {
    before = B_;
    // Gather: E_r = sum over links of F V B_s.
    std::fill(E_.begin(), E_.end(), glm::vec3(0.f));
    tbb::parallel_for(size_t(0), im.gChunk.size() - 1, [&](size_t c) {
      const size_t end = im.gChunk[c + 1];
      for (size_t i = im.gChunk[c]; i < end;) {
        const int r = im.gRecv[i];
        glm::vec3 e(0.f);
        for (; i < end && im.gRecv[i] == r; ++i) e += im.gK[i] * B_[im.gSrc[i]];
        E_[r] = e;
      }
    });
    st.residual = pushPull();
    st.iterations = it + 1;
    if (st.residual <= options_.tolerance || it + 1 == options_.maxIterations) break;  // (never on a jump)
    if ((it & 7) == 7) progress.poll();  // (a Cancel leaves a plain sweep's state)
    // This sweep's step against the last one's, per channel.
    glm::dvec3 dot(0.0), now(0.0), prev(0.0);
    for (size_t n = 0; n < nn; ++n) {
      const glm::dvec3 d(B_[n] - before[n]), p(last[n]);
      dot += d * p;
      now += d * d;
      prev += p * p;
      last[n] = glm::vec3(d);
    }
    // Each channel on its own (their rates differ with the albedos' colour). The rate must hold
    // to a tenth of the gain's sensitivity: d(gain) / gain = d(rate) / (rate (1 - rate)).
    glm::vec3 gain(0.f);
    bool any = false;
    for (int c = 0; c < 3; ++c) {
      ++plainSteps[c];
      if (!(now[c] > 0.0) || !(prev[c] > 0.0)) {  // (a channel already still: nothing to add)
        lastRate[c] = -1.0;
        continue;
      }
      const double rate = dot[c] / prev[c], cosine = dot[c] / std::sqrt(now[c] * prev[c]);
      const bool steady = plainSteps[c] >= 3 && cosine > 0.999 && rate > 0.5 && rate < 0.99 &&
                          std::abs(rate - lastRate[c]) <= 0.1 * rate * (1.0 - rate);
      lastRate[c] = rate;
      if (!steady) continue;
      gain[c] = float(rate / (1.0 - rate));
      plainSteps[c] = 0;
      lastRate[c] = -1.0;
      any = true;
    }
    if (any)
      for (size_t n = 0; n < nn; ++n) B_[n] += gain * last[n];
  }
  im.lastIterations = st.iterations;
  im.lastSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return st;
}

SolveStats HierarchicalRadiosity::solve(Progress& progress) {
  auto& im = *impl_;
  const auto t0 = std::chrono::steady_clock::now();
  im.raysAtStart = im.rays->raysCast();
  // Scale of the problem: mean first-bounce irradiance (emitted power over receiving area).
  double power = 0, area = 0;
  for (size_t s = 0; s < surfaces_.size(); ++s) {
    const double a = im.surfaceArea[s];
    const auto& e = surfaces_[s].exitance;
    power += im.shapes[s].faces() * a * std::max({e.x, e.y, e.z});
    if (!isEmitter(int(s))) area += a;
  }
  im.eRef = area > 0 && power > 0 ? power / area : 1.0;
  // Start from emission only: no irradiance anywhere, radiosity pulled up from the leaves.
  std::fill(E_.begin(), E_.end(), glm::vec3(0.f));
  std::fill(B_.begin(), B_.end(), glm::vec3(0.f));
  pushPull();
  SolveStats st;
  RefineContext ctx{*this, im, true, nullptr};
  for (int round = 0; round < options_.maxRefineRounds; ++round) {
    progress.report(double(round) / options_.maxRefineRounds, "refinement round " + std::to_string(round + 1));
    const bool changed = refineLinks(ctx, progress);
    st = iterate(progress);
    if (!changed) break;
  }
  im.lastSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  progress.report(1.0, "solved");
  return st;
}

void HierarchicalRadiosity::setExitance(int surface, const glm::dvec3& exitance) {
  surfaces_[surface].exitance = exitance;
  const glm::vec3 e(exitance);
  forSubtree(nodes_, children_, surfaceRoot_[surface], [&](int n) { impl_->emit[n] = e; });
}

void HierarchicalRadiosity::setReflectance(int surface, const glm::dvec3& reflectance) {
  surfaces_[surface].reflectance = reflectance;
  const glm::vec3 r(reflectance);
  forSubtree(nodes_, children_, surfaceRoot_[surface], [&](int n) {
    impl_->rho[n] = r;
    impl_->rhoMax[n] = maxc(r);
  });
}

size_t HierarchicalRadiosity::setDistantLight(int surface, std::shared_ptr<const DistantLight> light) {
  auto& im = *impl_;
  auto beamOnly = [](const std::shared_ptr<const DistantLight>& d) {
    return d && !d->radiance && d->beams.size() == 1;
  };
  // V is taken along the beam for a single beam, towards the whole element otherwise.
  for (size_t s = im.beamVisibility.size(); s < surfaces_.size(); ++s)
    im.beamVisibility.push_back(beamOnly(surfaces_[s].distant) ? 1 : 0);
  const bool newVisibility = beamOnly(light) || im.beamVisibility[size_t(surface)];
  im.beamVisibility[size_t(surface)] = beamOnly(light) ? 1 : 0;
  surfaces_[surface].distant = std::move(light);
  im.shapes[surface] = EmitterShape(surfaces_[surface].vertices, surfaces_[surface].twoSided,
                                    surfaces_[surface].photometry, surfaces_[surface].distant);
  std::vector<uint8_t> below(nodes_.size(), 0);
  forSubtree(nodes_, children_, surfaceRoot_[surface], [&](int n) { below[n] = 1; });
  std::vector<int> work;
  for (size_t i = 0; i < links_.size(); ++i)
    if (below[links_[i].source] && links_[i].receiver != links_[i].source) work.push_back(int(i));
  Kernel k{*this, im, nodes_, options_.quadratureOrder};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, work.size(), 8), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t j = r.begin(); j < r.end(); ++j) {
      Link& l = links_[work[j]];
      l.formFactor = float(k.formFactor(l.receiver, l.source, l.variation));
      if (newVisibility) {
        l.visibility = k.visibility(l.receiver, l.source, options_.visibilityRays, options_.seed);
        l.type = classify(l.visibility);
      }
    }
  });
  im.gatherDirty = true;
  return work.size();
}

std::vector<glm::vec4> HierarchicalRadiosity::splitRects(int element) const {
  const Node& n = nodes_[element];
  const float du = n.u1 - n.u0, dv = n.v1 - n.v0;
  const int nu = dv > 2 * du ? 1 : 2, nv = du > 2 * dv ? 1 : 2;
  std::vector<glm::vec4> out;
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i)
      out.emplace_back(n.u0 + du * i / nu, n.v0 + dv * j / nv, i + 1 == nu ? n.u1 : n.u0 + du * (i + 1) / nu,
                       j + 1 == nv ? n.v1 : n.v0 + dv * (j + 1) / nv);
  return out;
}

void HierarchicalRadiosity::subdivideElements(const std::vector<int>& elements) {
  Builder b{*this, *impl_};
  for (int e : elements)
    if (!nodes_[e].isCluster() && nodes_[e].isLeaf()) b.subdivide(e);
  impl_->gatherDirty = true;
}

void HierarchicalRadiosity::setElementReflectance(int node, const glm::dvec3& reflectance) {
  const glm::vec3 r(reflectance);
  forSubtree(nodes_, children_, node, [&](int n) {
    impl_->rho[n] = r;
    impl_->rhoMax[n] = maxc(r);
  });
}

const glm::vec3& HierarchicalRadiosity::reflectanceOf(int node) const { return impl_->rho[node]; }

void HierarchicalRadiosity::pushLampLinksToLeaves(Progress& progress) {
  RefineContext ctx{*this, *impl_, false, nullptr};
  ctx.force = [this](const Link& l) {
    if (!sourceIsEmitter(l.source)) return Open::None;
    return nodes_[l.receiver].isLeaf() ? Open::None : Open::Receiver;
  };
  // Only open existing children: an element leaf stays a leaf (no new subdivision here).
  refineLinks(ctx, progress);
}

void HierarchicalRadiosity::forceRefine(const std::vector<int>& receiverSurfaces,
                                        const std::vector<int>& sourceSurfaces, Progress& progress) {
  auto& im = *impl_;
  std::vector<uint8_t> isRecv(surfaces_.size(), 0), isSrc(surfaces_.size(), 0);
  for (int s : receiverSurfaces) isRecv[s] = 1;
  for (int s : sourceSurfaces) isSrc[s] = 1;
  auto within = [&](int node, const std::vector<uint8_t>& set, bool all) {
    const Node& n = nodes_[node];
    if (!n.isCluster()) return set[n.surface] != 0;
    bool any = false, every = true;
    for (int i = 0; i < im.rangeCount[node]; ++i) {
      const bool in = set[im.perm[im.rangeBegin[node] + i]] != 0;
      any = any || in;
      every = every && in;
    }
    return all ? every : any;
  };
  RefineContext ctx{*this, im, true, nullptr};
  ctx.force = [&](const Link& l) {
    if (nodes_[l.receiver].isCluster() && within(l.source, isSrc, true) && within(l.receiver, isRecv, false))
      return Open::Receiver;
    return Open::None;
  };
  refineLinks(ctx, progress);
  iterate(progress);
}

size_t HierarchicalRadiosity::translateSurfaces(const std::vector<int>& moved, const glm::dvec3& offset) {
  return moveSurfaces(moved, glm::dmat3(1.0), glm::dvec3(0.0), offset);
}

void HierarchicalRadiosity::rebuildRays() {
  auto& im = *impl_;
  const uint64_t counted = im.rays->raysCast();
  im.rays = std::make_shared<RayScene>(occluders(surfaces_));
  im.raysAtStart -= std::min(im.raysAtStart, counted);
}

// Bounds and centres of the clusters above touched nodes again, children before parents (a
// cluster's index is below its children's except for surfaces added later, which hang directly
// below the root, index 0, visited last).
void HierarchicalRadiosity::refitClusters(std::vector<uint8_t>& touched) {
  for (size_t i = nodes_.size(); i-- > 0;) {
    Node& me = nodes_[i];
    if (!me.isCluster()) continue;
    bool any = false;
    glm::vec3 lo(1e30f), hi(-1e30f), c(0.f);
    float area = 0.f;
    for (int k = 0; k < me.childCount; ++k) {
      const int ch = children_[me.childBegin + k];
      any = any || touched[ch];
      if (nodes_[ch].area <= 0.f) continue;  // removed surfaces
      lo = glm::min(lo, nodes_[ch].bmin);
      hi = glm::max(hi, nodes_[ch].bmax);
      c += nodes_[ch].center * nodes_[ch].area;
      area += nodes_[ch].area;
    }
    if (!any) continue;
    touched[i] = 1;
    if (area <= 0.f) lo = hi = me.center;
    me.bmin = lo;
    me.bmax = hi;
    me.area = area;
    me.center = area > 0 ? c / area : 0.5f * (lo + hi);
    float r = 0.f;
    for (int k = 0; k < 8; ++k) {
      const glm::vec3 corner((k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z);
      r = std::max(r, glm::length(corner - me.center));
    }
    me.radius = r;
  }
}

size_t HierarchicalRadiosity::redoLinks(const std::vector<uint8_t>& redo, int visibilityRays) {
  const int rays = visibilityRays > 0 ? visibilityRays : options_.visibilityRays;
  auto& im = *impl_;
  std::vector<int> work;
  for (size_t i = 0; i < links_.size(); ++i)
    if (redo[i] && links_[i].receiver != links_[i].source) work.push_back(int(i));
  Kernel k{*this, im, nodes_, options_.quadratureOrder};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, work.size(), 16), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t j = r.begin(); j < r.end(); ++j) {
      Link& l = links_[work[j]];
      if (redo[work[j]] == 2) l.formFactor = float(k.formFactor(l.receiver, l.source, l.variation));
      l.visibility = k.visibility(l.receiver, l.source, rays, options_.seed);
      l.type = classify(l.visibility);
    }
  });
  im.gatherDirty = true;
  return work.size();
}

size_t HierarchicalRadiosity::moveSurfaces(const std::vector<int>& moved, const glm::dmat3& rotation,
                                           const glm::dvec3& pivot, const glm::dvec3& offset, int visibilityRays) {
  auto& im = *impl_;
  glm::vec3 oldMin(1e30f), oldMax(-1e30f), newMin(1e30f), newMax(-1e30f);
  for (int s : moved) {
    oldMin = glm::min(oldMin, nodes_[surfaceRoot_[s]].bmin);
    oldMax = glm::max(oldMax, nodes_[surfaceRoot_[s]].bmax);
  }
  auto place = [&](const glm::dvec3& p) { return rotation * (p - pivot) + pivot + offset; };
  // Geometry: vertices, frames (uv stays: elements keep their rectangles), every element below.
  Builder b{*this, im};
  std::vector<uint8_t> touched(nodes_.size(), 0);  // nodes whose geometry changed
  for (int s : moved) {
    for (auto& v : surfaces_[s].vertices) v = place(v);
    im.shapes[s] = EmitterShape(surfaces_[s].vertices, surfaces_[s].twoSided, surfaces_[s].photometry,
                                surfaces_[s].distant);
    auto& f = im.frames[s];
    f.origin = place(f.origin);
    f.u = rotation * f.u;
    f.v = rotation * f.v;
    f.normal = rotation * f.normal;
    forSubtree(nodes_, children_, surfaceRoot_[s], [&](int n) {
      Node& N = nodes_[n];
      b.setElementGeometry(N, clipToRect(im.uvPolys[s], {N.u0, N.v0}, {N.u1, N.v1}), s);
      touched[n] = 1;
    });
    newMin = glm::min(newMin, nodes_[surfaceRoot_[s]].bmin);
    newMax = glm::max(newMax, nodes_[surfaceRoot_[s]].bmax);
  }
  refitClusters(touched);
  rebuildRays();
  // Links to update: an end moved (F and V), or the shaft crosses the old or new bounds (V).
  std::vector<uint8_t> redo(links_.size(), 0);
  for (int i : linksCrossingBox(oldMin, oldMax)) redo[i] = 1;
  for (int i : linksCrossingBox(newMin, newMax)) redo[i] = 1;
  for (size_t i = 0; i < links_.size(); ++i)
    if (touched[links_[i].receiver] || touched[links_[i].source]) redo[i] = 2;
  return redoLinks(redo, visibilityRays);
}

size_t HierarchicalRadiosity::refreshLinks(const std::vector<int>& surfaces, const glm::vec3& boxMin,
                                           const glm::vec3& boxMax) {
  std::vector<uint8_t> touched(nodes_.size(), 0);
  for (int s : surfaces) forSubtree(nodes_, children_, surfaceRoot_[s], [&](int n) { touched[n] = 1; });
  std::vector<uint8_t> redo(links_.size(), 0);
  for (int i : linksCrossingBox(boxMin, boxMax)) redo[i] = 1;
  for (size_t i = 0; i < links_.size(); ++i)
    if (touched[links_[i].receiver] || touched[links_[i].source]) redo[i] = 2;
  return redoLinks(redo);
}

std::vector<int> HierarchicalRadiosity::addSurfaces(const std::vector<Surface>& added, Progress& progress) {
  auto& im = *impl_;
  Builder b{*this, im};
  std::vector<int> ids;
  glm::vec3 lo(1e30f), hi(-1e30f);
  // Everything is checked before anything changes: a refused add leaves the hierarchy as it was.
  for (const auto& sf : added) {
    if (sf.vertices.size() < 3) throw std::invalid_argument("surface '" + sf.name + "' has fewer than 3 vertices");
    for (const auto& v : sf.vertices)
      if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
        throw std::invalid_argument("surface '" + sf.name + "' has a vertex that is not a finite number");
    if (!(polygonArea(sf.vertices) > 1e-10)) throw std::invalid_argument("surface '" + sf.name + "' has no area");
  }
  std::vector<int32_t> rootKids;  // the root's children, less removed surfaces
  for (int k = 0; k < nodes_[0].childCount; ++k) {
    const int c = children_[nodes_[0].childBegin + k];
    if (nodes_[c].isCluster() || !isRemoved(nodes_[c].surface)) rootKids.push_back(c);
  }
  for (const auto& sf : added) {
    const int s = int(surfaces_.size());
    surfaces_.push_back(sf);
    const auto& v = sf.vertices;
    im.shapes.emplace_back(v, sf.twoSided, sf.photometry, sf.distant);
    im.frames.push_back(PlaneFrame::of(v));
    im.uvPolys.emplace_back();
    for (const auto& q : v) im.uvPolys.back().push_back(im.frames.back().toUV(q));
    im.fanCdf.emplace_back();
    double acc = 0;
    for (size_t i = 1; i + 1 < v.size(); ++i) {
      acc += 0.5 * glm::length(glm::cross(v[i] - v[0], v[i + 1] - v[0]));
      im.fanCdf.back().push_back(acc);
    }
    im.surfaceArea.push_back(acc);
    surfaceRoot_.push_back(-1);
    im.posInPerm.push_back(int(im.perm.size()));
    im.perm.push_back(s);
    const int node = b.surfaceRootNode(s, 0);
    B_.push_back(im.emit[node]);
    E_.emplace_back(0.f);
    Edown_.emplace_back(0.f);
    rootKids.push_back(node);
    ids.push_back(s);
    lo = glm::min(lo, nodes_[node].bmin);
    hi = glm::max(hi, nodes_[node].bmax);
  }
  // The root cluster adopts them (its children move to the end of the child array).
  if (size_t(nodes_[0].childBegin) + size_t(nodes_[0].childCount) == children_.size())
    children_.resize(size_t(nodes_[0].childBegin));  // the range ends the array: rewrite it in place
  nodes_[0].childBegin = int32_t(children_.size());
  nodes_[0].childCount = int32_t(rootKids.size());
  children_.insert(children_.end(), rootKids.begin(), rootKids.end());
  im.rangeCount[0] += int32_t(added.size());
  std::vector<uint8_t> touched(nodes_.size(), 0);
  for (int s : ids) {
    touched[surfaceRoot_[s]] = 1;
    im.emitterOnly[0] = im.emitterOnly[0] && im.emitterOnly[surfaceRoot_[s]];
    im.rhoMax[0] = std::max(im.rhoMax[0], im.rhoMax[surfaceRoot_[s]]);
  }
  refitClusters(touched);
  rebuildRays();
  std::vector<uint8_t> redo(links_.size(), 0);
  for (int i : linksCrossingBox(lo, hi)) redo[i] = 1;
  redoLinks(redo);
  // New links, surface to surface, then refined by the oracle (the old ones are kept as they are).
  const size_t keep = links_.size();
  std::vector<uint8_t> isNew(surfaces_.size(), 0);
  for (int s : ids) isNew[s] = 1;
  for (int s : ids) {
    const bool reflects = im.rhoMax[surfaceRoot_[s]] > 0.f;
    for (size_t t = 0; t < surfaces_.size(); ++t) {
      if (int(t) == s || isRemoved(int(t))) continue;
      links_.push_back({surfaceRoot_[t], surfaceRoot_[s], 0.f, kUnknownVisibility, 0.f, VisibilityType::Visible});
      if (reflects && !isNew[t])  // between two new surfaces the loop over t adds both directions
        links_.push_back({surfaceRoot_[s], surfaceRoot_[int(t)], 0.f, kUnknownVisibility, 0.f, VisibilityType::Visible});
    }
  }
  {
    Kernel k{*this, im, nodes_, options_.quadratureOrder};
    tbb::parallel_for(tbb::blocked_range<size_t>(keep, links_.size(), 64), [&](const tbb::blocked_range<size_t>& rg) {
      for (size_t i = rg.begin(); i < rg.end(); ++i)
        links_[i].formFactor = float(k.formFactor(links_[i].receiver, links_[i].source, links_[i].variation));
    });
    size_t w = keep;
    for (size_t i = keep; i < links_.size(); ++i)
      if (links_[i].formFactor > 0.f || links_[i].variation > 0.f) links_[w++] = links_[i];
    links_.resize(w);
  }
  RefineContext ctx{*this, im, true, nullptr};
  ctx.keep = keep;
  refineLinks(ctx, progress);
  // The new links stay where the oracle left them (not pushed to leaves: push-pull carries their
  // light down, and the leaves below were cut for the real lamps' shadows, not for these).
  return ids;
}

size_t HierarchicalRadiosity::removeSurfaces(const std::vector<int>& removed) {
  auto& im = *impl_;
  glm::vec3 lo(1e30f), hi(-1e30f);
  std::vector<uint8_t> gone(nodes_.size(), 0), touched(nodes_.size(), 0);
  for (int s : removed) {
    if (isRemoved(s)) continue;
    lo = glm::min(lo, nodes_[surfaceRoot_[s]].bmin);
    hi = glm::max(hi, nodes_[surfaceRoot_[s]].bmax);
    surfaces_[s].vertices.clear();
    surfaces_[s].exitance = glm::dvec3(0.0);
    surfaces_[s].reflectance = glm::dvec3(0.0);
    im.surfaceArea[s] = 0;  // never sampled again
    im.fanCdf[s].clear();
    forSubtree(nodes_, children_, surfaceRoot_[s], [&](int n) {
      gone[n] = 1;
      im.emit[n] = glm::vec3(0.f);
      im.rho[n] = glm::vec3(0.f);
      im.rhoMax[n] = 0.f;
      nodes_[n].area = 0.f;
    });
    touched[surfaceRoot_[s]] = 1;
  }
  if (lo.x > hi.x) return 0;
  refitClusters(touched);
  // A cluster left with nothing in it goes too; the clusters that shrank get F and V again.
  for (size_t n = 0; n < nodes_.size(); ++n)
    if (touched[n] && nodes_[n].isCluster() && nodes_[n].area <= 0.f) gone[n] = 1;
  const size_t before = links_.size();
  links_.erase(std::remove_if(links_.begin(), links_.end(),
                              [&](const Link& l) { return gone[l.receiver] || gone[l.source]; }),
               links_.end());
  rebuildRays();
  std::vector<uint8_t> redo(links_.size(), 0);
  for (int i : linksCrossingBox(lo, hi)) redo[i] = 1;
  for (size_t i = 0; i < links_.size(); ++i)
    if (touched[links_[i].receiver] || touched[links_[i].source]) redo[i] = 2;
  im.gatherDirty = true;
  return before - links_.size() + redoLinks(redo);
}

std::vector<int> HierarchicalRadiosity::linksCrossingBox(const glm::vec3& cmin, const glm::vec3& cmax) const {
  // The shaft is the convex hull of the two bounding boxes A, B: the union over t in [0,1] of the
  // boxes (1-t)A + tB. The query box meets it iff some t satisfies, on every axis,
  // lo(t) <= cmax and hi(t) >= cmin, which are linear in t.
  std::vector<int> out;
  for (size_t i = 0; i < links_.size(); ++i) {
    const Node& A = nodes_[links_[i].receiver];
    const Node& B = nodes_[links_[i].source];
    double t0 = 0, t1 = 1;
    for (int a = 0; a < 3 && t0 <= t1; ++a) {
      // lo(t) = A.min + t (B.min - A.min) <= cmax ; hi(t) = A.max + t (B.max - A.max) >= cmin
      auto constrain = [&](double c0, double slope, double bound, bool lessEq) {
        // c0 + slope t (<= or >=) bound
        if (std::abs(slope) < 1e-12) {
          if (lessEq ? c0 > bound : c0 < bound) t1 = -1;
          return;
        }
        const double t = (bound - c0) / slope;
        const bool upper = lessEq == (slope > 0);
        if (upper) t1 = std::min(t1, t);
        else t0 = std::max(t0, t);
      };
      constrain(A.bmin[a], B.bmin[a] - A.bmin[a], cmax[a], true);
      constrain(A.bmax[a], B.bmax[a] - A.bmax[a], cmin[a], false);
    }
    if (t0 <= t1) out.push_back(int(i));
  }
  return out;
}

// ----------------------------------------------------------------------------------------------
// Results

glm::vec3 HierarchicalRadiosity::irradiance(int node) const { return Edown_[node]; }

namespace {
// Area mean of a per-node quantity over a surface's leaves.
glm::dvec3 areaMean(const std::vector<HierarchicalRadiosity::Node>& nodes, const std::vector<int32_t>& children,
                    int root, const std::vector<glm::vec3>& values) {
  glm::dvec3 sum(0.0);
  double area = 0;
  forLeaves(nodes, children, root, [&](int n) {
    sum += glm::dvec3(values[n]) * double(nodes[n].area);
    area += nodes[n].area;
  });
  return area > 0 ? sum / area : sum;
}
}  // namespace

glm::dvec3 HierarchicalRadiosity::surfaceRadiosity(int surface) const {
  return areaMean(nodes_, children_, surfaceRoot_[surface], B_);
}

glm::dvec3 HierarchicalRadiosity::surfaceIrradiance(int surface) const {
  return areaMean(nodes_, children_, surfaceRoot_[surface], Edown_);
}

int HierarchicalRadiosity::findLeaf(int surface, glm::dvec2 uv) const {
  int n = surfaceRoot_[surface];
  {  // points just outside the root (rounding at an edge) belong to the nearest element
    const Node& R = nodes_[n];
    uv = glm::clamp(uv, glm::dvec2(R.u0, R.v0), glm::dvec2(R.u1, R.v1));
  }
  for (;;) {
    const Node& N = nodes_[n];
    int next = -1;
    for (int i = 0; i < N.childCount; ++i) {
      const Node& C = nodes_[children_[N.childBegin + i]];
      if (uv.x >= C.u0 && uv.x <= C.u1 && uv.y >= C.v0 && uv.y <= C.v1) {
        next = children_[N.childBegin + i];
        break;
      }
    }
    if (next < 0) return n;
    n = next;
  }
}

Totals HierarchicalRadiosity::totals() const {
  Totals t;
  for (const auto& n : nodes_) {
    if (n.isCluster()) ++t.clusters;
    else if (isRemoved(n.surface)) continue;
    else {
      ++t.elements;
      if (n.isLeaf()) ++t.leaves;
    }
  }
  t.links = links_.size();
  t.rays = impl_->rays->raysCast();
  t.iterations = impl_->lastIterations;
  t.seconds = impl_->lastSeconds;
  const auto& im = *impl_;
  t.linkBytes = links_.capacity() * sizeof(Link) + im.gRecv.capacity() * 4 + im.gSrc.capacity() * 4 +
                im.gK.capacity() * 4;
  t.engineBytes = t.linkBytes + nodes_.capacity() * sizeof(Node) + children_.capacity() * 4 +
                  (B_.capacity() + E_.capacity() + Edown_.capacity() + im.rho.capacity() + im.emit.capacity()) *
                      sizeof(glm::vec3) +
                  (im.rangeBegin.capacity() + im.rangeCount.capacity() + im.rhoMax.capacity()) * 4 +
                  im.emitterOnly.capacity();
  return t;
}

}  // namespace relume::radiosity
