// The workbench's relighting renderer: the session's display mesh, photo textures and corner
// values on the GPU; texture x B / D per fragment (shaders/relight.frag), then the display
// transform (shaders/display.frag).
#include "relume/viewport/gl_renderer.h"

#include <QFile>
#include <QOpenGLContext>
#include <QOpenGLFunctions_3_3_Core>
#include <QOpenGLShaderProgram>
#include <QOpenGLVersionFunctionsFactory>
#include <algorithm>
#include <chrono>
#include <glm/mat4x4.hpp>
#include <vector>

#include "relume/geometry/error.h"
#include "relume/geometry/scene.h"
#include "relume/relight/relighter.h"

static void initShaderResources() { Q_INIT_RESOURCE(shaders); }

namespace relume {

namespace {

constexpr int kMaxLamps = 32;

struct SurfaceTextures {
  GLuint original = 0, unoccluded = 0;
  glm::vec2 origin{0.f}, size{1.f};
  float texel = 1.f;
};

// A colour + depth framebuffer object of floats, resized on demand.
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
    gl.glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, w, h);
    gl.glGenFramebuffers(1, &fbo);
    gl.glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    gl.glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, colour, 0);
    gl.glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
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

// With `seen` (per texel), the texture is RGBA and its alpha says whether a photo saw the texel.
GLuint uploadTexture(QOpenGLFunctions_3_3_Core& gl, int w, int h, const float* rgb, bool linear,
                     const std::vector<TexelSource>* seen = nullptr) {
  static const float black[3] = {0.f, 0.f, 0.f};
  if (w <= 0 || h <= 0 || !rgb) {
    w = h = 1;
    rgb = black;
    seen = nullptr;
  }
  GLuint id = 0;
  gl.glGenTextures(1, &id);
  gl.glBindTexture(GL_TEXTURE_2D, id);
  gl.glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  if (seen && seen->size() == size_t(w) * size_t(h)) {
    std::vector<float> rgba(size_t(w) * h * 4);
    for (size_t i = 0; i < size_t(w) * h; ++i) {
      for (int c = 0; c < 3; ++c) rgba[4 * i + c] = rgb[3 * i + c];
      rgba[4 * i + 3] = (*seen)[i] == TexelSource::Smooth ? 0.f : 1.f;
    }
    gl.glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, w, h, 0, GL_RGBA, GL_FLOAT, rgba.data());
  } else {
    gl.glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB32F, w, h, 0, GL_RGB, GL_FLOAT, rgb);
  }
  const GLint filter = linear ? GL_LINEAR : GL_NEAREST;
  gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
  gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
  gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return id;
}

// OpenCV camera -> OpenGL clip space: pixel (0,0)'s corner at the top-left of the viewport.
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

bool sameCamera(const Camera& a, const Camera& b) {
  return a.width == b.width && a.height == b.height && a.K == b.K && a.R == b.R && a.t == b.t;
}

}  // namespace

struct GlRelightRenderer::Impl {
  QOpenGLFunctions_3_3_Core* gl = nullptr;
  std::unique_ptr<QOpenGLShaderProgram> relight, display;
  GLuint vao = 0, vbo = 0, emptyVao = 0;
  GLuint cornerBuffer = 0, cornerTexture = 0, rectBuffer = 0, rectTexture = 0;
  GLuint glow = 0, glowLamp = 0;
  bool hasGlow = false;
  Camera photoCamera;
  std::vector<SurfaceTextures> textures;  // per scene polygon
  DisplayMesh mesh;
  bool meshReady = false, lightingReady = false;
  glm::vec3 boundsLo{0.f}, boundsHi{0.f};
  std::vector<glm::vec3> lampScale;
  FloatTarget linear, readback;
  double lastMs = 0;

  void releaseRoom() {
    for (auto& t : textures) {
      gl->glDeleteTextures(1, &t.original);
      gl->glDeleteTextures(1, &t.unoccluded);
    }
    textures.clear();
    if (glow) gl->glDeleteTextures(1, &glow);
    if (glowLamp) gl->glDeleteTextures(1, &glowLamp);
    glow = glowLamp = 0;
    hasGlow = false;
  }

