#pragma once
// CPU rendering of a radiosity solution seen through a photo's camera: radiance B/pi
// interpolated at leaf vertices as the display does, or false-colour inspection images.
#include "relume/geometry/camera.h"
#include "relume/geometry/progress.h"
#include "relume/image/image.h"
#include "relume/radiosity/hierarchy.h"

namespace relume {

enum class RenderShow { Radiance, Leaves, Links, Visibility };

ImageRGB renderSolution(const radiosity::HierarchicalRadiosity& solution, const Camera& camera,
                        RenderShow show = RenderShow::Radiance, Progress& progress = silentProgress());

}  // namespace relume
