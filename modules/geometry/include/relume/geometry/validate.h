#pragma once
// Checks a scene for what would break the radiosity engine and names the culprit.
#include <cstddef>

#include "relume/geometry/scene.h"

namespace relume {

struct ValidationOptions {
  double planarityTolerance = 1e-3;  // max distance off the plane, relative to the polygon's size
  double minArea = 1e-10;            // m^2
};

// Limits of a room Relume relights (a model rebuilt from photos has tens to thousands of
// polygons; a scanned mesh is not one): more polygons, or a polygon with more vertices, is refused.
inline constexpr size_t kMaxRoomPolygons = 50000;
inline constexpr size_t kMaxPolygonVertices = 1000;

// Throws relume::Error naming scene.sourceFile and the polygon / lamp / photo at fault:
// fewer than 3 vertices, zero area, non-planar, non-convex, NaN or infinite numbers, room shell
// polygons whose normal points out of the room, a camera whose R is not a rotation.
// (Photo files are checked by the project module, which can open images.)
void validateScene(const Scene& scene, const ValidationOptions& options = {});

}  // namespace relume
