#pragma once
// CPU rendering of a radiosity solution seen through a photo's camera: radiance B/pi
// interpolated at leaf vertices as the display does, or false-colour inspection images.
#include <array>
#include <cstdint>
#include <glm/vec2.hpp>
#include <vector>

#include "relume/geometry/camera.h"
#include "relume/geometry/progress.h"
#include "relume/image/image.h"
#include "relume/radiosity/hierarchy.h"

namespace relume {

enum class RenderShow { Radiance, Leaves, Links, Visibility };

// A per-node quantity at the four corners (u0v0, u1v0, u1v1, u0v1) of every leaf element: the
// mean of the leaves meeting at that corner, so that interpolated values are continuous.
// With `weights` (per node), the mean is weighted, e.g. towards elements a photo shows.
// The same as a linear map built once per mesh: which leaves (with normalised weights) make each
// leaf corner. Applying it to per-node values costs a few multiply-adds per corner, so values
// that change often (lighting) are re-cornered without searching the tree again.
class CornerStencil {
 public:
  CornerStencil() = default;
  CornerStencil(const radiosity::HierarchicalRadiosity& h, const std::vector<float>* weights = nullptr);
  // Corner values per node (leaves filled, other nodes left as they are in `out`).
  void apply(const std::vector<glm::vec3>& perNode, std::vector<std::array<glm::vec3, 4>>& out) const;
  // Corner values of leaf i of leaves() (compact).
  void applyCompact(const std::vector<glm::vec3>& perNode, std::vector<std::array<glm::vec3, 4>>& out) const;
  const std::vector<int32_t>& leaves() const { return leaves_; }
  size_t nodeCount() const { return nodes_; }

 private:
  size_t nodes_ = 0;
  std::vector<int32_t> leaves_;   // leaf elements, in node order
  std::vector<uint32_t> begin_;   // per leaf corner (4 per leaf), plus an end: into node_ / weight_
  std::vector<int32_t> node_;
  std::vector<float> weight_;
};

std::vector<std::array<glm::vec3, 4>> leafCornerValues(const radiosity::HierarchicalRadiosity& h,
                                                       const std::vector<glm::vec3>& perNode,
                                                       const std::vector<float>* weights = nullptr);
// Bilinear interpolation of corner values inside leaf L at plane coordinates uv.
glm::vec3 interpolateCorners(const radiosity::HierarchicalRadiosity::Node& L, const std::array<glm::vec3, 4>& corners,
                             glm::dvec2 uv);

// Radiance B / pi of per-node radiosities `perNode` (another solution on the same hierarchy, e.g.
// a combination of daylight bases), interpolated at leaf corners as the display does.
ImageRGB renderRadiosity(const radiosity::HierarchicalRadiosity& h, const std::vector<glm::vec3>& perNode,
                         const Camera& camera, Progress& progress = silentProgress());
ImageRGB renderSolution(const radiosity::HierarchicalRadiosity& solution, const Camera& camera,
                        RenderShow show = RenderShow::Radiance, Progress& progress = silentProgress());

}  // namespace relume
