#pragma once
// Polygons from reconstructed points (Loscos 2000 §3: "polygon picking"): a plane fit, the
// ordered convex polygon on it with its normal towards the cameras, optional constraints, and an
// editable set of picked polygons whose ids stay stable.
#include <glm/vec3.hpp>
#include <map>
#include <string>
#include <vector>

#include "relume/geometry/polygon.h"

namespace relume::recon {

struct Plane {
  glm::dvec3 point{0.0};
  glm::dvec3 normal{0, 0, 1};
  double rms = 0;  // distance of the fitted points to the plane, metres
  glm::dvec3 project(const glm::dvec3& p) const;
};

// Least-squares plane (smallest eigenvector of the scatter). Throws relume::Error (element
// `what`) for fewer than 3 points or points that are (nearly) collinear.
Plane fitPlane(const std::vector<glm::dvec3>& pts, const std::string& what);

struct PolygonConstraints {
  bool rectangle = false;  // edges parallel / orthogonal in pairs (4 corners)
  // Keep the corners in the order given (starting at the first, reversed if the normal would
  // face away) when they outline a convex polygon; else the convex hull's order.
  bool keepOrder = false;
};

// The convex polygon of `pts` projected onto `plane`, counter-clockwise around the normal, the
// normal turned to the side of `viewer` (e.g. the centre of the cameras that saw it). Points
// inside the hull are dropped. Throws for collinear points.
std::vector<glm::dvec3> convexPolygon(const std::vector<glm::dvec3>& pts, const Plane& plane, const glm::dvec3& viewer,
                                      const std::string& what, const PolygonConstraints& constraints = {});

// Makes a planar quadrilateral a rectangle: the in-plane axes that best fit its four edges, and
// per side the mean of its two corners.
std::vector<glm::dvec3> rectify(const std::vector<glm::dvec3>& quad, const std::string& what);

// An editable set of picked polygons. Ids are assigned once and never reused, so links,
// overrides and selections that name a polygon keep naming it across edits.
class PickedPolygons {
 public:
  struct Entry {
    Polygon polygon;
    glm::dvec3 viewer{0.0};
  };

  // Fits and adds a polygon; returns its id.
  int add(const std::string& name, const std::string& group, bool lamp, const std::vector<glm::dvec3>& pts,
          const glm::dvec3& viewer, const PolygonConstraints& constraints = {});
  // Adds a polygon given by its corners (typed measurements), ordered as given.
  int addExact(Polygon polygon);
  // Moves one vertex and re-fits the polygon's plane through its corners.
  void moveVertex(int id, int vertex, const glm::dvec3& to);
  void remove(int id);
  // Merges `b` into `a` (coplanar within `tolerance` metres): the convex polygon of both; `b` is
  // removed, `a` keeps its id, name and group.
  void merge(int a, int b, double tolerance = 0.02);
  // Fits one plane to the corners of all `ids` and projects them onto it.
  void snapToCommonPlane(const std::vector<int>& ids);

  const Polygon& get(int id) const;
  bool contains(int id) const { return entries_.count(id) > 0; }
  std::vector<int> ids() const;
  const std::map<int, Entry>& entries() const { return entries_; }

 private:
  Entry& entry(int id);
  std::map<int, Entry> entries_;
  int next_ = 1;
};

}  // namespace relume::recon
