#include "relume/raytrace/ray_scene.h"

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <functional>
#include <glm/geometric.hpp>
#include <limits>
#include <stdexcept>
#include <string>

namespace relume {

struct RayScene::Impl {
  static constexpr size_t kCountSlots = 16;
  struct alignas(64) Count {
    std::atomic<uint64_t> rays{0};
  };
  Count counts[kCountSlots];
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<int> triangleToPolygon;

  explicit Impl(RTCBuildQuality quality) {
    device = rtcNewDevice("threads=0");
    if (!device) throw std::runtime_error("Embree: cannot create a device");
    scene = rtcNewScene(device);
    rtcSetSceneBuildQuality(scene, quality);
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
  }
  // A triangle geometry of nv vertices and nt triangles: fill vb (x, y, z) and ib, then attach().
  RTCGeometry triangles(size_t nv, size_t nt, float*& vb, unsigned*& ib) const {
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    vb = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), nv));
    ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), nt));
    return geom;
  }
  // Attaches it (if any) and builds the scene.
  void commit(RTCGeometry geom) {
    if (geom) {
      rtcCommitGeometry(geom);
      rtcAttachGeometry(scene, geom);
      rtcReleaseGeometry(geom);
    }
    rtcCommitScene(scene);
  }
};

RayScene::RayScene(const std::vector<std::vector<glm::dvec3>>& polygons)
    : impl_(std::make_unique<Impl>(RTC_BUILD_QUALITY_HIGH)), polygonCount_(int(polygons.size())) {
  size_t nv = 0, nt = 0;
  for (const auto& p : polygons) {
    nv += p.size();
    nt += p.size() >= 3 ? p.size() - 2 : 0;
  }
  if (nt == 0) {
    impl_->commit(nullptr);
    return;
  }
  float* vb;
  unsigned* ib;
  RTCGeometry geom = impl_->triangles(nv, nt, vb, ib);
  impl_->triangleToPolygon.reserve(nt);
  size_t v = 0, t = 0;
  for (size_t pi = 0; pi < polygons.size(); ++pi) {
    const auto& p = polygons[pi];
    const size_t base = v;
    for (const auto& q : p) {
      vb[3 * v + 0] = float(q.x);
      vb[3 * v + 1] = float(q.y);
      vb[3 * v + 2] = float(q.z);
      ++v;
    }
    for (size_t k = 1; k + 1 < p.size(); ++k) {
      ib[3 * t + 0] = unsigned(base);
      ib[3 * t + 1] = unsigned(base + k);
      ib[3 * t + 2] = unsigned(base + k + 1);
      impl_->triangleToPolygon.push_back(int(pi));
      ++t;
    }
  }
  impl_->commit(geom);
}

RayScene::RayScene(std::span<const glm::vec3> vertices, std::span<const glm::uvec3> triangles)
    : impl_(std::make_unique<Impl>(RTC_BUILD_QUALITY_MEDIUM)), polygonCount_(int(triangles.size())) {
  if (triangles.empty()) {
    impl_->commit(nullptr);
    return;
  }
  float* vb;
  unsigned* ib;
  RTCGeometry geom = impl_->triangles(vertices.size(), triangles.size(), vb, ib);
  for (size_t v = 0; v < vertices.size(); ++v)
    for (int k = 0; k < 3; ++k) vb[3 * v + k] = vertices[v][k];
  impl_->triangleToPolygon.resize(triangles.size());
  for (size_t t = 0; t < triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) ib[3 * t + k] = triangles[t][k];
    impl_->triangleToPolygon[t] = int(t);
  }
  impl_->commit(geom);
}

RayScene::~RayScene() {
  if (impl_->scene) rtcReleaseScene(impl_->scene);
  if (impl_->device) rtcReleaseDevice(impl_->device);
}

namespace {

inline bool occludedOne(RTCScene scene, const Segment& s, float eps) {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRay r;
  r.org_x = s.from.x;
  r.org_y = s.from.y;
  r.org_z = s.from.z;
  r.dir_x = s.to.x - s.from.x;
  r.dir_y = s.to.y - s.from.y;
  r.dir_z = s.to.z - s.from.z;
  r.tnear = eps;
  r.tfar = 1.f - eps;
  r.time = 0.f;
  r.mask = 0xFFFFFFFF;
  r.id = 0;
  r.flags = 0;
  rtcOccluded1(scene, &ctx, &r);
  return r.tfar < 0.f;
}

}  // namespace

