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

Camera Camera::lookAt(const glm::dvec3& eye, const glm::dvec3& target, int w, int h, double f) {
  Camera c;
  c.width = w;
  c.height = h;
  c.K[0][0] = c.K[1][1] = f;
  c.K[2][0] = w / 2.0;
  c.K[2][1] = h / 2.0;
  const glm::dvec3 z = glm::normalize(target - eye), x = glm::normalize(glm::cross(glm::dvec3(0, 0, -1), z)),
                   y = glm::cross(z, x);
  for (int k = 0; k < 3; ++k) c.R[k][0] = x[k], c.R[k][1] = y[k], c.R[k][2] = z[k];
  c.t = -(c.R * eye);
  return c;
}

}  // namespace relume
