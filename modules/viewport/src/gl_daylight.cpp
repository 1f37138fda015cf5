// The daylight viewport's renderer: see gl_daylight.h. One pass per shadow map (the room, then the
// objects, into two channels of one layer), then the room and the objects through the photo's
// camera (shaders/daylight.vert, daylight.frag) with the display transform in the same pass.
#include "relume/viewport/gl_daylight.h"

#include <QFile>
#include <QMatrix4x4>
#include <QOpenGLContext>
#include <QOpenGLFunctions_3_3_Core>
#include <QOpenGLShaderProgram>
#include <QOpenGLVersionFunctionsFactory>
#include <algorithm>
#include <chrono>
#include <functional>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <map>

#include "gl_common.h"
#include "gl_fans.h"
#include "relume/daylight/relight.h"
#include "relume/geometry/error.h"
#include "relume/geometry/polygon.h"
#include "relume/ibr/relit_objects.h"

static void initDaylightShaderResources() { Q_INIT_RESOURCE(shaders); }

namespace relume {

namespace {

// Vertex layout of the view pass: position, face normal, front and back indirect light, albedo.
constexpr int kFloats = 15;
// Lamps an image-based object is lit by in daylight (ibr::daylightAt: a lamp per window sample it
// sees, and the sun): the strongest this many.
constexpr int kImageLamps = 128;

void fanTriangles(const std::vector<glm::dvec3>& v, const std::function<void(size_t)>& corner) {
  for (size_t t = 1; t + 1 < v.size(); ++t) {
    corner(0);
    corner(t);
    corner(t + 1);
  }
}

GLuint floatTexture(QOpenGLFunctions_3_3_Core& gl, int w, int h, GLenum internal, GLenum format, const float* data,
                    GLenum filter) {
  GLuint id = 0;
  gl.glGenTextures(1, &id);
  gl.glBindTexture(GL_TEXTURE_2D, id);
  gl.glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  gl.glTexImage2D(GL_TEXTURE_2D, 0, GLint(internal), w, h, 0, format, GL_FLOAT, data);
  gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GLint(filter));
  gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GLint(filter));
  gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return id;
}

// A shadow map's camera: its matrix, origin, the direction of the light (orthographic) or the
// window's normal (perspective), and a texel's width per metre of distance (perspective) or in
// metres (orthographic).
struct MapCamera {
  glm::mat4 clip{1.f};
  glm::vec4 reach{0.f};  // perspective: the cone's axis and cos(half-angle); orthographic: w the cylinder's radius
  glm::vec3 origin{0.f}, direction{0.f};
  float footprint = 0, area = 0;
  bool ortho = false;
};

