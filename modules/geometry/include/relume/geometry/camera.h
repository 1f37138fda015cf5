#pragma once
// A pinhole camera in the OpenCV convention: x_cam = R * X + t, x right, y down, z forward.
#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace relume {

struct Camera {
  glm::dmat3 K{1.0};  // pixels; K[col][row] as glm stores it, use fx()/fy()/cx()/cy()
  glm::dmat3 R{1.0};  // world to camera rotation
  glm::dvec3 t{0.0};
  int width = 0, height = 0;

  double fx() const { return K[0][0]; }
  double fy() const { return K[1][1]; }
  double cx() const { return K[2][0]; }
  double cy() const { return K[2][1]; }
  glm::dvec3 center() const;  // -R^T t
  // Ray direction (world, unit) through pixel coordinates (x, y), pixel centres at +0.5.
  glm::dvec3 rayDirection(double x, double y) const;
  // Projects a world point; returns false when it lies behind the camera.
  bool project(const glm::dvec3& X, glm::dvec2& pixel) const;
  // A w x h camera of focal length f pixels (principal point at the centre) at `eye` looking at
  // `target`, the image's y axis towards the world's -Z (upright for +Z up).
  static Camera lookAt(const glm::dvec3& eye, const glm::dvec3& target, int w, int h, double f);
};

}  // namespace relume
