#pragma once
// Casting a camera's pixel rays into a solution and shading each hit (internal).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <glm/geometric.hpp>

#include "relume/geometry/camera.h"
#include "relume/image/image.h"
#include "relume/radiosity/hierarchy.h"
#include "relume/raytrace/ray_scene.h"

namespace relume::detail {

// shade(surface, leaf, uv) gives the radiance of a front-facing hit; back faces stay black.
template <typename Shade>
ImageRGB castView(const radiosity::HierarchicalRadiosity& h, const Camera& cam, Progress& progress, const Shade& shade) {
  ImageRGB img(cam.width, cam.height);
  const glm::dvec3 eye = cam.center();
  tbb::parallel_for(tbb::blocked_range<int>(0, cam.height, 8), [&](const tbb::blocked_range<int>& rows) {
    std::vector<Ray> rays(cam.width);
    std::vector<RayHit> hits(cam.width);
    for (int y = rows.begin(); y < rows.end(); ++y) {
      for (int x = 0; x < cam.width; ++x)
        rays[x] = Ray{glm::vec3(eye), glm::vec3(cam.rayDirection(x + 0.5, y + 0.5)), 0.f, 1e30f};
      h.rayScene().intersect(rays, hits);
      for (int x = 0; x < cam.width; ++x) {
        const RayHit& hit = hits[x];
        if (hit.polygon < 0) continue;
        const glm::dvec3 d = cam.rayDirection(x + 0.5, y + 0.5);
        const auto& surf = h.surfaces()[hit.polygon];
        if (glm::dot(d, glm::cross(surf.vertices[1] - surf.vertices[0], surf.vertices[2] - surf.vertices[0])) > 0)
          continue;  // back faces are black
        const glm::dvec2 uv = h.toUV(hit.polygon, eye + double(hit.t) * d);
        img.set(x, y, shade(hit.polygon, h.findLeaf(hit.polygon, uv), uv));
      }
    }
    progress.poll();
  });
  return img;
}

}  // namespace relume::detail