  void drawLinear(const Camera& camera, ViewMode mode, int w, int h) {
    linear.ensure(*gl, w, h);
    gl->glBindFramebuffer(GL_FRAMEBUFFER, linear.fbo);
    gl->glViewport(0, 0, w, h);
    gl->glDisable(GL_BLEND);
    gl->glClearColor(0.f, 0.f, 0.f, 0.f);  // alpha 0: nothing drawn (the display fills cracks)
    gl->glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    if (!meshReady || !lightingReady) return;
    gl->glEnable(GL_DEPTH_TEST);
    gl->glDepthFunc(GL_LESS);
    // Near and far from the room's bounds as this camera sees them.
    const glm::dvec3 eye = camera.center();
    double farZ = 0.1;
    for (int k = 0; k < 8; ++k) {
      const glm::dvec3 p((k & 1) ? boundsHi.x : boundsLo.x, (k & 2) ? boundsHi.y : boundsLo.y, (k & 4) ? boundsHi.z : boundsLo.z);
      farZ = std::max(farZ, glm::length(p - eye));
    }
    farZ = farZ * 1.05 + 0.1;
    const double nearZ = std::clamp(farZ * 1e-3, 0.005, 0.05);
    relight->bind();
    relight->setUniformValue("worldToClip", QMatrix4x4(&glm::transpose(worldToClip(camera, nearZ, farZ))[0][0]));
    relight->setUniformValue("eye", QVector3D(float(eye.x), float(eye.y), float(eye.z)));
    relight->setUniformValue("mode", int(mode));
    // Away from the photo's own view, texels no photo saw are drawn as a checker.
    relight->setUniformValue("checkerUnseen", sameCamera(camera, photoCamera) ? 0 : 1);
    relight->setUniformValue("corners", 0);
    relight->setUniformValue("rects", 1);
    relight->setUniformValue("original", 2);
    relight->setUniformValue("unoccluded", 3);
    gl->glActiveTexture(GL_TEXTURE0);
    gl->glBindTexture(GL_TEXTURE_BUFFER, cornerTexture);
    gl->glActiveTexture(GL_TEXTURE1);
    gl->glBindTexture(GL_TEXTURE_BUFFER, rectTexture);
    gl->glBindVertexArray(vao);
    for (const auto& r : mesh.ranges) {
      relight->setUniformValue("kind", int(r.kind));
      relight->setUniformValue("normal", QVector3D(r.normal.x, r.normal.y, r.normal.z));
      if (size_t(r.surface) < textures.size()) {
        const auto& t = textures[r.surface];
        gl->glActiveTexture(GL_TEXTURE2);
        gl->glBindTexture(GL_TEXTURE_2D, t.original);
        gl->glActiveTexture(GL_TEXTURE3);
        gl->glBindTexture(GL_TEXTURE_2D, t.unoccluded);
        relight->setUniformValue("texOrigin", QVector2D(t.origin.x, t.origin.y));
        relight->setUniformValue("texelSize", t.texel);
        relight->setUniformValue("texSize", QVector2D(t.size.x, t.size.y));
      }
      gl->glDrawArrays(GL_TRIANGLES, GLint(r.first), GLsizei(r.count));
    }
    gl->glBindVertexArray(0);
    gl->glDisable(GL_DEPTH_TEST);
    relight->release();
  }

  void present(const Camera& camera, const DisplaySettings& s, GLuint target, const ViewRect& rect) {
    gl->glBindFramebuffer(GL_FRAMEBUFFER, target);
    gl->glViewport(rect.x, rect.y, rect.width, rect.height);
    gl->glDisable(GL_DEPTH_TEST);
    display->bind();
    display->setUniformValue("linearImage", 0);
    display->setUniformValue("glow", 1);
    display->setUniformValue("glowLamp", 2);
    gl->glActiveTexture(GL_TEXTURE0);
    gl->glBindTexture(GL_TEXTURE_2D, linear.colour);
    const bool glowOn = hasGlow && sameCamera(camera, photoCamera);
    display->setUniformValue("glowOn", glowOn ? 1 : 0);
    if (glowOn) {
      gl->glActiveTexture(GL_TEXTURE1);
      gl->glBindTexture(GL_TEXTURE_2D, glow);
      gl->glActiveTexture(GL_TEXTURE2);
      gl->glBindTexture(GL_TEXTURE_2D, glowLamp);
      std::vector<GLfloat> scales(3 * kMaxLamps, 1.f);
      for (size_t l = 0; l < lampScale.size() && l < size_t(kMaxLamps); ++l)
        for (int c = 0; c < 3; ++c) scales[3 * l + c] = lampScale[l][c];
      display->setUniformValueArray("lampScale", scales.data(), kMaxLamps, 3);
    }
    display->setUniformValue("viewOrigin", QVector2D(float(rect.x), float(rect.y)));
    display->setUniformValue("viewSize", QVector2D(float(rect.width), float(rect.height)));
    display->setUniformValue("outputMode", int(s.output));
    display->setUniformValue("exposure", float(s.exposure));
    display->setUniformValue("falseMin", float(s.falseMin));
    display->setUniformValue("falseMax", float(s.falseMax));
    gl->glBindVertexArray(emptyVao);
    gl->glDrawArrays(GL_TRIANGLES, 0, 3);
    gl->glBindVertexArray(0);
    display->release();
    gl->glActiveTexture(GL_TEXTURE0);
  }
};

