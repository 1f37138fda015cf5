// Image-based objects on the GPU: see gl_fans.h.
#include "gl_fans.h"

#include <QMatrix4x4>
#include <QOpenGLFunctions_3_3_Core>
#include <QOpenGLShaderProgram>
#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <set>

#include "gl_common.h"
#include "relume/geometry/error.h"

namespace relume::gl {

namespace {

constexpr int kMinLayers = 16;  // fan views kept per object: 3 drawn, the lamps' own-shadow views, spare

// A fan view as the shaders read it: code, depth, coverage (16-bit integers) and albedo (sRGB).
void fanTexels(const ibr::FanView& v, int size, std::vector<uint16_t>& data, std::vector<uint8_t>& albedo) {
  const size_t n = size_t(size) * size_t(size);
  data.assign(n * 4, 0);
  albedo.assign(n * 4, 0);
  for (size_t i = 0; i < n; ++i) {
    data[4 * i] = v.code[i];
    data[4 * i + 1] = v.depth[i];
    data[4 * i + 2] = v.alpha[i];
    for (size_t c = 0; c < 3; ++c) albedo[4 * i + c] = v.colour[3 * i + c];
    albedo[4 * i + 3] = v.alpha[i];
  }
}

GLuint textureArray(QOpenGLFunctions_3_3_Core& gl, GLenum internal, GLenum format, GLenum type, int size, int layers) {
  GLuint id = 0;
  gl.glGenTextures(1, &id);
  gl.glBindTexture(GL_TEXTURE_2D_ARRAY, id);
  gl.glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, GLint(internal), size, size, layers, 0, format, type, nullptr);
  gl.glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  gl.glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  return id;
}

// The three axes of fan view k (right, up, towards its camera) into `out` from `at` on.
void putAxes(const ibr::ImageFan& fan, int k, std::vector<glm::vec3>& out, size_t at) {
  const auto ax = fan.axes(k);
  out[at] = glm::vec3(ax.right);
  out[at + 1] = glm::vec3(ax.up);
  out[at + 2] = glm::vec3(ax.toCamera);
}

}  // namespace

FanObjects::FanObjects(int maxLamps, bool daylight) : maxLamps_(maxLamps), daylight_(daylight) {}

FanObjects::~FanObjects() = default;  // (the owner calls release() with its context current)

void FanObjects::initialize(QOpenGLFunctions_3_3_Core* gl, const QByteArray& fragmentPrefix, const QByteArray& defines,
                            bool compileNow) {
  gl_ = gl;
  prefix_ = fragmentPrefix;
  defines_ = defines;
  vertex_ = shaderSource(":/shaders/ibr_object.vert");
  fragment_ = shaderSource(":/shaders/ibr_object.frag");
  programs_.clear();
  if (!vao_) gl_->glGenVertexArrays(1, &vao_);  // (the octagons are made from gl_VertexID: an empty array)
  if (compileNow) program(DisplayOutput::Exposed);  // errors show now
}

void FanObjects::release() {
  if (!gl_) return;
  for (auto& o : objects_) releaseObject(o);
  objects_.clear();
  if (vao_) gl_->glDeleteVertexArrays(1, &vao_);
  vao_ = 0;
  programs_.clear();
}

void FanObjects::releaseObject(Object& o) {
  for (unsigned* t : {&o.data, &o.albedo, &o.tableTexture})
    if (*t) gl_->glDeleteTextures(1, t);
}

QOpenGLShaderProgram& FanObjects::program(DisplayOutput output) {
  if (programs_.size() < 4) programs_.resize(4);
  auto& p = programs_[size_t(output)];
  if (!p) {
    const QByteArray defines = "#version 330 core\n#define OUTPUT " + QByteArray::number(int(output)) + "\n#define MAX_LAMPS " +
                               QByteArray::number(maxLamps_) + "\n#define DAYLIGHT " + QByteArray::number(daylight_ ? 1 : 0) +
                               "\n" + defines_;
    auto q = std::make_unique<QOpenGLShaderProgram>();
    if (!q->addShaderFromSourceCode(QOpenGLShader::Vertex, defines + vertex_) ||
        !q->addShaderFromSourceCode(QOpenGLShader::Fragment, defines + prefix_ + fragment_) || !q->link())
      throw Error(":/shaders/ibr_object.frag", "shader", q->log().toStdString());
    p = std::move(q);
  }
  return *p;
}

