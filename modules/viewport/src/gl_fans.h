#pragma once
// Image-based objects (Dinh, Metoyer, Turk §3) on the GPU, for both viewports' renderers: each
// object's fan views in the layers of a texture array (uploaded as a frame needs them, the least
// recently needed making room), its tables as a texture, and the draw (shaders/ibr_object.vert,
// ibr_object.frag), as the CPU renderer (ibr::drawObject) draws it. The light is the library's:
// the tables are computed from it (ibr::viewTables), or handed over made (ibr::drawnTables).
// Needs a current OpenGL 3.3 context for every call but the constructor.
#include <QByteArray>
#include <array>
#include <functional>
#include <memory>
#include <vector>

#include <glm/mat4x4.hpp>

#include "relume/geometry/camera.h"
#include "relume/ibr/ibr_object.h"
#include "relume/ibr/relit_objects.h"
#include "relume/viewport/gl_renderer.h"

class QOpenGLFunctions_3_3_Core;
class QOpenGLShaderProgram;

namespace relume::gl {

class FanObjects {
 public:
  // maxLamps: the lamps per object the shader takes (the strongest kept); `daylight`: the shader
  // reads the sun's shadow maps for the lamp seen per point (the daylight view's, bound by
  // draw()'s `bind`).
  FanObjects(int maxLamps, bool daylight);
  ~FanObjects();
  // `fragmentPrefix`: what the fragment shader is given before its own source (display.glsl, and
  // for daylight the maps' declarations); `defines` after the version line in both shaders.
  // `compileNow`: the shader is compiled here (its errors show at once), else at the first draw
  // with objects (a display that may never draw any does not depend on it).
  void initialize(QOpenGLFunctions_3_3_Core* gl, const QByteArray& fragmentPrefix, const QByteArray& defines = {},
                  bool compileNow = true);
  void release();
  // The objects and their light (one each). `tables`, when given (one each), are their drawn
  // views' tables made by the library (ibr::drawnTables, after the same keepDisplayLamps(maxLamps));
  // a view they do not cover gets its tables from the light.
  // `moreViews` (per object, when given): fan views also needed at every frame (the daylight
  // view's shadow maps'), so that the layers hold them all without uploading them again.
  void set(const std::vector<ibr::ImageObject>& objects, const std::vector<ibr::ObjectLighting>& lights,
           std::vector<ibr::DrawnTables> tables = {}, const std::vector<std::vector<int>>& moreViews = {});
  bool empty() const { return objects_.empty(); }
  size_t size() const { return objects_.size(); }
  const ibr::ImageFan& fan(size_t i) const { return *objects_[i].fan; }
  const ibr::Placement& place(size_t i) const { return objects_[i].place; }
  // The farthest any object's drawn octagon reaches from `eye` (for a far plane).
  double reach(const glm::dvec3& eye) const;
  // Draws them into the bound framebuffer (depth test on, colour blended by coverage), farthest
  // first. `bind` sets a daylight program's own uniforms and textures (units 3 and up are free).
  void draw(const Camera& camera, const glm::mat4& clip, const DisplaySettings& s,
            const std::function<void(QOpenGLShaderProgram&)>& bind = {});
  // The texture-array layer holding fan view `view` of object i (uploaded if it is not there), and
  // the array (code, depth, coverage as 16-bit integers): for the daylight view's shadow maps.
  int layerFor(size_t i, int view);
  unsigned dataTexture(size_t i) const { return objects_[i].data; }
  // A vertex array with no attributes (for draws whose vertices come from gl_VertexID).
  unsigned emptyVertexArray() const { return vao_; }

 private:
  struct Object {
    std::shared_ptr<const ibr::ImageFan> fan;
    ibr::Placement place;
    ibr::ObjectLighting light;  // its lamps as keepDisplayLamps left them
    ibr::DrawnTables made;      // tables handed over (rows empty: none)
    unsigned data = 0, albedo = 0, tableTexture = 0;
    int layers = 0;
    std::vector<int> layerView;       // the fan view in each layer (-1: free)
    std::vector<uint64_t> layerUsed;  // the frame that last needed it
    std::array<int, ibr::kDrawnViews> tableViews{-2, -2, -2};
    int rowsPerView = 0, indirectRows = 1;
  };
  QOpenGLShaderProgram& program(DisplayOutput output);
  void releaseObject(Object& o);
  QOpenGLFunctions_3_3_Core* gl_ = nullptr;
  int maxLamps_;
  bool daylight_;
  QByteArray prefix_, defines_, vertex_, fragment_;
  std::vector<std::unique_ptr<QOpenGLShaderProgram>> programs_;  // by output
  std::vector<Object> objects_;
  uint64_t frame_ = 0;
  unsigned vao_ = 0;
};

}  // namespace relume::gl
