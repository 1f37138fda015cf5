#pragma once
// CPU rendering of a radiosity solution seen through a photo's camera: radiance B/pi
// interpolated at leaf vertices as the display does, or false-colour inspection images.
#include <array>
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
std::vector<std::array<glm::vec3, 4>> leafCornerValues(const radiosity::HierarchicalRadiosity& h,
                                                       const std::vector<glm::vec3>& perNode,
                                                       const std::vector<float>* weights = nullptr);
// Bilinear interpolation of corner values inside leaf L at plane coordinates uv.
glm::vec3 interpolateCorners(const radiosity::HierarchicalRadiosity::Node& L, const std::array<glm::vec3, 4>& corners,
                             glm::dvec2 uv);

ImageRGB renderSolution(const radiosity::HierarchicalRadiosity& solution, const Camera& camera,
                        RenderShow show = RenderShow::Radiance, Progress& progress = silentProgress());

}  // namespace relume