void FanObjects::set(const std::vector<ibr::ImageObject>& objects, const std::vector<ibr::ObjectLighting>& lights,
                     std::vector<ibr::DrawnTables> tables, const std::vector<std::vector<int>>& moreViews) {
  auto& gl = *gl_;
  GLint maxLayers = 256;
  gl.glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
  // Objects whose fan is already up keep their layers (a move or a new light needs no upload).
  std::vector<Object> before = std::move(objects_);
  objects_.clear();
  for (size_t i = 0; i < objects.size() && i < lights.size(); ++i) {
    Object o;
    o.fan = objects[i].fan;
    o.place = objects[i].place;
    o.light = lights[i];
    ibr::keepDisplayLamps(o.light, *o.fan, o.place, size_t(maxLamps_));
    if (i < tables.size()) o.made = std::move(tables[i]);
    std::set<int> views;
    for (const auto& l : o.light.lamps) views.insert(ibr::lampView(*o.fan, o.place, l.position));
    if (i < moreViews.size()) views.insert(moreViews[i].begin(), moreViews[i].end());
    const int layers = std::clamp(int(views.size()) + ibr::kDrawnViews + 2, kMinLayers, std::max(kMinLayers, int(maxLayers)));
    for (auto& b : before)
      if (b.fan == o.fan && b.data && b.layers >= layers) {
        o.data = b.data, o.albedo = b.albedo, o.tableTexture = b.tableTexture, o.layers = b.layers;
        o.layerView = std::move(b.layerView);
        o.layerUsed = std::move(b.layerUsed);
        b.data = b.albedo = b.tableTexture = 0;
        break;
      }
    if (!o.data) {
      const int S = o.fan->size;
      o.layers = layers;
      o.data = textureArray(gl, GL_RGBA16UI, GL_RGBA_INTEGER, GL_UNSIGNED_SHORT, S, layers);
      o.albedo = textureArray(gl, GL_SRGB8_ALPHA8, GL_RGBA, GL_UNSIGNED_BYTE, S, layers);
      gl.glGenTextures(1, &o.tableTexture);
      gl.glBindTexture(GL_TEXTURE_2D, o.tableTexture);
      gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
      gl.glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
      o.layerView.assign(size_t(layers), -1);
      o.layerUsed.assign(size_t(layers), 0);
    }
    objects_.push_back(std::move(o));
  }
  for (auto& b : before) releaseObject(b);
}

double FanObjects::reach(const glm::dvec3& eye) const {
  double r = 0;
  for (const auto& o : objects_)  // an object's octagon may reach beyond the room's walls
    r = std::max(r, glm::length(o.place.toWorld(*o.fan, o.fan->centre) - eye) + 1.8 * o.fan->radius * o.place.scale);
  return r;
}

int FanObjects::layerFor(size_t i, int view) {
  Object& o = objects_[i];
  for (size_t l = 0; l < o.layerView.size(); ++l)
    if (o.layerView[l] == view) {
      o.layerUsed[l] = frame_;
      return int(l);
    }
  // A free layer, else the least recently needed.
  size_t best = 0;
  for (size_t l = 1; l < o.layerView.size(); ++l)
    if ((o.layerView[l] < 0) != (o.layerView[best] < 0) ? o.layerView[l] < 0 : o.layerUsed[l] < o.layerUsed[best]) best = l;
  const int S = o.fan->size;
  std::vector<uint16_t> data;
  std::vector<uint8_t> albedo;
  fanTexels(o.fan->view(view), S, data, albedo);
  gl_->glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  gl_->glBindTexture(GL_TEXTURE_2D_ARRAY, o.data);
  gl_->glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, 0, GLint(best), S, S, 1, GL_RGBA_INTEGER, GL_UNSIGNED_SHORT, data.data());
  gl_->glBindTexture(GL_TEXTURE_2D_ARRAY, o.albedo);
  gl_->glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, 0, GLint(best), S, S, 1, GL_RGBA, GL_UNSIGNED_BYTE, albedo.data());
  o.layerView[best] = view;
  o.layerUsed[best] = frame_;
  return int(best);
}

