#pragma once
// The one Embree 3 scene of all polygons: batched occlusion and intersection queries (TBB).
#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <memory>
#include <span>
#include <vector>

namespace relume {

struct Segment {
  glm::vec3 from, to;  // the open segment between them is tested (ends excluded)
};

struct Ray {
  glm::vec3 origin, direction;  // direction need not be unit; hits at origin + t * direction
  float tnear = 0.f, tfar = 1e30f;
};

struct RayHit {
  int polygon = -1;  // -1: no hit
  float t = 0.f;
  glm::vec3 point{0.f};
  glm::vec3 geometricNormal{0.f};
  glm::vec2 barycentric{0.f};  // (u, v) on the hit triangle: point = (1-u-v) a + u b + v c
  int triangle = -1;           // the triangle hit (its polygon's fan triangle)
};

class RayScene {
 public:
  // Each polygon is convex and planar; it is triangulated as a fan.
  explicit RayScene(const std::vector<std::vector<glm::dvec3>>& polygons);
  // An indexed triangle mesh (a million triangles and more): polygon i is triangle i.
  RayScene(std::span<const glm::vec3> vertices, std::span<const glm::uvec3> triangles);
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  // blocked[i] = 1 when something lies strictly between segs[i].from and segs[i].to.
  // `endEpsilon` shortens both ends by that fraction of the length, so surfaces the ends lie on
  // do not count. Parallel (TBB) for large batches.
  void occluded(std::span<const Segment> segs, std::span<uint8_t> blocked,
                float endEpsilon = 1e-4f) const;
  bool occluded(const glm::vec3& from, const glm::vec3& to, float endEpsilon = 1e-4f) const;

  void intersect(std::span<const Ray> rays, std::span<RayHit> hits) const;
  RayHit intersect(const Ray& ray) const;

  // Fraction of the N ray pairs (a[i], b[i]) that are unblocked: the attenuation (visibility)
  // factor between two elements sampled with matching stratified, jittered points.
  float visibility(std::span<const glm::vec3> a, std::span<const glm::vec3> b,
                   float endEpsilon = 1e-4f) const;

  int polygonCount() const { return polygonCount_; }
  uint64_t raysCast() const;
  void resetRayCount();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int polygonCount_ = 0;
  // Rays cast, counted per thread slot (one shared counter, bumped per single ray from every
  // thread, cost a tenth of a shadow pass in cache-line traffic).
  void count(uint64_t n) const;
};

}  // namespace relume