GlRelightRenderer::GlRelightRenderer() : impl_(std::make_unique<Impl>()) {}

GlRelightRenderer::~GlRelightRenderer() {
  auto& im = *impl_;
  if (!im.gl || !QOpenGLContext::currentContext()) return;  // the context went first: GL frees it all
  im.releaseRoom();
  im.linear.release(*im.gl);
  im.readback.release(*im.gl);
  for (GLuint* b : {&im.vbo, &im.cornerBuffer, &im.rectBuffer})
    if (*b) im.gl->glDeleteBuffers(1, b);
  for (GLuint* t : {&im.cornerTexture, &im.rectTexture})
    if (*t) im.gl->glDeleteTextures(1, t);
  for (GLuint* a : {&im.vao, &im.emptyVao})
    if (*a) im.gl->glDeleteVertexArrays(1, a);
}

void GlRelightRenderer::initialize() {
  initShaderResources();
  auto& im = *impl_;
  QOpenGLContext* ctx = QOpenGLContext::currentContext();
  if (!ctx) throw Error("", "OpenGL", "no current context");
  im.gl = QOpenGLVersionFunctionsFactory::get<QOpenGLFunctions_3_3_Core>(ctx);
  if (!im.gl || !im.gl->initializeOpenGLFunctions())
    throw Error("", "OpenGL", "the display does not offer OpenGL 3.3 core");
  auto program = [](const char* vert, const char* frag) {
    auto p = std::make_unique<QOpenGLShaderProgram>();
    if (!p->addShaderFromSourceFile(QOpenGLShader::Vertex, vert) ||
        !p->addShaderFromSourceFile(QOpenGLShader::Fragment, frag) || !p->link())
      throw Error(frag, "shader", p->log().toStdString());
    return p;
  };
  im.relight = program(":/shaders/relight.vert", ":/shaders/relight.frag");
  im.display = program(":/shaders/display.vert", ":/shaders/display.frag");
  auto& gl = *im.gl;
  gl.glGenVertexArrays(1, &im.vao);
  gl.glGenVertexArrays(1, &im.emptyVao);
  gl.glGenBuffers(1, &im.vbo);
  gl.glGenBuffers(1, &im.cornerBuffer);
  gl.glGenBuffers(1, &im.rectBuffer);
  gl.glGenTextures(1, &im.cornerTexture);
  gl.glGenTextures(1, &im.rectTexture);
  gl.glBindVertexArray(im.vao);
  gl.glBindBuffer(GL_ARRAY_BUFFER, im.vbo);
  using V = DisplayMesh::Vertex;
  gl.glEnableVertexAttribArray(0);
  gl.glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(V), reinterpret_cast<void*>(offsetof(V, position)));
  gl.glEnableVertexAttribArray(1);
  gl.glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, sizeof(V), reinterpret_cast<void*>(offsetof(V, uv)));
  gl.glEnableVertexAttribArray(2);
  gl.glVertexAttribIPointer(2, 1, GL_INT, sizeof(V), reinterpret_cast<void*>(offsetof(V, leaf)));
  gl.glBindVertexArray(0);
}

void GlRelightRenderer::setRoom(const Scene& scene, const RelightData& data) {
  auto& im = *impl_;
  auto& gl = *im.gl;
  im.releaseRoom();
  for (const auto& t : data.textures) {
    SurfaceTextures s;
    const float* orig = t.original.empty() ? nullptr : &t.original[0].x;
    const float* fin = t.unoccluded.empty() ? orig : &t.unoccluded[0].x;
    s.original = uploadTexture(gl, t.width, t.height, orig, true, &t.source);
    s.unoccluded = uploadTexture(gl, t.width, t.height, fin, true, &t.source);
    s.origin = glm::vec2(t.origin);
    s.texel = float(t.texel);
    s.size = glm::vec2(std::max(1, t.width), std::max(1, t.height));
    im.textures.push_back(s);
  }
  if (const Photo* ph = scene.findPhoto(data.photo)) im.photoCamera = ph->camera;
  im.hasGlow = data.glow.width > 0 && data.glowLamp.size() == size_t(data.glow.width) * data.glow.height;
  if (im.hasGlow) {
    im.glow = uploadTexture(gl, data.glow.width, data.glow.height, data.glow.pixels.data(), false);
    std::vector<float> which(data.glowLamp.size() * 3);
    for (size_t k = 0; k < data.glowLamp.size(); ++k) which[3 * k] = which[3 * k + 1] = which[3 * k + 2] = float(data.glowLamp[k]);
    im.glowLamp = uploadTexture(gl, data.glow.width, data.glow.height, which.data(), false);
  }
  im.meshReady = im.lightingReady = false;
}