void FanObjects::draw(const Camera& camera, const glm::mat4& clip, const DisplaySettings& s,
                      const std::function<void(QOpenGLShaderProgram&)>& bind) {
  if (objects_.empty()) return;
  auto* gl = gl_;
  ++frame_;
  const glm::dvec3 eye = camera.center();
  std::vector<size_t> order(objects_.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  auto dist = [&](size_t i) { return glm::length(objects_[i].place.toWorld(*objects_[i].fan, objects_[i].fan->centre) - eye); };
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return dist(a) > dist(b); });
  auto& prog = program(s.output);
  prog.bind();
  prog.setUniformValue("worldToClip", QMatrix4x4(&glm::transpose(clip)[0][0]));
  prog.setUniformValue("eye", QVector3D(float(eye.x), float(eye.y), float(eye.z)));
  prog.setUniformValue("exposure", float(s.exposure));
  prog.setUniformValue("falseMin", float(s.falseMin));
  prog.setUniformValue("falseMax", float(s.falseMax));
  prog.setUniformValue("fanData", 0);
  prog.setUniformValue("fanAlbedo", 1);
  prog.setUniformValue("tables", 2);
  if (bind) bind(prog);
  gl->glActiveTexture(GL_TEXTURE0);  // (the uploads below bind on unit 0, which the draw binds again)
  gl->glEnable(GL_DEPTH_TEST);
  gl->glDepthFunc(GL_LESS);
  gl->glEnable(GL_BLEND);
  // Colour blended by coverage; the target's alpha stays 1 (a frame with see-through edges is
  // composed over whatever lies behind the window: pale fringes).
  gl->glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
  gl->glBindVertexArray(vao_);
  const size_t L = size_t(maxLamps_);
  std::vector<GLint> lampLayers(L, 0);
  std::vector<glm::vec3> lampPositions(L, glm::vec3(0.f)), lampAxes(3 * L, glm::vec3(0.f));
  std::vector<GLint> perPoint(L, 0);
  for (size_t i : order) {
    Object& o = objects_[i];
    const ibr::ImageFan& fan = *o.fan;
    const std::array<int, ibr::kDrawnViews> views = ibr::viewsToward(fan, o.place, eye);
    if (views[0] < 0) continue;  // the eye is inside the object
    int nViews = 1;
    while (nViews < ibr::kDrawnViews && views[size_t(nViews)] >= 0) ++nViews;
    if (views != o.tableViews) {  // the tables of the views now drawn: handed over, or from the light
      std::vector<glm::vec3> own;
      const bool made = !o.made.rows.empty() && o.made.views == views;
      if (!made)
        for (int j = 0; j < nViews; ++j) {
          const auto t = ibr::viewTables(fan, views[size_t(j)], o.place, o.light);
          own.insert(own.end(), t.begin(), t.end());
        }
      const std::vector<glm::vec3>& rows = made ? o.made.rows : own;
      o.indirectRows = made ? o.made.indirectRows : ibr::indirectRows(o.light);
      o.rowsPerView = int(rows.size() / size_t(ibr::kNormalCodes) / size_t(nViews));
      GLint largest = 0;
      gl->glGetIntegerv(GL_MAX_TEXTURE_SIZE, &largest);
      if (o.rowsPerView * nViews > largest)
        throw Error("", "OpenGL", "an image-based object's tables (" + std::to_string(o.rowsPerView * nViews) +
                                      " rows) do not fit a texture of this display (" + std::to_string(largest) + ")");
      gl->glBindTexture(GL_TEXTURE_2D, o.tableTexture);
      gl->glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
      gl->glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB32F, ibr::kNormalCodes, o.rowsPerView * nViews, 0, GL_RGB, GL_FLOAT, rows.data());
      o.tableViews = views;
    }
    GLint layers[ibr::kDrawnViews] = {0, 0, 0};
    for (int j = 0; j < nViews; ++j) layers[j] = layerFor(i, views[size_t(j)]);
    const int lampCount = int(std::min(o.light.lamps.size(), L));
    for (int l = 0; l < lampCount; ++l) {
      const auto& lamp = o.light.lamps[size_t(l)];
      const int k = ibr::lampView(fan, o.place, lamp.position);
      lampLayers[size_t(l)] = layerFor(i, k);
      lampPositions[size_t(l)] = glm::vec3(lamp.position);
      putAxes(fan, k, lampAxes, 3 * size_t(l));
      perPoint[size_t(l)] = lamp.perPoint ? 1 : 0;
    }
    std::vector<glm::vec3> viewAxes(3 * ibr::kDrawnViews, glm::vec3(0.f));
    for (int j = 0; j < nViews; ++j) putAxes(fan, views[size_t(j)], viewAxes, 3 * size_t(j));
    const glm::dvec3 cw = o.place.toWorld(fan, fan.centre);
    const double rs = fan.radius * o.place.scale;
    const glm::dvec3 eyeObj = o.place.toObject(fan, eye);
    // A world direction into the object frame: turned back by the yaw, divided by the scale.
    const float c = float(std::cos(o.place.yaw) / o.place.scale), sn = float(std::sin(o.place.yaw) / o.place.scale);
    const GLfloat toObject[9] = {c, -sn, 0.f, sn, c, 0.f, 0.f, 0.f, float(1.0 / o.place.scale)};  // columns
    const double texel = 2.0 * rs / fan.size, pixel = glm::length(cw - eye) / std::max(camera.fx(), 1e-9);
    prog.setUniformValue("sphere", QVector4D(float(cw.x), float(cw.y), float(cw.z), float(rs)));
    prog.setUniformValue("eyeObject", QVector3D(float(eyeObj.x), float(eyeObj.y), float(eyeObj.z)));
    gl->glUniformMatrix3fv(prog.uniformLocation("worldToObject"), 1, GL_FALSE, toObject);
    prog.setUniformValue("fanCentre", QVector3D(float(fan.centre.x), float(fan.centre.y), float(fan.centre.z)));
    prog.setUniformValue("fanRadius", float(fan.radius));
    prog.setUniformValue("fanSize", fan.size);
    prog.setUniformValue("rowsPerView", o.rowsPerView);
    prog.setUniformValue("indirectRows", o.indirectRows);
    prog.setUniformValue("viewCount", nViews);
    gl->glUniform1iv(prog.uniformLocation("viewLayer"), ibr::kDrawnViews, layers);
    prog.setUniformValueArray("viewAxes", &viewAxes[0].x, 3 * ibr::kDrawnViews, 3);
    prog.setUniformValue("lampCount", lampCount);
    prog.setUniformValueArray("lampPosition", &lampPositions[0].x, int(L), 3);
    gl->glUniform1iv(prog.uniformLocation("lampLayer"), GLsizei(L), lampLayers.data());
    if (daylight_) gl->glUniform1iv(prog.uniformLocation("lampPerPoint"), GLsizei(L), perPoint.data());
    prog.setUniformValueArray("lampAxes", &lampAxes[0].x, 3 * int(L), 3);
    prog.setUniformValue("footprint", std::clamp(int(std::lround(pixel / texel)), 1, 4));
    gl->glActiveTexture(GL_TEXTURE0);
    gl->glBindTexture(GL_TEXTURE_2D_ARRAY, o.data);
    gl->glActiveTexture(GL_TEXTURE1);
    gl->glBindTexture(GL_TEXTURE_2D_ARRAY, o.albedo);
    gl->glActiveTexture(GL_TEXTURE2);
    gl->glBindTexture(GL_TEXTURE_2D, o.tableTexture);
    gl->glDrawArrays(GL_TRIANGLE_FAN, 0, 8);  // the octagon around the sphere's outline (ibr_object.vert)
  }
  gl->glBindVertexArray(0);
  gl->glDisable(GL_CULL_FACE);
  gl->glDisable(GL_BLEND);
  gl->glActiveTexture(GL_TEXTURE0);
  prog.release();
}

}  // namespace relume::gl