// A perspective map from `from` around the sphere (centre, radius); from inside the sphere, a wide
// one along `normal` (the window's, into the room).
MapCamera windowMap(const glm::dvec3& from, const glm::dvec3& normal, double area, const glm::dvec3& centre, double radius,
                    int size) {
  MapCamera m;
  m.origin = glm::vec3(from);
  m.direction = glm::vec3(normal);
  m.area = float(area);
  glm::dvec3 axis = centre - from;
  const double d = glm::length(axis);
  double half;
  if (d > 1.25 * radius) {  // (half-angle under 57 degrees: a narrower map holds the sphere well)
    axis /= d;
    half = std::asin(1.05 * radius / d) * 1.02;
  } else {  // at or inside the sphere: a wide map along the window's normal (directions beyond 80 degrees from it left out)
    axis = normal;
    half = 80.0 * 3.14159265358979 / 180.0;
  }
  const glm::dvec3 up = std::abs(axis.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
  const glm::dmat4 view = glm::lookAt(from, from + axis, up);
  const glm::dmat4 proj = glm::perspective(2 * half, 1.0, 0.002, 500.0);
  m.clip = glm::mat4(proj * view);
  m.footprint = float(2 * std::tan(half) / size);
  m.reach = glm::vec4(glm::vec3(axis), float(std::cos(half * std::sqrt(2.0))));  // (the square's corners)
  return m;
}

// An orthographic map along the sun's direction `toSun` around the sphere, from well beyond the room.
MapCamera sunMap(const glm::dvec3& toSun, const glm::dvec3& centre, double radius, int size) {
  MapCamera m;
  const glm::dvec3 s = glm::normalize(toSun);
  const glm::dvec3 from = centre + 200.0 * s;
  m.origin = glm::vec3(from);
  m.direction = glm::vec3(-s);
  m.ortho = true;
  const double r = 1.05 * radius;
  const glm::dvec3 up = std::abs(s.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
  const glm::dmat4 view = glm::lookAt(from, centre, up);
  const glm::dmat4 proj = glm::ortho(-r, r, -r, r, 0.0, 500.0);
  m.clip = glm::mat4(proj * view);
  m.footprint = float(2 * r / size);
  m.reach = glm::vec4(0.f, 0.f, 0.f, float(r * std::sqrt(2.0)));
  return m;
}

}  // namespace

struct GlDaylightRenderer::Impl {
  QOpenGLFunctions_3_3_Core* gl = nullptr;
  QByteArray displaySource, mapsSource, viewVertex, viewFragment, mapVertex, mapFragment, atlasVertex, atlasFragment;
  std::map<int, std::unique_ptr<QOpenGLShaderProgram>> viewPrograms;  // by OBJECT * 4 + OUTPUT
  std::unique_ptr<QOpenGLShaderProgram> mapProgram;    // depth and stencil through one camera
  std::unique_ptr<QOpenGLShaderProgram> atlasProgram;  // the shadow maps, all of an atlas in one draw
  std::unique_ptr<QOpenGLShaderProgram> imageAtlasProgram;  // an image-based object's silhouette in one map
  gl::FanObjects images{kImageLamps, true};
  glm::dvec3 boxLo{0.0}, boxHi{0.0};  // the boxes' and meshes' bounds (when haveObjects)
  std::map<int, std::unique_ptr<QOpenGLShaderProgram>> compositePrograms;  // by OUTPUT
  QByteArray compositeVertex, compositeFragment;
  GLuint roomVao = 0, roomVbo = 0, objectVao = 0, objectVbo = 0, backgroundVao = 0, backgroundVbo = 0, tileVao = 0, tileVbo = 0;
  GLsizei tileVertices = 0;  // the tiles an object's shadow may reach, as triangles in the photo's clip space
  GLsizei roomVertices = 0, objectVertices = 0;
  GLuint roomTexture = 0, gainTexture = 0, sunTexture = 0, skyTexture = 0, reachTexture = 0, mapBuffer = 0;
  int maxMaps = 0;  // as many maps' data as the largest uniform block holds (seven vec4 each)
  // The maps: the window samples' (soft shadows: 128^2 by default) and the sun's (sharp: 256^2),
  // each set in the square tiles of one RG32F texture, `columns` x `rows` of them.
  struct Atlas {
    GLuint texture = 0;
    int count = 0, size = 0, columns = 1, rows = 1;
  };
  Atlas windowMaps, sunMaps;
  GLuint mapFbo = 0;
  int mapSize = 128, sunMapSize = 256;
  bool haveRoom = false, haveSky = false, mapsStale = true;
  Camera camera;
  std::vector<daylight::DirectSample> window;
  bool sun = false;
  glm::dvec3 sunIrradiance{0.0};
  std::vector<glm::dvec3> sunDirections;
  glm::dvec3 centre{0.0};
  double radius = 0;
  bool haveObjects = false;  // boxes or meshes
  bool anyObjects() const { return haveObjects || !images.empty(); }
  int reachWords = 0;
  gl::FloatTarget readback, photoTarget;  // (photoTarget: the room at the photo's pixels)
  double lastMs = 0, lastMapMs = 0;

  std::unique_ptr<QOpenGLShaderProgram> compile(const QByteArray& vertex, const QByteArray& fragment, const char* name) const {
    auto q = std::make_unique<QOpenGLShaderProgram>();
    if (!q->addShaderFromSourceCode(QOpenGLShader::Vertex, vertex) ||
        !q->addShaderFromSourceCode(QOpenGLShader::Fragment, fragment) || !q->link())
      throw Error(name, "shader", q->log().toStdString());
    return q;
  }
  // The maps' uniform block (MapBlock) read from binding 0, where bindView and makeMaps put it.
  void bindMapBlock(QOpenGLShaderProgram& p) const {
    const GLuint block = gl->glGetUniformBlockIndex(p.programId(), "MapBlock");
    if (block != GL_INVALID_INDEX) gl->glUniformBlockBinding(p.programId(), block, 0);
  }
  QOpenGLShaderProgram& viewProgram(bool object, DisplayOutput output) {
    auto& p = viewPrograms[(object ? 4 : 0) + int(output)];
    if (!p) {
      const QByteArray defines = "#version 330 core\n#define OBJECT " + QByteArray::number(object ? 1 : 0) +
                                 "\n#define OUTPUT " + QByteArray::number(int(output)) + "\n#define MAX_MAPS " +
                                 QByteArray::number(maxMaps) + "\n";
      p = compile(defines + viewVertex, defines + displaySource + mapsSource + viewFragment, ":/shaders/daylight.frag");
      bindMapBlock(*p);
    }
    return *p;
  }

  QOpenGLShaderProgram& compositeProgram(DisplayOutput output) {
    auto& p = compositePrograms[int(output)];
    if (!p) {
      const QByteArray defines = "#version 330 core\n#define OUTPUT " + QByteArray::number(int(output)) + "\n";
      p = compile(defines + compositeVertex, defines + displaySource + compositeFragment, ":/shaders/daylight_composite.frag");
    }
    return *p;
  }

  static void setLayout(QOpenGLFunctions_3_3_Core& gl) {
    for (int a = 0; a < 5; ++a) {
      gl.glEnableVertexAttribArray(GLuint(a));
      gl.glVertexAttribPointer(GLuint(a), 3, GL_FLOAT, GL_FALSE, kFloats * sizeof(float),
                               reinterpret_cast<const void*>(size_t(a) * 3 * sizeof(float)));
    }
  }
  void upload(GLuint vao, GLuint vbo, const std::vector<float>& data) {
    gl->glBindVertexArray(vao);
    gl->glBindBuffer(GL_ARRAY_BUFFER, vbo);
    gl->glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(data.size() * sizeof(float)), data.data(), GL_STATIC_DRAW);
    setLayout(*gl);
    gl->glBindVertexArray(0);
  }
  void replaceTexture(GLuint& t, GLuint fresh) {
    if (t) gl->glDeleteTextures(1, &t);
    t = fresh;
  }
  int layersNeeded() const { return int(window.size()) + (sun ? int(sunDirections.size()) : 0); }

  // The maps' cameras, in layer order: the window samples, then the sun's directions.
  std::vector<MapCamera> mapCameras() const {
    std::vector<MapCamera> out;
    for (const auto& w : window) out.push_back(windowMap(w.point, w.normal, w.area, centre, radius, mapSize));
    if (sun)
      for (const auto& d : sunDirections) out.push_back(sunMap(d, centre, radius, sunMapSize));
    return out;
  }

  void makeMaps() {
    const auto t0 = std::chrono::steady_clock::now();
    const int layers = layersNeeded();
    if (layers > maxMaps)
      throw Error("", "OpenGL", std::to_string(window.size()) + " window samples' shadow maps asked for, the display holds " +
                                    std::to_string(maxMaps - 4) + ": use fewer direct-light samples");
    // (The blending and target below are put back however this ends.)
    struct Restore {
      QOpenGLFunctions_3_3_Core* gl;
      ~Restore() {
        gl->glBlendEquation(GL_FUNC_ADD);
        gl->glDisable(GL_BLEND);
        for (GLenum c = 0; c < 4; ++c) gl->glDisable(GL_CLIP_DISTANCE0 + c);
        gl->glBindFramebuffer(GL_FRAMEBUFFER, 0);
      }
    } restore{gl};
    GLint maxSize = 0, maxViewport[2] = {0, 0};
    gl->glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
    gl->glGetIntegerv(GL_MAX_VIEWPORT_DIMS, maxViewport);
    maxSize = std::min({maxSize, maxViewport[0], maxViewport[1]});  // (the atlas is drawn whole: one viewport)
    auto ensure = [&](Atlas& a, int count, int size) {
      if (a.texture && a.count == count && a.size == size) return;
      const int columns = std::max(1, int(std::ceil(std::sqrt(double(std::max(count, 1)))))),
                rows = std::max(1, (std::max(count, 1) + columns - 1) / columns);
      if (std::max(columns, rows) * size > maxSize)
        throw Error("", "OpenGL", std::to_string(count) + " shadow maps of " + std::to_string(size) + "x" + std::to_string(size) +
                                      " do not fit the display's largest texture or viewport (" + std::to_string(maxSize) +
                                      " texels a side): use fewer direct-light samples or smaller maps");
      if (a.texture) gl->glDeleteTextures(1, &a.texture);
      gl->glGenTextures(1, &a.texture);
      gl->glBindTexture(GL_TEXTURE_2D, a.texture);
      gl->glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, columns * size, rows * size, 0, GL_RGBA, GL_FLOAT, nullptr);
      gl->glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
      gl->glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
      gl->glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
      gl->glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
      a.count = count;
      a.size = size;
      a.columns = columns;
      a.rows = rows;
    };
    ensure(windowMaps, int(window.size()), mapSize);
    ensure(sunMaps, sun ? int(sunDirections.size()) : 0, sunMapSize);
    const std::vector<MapCamera> cams = mapCameras();
    // The cameras for the view pass: seven vectors per map (the block's whole size, as GL asks).
    std::vector<float> info(size_t(maxMaps) * 7 * 4, 0.f);
    for (size_t m = 0; m < cams.size(); ++m) {
      float* row = &info[m * 28];
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) row[4 * c + r] = cams[m].clip[c][r];
      row[16] = cams[m].origin.x, row[17] = cams[m].origin.y, row[18] = cams[m].origin.z, row[19] = cams[m].footprint;
      row[20] = cams[m].direction.x, row[21] = cams[m].direction.y, row[22] = cams[m].direction.z, row[23] = cams[m].area;
      for (int c = 0; c < 4; ++c) row[24 + c] = cams[m].reach[c];
    }
    gl->glBindBuffer(GL_UNIFORM_BUFFER, mapBuffer);
    gl->glBufferData(GL_UNIFORM_BUFFER, GLsizeiptr(info.size() * sizeof(float)), info.data(), GL_DYNAMIC_DRAW);
    gl->glBindBuffer(GL_UNIFORM_BUFFER, 0);

    if (!mapFbo) gl->glGenFramebuffers(1, &mapFbo);
    gl->glBindFramebuffer(GL_FRAMEBUFFER, mapFbo);
    gl->glDisable(GL_DEPTH_TEST);
    gl->glDisable(GL_CULL_FACE);
    gl->glDisable(GL_SCISSOR_TEST);
    for (GLenum c = 0; c < 4; ++c) gl->glEnable(GL_CLIP_DISTANCE0 + c);
    gl->glEnable(GL_BLEND);
    gl->glBlendEquation(GL_MIN);
    gl->glBlendFunc(GL_ONE, GL_ONE);
    gl->glClearColor(1e30f, 1e30f, 1e30f, 1e30f);
    atlasProgram->bind();
    gl->glBindBufferBase(GL_UNIFORM_BUFFER, 0, mapBuffer);
    for (int set = 0; set < 2; ++set) {
      const Atlas& a = set == 0 ? windowMaps : sunMaps;
      const int first = set == 0 ? 0 : int(window.size()), count = set == 0 ? int(window.size()) : (sun ? int(sunDirections.size()) : 0);
      gl->glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, a.texture, 0);
      if (gl->glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw Error("", "OpenGL", "cannot draw into a float shadow map atlas of " + std::to_string(a.columns * a.size) +
                                      "x" + std::to_string(a.rows * a.size));
      gl->glViewport(0, 0, a.columns * a.size, a.rows * a.size);
      gl->glClear(GL_COLOR_BUFFER_BIT);
      if (count == 0) continue;
      atlasProgram->setUniformValue("firstMap", first);
      gl->glUniform2i(atlasProgram->uniformLocation("grid"), a.columns, a.rows);
      atlasProgram->setUniformValue("ortho", set == 1 ? 1 : 0);
      atlasProgram->setUniformValue("channel", 0);
      gl->glBindVertexArray(roomVao);
      gl->glDrawArraysInstanced(GL_TRIANGLES, 0, roomVertices, count);
      if (haveObjects) {
        atlasProgram->setUniformValue("channel", 1);
        gl->glBindVertexArray(objectVao);
        gl->glDrawArraysInstanced(GL_TRIANGLES, 0, objectVertices, count);
      }
      if (!images.empty()) {
        drawSilhouettes(first, count, a, set == 1);
        atlasProgram->bind();
      }
    }
    gl->glBindVertexArray(0);
    mapsStale = false;
    gl->glFinish();
    lastMapMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }

  // Per map (in layer order: the window samples, then the sun's directions) the fan view of
  // `object` nearest the map's light, a window sample's point or far along the sun's direction
  // (as the library's lamps for the object stand: ibr::daylightAt).
  std::vector<int> mapViews(const ibr::ImageFan& fan, const ibr::Placement& place) const {
    const glm::dvec3 cw = place.toWorld(fan, fan.centre);
    std::vector<int> v;
    for (const auto& w : window) v.push_back(ibr::lampView(fan, place, w.point));
    if (sun)
      for (const auto& d : sunDirections) v.push_back(ibr::lampView(fan, place, cw + 2000.0 * d));
    return v;
  }
  std::vector<std::vector<int>> imageMapViews;  // per image-based object (setImageObjects, setSky)
  void findImageMapViews() {
    imageMapViews.clear();
    for (size_t i = 0; i < images.size(); ++i) imageMapViews.push_back(mapViews(images.fan(i), images.place(i)));
  }

  // The image-based objects' silhouettes into channel 2 of maps first .. first + count - 1 (of
  // atlas `a`): per map and object the fan view nearest the map's light (a window sample's point,
  // or far along one of the sun's directions), as the library's shadows read it.
  void drawSilhouettes(int first, int count, const Atlas& a, bool ortho) {
    QOpenGLShaderProgram& p = *imageAtlasProgram;
    p.bind();
    p.setUniformValue("ortho", ortho ? 1 : 0);
    p.setUniformValue("channel", 2);
    gl->glUniform2i(p.uniformLocation("grid"), a.columns, a.rows);
    p.setUniformValue("fanData", 0);
    gl->glBindVertexArray(images.emptyVertexArray());  // (the square is made from gl_VertexID)
    gl->glActiveTexture(GL_TEXTURE0);
    for (size_t i = 0; i < images.size(); ++i) {
      const ibr::ImageFan& fan = images.fan(i);
      const ibr::Placement& place = images.place(i);
      const glm::dvec3 cw = place.toWorld(fan, fan.centre);
      p.setUniformValue("fanSize", fan.size);
      p.setUniformValue("fanHalf", float(fan.radius * place.scale));
      p.setUniformValue("fanCentre", float(cw.x), float(cw.y), float(cw.z));
      for (int k = 0; k < count; ++k) {
        const int view = imageMapViews[i][size_t(first + k)];
        const int layer = images.layerFor(i, view);
        const glm::vec3 r(place.toWorldDirection(fan.right(view))), u(place.toWorldDirection(fan.up(view))),
            t(place.toWorldDirection(fan.toCamera(view)));
        p.setUniformValue("firstMap", first + k);
        p.setUniformValue("tile", k);
        p.setUniformValue("fanLayer", layer);
        p.setUniformValue("fanRight", r.x, r.y, r.z);
        p.setUniformValue("fanUp", u.x, u.y, u.z);
        p.setUniformValue("fanToCamera", t.x, t.y, t.z);
        gl->glBindTexture(GL_TEXTURE_2D_ARRAY, images.dataTexture(i));
        gl->glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
      }
    }
  }

  // The maps as daylight_maps.glsl reads them: the window samples' atlas on texture unit
  // `mapUnit`, the sun's on `sunUnit`, their cameras in the uniform block.
  void bindMaps(QOpenGLShaderProgram& p, int mapUnit, int sunUnit) {
    p.setUniformValue("windowSamples", anyObjects() ? int(window.size()) : 0);
    p.setUniformValue("sunMaps", anyObjects() && sun ? int(sunDirections.size()) : 0);
    gl->glActiveTexture(GLenum(GL_TEXTURE0 + mapUnit));
    gl->glBindTexture(GL_TEXTURE_2D, windowMaps.texture);
    p.setUniformValue("maps", mapUnit);
    gl->glUniform2i(p.uniformLocation("mapGrid"), windowMaps.columns, windowMaps.rows);
    p.setUniformValue("mapTexels", float(std::max(windowMaps.size, 1)));
    gl->glActiveTexture(GLenum(GL_TEXTURE0 + sunUnit));
    gl->glBindTexture(GL_TEXTURE_2D, sunMaps.texture);
    p.setUniformValue("sunAtlas", sunUnit);
    gl->glUniform2i(p.uniformLocation("sunGrid"), sunMaps.columns, sunMaps.rows);
    p.setUniformValue("sunTexels", float(std::max(sunMaps.size, 1)));
    bindMapBlock(p);
    gl->glBindBufferBase(GL_UNIFORM_BUFFER, 0, mapBuffer);
  }

  // The maps' sphere: around the boxes' bounds and the image-based objects' spheres.
  void fitMaps() {
    glm::dvec3 lo = haveObjects ? boxLo : glm::dvec3(1e300), hi = haveObjects ? boxHi : glm::dvec3(-1e300);
    for (size_t i = 0; i < images.size(); ++i) {
      const ibr::ImageFan& f = images.fan(i);
      const glm::dvec3 c = images.place(i).toWorld(f, f.centre);
      const double r = f.radius * images.place(i).scale;
      lo = glm::min(lo, c - r);
      hi = glm::max(hi, c + r);
    }
    if (!anyObjects()) return;
    centre = 0.5 * (lo + hi);
    radius = 0.5 * glm::length(hi - lo);
    mapsStale = true;
  }

  // The uniforms and textures every pass of the view program reads.
  QOpenGLShaderProgram& bindView(bool object, DisplayOutput output, const DisplaySettings& s, const glm::mat4& clip,
                                 const ViewRect& rect) {
    const glm::dvec3 eye = camera.center();
    QOpenGLShaderProgram& p = viewProgram(object, output);
    p.bind();
    p.setUniformValue("worldToClip", QMatrix4x4(&glm::transpose(clip)[0][0]));
    p.setUniformValue("exposure", float(s.exposure));
    p.setUniformValue("falseMin", float(s.falseMin));
    p.setUniformValue("falseMax", float(s.falseMax));
    p.setUniformValue("eye", float(eye.x), float(eye.y), float(eye.z));
    const glm::vec3 q(sunIrradiance / double(std::max<size_t>(sunDirections.size(), 1)));
    p.setUniformValue("sunQuarter", q.x, q.y, q.z);
    bindMaps(p, 0, 7);
    gl->glActiveTexture(GL_TEXTURE2);
    gl->glBindTexture(GL_TEXTURE_2D, skyTexture);
    p.setUniformValue("skyRadiance", 2);
    if (!object) {
      gl->glActiveTexture(GL_TEXTURE3);
      gl->glBindTexture(GL_TEXTURE_2D, roomTexture);
      p.setUniformValue("room", 3);
      gl->glActiveTexture(GL_TEXTURE4);
      gl->glBindTexture(GL_TEXTURE_2D, gainTexture);
      p.setUniformValue("gain", 4);
      gl->glActiveTexture(GL_TEXTURE5);
      gl->glBindTexture(GL_TEXTURE_2D, reachTexture);
      p.setUniformValue("reach", 5);
      gl->glActiveTexture(GL_TEXTURE6);
      gl->glBindTexture(GL_TEXTURE_2D, sunTexture);
      p.setUniformValue("sunLight", 6);
      p.setUniformValue("reachWords", anyObjects() ? reachWords : 0);
      p.setUniformValue("viewOrigin", float(rect.x), float(rect.y));
      p.setUniformValue("viewSize", float(rect.width), float(rect.height));
      p.setUniformValue("photoSize", float(camera.width), float(camera.height));
    }
    return p;
  }

  static DisplaySettings linearSettings() {
    DisplaySettings linear;
    linear.output = DisplayOutput::Linear;
    return linear;
  }
  // Depth (and stencil) only through `clip`: the map program, colour masked.
  void depthOnly(GLuint vao, GLsizei vertices, const glm::mat4& clip) {
    mapProgram->bind();
    mapProgram->setUniformValue("worldToClip", QMatrix4x4(&glm::transpose(clip)[0][0]));
    gl->glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    gl->glBindVertexArray(vao);
    gl->glDrawArrays(GL_TRIANGLES, 0, vertices);
    gl->glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  }

  // `image` over the whole of `rect` with the display transform (depth neither tested nor written).
  void composite(const DisplaySettings& s, GLuint image, bool topFirst, const ViewRect& rect) {
    QOpenGLShaderProgram& p = compositeProgram(s.output);
    p.bind();
    p.setUniformValue("exposure", float(s.exposure));
    p.setUniformValue("falseMin", float(s.falseMin));
    p.setUniformValue("falseMax", float(s.falseMax));
    p.setUniformValue("viewOrigin", float(rect.x), float(rect.y));
    p.setUniformValue("viewSize", float(rect.width), float(rect.height));
    p.setUniformValue("topFirst", topFirst ? 1 : 0);
    gl->glActiveTexture(GL_TEXTURE0);
    gl->glBindTexture(GL_TEXTURE_2D, image);
    p.setUniformValue("image", 0);
    gl->glDisable(GL_DEPTH_TEST);
    gl->glDepthMask(GL_FALSE);
    gl->glBindVertexArray(backgroundVao);
    gl->glDrawArrays(GL_TRIANGLES, 0, 3);
    gl->glDepthMask(GL_TRUE);
    gl->glEnable(GL_DEPTH_TEST);
  }

  void drawView(const DisplaySettings& s, GLuint target, const ViewRect& rect) {
    if (anyObjects() && mapsStale) makeMaps();
    else lastMapMs = 0;
    gl->glDisable(GL_SCISSOR_TEST);
    gl->glDisable(GL_BLEND);
    gl->glDisable(GL_CULL_FACE);
    gl->glEnable(GL_DEPTH_TEST);
    gl->glDepthMask(GL_TRUE);
    gl->glDepthFunc(GL_LESS);
    gl->glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    gl->glClearDepth(1.0);
    const glm::mat4 clip = gl::worldToClip(camera, 0.02, 1000.0);
    // 1. The relit photo, linear, at the photo's own pixels (or the view's, when the view is
    // smaller): differential rendering is defined per photo pixel, as on the CPU path. The light the
    // objects take away is found once per pixel of it, and the objects are drawn at the same
    // pixels as the room around them, whatever the size of the view (a view larger than the photo
    // magnifies both alike; it also costs llvmpipe a quarter of the shading at twice the size).
    const double shrink = std::min({1.0, double(rect.width) / camera.width, double(rect.height) / camera.height});
    const int w = std::max(1, int(std::lround(camera.width * shrink))), h = std::max(1, int(std::lround(camera.height * shrink)));
    photoTarget.ensure(*gl, w, h);
    gl->glBindFramebuffer(GL_FRAMEBUFFER, photoTarget.fbo);
    gl->glViewport(0, 0, w, h);
    gl->glClearColor(0.f, 0.f, 0.f, 1.f);
    gl->glClearStencil(0);
    gl->glStencilMask(0xFF);
    gl->glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
    // The library's room under the sky everywhere (the sky through a window included), and the
    // depth of the room and of the objects...
    composite(linearSettings(), roomTexture, true, {0, 0, w, h});
    if (anyObjects()) {
      // (A room pixel a box covers is then not shaded, nor a box's face behind another: each
      // pixel is shaded once below, as llvmpipe shades every fragment that passes the tests.)
      depthOnly(roomVao, roomVertices, clip);
      if (haveObjects) depthOnly(objectVao, objectVertices, clip);
    }
    // ... and where an object's shadow may fall (its tiles marked in the stencil), the room's
    // polygons shaded with what the objects take away.
    if (anyObjects() && tileVertices > 0) {
      gl->glDisable(GL_DEPTH_TEST);
      gl->glEnable(GL_STENCIL_TEST);
      gl->glStencilFunc(GL_ALWAYS, 1, 0xFF);
      gl->glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
      depthOnly(tileVao, tileVertices, glm::mat4(1.f));
      gl->glEnable(GL_DEPTH_TEST);
      gl->glStencilFunc(GL_EQUAL, 1, 0xFF);
      gl->glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
      gl->glDepthFunc(GL_LEQUAL);
      bindView(false, DisplayOutput::Linear, linearSettings(), clip, {0, 0, w, h});
      gl->glBindVertexArray(roomVao);
      gl->glDrawArrays(GL_TRIANGLES, 0, roomVertices);
      gl->glDepthFunc(GL_LESS);
      gl->glDisable(GL_STENCIL_TEST);
    }
    if (haveObjects) {
      // The objects, each of their pixels once (their depth is there).
      gl->glDepthFunc(GL_LEQUAL);
      bindView(true, DisplayOutput::Linear, linearSettings(), clip, {0, 0, w, h});
      gl->glBindVertexArray(objectVao);
      gl->glDrawArrays(GL_TRIANGLES, 0, objectVertices);
      gl->glDepthFunc(GL_LESS);
    }
    // The image-based objects, depth-tested against the room and the boxes (ibr_object.frag: the
    // library's tables, the sun seen per point through its maps).
    if (!images.empty()) {
      images.draw(camera, clip, linearSettings(), [this](QOpenGLShaderProgram& p) { bindMaps(p, 3, 4); });
      gl->glEnable(GL_DEPTH_TEST);
    }
    // 2. The view: that image with the display transform.
    gl->glBindFramebuffer(GL_FRAMEBUFFER, target);
    if (s.output == DisplayOutput::Linear) gl->glClearColor(0.f, 0.f, 0.f, 1.f);
    else gl->glClearColor(0.16f, 0.16f, 0.17f, 1.f);
    gl->glViewport(0, 0, rect.x + rect.width, rect.y + rect.height);
    gl->glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    gl->glViewport(rect.x, rect.y, rect.width, rect.height);
    composite(s, photoTarget.colour, false, rect);
    gl->glBindVertexArray(0);
    gl->glActiveTexture(GL_TEXTURE0);
    gl->glDisable(GL_DEPTH_TEST);
  }
};