void RayScene::occluded(std::span<const Segment> segs, std::span<uint8_t> blocked, float eps) const {
  const size_t n = segs.size();
  count(n);
  RTCScene scene = impl_->scene;
  auto body = [&](size_t b, size_t e) {
    for (size_t i = b; i < e; ++i) blocked[i] = occludedOne(scene, segs[i], eps) ? 1 : 0;
  };
  if (n < 512) {
    body(0, n);
    return;
  }
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 256),
                    [&](const tbb::blocked_range<size_t>& r) { body(r.begin(), r.end()); });
}

void RayScene::count(uint64_t n) const {
  // Each thread takes the next slot in turn the first time it counts, so that threads spread
  // over the slots evenly (a hash of the thread id may put two of them on one cache line).
  static std::atomic<unsigned> next{0};
  static thread_local const size_t slot = next.fetch_add(1, std::memory_order_relaxed) % Impl::kCountSlots;
  impl_->counts[slot].rays.fetch_add(n, std::memory_order_relaxed);
}

uint64_t RayScene::raysCast() const {
  uint64_t n = 0;
  for (const auto& c : impl_->counts) n += c.rays.load(std::memory_order_relaxed);
  return n;
}

void RayScene::resetRayCount() {
  for (auto& c : impl_->counts) c.rays.store(0);
}

bool RayScene::occluded(const glm::vec3& from, const glm::vec3& to, float eps) const {
  count(1);
  return occludedOne(impl_->scene, Segment{from, to}, eps);
}

float RayScene::visibility(std::span<const glm::vec3> a, std::span<const glm::vec3> b, float eps) const {
  const size_t n = std::min(a.size(), b.size());
  if (n == 0) return 1.f;
  count(n);
  size_t free = 0;
  for (size_t i = 0; i < n; ++i) free += occludedOne(impl_->scene, Segment{a[i], b[i]}, eps) ? 0 : 1;
  return float(free) / float(n);
}

namespace {

RayHit intersectOne(RTCScene scene, const std::vector<int>& triangleToPolygon, const Ray& ray) {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh;
  rh.ray.org_x = ray.origin.x;
  rh.ray.org_y = ray.origin.y;
  rh.ray.org_z = ray.origin.z;
  rh.ray.dir_x = ray.direction.x;
  rh.ray.dir_y = ray.direction.y;
  rh.ray.dir_z = ray.direction.z;
  rh.ray.tnear = ray.tnear;
  rh.ray.tfar = ray.tfar;
  rh.ray.time = 0.f;
  rh.ray.mask = 0xFFFFFFFF;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene, &ctx, &rh);
  RayHit h;
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return h;
  h.polygon = triangleToPolygon[rh.hit.primID];
  h.triangle = int(rh.hit.primID);
  h.barycentric = glm::vec2(rh.hit.u, rh.hit.v);
  h.t = rh.ray.tfar;
  h.point = ray.origin + h.t * ray.direction;
  const glm::vec3 ng(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
  const float l = glm::length(ng);
  h.geometricNormal = l > 0 ? ng / l : ng;
  return h;
}

}  // namespace

RayHit RayScene::intersect(const Ray& ray) const {
  count(1);
  return intersectOne(impl_->scene, impl_->triangleToPolygon, ray);
}

void RayScene::intersect(std::span<const Ray> rays, std::span<RayHit> hits) const {
  count(rays.size());  // counted once, not per ray
  auto body = [&](size_t b, size_t e) {
    for (size_t i = b; i < e; ++i) hits[i] = intersectOne(impl_->scene, impl_->triangleToPolygon, rays[i]);
  };
  if (rays.size() < 512) return body(0, rays.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 256),
                    [&](const tbb::blocked_range<size_t>& r) { body(r.begin(), r.end()); });
}

}  // namespace relume
