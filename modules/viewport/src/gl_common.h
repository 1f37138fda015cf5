#pragma once
// What the viewport's renderers share (internal: Qt's GL headers stay in this module's .cpp files).
#include <QFile>
#include <QOpenGLContext>
#include <QOpenGLFunctions_3_3_Core>
#include <QOpenGLVersionFunctionsFactory>
#include <glm/mat4x4.hpp>
#include <string>

#include "relume/geometry/camera.h"
#include "relume/geometry/error.h"

namespace relume::gl {

// A colour + depth (and stencil) framebuffer object of floats, resized on demand.
struct FloatTarget {
  GLuint fbo = 0, colour = 0, depth = 0;
  int width = 0, height = 0;
  void ensure(QOpenGLFunctions_3_3_Core& gl, int w, int h) {
    if (fbo && w == width && h == height) return;
    release(gl);
    width = w;
    height = h;
    gl.glGenTextures(1, &colour);
    gl.glBindTexture(GL_TEXTURE_2D, colour);
    gl.glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, w, h, 0, GL_RGBA, GL_FLOAT, nullptr);
    gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gl.glGenRenderbuffers(1, &depth);
    gl.glBindRenderbuffer(GL_RENDERBUFFER, depth);
    gl.glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, w, h);  // (a stencil for the daylight view's tiles)
    gl.glGenFramebuffers(1, &fbo);
    gl.glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    gl.glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, colour, 0);
    gl.glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depth);
    if (gl.glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw Error("", "OpenGL", "cannot create a floating-point framebuffer of " + std::to_string(w) + "x" + std::to_string(h));
  }
  void release(QOpenGLFunctions_3_3_Core& gl) {
    if (fbo) gl.glDeleteFramebuffers(1, &fbo);
    if (colour) gl.glDeleteTextures(1, &colour);
    if (depth) gl.glDeleteRenderbuffers(1, &depth);
    fbo = colour = depth = 0;
    width = height = 0;
  }
};

inline // OpenCV camera -> OpenGL clip space: pixel (0,0)'s corner at the top-left of the viewport.
glm::mat4 worldToClip(const Camera& c, double nearZ, double farZ) {
  glm::dmat4 V(1.0);
  for (int col = 0; col < 3; ++col)
    for (int row = 0; row < 3; ++row) V[col][row] = c.R[col][row];
  V[3] = glm::dvec4(c.t, 1.0);
  const double W = c.width, H = c.height;
  glm::dmat4 P(0.0);
  P[0][0] = 2 * c.fx() / W;
  P[1][0] = 2 * c.K[1][0] / W;  // skew
  P[2][0] = 2 * c.cx() / W - 1;
  P[1][1] = -2 * c.fy() / H;
  P[2][1] = 1 - 2 * c.cy() / H;
  P[2][2] = (farZ + nearZ) / (farZ - nearZ);
  P[3][2] = -2 * farZ * nearZ / (farZ - nearZ);
  P[2][3] = 1;
  return glm::mat4(P * V);
}


// The current context's OpenGL 3.3 core functions; relume::Error when there are none.
inline QOpenGLFunctions_3_3_Core* currentFunctions() {
  QOpenGLContext* ctx = QOpenGLContext::currentContext();
  if (!ctx) throw Error("", "OpenGL", "no current context");
  auto* f = QOpenGLVersionFunctionsFactory::get<QOpenGLFunctions_3_3_Core>(ctx);
  if (!f || !f->initializeOpenGLFunctions()) throw Error("", "OpenGL", "the display does not offer OpenGL 3.3 core");
  return f;
}

// A shader's source from the binary's resources; relume::Error naming it when it is missing.
inline QByteArray shaderSource(const char* name) {
  QFile f(name);
  if (!f.open(QIODevice::ReadOnly)) throw Error(name, "shader", "missing from the binary's resources");
  return f.readAll();
}

}  // namespace relume::gl