GlDaylightRenderer::GlDaylightRenderer() : impl_(std::make_unique<Impl>()) {}

GlDaylightRenderer::~GlDaylightRenderer() {
  auto& im = *impl_;
  if (!im.gl || !QOpenGLContext::currentContext()) return;  // (without its context, its objects go with it)
  for (GLuint* t : {&im.roomTexture, &im.gainTexture, &im.sunTexture, &im.skyTexture, &im.reachTexture, &im.windowMaps.texture, &im.sunMaps.texture})
    if (*t) im.gl->glDeleteTextures(1, t);
  for (GLuint* b : {&im.roomVbo, &im.objectVbo, &im.backgroundVbo, &im.mapBuffer, &im.tileVbo})
    if (*b) im.gl->glDeleteBuffers(1, b);
  for (GLuint* a : {&im.roomVao, &im.objectVao, &im.backgroundVao, &im.tileVao})
    if (*a) im.gl->glDeleteVertexArrays(1, a);
  if (im.mapFbo) im.gl->glDeleteFramebuffers(1, &im.mapFbo);
  im.readback.release(*im.gl);
  im.photoTarget.release(*im.gl);
  im.images.release();
}

void GlDaylightRenderer::initialize() {
  initDaylightShaderResources();
  auto& im = *impl_;
  im.gl = gl::currentFunctions();
  auto read = [](const char* name) { return gl::shaderSource(name); };
  im.displaySource = read(":/shaders/display.glsl");
  im.mapsSource = read(":/shaders/daylight_maps.glsl");
  im.viewVertex = read(":/shaders/daylight.vert");
  im.viewFragment = read(":/shaders/daylight.frag");
  im.mapVertex = read(":/shaders/daylight_map.vert");
  im.mapFragment = read(":/shaders/daylight_map.frag");
  im.atlasVertex = read(":/shaders/daylight_atlas.vert");
  im.atlasFragment = read(":/shaders/daylight_atlas.frag");
  im.compositeVertex = read(":/shaders/daylight_composite.vert");
  im.compositeFragment = read(":/shaders/daylight_composite.frag");
  im.compositePrograms.clear();
  {
    GLint block = 0;
    im.gl->glGetIntegerv(GL_MAX_UNIFORM_BLOCK_SIZE, &block);
    im.maxMaps = std::clamp(int(block / (7 * 16)), 1, 1028);
  }
  const QByteArray version = "#version 330 core\n";
  im.mapProgram = im.compile(version + im.mapVertex, version + im.mapFragment, ":/shaders/daylight_map.frag");
  {
    const QByteArray defines = version + "#define MAX_MAPS " + QByteArray::number(im.maxMaps) + "\n";
    const QByteArray rooms = defines + "#define IMAGE 0\n", images = defines + "#define IMAGE 1\n";
    im.atlasProgram = im.compile(rooms + im.atlasVertex, rooms + im.atlasFragment, ":/shaders/daylight_atlas.vert");
    im.bindMapBlock(*im.atlasProgram);
    im.imageAtlasProgram = im.compile(images + im.atlasVertex, images + im.atlasFragment, ":/shaders/daylight_atlas.frag");
    im.bindMapBlock(*im.imageAtlasProgram);
    // (Compiled at the first draw with image-based objects: a display whose limits its 128 lamps
    // exceed still draws the rest.)
    im.images.initialize(im.gl, im.displaySource + im.mapsSource, "#define MAX_MAPS " + QByteArray::number(im.maxMaps) + "\n",
                         false);
  }
  im.viewPrograms.clear();
  im.viewProgram(false, DisplayOutput::Exposed);  // errors show now
  im.viewProgram(true, DisplayOutput::Exposed);
  auto& gl = *im.gl;
  gl.glGenVertexArrays(1, &im.roomVao);
  gl.glGenVertexArrays(1, &im.objectVao);
  gl.glGenBuffers(1, &im.roomVbo);
  gl.glGenBuffers(1, &im.objectVbo);
  gl.glGenVertexArrays(1, &im.tileVao);
  gl.glGenBuffers(1, &im.tileVbo);
  gl.glGenVertexArrays(1, &im.backgroundVao);
  gl.glGenBuffers(1, &im.backgroundVbo);
  {
    std::vector<float> tri(3 * kFloats, 0.f);
    const float corners[3][2] = {{-1, -1}, {3, -1}, {-1, 3}};
    for (int k = 0; k < 3; ++k) {
      tri[size_t(k) * kFloats] = corners[k][0];
      tri[size_t(k) * kFloats + 1] = corners[k][1];
      tri[size_t(k) * kFloats + 2] = 0.9999f;
    }
    im.upload(im.backgroundVao, im.backgroundVbo, tri);
  }
  // Until a sky comes: an empty reach and one cleared map, so that every sampler has a texture.
  const float zero[4] = {0, 0, 0, 0};
  im.skyTexture = floatTexture(gl, 1, 1, GL_RGBA32F, GL_RGBA, zero, GL_NEAREST);
  im.roomTexture = floatTexture(gl, 1, 1, GL_RGBA32F, GL_RGBA, zero, GL_NEAREST);
  im.gainTexture = floatTexture(gl, 1, 1, GL_RGBA32F, GL_RGBA, zero, GL_NEAREST);
  im.sunTexture = floatTexture(gl, 1, 1, GL_RGBA32F, GL_RGBA, zero, GL_NEAREST);
  gl.glGenBuffers(1, &im.mapBuffer);
  {
    std::vector<float> none(size_t(im.maxMaps) * 7 * 4, 0.f);
    gl.glBindBuffer(GL_UNIFORM_BUFFER, im.mapBuffer);
    gl.glBufferData(GL_UNIFORM_BUFFER, GLsizeiptr(none.size() * sizeof(float)), none.data(), GL_DYNAMIC_DRAW);
    gl.glBindBuffer(GL_UNIFORM_BUFFER, 0);
  }
  gl.glGenTextures(1, &im.reachTexture);
  gl.glBindTexture(GL_TEXTURE_2D, im.reachTexture);
  const uint32_t none = 0;
  gl.glTexImage2D(GL_TEXTURE_2D, 0, GL_R32UI, 1, 1, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &none);
  gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
}

