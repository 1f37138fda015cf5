// The workbench's relighting renderer: the session's display mesh, photo textures and corner
// values on the GPU; texture x B / D with B and D per vertex (shaders/relight.vert), and the
// display transform, in one pass (shaders/relight.frag): on llvmpipe every full-screen pass
// costs about as much as the shading itself, so there is no second one.
#include "relume/viewport/gl_renderer.h"

#include "gl_common.h"
#include "gl_fans.h"

#include <QFile>
#include <QOpenGLContext>
#include <QOpenGLFunctions_3_3_Core>
#include <QOpenGLShaderProgram>
#include <QOpenGLVersionFunctionsFactory>
#include <algorithm>
#include <chrono>
#include <glm/mat4x4.hpp>
#include <glm/geometric.hpp>
#include <map>
#include <set>
#include <vector>

#include "relume/geometry/error.h"
#include "relume/geometry/polygon.h"
#include "relume/geometry/scene.h"
#include "relume/ibr/ibr_object.h"
#include "relume/ibr/relit_objects.h"
#include "relume/relight/relighter.h"

static void initShaderResources() { Q_INIT_RESOURCE(shaders); }

namespace relume {

namespace {

constexpr int kMaxLamps = 32;
// Image-based objects: lamps an object is lit by (their tables, own shadows), as many as the shader takes.
constexpr int kObjectLamps = 8;

struct SurfaceTextures {
  GLuint original = 0, unoccluded = 0;
  glm::vec2 origin{0.f}, size{1.f};
  float texel = 1.f;
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

bool sameCamera(const Camera& a, const Camera& b) {
  return a.width == b.width && a.height == b.height && a.K == b.K && a.R == b.R && a.t == b.t;
}

}  // namespace

struct GlRelightRenderer::Impl {
  QOpenGLFunctions_3_3_Core* gl = nullptr;
  QByteArray vertexSource, fragmentSource, displaySource;
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
  gl::FloatTarget readback;
  double lastMs = 0;

  // --- image-based objects ---
  gl::FanObjects fans{kObjectLamps, false};
  struct ShadowMap {  // the objects' shadows over one surface (ibr::shadowMaps)
    GLuint texture = 0;
    glm::vec4 frame{0.f};  // origin u, v; 1 / width, 1 / height (metres)
  };
  std::map<int, ShadowMap> shadowMaps;  // by engine surface
  // Each object's own maps, kept while it stays where it is and the room's light and mesh stay
  // (lightVersion counts their changes): a drag recomputes the moved object's alone.
  struct ObjectShadowMaps {
    std::shared_ptr<const ibr::ImageFan> fan;
    ibr::Placement place;
    uint64_t version = 0;
    std::vector<ibr::SurfaceShadow> maps;
  };
  std::vector<ObjectShadowMaps> shadowCache;
  uint64_t lightVersion = 1;
  void releaseObjects() {
    fans.release();
    releaseShadowMaps();
  }

  void releaseShadowMaps() {
    for (auto& [s, m] : shadowMaps) gl->glDeleteTextures(1, &m.texture);
    shadowMaps.clear();
  }

  // A program of `defines` + the vertex source, and `defines` + the display transform + the
  // fragment source; the shader log, naming `name`, when it does not compile or link.
  std::unique_ptr<QOpenGLShaderProgram> compile(const QByteArray& defines, const QByteArray& vertex,
                                                const QByteArray& fragment, const char* name) const {
    auto q = std::make_unique<QOpenGLShaderProgram>();
    if (!q->addShaderFromSourceCode(QOpenGLShader::Vertex, defines + vertex) ||
        !q->addShaderFromSourceCode(QOpenGLShader::Fragment, defines + displaySource + fragment) || !q->link())
      throw Error(name, "shader", q->log().toStdString());
    return q;
  }

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
  QOpenGLShaderProgram& program(ViewMode mode, DisplayOutput output, bool glowOn, bool checker, bool shadows = false) {
    const int key = int(mode) * 32 + int(output) * 8 + (glowOn ? 4 : 0) + (checker ? 2 : 0) + (shadows ? 1 : 0);
    auto& p = programs[key];
    if (!p) {
      const QByteArray defines = "#version 330 core\n#define MODE " + QByteArray::number(int(mode)) + "\n#define OUTPUT " +
                                 QByteArray::number(int(output)) + "\n#define GLOW " + QByteArray::number(glowOn ? 1 : 0) +
                                 "\n#define CHECKER " + QByteArray::number(checker ? 1 : 0) +
                                 "\n#define SHADOWS " + QByteArray::number(shadows ? 1 : 0) + "\n";
      p = compile(defines, vertexSource, fragmentSource, ":/shaders/relight.frag");
    }
    return *p;
  }

