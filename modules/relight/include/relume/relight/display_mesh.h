#pragma once
// What a display draws of a relighting session (Loscos 2000 §2.4: texture x B / D): the leaf
// elements of the session's mesh clipped to their polygons as indexed triangles, and per leaf the
// corner values of B, D and B_orig. Within a polygon the triangles are watertight: every corner
// of a neighbouring leaf that lies on a leaf's edge (a T-junction) is a vertex of that leaf's
// outline too; a leaf with such vertices is a fan around its centre, a plain one two triangles.
// A display that evaluates the leaf's bilinear B and D at these vertices and interpolates them
// linearly (Gouraud, as the paper's display does) matches the CPU renderer's per-pixel bilinear
// values (RelightSession::render) exactly along every leaf edge. No light is computed from it: it is the
// session's solution laid out for a GPU.
#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <vector>

namespace relume {

// How a surface is shown: photo texture x ratio (real polygons and lamps), texture alone
// (windows), or the solution's own radiance B / pi (virtual lamps and objects, and lamps that no
// photo shows).
enum class DisplaySurfaceKind : uint8_t { Textured = 0, Window = 1, Virtual = 2 };

struct DisplayMesh {
  struct Vertex {
    glm::vec3 position;  // world, metres
    glm::vec2 uv;        // the surface's plane frame (as PolygonTexture and the engine use it)
    int32_t leaf;        // index into leafNode / leafRect
  };
  struct Range {
    int surface = -1;  // engine surface; for surface < realPolygons, also the scene polygon / texture
    DisplaySurfaceKind kind = DisplaySurfaceKind::Textured;
    glm::vec3 normal{0.f};  // front side (back faces are drawn black)
    size_t first = 0, count = 0;  // into indices (a triangle list)
  };
  std::vector<Vertex> vertices;
  std::vector<uint32_t> indices;    // three per triangle
  std::vector<Range> ranges;        // one per surface that has triangles
  std::vector<int> leafNode;        // engine node of each drawn leaf
  std::vector<glm::vec4> leafRect;  // its u0, v0, u1, v1
  size_t realPolygons = 0;          // surfaces [0, realPolygons) are the scene's polygons
};

// Per drawn leaf (DisplayMesh::leafNode order) kDisplayCornerTexels values: the corners (u0v0,
// u1v0, u1v1, u0v1) of B, then of D, then of B_orig (radiosity on lamps and virtual surfaces,
// irradiance on real surfaces: what the session's ratio is made of). Alpha is 1, except texel 4
// (D's first corner) whose alpha is the leaf's §4.3 category (0 none, or the two below).
inline constexpr int kDisplayCornerTexels = 12;
// Per vertex: B, D and B_orig (RGB each) of its leaf at its place.
inline constexpr int kDisplayVertexLight = 9;
inline constexpr uint8_t kOccludedElement = 2, kFrontierElement = 3;

}  // namespace relume
