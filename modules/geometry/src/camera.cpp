#include "relume/geometry/camera.h"

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

namespace relume {

glm::dvec3 Camera::center() const { return -(glm::transpose(R) * t); }

glm::dvec3 Camera::rayDirection(double x, double y) const {
  const glm::dvec3 dc((x - cx()) / fx(), (y - cy()) / fy(), 1.0);
  return glm::normalize(glm::transpose(R) * dc);
}

bool Camera::project(const glm::dvec3& X, glm::dvec2& pixel) const {
  const glm::dvec3 c = R * X + t;
  if (c.z <= 1e-9) return false;
  pixel = {fx() * c.x / c.z + cx(), fy() * c.y / c.z + cy()};
  return true;
}

}  // namespace relume
