#pragma once
// Internals shared by preprocessing and the relighting session (not installed).
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <vector>

#include "relume/radiosity/hierarchy.h"
#include "relume/relight/relighter.h"

namespace relume::detail {

using radiosity::HierarchicalRadiosity;

// Sums over the links arriving at each node and its ancestors (the light a leaf receives).
struct LinkSums {
  std::vector<glm::vec3> blocked;        // E-bar (Eq. 5): F (1 - V) B_s; direct, + indirect if asked
  std::vector<glm::vec3> direct;         // F B_s from emitters (unoccluded direct irradiance)
  std::vector<glm::vec3> directBlocked;  // F (1 - V) B_s from emitters
  std::vector<glm::vec3> unoccluded;     // E + E-bar
};
LinkSums linkSums(const HierarchicalRadiosity& h, bool indirect);

// Attenuation of the light from each lamp surface at a rectangle of a surface, by ray pairs.
class LampVisibility {
 public:
  LampVisibility(const HierarchicalRadiosity& h, std::vector<int> lampSurfaces);
  std::vector<float> at(int surface, const glm::vec4& rect) const;
  size_t lampCount() const { return lamps_.size(); }

 private:
  const HierarchicalRadiosity& h_;
  std::vector<int> lamps_;
  std::vector<std::vector<glm::dvec3>> points_;
  std::vector<glm::dvec3> normals_;
};

// Leaf elements sharing an edge with `leaf` (probed just outside its edges).
std::vector<int> neighbours(const HierarchicalRadiosity& h, int leaf);

std::vector<int> leavesOf(const HierarchicalRadiosity& h, const std::vector<uint8_t>& surfaceMask);

glm::vec4 rectOf(const HierarchicalRadiosity::Node& n);

// Texture-based refinement for shadow boundaries (Fig. 12) on the surfaces in `mask`;
// colourScale turns texture radiance into Eq. 1 reflectance for the CIELAB comparison.
void textureRefine(HierarchicalRadiosity& h, const std::vector<PolygonTexture>& textures,
                   const std::vector<int>& lampSurfaces, const std::vector<uint8_t>& mask, double colourScale,
                   const RelightOptions& o, RelightEstimates* est, Progress& progress);

// The engine's surfaces for a scene (polygon order kept) with the given per-polygon reflectances
// and per-lamp exitances; window polygons absorb.
std::vector<radiosity::Surface> engineSurfaces(const Scene& scene, const std::vector<glm::dvec3>& reflectance,
                                               const std::vector<glm::dvec3>& lampExitance);

}  // namespace relume::detail
