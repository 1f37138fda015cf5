// The workbench's relighting renderer: the session's display mesh, photo textures and corner
// values on the GPU; texture x B / D with B and D per vertex (shaders/relight.vert), and the
// display transform, in one pass (shaders/relight.frag): on llvmpipe every full-screen pass
// costs about as much as the shading itself, so there is no second one.
#include "relume/viewport/gl_renderer.h"

#include <QFile>
#include <QOpenGLContext>
#include <QOpenGLFunctions_3_3_Core>
#include <QOpenGLShaderProgram>
#include <QOpenGLVersionFunctionsFactory>
#include <algorithm>
#include <chrono>
#include <glm/mat4x4.hpp>
#include <map>
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

// An RGBA float texture: `rgb` per texel and `alpha(texel)` (for the photo textures whether a
// photo saw the texel, for the glow its lamp).
template <class Alpha>
GLuint uploadTexture(QOpenGLFunctions_3_3_Core& gl, int w, int h, const float* rgb, bool linear, Alpha alpha) {
  static const float black[3] = {0.f, 0.f, 0.f};
  const bool empty = w <= 0 || h <= 0 || !rgb;
  if (empty) {
    w = h = 1;
    rgb = black;
  }
  std::vector<float> rgba(size_t(w) * h * 4);
  for (size_t i = 0; i < size_t(w) * h; ++i) {
    for (int c = 0; c < 3; ++c) rgba[4 * i + c] = rgb[3 * i + c];
    rgba[4 * i + 3] = empty ? 1.f : alpha(i);
  }
  GLuint id = 0;
  gl.glGenTextures(1, &id);
  gl.glBindTexture(GL_TEXTURE_2D, id);
  gl.glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  gl.glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, w, h, 0, GL_RGBA, GL_FLOAT, rgba.data());
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
  QByteArray vertexSource, fragmentSource;
  std::map<int, std::unique_ptr<QOpenGLShaderProgram>> programs;  // by variant
  GLuint vao = 0, vbo = 0, ebo = 0, lightVbo = 0;
  GLuint cornerBuffer = 0, cornerTexture = 0, rectBuffer = 0, rectTexture = 0;
  GLuint glow = 0;
  bool hasGlow = false;
  glm::vec4 glowBox{0.f};  // the glow's pixels, as texture coordinates x0, y0, x1, y1
  Camera photoCamera;
  std::vector<SurfaceTextures> textures;  // per scene polygon
  DisplayMesh mesh;
  bool meshReady = false, lightingReady = false;
  glm::vec3 boundsLo{0.f}, boundsHi{0.f};
  std::vector<glm::vec3> lampScale;
  FloatTarget readback;
  double lastMs = 0;

  void releaseRoom() {
    for (auto& t : textures) {
      gl->glDeleteTextures(1, &t.original);
      gl->glDeleteTextures(1, &t.unoccluded);
    }
    textures.clear();
    if (glow) gl->glDeleteTextures(1, &glow);
    glow = 0;
    hasGlow = false;
  }

  // The program for a view mode, output, glow on or off and checker on or off, compiled on first use.
  QOpenGLShaderProgram& program(ViewMode mode, DisplayOutput output, bool glowOn, bool checker) {
    const int key = int(mode) * 16 + int(output) * 4 + (glowOn ? 2 : 0) + (checker ? 1 : 0);
    auto& p = programs[key];
    if (!p) {
      const QByteArray defines = "#version 330 core\n#define MODE " + QByteArray::number(int(mode)) + "\n#define OUTPUT " +
                                 QByteArray::number(int(output)) + "\n#define GLOW " + QByteArray::number(glowOn ? 1 : 0) +
                                 "\n#define CHECKER " + QByteArray::number(checker ? 1 : 0) + "\n";
      auto q = std::make_unique<QOpenGLShaderProgram>();
      if (!q->addShaderFromSourceCode(QOpenGLShader::Vertex, defines + vertexSource) ||
          !q->addShaderFromSourceCode(QOpenGLShader::Fragment, defines + fragmentSource) || !q->link())
        throw Error(":/shaders/relight.frag", "shader", q->log().toStdString());
      p = std::move(q);
    }
    return *p;
  }

  void drawView(const Camera& camera, ViewMode mode, const DisplaySettings& s, GLuint target, const ViewRect& rect) {
    gl->glBindFramebuffer(GL_FRAMEBUFFER, target);
    // The whole target (a scissored clear is a full-screen draw on llvmpipe): black where the
    // values are radiance, the workbench's grey on a display.
    gl->glDisable(GL_SCISSOR_TEST);
    gl->glDisable(GL_BLEND);
    if (s.output == DisplayOutput::Linear) gl->glClearColor(0.f, 0.f, 0.f, 1.f);
    else gl->glClearColor(0.16f, 0.16f, 0.17f, 1.f);
    gl->glClearDepth(1.0);
    gl->glDepthMask(GL_TRUE);
    gl->glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    gl->glViewport(rect.x, rect.y, rect.width, rect.height);
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
    const bool glowOn = hasGlow && sameCamera(camera, photoCamera);
    // Away from the photo's own view, texels no photo saw are drawn as a checker.
    auto& relight = program(mode, s.output, glowOn, !sameCamera(camera, photoCamera));
    relight.bind();
    relight.setUniformValue("worldToClip", QMatrix4x4(&glm::transpose(worldToClip(camera, nearZ, farZ))[0][0]));
    relight.setUniformValue("eye", QVector3D(float(eye.x), float(eye.y), float(eye.z)));
    relight.setUniformValue("corners", 0);
    relight.setUniformValue("rects", 1);
    relight.setUniformValue("original", 2);
    relight.setUniformValue("unoccluded", 3);
    relight.setUniformValue("glow", 4);
    if (glowOn) {
      gl->glActiveTexture(GL_TEXTURE4);
      gl->glBindTexture(GL_TEXTURE_2D, glow);
      relight.setUniformValue("glowBox", QVector4D(glowBox.x, glowBox.y, glowBox.z, glowBox.w));
      std::vector<GLfloat> scales(3 * kMaxLamps, 1.f);
      for (size_t l = 0; l < lampScale.size() && l < size_t(kMaxLamps); ++l)
        for (int c = 0; c < 3; ++c) scales[3 * l + c] = lampScale[l][c];
      relight.setUniformValueArray("lampScale", scales.data(), kMaxLamps, 3);
    }
    relight.setUniformValue("viewOrigin", QVector2D(float(rect.x), float(rect.y)));
    relight.setUniformValue("viewSize", QVector2D(float(rect.width), float(rect.height)));
    relight.setUniformValue("exposure", float(s.exposure));
    relight.setUniformValue("falseMin", float(s.falseMin));
    relight.setUniformValue("falseMax", float(s.falseMax));
    gl->glActiveTexture(GL_TEXTURE0);
    gl->glBindTexture(GL_TEXTURE_BUFFER, cornerTexture);
    gl->glActiveTexture(GL_TEXTURE1);
    gl->glBindTexture(GL_TEXTURE_BUFFER, rectTexture);
    gl->glBindVertexArray(vao);
    for (const auto& r : mesh.ranges) {
      relight.setUniformValue("kind", int(r.kind));
      relight.setUniformValue("normal", QVector3D(r.normal.x, r.normal.y, r.normal.z));
      if (size_t(r.surface) < textures.size()) {
        const auto& t = textures[r.surface];
        gl->glActiveTexture(GL_TEXTURE2);
        gl->glBindTexture(GL_TEXTURE_2D, t.original);
        gl->glActiveTexture(GL_TEXTURE3);
        gl->glBindTexture(GL_TEXTURE_2D, t.unoccluded);
        relight.setUniformValue("texOrigin", QVector2D(t.origin.x, t.origin.y));
        relight.setUniformValue("texelSize", t.texel);
        relight.setUniformValue("texSize", QVector2D(t.size.x, t.size.y));
      }
      gl->glDrawElements(GL_TRIANGLES, GLsizei(r.count), GL_UNSIGNED_INT,
                         reinterpret_cast<const void*>(r.first * sizeof(uint32_t)));
    }
    gl->glBindVertexArray(0);
    gl->glDisable(GL_DEPTH_TEST);
    gl->glActiveTexture(GL_TEXTURE0);
    relight.release();
  }
};