  void drawView(const Camera& camera, ViewMode mode, const DisplaySettings& s, GLuint target, const ViewRect& rect) {
    gl->glBindFramebuffer(GL_FRAMEBUFFER, target);
    // The whole target (a scissored clear is a full-screen draw on llvmpipe): black where the
    // values are radiance, the workbench's grey on a display.
    gl->glDisable(GL_SCISSOR_TEST);
    gl->glDisable(GL_BLEND);
    gl->glDisable(GL_CULL_FACE);
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
    farZ = std::max(farZ, fans.reach(eye));
    farZ = farZ * 1.05 + 0.1;
    const double nearZ = std::clamp(farZ * 1e-3, 0.005, 0.05);
    const bool glowOn = hasGlow && sameCamera(camera, photoCamera);
    const bool objectsShown = !fans.empty() && (mode == ViewMode::Relit || mode == ViewMode::RatioOnly);
    const bool shadows = objectsShown && !shadowMaps.empty();
    // Only the surfaces a shadow reaches take the shadow-map fetch: a texture fetch costs every
    // fragment of a surface on llvmpipe (a branch on a uniform does not skip it), and the floor's
    // map should not cost the walls and the ceiling.
    // Away from the photo's own view, texels no photo saw are drawn as a checker.
    const bool checker = !sameCamera(camera, photoCamera);
    QOpenGLShaderProgram* plain = &program(mode, s.output, glowOn, checker, false);
    QOpenGLShaderProgram* shadowing = shadows ? &program(mode, s.output, glowOn, checker, true) : nullptr;
    const glm::mat4 clip = gl::worldToClip(camera, nearZ, farZ);
    for (QOpenGLShaderProgram* relight : {plain, shadowing}) {
      if (!relight) continue;
      relight->bind();
      relight->setUniformValue("worldToClip", QMatrix4x4(&glm::transpose(clip)[0][0]));
      relight->setUniformValue("corners", 0);
      relight->setUniformValue("rects", 1);
      relight->setUniformValue("original", 2);
      relight->setUniformValue("unoccluded", 3);
      relight->setUniformValue("glow", 4);
      if (relight == shadowing) relight->setUniformValue("shadowMap", 5);
      if (glowOn) {
        relight->setUniformValue("glowBox", QVector4D(glowBox.x, glowBox.y, glowBox.z, glowBox.w));
        std::vector<GLfloat> scales(3 * kMaxLamps, 1.f);
        for (size_t l = 0; l < lampScale.size() && l < size_t(kMaxLamps); ++l)
          for (int c = 0; c < 3; ++c) scales[3 * l + c] = lampScale[l][c];
        relight->setUniformValueArray("lampScale", scales.data(), kMaxLamps, 3);
      }
      relight->setUniformValue("viewOrigin", QVector2D(float(rect.x), float(rect.y)));
      relight->setUniformValue("viewSize", QVector2D(float(rect.width), float(rect.height)));
      relight->setUniformValue("exposure", float(s.exposure));
      relight->setUniformValue("falseMin", float(s.falseMin));
      relight->setUniformValue("falseMax", float(s.falseMax));
    }
    if (glowOn) {
      gl->glActiveTexture(GL_TEXTURE4);
      gl->glBindTexture(GL_TEXTURE_2D, glow);
    }
    gl->glActiveTexture(GL_TEXTURE0);
    gl->glBindTexture(GL_TEXTURE_BUFFER, cornerTexture);
    gl->glActiveTexture(GL_TEXTURE1);
    gl->glBindTexture(GL_TEXTURE_BUFFER, rectTexture);
    gl->glBindVertexArray(vao);
    QOpenGLShaderProgram* bound = shadowing ? shadowing : plain;  // (the last one set up above)
    for (const auto& r : mesh.ranges) {
      const auto m = !shadows || r.kind == DisplaySurfaceKind::Window ? shadowMaps.end() : shadowMaps.find(r.surface);
      QOpenGLShaderProgram* relight = m == shadowMaps.end() ? plain : shadowing;
      if (relight != bound) {
        relight->bind();
        bound = relight;
      }
      relight->setUniformValue("kind", int(r.kind));
      if (m != shadowMaps.end()) {
        gl->glActiveTexture(GL_TEXTURE5);
        gl->glBindTexture(GL_TEXTURE_2D, m->second.texture);
        relight->setUniformValue("shadowFrame", QVector4D(m->second.frame.x, m->second.frame.y, m->second.frame.z, m->second.frame.w));
      }
      // A range lies in its surface's plane: the camera sees all of its front or all of its back.
      const glm::vec3 p0 = r.count ? mesh.vertices[mesh.indices[r.first]].position : glm::vec3(0.f);
      relight->setUniformValue("front", glm::dot(glm::dvec3(p0) - eye, glm::dvec3(r.normal)) > 0.0 ? 0.f : 1.f);
      if (size_t(r.surface) < textures.size()) {
        const auto& t = textures[r.surface];
        gl->glActiveTexture(GL_TEXTURE2);
        gl->glBindTexture(GL_TEXTURE_2D, t.original);
        gl->glActiveTexture(GL_TEXTURE3);
        gl->glBindTexture(GL_TEXTURE_2D, t.unoccluded);
        relight->setUniformValue("texOrigin", QVector2D(t.origin.x, t.origin.y));
        relight->setUniformValue("texExtent", QVector2D(t.texel * t.size.x, t.texel * t.size.y));
      } else {  // (texture coordinates = plane coordinates: the shader's uv is exact)
        relight->setUniformValue("texOrigin", QVector2D(0.f, 0.f));
        relight->setUniformValue("texExtent", QVector2D(1.f, 1.f));
      }
      gl->glDrawElements(GL_TRIANGLES, GLsizei(r.count), GL_UNSIGNED_INT,
                         reinterpret_cast<const void*>(r.first * sizeof(uint32_t)));
    }
    gl->glBindVertexArray(0);
    bound->release();
    if (objectsShown) {
      try {
        fans.draw(camera, clip, s);
      } catch (...) {  // (a fan view that cannot be read): the state the room's pass expects, then the error
        gl->glBindVertexArray(0);
        gl->glDisable(GL_CULL_FACE);
        gl->glDisable(GL_BLEND);
        gl->glDisable(GL_DEPTH_TEST);
        gl->glActiveTexture(GL_TEXTURE0);
        gl->glUseProgram(0);
        throw;
      }
    }
    gl->glDisable(GL_DEPTH_TEST);
    gl->glActiveTexture(GL_TEXTURE0);
  }
};

GlRelightRenderer::GlRelightRenderer() : impl_(std::make_unique<Impl>()) {}

GlRelightRenderer::~GlRelightRenderer() {
  auto& im = *impl_;
  if (!im.gl || !QOpenGLContext::currentContext()) return;  // the context went first: GL frees it all
  im.releaseRoom();
  im.releaseObjects();
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
  im.gl = gl::currentFunctions();
  auto read = [](const char* name) { return gl::shaderSource(name); };
  im.vertexSource = read(":/shaders/relight.vert");
  im.fragmentSource = read(":/shaders/relight.frag");
  im.displaySource = read(":/shaders/display.glsl");
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
  im.fans.initialize(im.gl, im.displaySource);
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
  ++im.lightVersion;
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
  ++im.lightVersion;  // (setMesh comes here too) the objects' shadows are to be made anew
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

void GlRelightRenderer::setImageObjects(const std::vector<ibr::ImageObject>& objects,
                                        const std::vector<ibr::ObjectLighting>& lights,
                                        const radiosity::HierarchicalRadiosity& engine) {
  auto& im = *impl_;
  auto& gl = *im.gl;
  im.fans.set(objects, lights);
  // Their shadows on the room, as maps over the surfaces (the library's light).
  im.releaseShadowMaps();
  std::vector<Impl::ObjectShadowMaps> cache;
  for (size_t i = 0; i < objects.size() && i < lights.size(); ++i) {
    const auto& p = objects[i].place;
    Impl::ObjectShadowMaps c{objects[i].fan, p, im.lightVersion, {}};
    bool found = false;
    for (auto& old : im.shadowCache)
      if (!found && old.fan == c.fan && old.version == c.version && old.place.position == p.position &&
          old.place.scale == p.scale && old.place.yaw == p.yaw) {
        c.maps = std::move(old.maps);
        old.fan.reset();  // taken
        found = true;
      }
    if (!found) c.maps = ibr::shadowMaps(engine, {objects[i]}, {lights[i]});
    cache.push_back(std::move(c));
  }
  im.shadowCache = std::move(cache);
  std::vector<const std::vector<ibr::SurfaceShadow>*> parts;
  for (const auto& c : im.shadowCache) parts.push_back(&c.maps);
  for (const auto& m : ibr::multiplyShadowMaps(parts)) {
    Impl::ShadowMap t;
    gl.glGenTextures(1, &t.texture);
    gl.glBindTexture(GL_TEXTURE_2D, t.texture);
    // The share kept lies in [0, 1]: 8 bits a channel (steps of 0.4 % of the light, below what a
    // display shows) sample several times faster on llvmpipe than a float texture.
    std::vector<uint8_t> keep(m.keep.size() * 4, 255);
    for (size_t i = 0; i < m.keep.size(); ++i)
      for (int c = 0; c < 3; ++c) keep[4 * i + size_t(c)] = uint8_t(std::lround(std::clamp(m.keep[i][c], 0.f, 1.f) * 255.f));
    gl.glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    gl.glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, m.width, m.height, 0, GL_RGBA, GL_UNSIGNED_BYTE, keep.data());
    gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    t.frame = glm::vec4(float(m.origin.x), float(m.origin.y), float(1.0 / (m.texel * m.width)), float(1.0 / (m.texel * m.height)));
    im.shadowMaps[m.surface] = t;
  }
}

size_t GlRelightRenderer::imageObjectCount() const { return impl_->fans.size(); }

}  // namespace relume
