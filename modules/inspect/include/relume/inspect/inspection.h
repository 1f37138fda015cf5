#pragma once
// What the inspector shows of a relighting session's radiosity engine: its leaf elements as 3-D
// polygons, one quantity per element, the links an element holds, the visibility class of the
// light a lamp sends it, and counts per polygon. Read from the engine and the session; no light is
// computed here (only gathered and laid out).
#include <cstddef>
#include <cstdint>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

namespace relume {
class RelightSession;
namespace radiosity {
class HierarchicalRadiosity;
}
}  // namespace relume

namespace relume::inspect {

// The leaf elements of the engine's live surfaces, each clipped to its polygon, in world metres.
struct ElementMesh {
  std::vector<int> node;                          // engine node per element
  std::vector<int> surface;                       // engine surface per element
  std::vector<std::vector<glm::dvec3>> outline;  // its polygon (3 or more corners)
};
ElementMesh elementMesh(const radiosity::HierarchicalRadiosity& h);

enum class Quantity {
  Radiosity,       // B
  Irradiance,      // E
  DisplayFactor,   // D: the original lighting's B (irradiance + blocked light on real surfaces)
  Ratio,           // B / D as the display uses it (E / D on real surfaces)
  Reflectance,     // the element's reflectance
  FinalTexture,    // T_final, mean over the element (real polygons; NaN elsewhere)
  Level,           // depth in its polygon's quadtree (0: the polygon)
  LampVisibility,  // the class of the links from a lamp (see LampVisibilityClass)
};

enum class LampVisibilityClass : int8_t { None = -1, Visible = 0, Invisible = 1, Partial = 2 };

// Per element of `mesh`, its value of `q`: RGB quantities as the mean of R, G and B; NaN where
// it has none. For LampVisibility, `lampSurface` names the lamp (an engine surface) and the value
// is the element's LampVisibilityClass as a number. The session's engine must be current
// (RelightSession::syncEngine).
std::vector<double> elementValues(const RelightSession& session, const ElementMesh& mesh, Quantity q, int lampSurface = -1);

// The class of the light `lampSurface` sends to `node` along the engine's links (those arriving
// at the node or an ancestor from an element of the lamp; a relighting session pushes a lamp's
// links down to the leaves, so none of its light comes through a cluster): Visible when every
// such link is of type Visible, Invisible when every one is Invisible, Partial otherwise; None
// when no link of the lamp reaches it.
LampVisibilityClass lampVisibility(const radiosity::HierarchicalRadiosity& h, int node, int lampSurface);
std::vector<LampVisibilityClass> lampVisibility(const radiosity::HierarchicalRadiosity& h, const std::vector<int>& nodes,
                                                int lampSurface);

// A link of the engine that an element holds: it receives by it, or sends by it.
struct LinkRow {
  int link = -1;
  int source = -1, receiver = -1;  // engine nodes
  bool receives = true;            // the element is the receiver (else the source)
  float formFactor = 0, visibility = 1, error = 0;
  int type = 0;                    // radiosity::VisibilityType as a number
};
std::vector<LinkRow> linksOf(const radiosity::HierarchicalRadiosity& h, int node);

struct PolygonCounts {
  int surface = -1;
  std::string name;
  size_t elements = 0, leaves = 0, links = 0;  // links: those its elements receive by
};
std::vector<PolygonCounts> countsPerPolygon(const radiosity::HierarchicalRadiosity& h);

// A node's centre (elements: the centre of its rectangle on the plane; clusters: of their box).
glm::dvec3 nodeCentre(const radiosity::HierarchicalRadiosity& h, int node);

}  // namespace relume::inspect