GlRelightRenderer::GlRelightRenderer() : impl_(std::make_unique<Impl>()) {}

GlRelightRenderer::~GlRelightRenderer() {
  auto& im = *impl_;
  if (!im.gl || !QOpenGLContext::currentContext()) return;  // the context went first: GL frees it all
  im.releaseRoom();
  im.readback.release(*im.gl);
  for (GLuint* b : {&im.vbo, &im.ebo, &im.lightVbo, &im.cornerBuffer, &im.rectBuffer})
    if (*b) im.gl->glDeleteBuffers(1, b);
  for (GLuint* t : {&im.cornerTexture, &im.rectTexture})
    if (*t) im.gl->glDeleteTextures(1, t);
  if (im.vao) im.gl->glDeleteVertexArrays(1, &im.vao);
}

void GlRelightRenderer::initialize() {
  initShaderResources();
  auto& im = *impl_;
  QOpenGLContext* ctx = QOpenGLContext::currentContext();
  if (!ctx) throw Error("", "OpenGL", "no current context");
  im.gl = QOpenGLVersionFunctionsFactory::get<QOpenGLFunctions_3_3_Core>(ctx);
  if (!im.gl || !im.gl->initializeOpenGLFunctions())
    throw Error("", "OpenGL", "the display does not offer OpenGL 3.3 core");
  auto read = [](const char* name) {
    QFile f(name);
    if (!f.open(QIODevice::ReadOnly)) throw Error(name, "shader", "missing from the binary's resources");
    return f.readAll();
  };
  im.vertexSource = read(":/shaders/relight.vert");
  im.fragmentSource = read(":/shaders/relight.frag");
  im.programs.clear();
  im.program(ViewMode::Relit, DisplayOutput::Exposed, true, false);  // the usual view: errors show now
  auto& gl = *im.gl;
  gl.glGenVertexArrays(1, &im.vao);
  gl.glGenBuffers(1, &im.vbo);
  gl.glGenBuffers(1, &im.ebo);
  gl.glGenBuffers(1, &im.lightVbo);
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
  gl.glBindBuffer(GL_ARRAY_BUFFER, im.lightVbo);
  for (GLuint k = 0; k < 3; ++k) {
    gl.glEnableVertexAttribArray(3 + k);
    gl.glVertexAttribPointer(3 + k, 3, GL_FLOAT, GL_FALSE, kDisplayVertexLight * sizeof(float),
                             reinterpret_cast<void*>(3 * k * sizeof(float)));
  }
  gl.glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, im.ebo);  // part of the vertex array's state
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
    const bool known = t.source.size() == size_t(std::max(0, t.width)) * size_t(std::max(0, t.height));
    auto seen = [&](size_t i) { return known && t.source[i] == TexelSource::Smooth ? 0.f : 1.f; };
    s.original = uploadTexture(gl, t.width, t.height, orig, true, seen);
    s.unoccluded = uploadTexture(gl, t.width, t.height, fin, true, seen);
    s.origin = glm::vec2(t.origin);
    s.texel = float(t.texel);
    s.size = glm::vec2(std::max(1, t.width), std::max(1, t.height));
    im.textures.push_back(s);
  }
  if (const Photo* ph = scene.findPhoto(data.photo)) im.photoCamera = ph->camera;
  im.hasGlow = data.glow.width > 0 && data.glowLamp.size() == size_t(data.glow.width) * data.glow.height;
  if (im.hasGlow) {
    const int w = data.glow.width, h = data.glow.height;
    im.glow = uploadTexture(gl, w, h, data.glow.pixels.data(), false, [&](size_t i) { return float(data.glowLamp[i]); });
    // The pixels that have glow, so that the fragments elsewhere skip the lookup.
    int x0 = w, y0 = h, x1 = 0, y1 = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        if (data.glowLamp[size_t(y) * w + x] >= 0) {
          x0 = std::min(x0, x);
          y0 = std::min(y0, y);
          x1 = std::max(x1, x + 1);
          y1 = std::max(y1, y + 1);
        }
    im.glowBox = x1 > x0 ? glm::vec4(float(x0) / w, float(y0) / h, float(x1) / w, float(y1) / h) : glm::vec4(0.f);
    im.hasGlow = x1 > x0;
  }
  im.meshReady = im.lightingReady = false;
}