void GlDaylightRenderer::setRoom(const std::vector<std::vector<glm::dvec3>>& polygons, const Camera& photoCamera) {
  auto& im = *impl_;
  std::vector<float> data;
  for (const auto& v : polygons) {
    if (v.size() < 3) continue;
    const glm::vec3 n(polygonNormal(v));
    fanTriangles(v, [&](size_t k) {
      const glm::vec3 p(v[k]);
      const float vertex[kFloats] = {p.x, p.y, p.z, n.x, n.y, n.z, 0, 0, 0, 0, 0, 0, 0, 0, 0};
      data.insert(data.end(), vertex, vertex + kFloats);
    });
  }
  im.upload(im.roomVao, im.roomVbo, data);
  im.roomVertices = GLsizei(data.size() / kFloats);
  im.camera = photoCamera;
  im.haveRoom = true;
  im.mapsStale = true;
}

void GlDaylightRenderer::setSky(const daylight::InteractiveSky& sky) {
  auto& im = *impl_;
  auto& gl = *im.gl;
  auto rgba = [](const ImageRGB& img) {
    std::vector<float> out(size_t(img.width) * size_t(img.height) * 4, 1.f);
    for (size_t i = 0; i < size_t(img.width) * size_t(img.height); ++i)
      for (int c = 0; c < 3; ++c) out[4 * i + size_t(c)] = img.pixels[3 * i + size_t(c)];
    return out;
  };
  if (sky.room.width != im.camera.width || sky.room.height != im.camera.height || sky.gain.width != sky.room.width ||
      sky.gain.height != sky.room.height)
    throw Error("", "daylight view", "the sky's room image is not of the photo camera's size");
  im.replaceTexture(im.roomTexture, floatTexture(gl, sky.room.width, sky.room.height, GL_RGBA32F, GL_RGBA,
                                                 rgba(sky.room).data(), GL_NEAREST));
  im.replaceTexture(im.gainTexture, floatTexture(gl, sky.gain.width, sky.gain.height, GL_RGBA32F, GL_RGBA,
                                                 rgba(sky.gain).data(), GL_NEAREST));
  const ImageRGB sunLight = sky.sunLight.width == sky.room.width && sky.sunLight.height == sky.room.height
                                ? sky.sunLight : ImageRGB(sky.room.width, sky.room.height);
  im.replaceTexture(im.sunTexture, floatTexture(gl, sunLight.width, sunLight.height, GL_RGBA32F, GL_RGBA,
                                                rgba(sunLight).data(), GL_NEAREST));
  im.replaceTexture(im.skyTexture, floatTexture(gl, sky.radiance.width, sky.radiance.height, GL_RGBA32F, GL_RGBA,
                                                rgba(sky.radiance).data(), GL_NEAREST));
  gl.glBindTexture(GL_TEXTURE_2D, im.skyTexture);
  gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);  // around the azimuth
  im.window = sky.window;
  im.sun = sky.sun;
  im.sunIrradiance = sky.sunIrradiance;
  im.sunDirections = sky.sun ? sky.sunDirections : std::vector<glm::dvec3>{};
  im.haveSky = true;
  im.findImageMapViews();  // (the maps' lights have changed)
  im.mapsStale = true;
}