void GlRelightRenderer::setMesh(const RelightSession& session) {
  auto& im = *impl_;
  auto& gl = *im.gl;
  im.mesh = session.displayMesh();
  im.boundsLo = glm::vec3(1e30f);
  im.boundsHi = glm::vec3(-1e30f);
  for (const auto& v : im.mesh.vertices) {
    im.boundsLo = glm::min(im.boundsLo, v.position);
    im.boundsHi = glm::max(im.boundsHi, v.position);
  }
  gl.glBindBuffer(GL_ARRAY_BUFFER, im.vbo);
  gl.glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(im.mesh.vertices.size() * sizeof(DisplayMesh::Vertex)),
                  im.mesh.vertices.data(), GL_STATIC_DRAW);
  gl.glBindBuffer(GL_TEXTURE_BUFFER, im.rectBuffer);
  gl.glBufferData(GL_TEXTURE_BUFFER, GLsizeiptr(im.mesh.leafRect.size() * sizeof(glm::vec4)), im.mesh.leafRect.data(),
                  GL_STATIC_DRAW);
  gl.glBindTexture(GL_TEXTURE_BUFFER, im.rectTexture);
  gl.glTexBuffer(GL_TEXTURE_BUFFER, GL_RGBA32F, im.rectBuffer);
  GLint maxTexels = 0;
  gl.glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
  if (size_t(maxTexels) < im.mesh.leafNode.size() * kDisplayCornerTexels)
    throw Error("", "OpenGL", "the mesh's " + std::to_string(im.mesh.leafNode.size()) +
                                  " leaves exceed the display's texture-buffer size");
  im.meshReady = true;
  setLighting(session);
}

void GlRelightRenderer::setLighting(const RelightSession& session) {
  auto& im = *impl_;
  auto& gl = *im.gl;
  const auto corners = session.displayCorners(im.mesh);
  gl.glBindBuffer(GL_TEXTURE_BUFFER, im.cornerBuffer);
  gl.glBufferData(GL_TEXTURE_BUFFER, GLsizeiptr(corners.size() * sizeof(glm::vec4)), corners.data(), GL_DYNAMIC_DRAW);
  gl.glBindTexture(GL_TEXTURE_BUFFER, im.cornerTexture);
  gl.glTexBuffer(GL_TEXTURE_BUFFER, GL_RGBA32F, im.cornerBuffer);
  gl.glBindBuffer(GL_TEXTURE_BUFFER, 0);
  im.lampScale.resize(session.lampCount());
  for (size_t l = 0; l < im.lampScale.size(); ++l) im.lampScale[l] = glm::vec3(session.lampScale(int(l)));
  im.lightingReady = true;
}

bool GlRelightRenderer::ready() const { return impl_->meshReady && impl_->lightingReady; }
size_t GlRelightRenderer::leafCount() const { return impl_->mesh.leafNode.size(); }
double GlRelightRenderer::lastDrawMilliseconds() const { return impl_->lastMs; }

void GlRelightRenderer::draw(const Camera& camera, ViewMode mode, const DisplaySettings& display, unsigned target,
                             const ViewRect& rect) {
  auto& im = *impl_;
  if (rect.width <= 0 || rect.height <= 0) return;
  im.gl->glFinish();
  const auto t0 = std::chrono::steady_clock::now();
  im.drawLinear(camera, mode, rect.width, rect.height);
  im.present(camera, display, target, rect);
  im.gl->glFinish();
  im.lastMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

ImageRGB GlRelightRenderer::renderLinear(const Camera& camera, ViewMode mode) {
  auto& im = *impl_;
  im.readback.ensure(*im.gl, camera.width, camera.height);
  DisplaySettings linear;
  linear.output = DisplayOutput::Linear;
  draw(camera, mode, linear, im.readback.fbo, {0, 0, camera.width, camera.height});
  std::vector<float> rgba(size_t(camera.width) * camera.height * 4);
  im.gl->glBindFramebuffer(GL_FRAMEBUFFER, im.readback.fbo);
  im.gl->glPixelStorei(GL_PACK_ALIGNMENT, 4);
  im.gl->glReadPixels(0, 0, camera.width, camera.height, GL_RGBA, GL_FLOAT, rgba.data());
  ImageRGB img(camera.width, camera.height);
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x) {
      const float* p = &rgba[(size_t(camera.height - 1 - y) * camera.width + x) * 4];
      img.set(x, y, {p[0], p[1], p[2]});
    }
  return img;
}

}  // namespace relume