void GlRelightRenderer::setMesh(const RelightSession& session) {
  auto& im = *impl_;
  auto& gl = *im.gl;
  im.meshReady = im.lightingReady = false;  // until the whole mesh is up
  im.mesh = session.displayMesh();
  GLint maxTexels = 0;
  gl.glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &maxTexels);
  if (size_t(maxTexels) < im.mesh.leafNode.size() * kDisplayCornerTexels)
    throw Error("", "OpenGL", "the mesh's " + std::to_string(im.mesh.leafNode.size()) +
                                  " leaves exceed the display's texture-buffer size");
  im.boundsLo = glm::vec3(1e30f);
  im.boundsHi = glm::vec3(-1e30f);
  for (const auto& v : im.mesh.vertices) {
    im.boundsLo = glm::min(im.boundsLo, v.position);
    im.boundsHi = glm::max(im.boundsHi, v.position);
  }
  gl.glBindBuffer(GL_ARRAY_BUFFER, im.vbo);
  gl.glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(im.mesh.vertices.size() * sizeof(DisplayMesh::Vertex)),
                  im.mesh.vertices.data(), GL_STATIC_DRAW);
  gl.glBindVertexArray(im.vao);
  gl.glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, im.ebo);
  gl.glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(im.mesh.indices.size() * sizeof(uint32_t)), im.mesh.indices.data(),
                  GL_STATIC_DRAW);
  gl.glBindVertexArray(0);
  gl.glBindBuffer(GL_TEXTURE_BUFFER, im.rectBuffer);
  gl.glBufferData(GL_TEXTURE_BUFFER, GLsizeiptr(im.mesh.leafRect.size() * sizeof(glm::vec4)), im.mesh.leafRect.data(),
                  GL_STATIC_DRAW);
  gl.glBindTexture(GL_TEXTURE_BUFFER, im.rectTexture);
  gl.glTexBuffer(GL_TEXTURE_BUFFER, GL_RGBA32F, im.rectBuffer);
  // The corner values serve the references view (the §4.3 category, which changes only with the
  // mesh); the light itself travels per vertex.
  const auto corners = session.displayCorners(im.mesh);
  gl.glBindBuffer(GL_TEXTURE_BUFFER, im.cornerBuffer);
  gl.glBufferData(GL_TEXTURE_BUFFER, GLsizeiptr(corners.size() * sizeof(glm::vec4)), corners.data(), GL_STATIC_DRAW);
  gl.glBindTexture(GL_TEXTURE_BUFFER, im.cornerTexture);
  gl.glTexBuffer(GL_TEXTURE_BUFFER, GL_RGBA32F, im.cornerBuffer);
  gl.glBindBuffer(GL_TEXTURE_BUFFER, 0);
  im.meshReady = true;
  setLighting(session);
}

void GlRelightRenderer::setLighting(const RelightSession& session) {
  auto& im = *impl_;
  auto& gl = *im.gl;
  const auto light = session.displayVertexLight(im.mesh);
  gl.glBindBuffer(GL_ARRAY_BUFFER, im.lightVbo);
  gl.glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(light.size() * sizeof(float)), light.data(), GL_DYNAMIC_DRAW);
  gl.glBindBuffer(GL_ARRAY_BUFFER, 0);
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
  im.drawView(camera, mode, display, target, rect);
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
