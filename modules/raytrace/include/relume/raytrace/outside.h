#pragma once
// Which of a room's polygons lie outside it: seen through one of its windows, beyond the window's
// plane (a ground plane, the street, the neighbour's wall). Daylight takes their light as the
// ground's; the room's bounds for virtual objects leave them out.
#include <vector>

#include "relume/geometry/scene.h"

namespace relume {

// The polygons (not windows) that lie beyond some window's plane — no vertex more than 1 cm on the
// room's side of it, some vertex more than 1 cm beyond — and that the window sees: a line from a
// point of the window to a point of the polygon, meeting no other polygon, reaches the polygon's
// front face. The second test keeps a room's own walls that lie beyond the plane of a window in
// another part of it (the far wing of an L-shaped room: hidden behind the near wing's walls, or
// seen from their backs) inside.
std::vector<int> outsidePolygons(const Scene& scene);

}  // namespace relume
