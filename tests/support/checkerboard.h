#pragma once
// Photos of a checkerboard made by the tests themselves (for calibration).
#include "relume/geometry/camera.h"
#include "relume/image/image.h"

namespace relume::test {

// A checkerboard of cols x rows inner corners (cols+1 x rows+1 squares of `sq` metres, white
// border) on the plane z = 0, corner 0 at the origin, seen by `cam` with radial distortion k1
// (COLMAP's RADIAL model), 3 x 3 supersampled, 8-bit grey.
Image8 renderCheckerboard(const Camera& cam, double k1, int cols, int rows, double sq);

}  // namespace relume::test