void GlDaylightRenderer::setObjects(const std::vector<Polygon>& objects, const daylight::ObjectIndirect& indirect,
                                    const daylight::ShadowReach& reach) {
  auto& im = *impl_;
  auto& gl = *im.gl;
  std::vector<float> data;
  glm::dvec3 lo(1e300), hi(-1e300);
  for (size_t o = 0; o < objects.size(); ++o) {
    const auto& v = objects[o].vertices;
    if (v.size() < 3) continue;
    for (const auto& q : v) {
      lo = glm::min(lo, q);
      hi = glm::max(hi, q);
    }
    const glm::vec3 n(polygonNormal(v)), a(objects[o].albedo);
    const bool lit = o < indirect.front.size() && indirect.front[o].size() == v.size() && o < indirect.back.size() &&
                     indirect.back[o].size() == v.size();
    fanTriangles(v, [&](size_t k) {
      const glm::vec3 p(v[k]);
      const glm::vec3 f = lit ? glm::vec3(indirect.front[o][k]) : glm::vec3(0.f);
      const glm::vec3 b = lit ? glm::vec3(indirect.back[o][k]) : glm::vec3(0.f);
      const float vertex[kFloats] = {p.x, p.y, p.z, n.x, n.y, n.z, f.x, f.y, f.z, b.x, b.y, b.z, a.x, a.y, a.z};
      data.insert(data.end(), vertex, vertex + kFloats);
    });
  }
  im.upload(im.objectVao, im.objectVbo, data);
  im.objectVertices = GLsizei(data.size() / kFloats);
  im.haveObjects = im.objectVertices > 0;
  im.boxLo = lo;
  im.boxHi = hi;
  im.fitMaps();
  // The tiles' samples, as the shader reads them: (tile x * words + word, tile y).
  im.reachWords = std::max(reach.words, 1);
  const int w = std::max(reach.tilesX, 1) * im.reachWords, h = std::max(reach.tilesY, 1);
  std::vector<uint32_t> bits(size_t(w) * size_t(h), 0);
  if (reach.bits.size() == size_t(reach.tilesX) * size_t(reach.tilesY) * size_t(reach.words)) bits.assign(reach.bits.begin(), reach.bits.end());
  if (bits.empty()) bits.assign(size_t(w) * size_t(h), 0);
  // The flagged tiles as quads (photo pixels -> clip space, top row first as the photo's).
  {
    std::vector<float> quads;
    const double pw = std::max(im.camera.width, 1), ph = std::max(im.camera.height, 1);
    for (int ty = 0; ty < reach.tilesY; ++ty)
      for (int tx = 0; tx < reach.tilesX; ++tx) {
        if (reach.bits.size() != size_t(reach.tilesX) * size_t(reach.tilesY) * size_t(reach.words) ||
            !reach.any(size_t(ty) * size_t(reach.tilesX) + size_t(tx)))
          continue;
        const float x0 = float(2 * tx * daylight::ShadowReach::kTile / pw - 1);
        const float x1 = float(std::min(2 * (tx + 1) * daylight::ShadowReach::kTile / pw, 2.0) - 1);
        const float y0 = float(1 - 2 * ty * daylight::ShadowReach::kTile / ph);
        const float y1 = float(1 - std::min(2 * (ty + 1) * daylight::ShadowReach::kTile / ph, 2.0));
        const float corners[6][2] = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y0}, {x1, y1}, {x0, y1}};
        for (const auto& c : corners) {
          float v[kFloats] = {};
          v[0] = c[0], v[1] = c[1], v[2] = 0.f;
          quads.insert(quads.end(), v, v + kFloats);
        }
      }
    im.upload(im.tileVao, im.tileVbo, quads);
    im.tileVertices = GLsizei(quads.size() / kFloats);
  }
  GLint largest = 0;
  gl.glGetIntegerv(GL_MAX_TEXTURE_SIZE, &largest);
  if (w > largest || h > largest)
    throw Error("", "OpenGL", "the shadows' tiles (" + std::to_string(w) + " x " + std::to_string(h) +
                                  ") do not fit a texture of this display: use fewer direct-light samples");
  gl.glBindTexture(GL_TEXTURE_2D, im.reachTexture);
  gl.glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  gl.glTexImage2D(GL_TEXTURE_2D, 0, GL_R32UI, w, h, 0, GL_RED_INTEGER, GL_UNSIGNED_INT, bits.data());
  im.mapsStale = true;
}

