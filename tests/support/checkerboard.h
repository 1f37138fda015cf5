#pragma once
// Photos of a checkerboard made by the tests themselves (for calibration).
#include "relume/geometry/camera.h"
#include "relume/image/image.h"

namespace relume::test {

// A checkerboard of cols x rows inner corners (cols+1 x rows+1 squares of `sq` metres, white
// border) on the plane z = 0, corner 0 at the origin, seen by `cam` with radial distortion k1
// (COLMAP's RADIAL model), 3 x 3 supersampled, 8-bit grey.
Image8 renderCheckerboard(const Camera& cam, double k1, int cols, int rows, double sq);

// The same board seen through a fisheye at `cam`'s pose and image size: OpenCV's fisheye model
// (theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8), focal `f` pixels,
// principal point (cx, cy), pixel centres at +0.5), 3 x 3 supersampled; what lies beyond 100
// degrees from the axis is black.
Image8 renderFisheyeCheckerboard(const Camera& cam, double f, double cx, double cy, const double (&k)[4], int cols, int rows,
                                 double sq);

}  // namespace relume::test