void GlDaylightRenderer::setImageObjects(const std::vector<ibr::ImageObject>& objects,
                                         const std::vector<ibr::ObjectLighting>& lights,
                                         std::vector<ibr::DrawnTables> tables) {
  auto& im = *impl_;
  // The fan views the maps read (one per window sample and direction of the sun's disc), kept in
  // the objects' layers beside the drawn and lit ones.
  std::vector<std::vector<int>> views;
  for (const auto& o : objects) views.push_back(im.mapViews(*o.fan, o.place));
  im.images.set(objects, lights, std::move(tables), views);
  im.findImageMapViews();
  im.fitMaps();
  im.mapsStale = true;
}

void GlDaylightRenderer::setMapSize(int size) {
  impl_->mapSize = std::clamp(size, 16, 4096);
  impl_->mapsStale = true;
}
void GlDaylightRenderer::setSunMapSize(int size) {
  impl_->sunMapSize = std::clamp(size, 16, 4096);
  impl_->mapsStale = true;
}
int GlDaylightRenderer::imageLamps() { return kImageLamps; }
int GlDaylightRenderer::mapSize() const { return impl_->mapSize; }
int GlDaylightRenderer::sunMapSize() const { return impl_->sunMapSize; }
int GlDaylightRenderer::mapCount() const { return impl_->layersNeeded(); }
bool GlDaylightRenderer::ready() const { return impl_->haveRoom && impl_->haveSky; }

void GlDaylightRenderer::draw(const DisplaySettings& display, unsigned target, const ViewRect& rect) {
  auto& im = *impl_;
  if (!ready() || rect.width <= 0 || rect.height <= 0) return;
  im.gl->glFinish();
  const auto t0 = std::chrono::steady_clock::now();
  im.drawView(display, target, rect);
  im.gl->glFinish();
  im.lastMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

ImageRGB GlDaylightRenderer::renderLinear() {
  auto& im = *impl_;
  if (!ready()) throw Error("", "daylight view", "no room or sky to draw yet");
  const int w = im.camera.width, h = im.camera.height;
  im.readback.ensure(*im.gl, w, h);
  DisplaySettings linear;
  linear.output = DisplayOutput::Linear;
  draw(linear, im.readback.fbo, {0, 0, w, h});
  std::vector<float> rgba(size_t(w) * size_t(h) * 4);
  im.gl->glBindFramebuffer(GL_FRAMEBUFFER, im.readback.fbo);
  im.gl->glPixelStorei(GL_PACK_ALIGNMENT, 4);
  im.gl->glReadPixels(0, 0, w, h, GL_RGBA, GL_FLOAT, rgba.data());
  ImageRGB img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float* p = &rgba[(size_t(h - 1 - y) * size_t(w) + size_t(x)) * 4];
      img.set(x, y, {p[0], p[1], p[2]});
    }
  return img;
}

double GlDaylightRenderer::lastDrawMilliseconds() const { return impl_->lastMs; }
double GlDaylightRenderer::lastMapMilliseconds() const { return impl_->lastMapMs; }

}  // namespace relume
