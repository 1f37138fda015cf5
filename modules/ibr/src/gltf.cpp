// glTF 2.0 meshes (.gltf with its buffers, or .glb): triangles of every mesh the default scene's
// nodes place (their transforms applied), normals and colours where given, each primitive's
// material base colour as its albedo; turned from glTF's +Y up to Relume's +Z up.
#include <QByteArray>
#include <QJsonArray>
#include <QJsonDocument>
#include <QJsonObject>
#include <cmath>
#include <cstring>
#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <map>

#include "relume/geometry/error.h"
#include "relume/ibr/mesh.h"

namespace relume::ibr {

namespace {

// Instancing a mesh many times could multiply it without end: a cap far above any furniture.
constexpr size_t kMaxTriangles = 50'000'000;

uint32_t le32(const std::string& b, size_t at) {
  uint32_t v = 0;
  for (int k = 0; k < 4; ++k) v |= uint32_t(uint8_t(b[at + k])) << (8 * k);
  return v;
}

class Gltf {
 public:
  Gltf(const std::string& name, const std::function<std::string(const std::string&)>& files) : name_(name), files_(files) {}

  [[noreturn]] void fail(const std::string& element, const std::string& problem) const { throw Error(name_, element, problem); }

  void load(const std::string& bytes) {
    std::string json;
    if (bytes.size() >= 12 && bytes.compare(0, 4, "glTF") == 0) {  // binary container
      if (le32(bytes, 4) != 2) fail("header", "a glTF " + std::to_string(le32(bytes, 4)) + " file; Relume reads glTF 2");
      size_t at = 12;
      while (at + 8 <= bytes.size()) {
        const uint32_t len = le32(bytes, at), type = le32(bytes, at + 4);
        if (len > bytes.size() - at - 8) fail("chunk", "the file is truncated (a chunk runs past its end)");
        if (type == 0x4E4F534A) json = bytes.substr(at + 8, len);
        else if (type == 0x004E4942 && glb_.empty()) glb_ = bytes.substr(at + 8, len);
        at += 8 + ((len + 3) & ~3u);
      }
      if (json.empty()) fail("chunk", "no JSON chunk");
    } else {
      json = bytes;
    }
    QJsonParseError err;
    const QJsonDocument doc = QJsonDocument::fromJson(QByteArray(json.data(), qsizetype(json.size())), &err);
    if (doc.isNull() || !doc.isObject()) fail("", "not a glTF file (its JSON does not parse: " + err.errorString().toStdString() + ")");
    root_ = doc.object();
    if (!root_["asset"].toObject()["version"].toString().startsWith("2"))
      fail("asset", "not glTF 2 (asset.version is '" + root_["asset"].toObject()["version"].toString().toStdString() + "')");
  }

  Mesh mesh() {
    Mesh m;
    m.name = name_;
    const QJsonArray scenes = root_["scenes"].toArray();
    QJsonArray roots;
    if (!scenes.isEmpty()) {
      const int s = root_["scene"].toInt(0);
      if (s < 0 || s >= scenes.size()) fail("scene", "names a scene that does not exist");
      roots = scenes[s].toObject()["nodes"].toArray();
    }
    const QJsonArray nodes = root_["nodes"].toArray();
    if (roots.isEmpty() && !nodes.isEmpty()) {  // no scene: every node that is nobody's child
      std::vector<char> child(size_t(nodes.size()), 0);
      for (const auto& n : nodes)
        for (const auto& c : n.toObject()["children"].toArray())
          if (c.toInt(-1) >= 0 && c.toInt(-1) < nodes.size()) child[size_t(c.toInt())] = 1;
      for (int i = 0; i < nodes.size(); ++i)
        if (!child[size_t(i)]) roots.append(i);
    }
    visited_.assign(size_t(nodes.size()), 0);
    // glTF's +Y up to +Z up: (x, y, z) -> (x, -z, y).
    const glm::dmat4 up(glm::dvec4(1, 0, 0, 0), glm::dvec4(0, 0, 1, 0), glm::dvec4(0, -1, 0, 0), glm::dvec4(0, 0, 0, 1));
    int depth = 0;
    for (const auto& r : roots) visit(r.toInt(-1), up, m, depth);
    if (m.triangles.empty()) fail("meshes", "the scene holds no triangles");
    validateMesh(m);
    return m;
  }

 private:
  void visit(int n, const glm::dmat4& parent, Mesh& m, int& depth) {
    const QJsonArray nodes = root_["nodes"].toArray();
    if (n < 0 || n >= nodes.size()) fail("nodes", "a node names a node that does not exist");
    if (visited_[size_t(n)]) fail("node " + std::to_string(n), "appears twice in the scene (glTF allows a node one parent)");
    visited_[size_t(n)] = 1;
    if (++depth > 64) fail("nodes", "nodes nest more than 64 deep");
    const QJsonObject node = nodes[n].toObject();
    glm::dmat4 local(1.0);
    if (node.contains("matrix")) {
      const QJsonArray a = node["matrix"].toArray();
      if (a.size() != 16) fail("node " + std::to_string(n), "a matrix needs 16 numbers");
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) local[c][r] = a[c * 4 + r].toDouble();
    } else {
      const QJsonArray t = node["translation"].toArray(), q = node["rotation"].toArray(), s = node["scale"].toArray();
      glm::dmat4 T(1.0), R(1.0), S(1.0);
      if (t.size() == 3) T[3] = glm::dvec4(t[0].toDouble(), t[1].toDouble(), t[2].toDouble(), 1.0);
      if (q.size() == 4) R = glm::dmat4(glm::mat3_cast(glm::dquat(q[3].toDouble(), q[0].toDouble(), q[1].toDouble(), q[2].toDouble())));
      if (s.size() == 3) S = glm::dmat4(glm::dvec4(s[0].toDouble(), 0, 0, 0), glm::dvec4(0, s[1].toDouble(), 0, 0),
                                       glm::dvec4(0, 0, s[2].toDouble(), 0), glm::dvec4(0, 0, 0, 1));
      local = T * R * S;
    }
    const glm::dmat4 world = parent * local;
    if (node.contains("mesh")) addMesh(node["mesh"].toInt(-1), world, m);
    for (const auto& c : node["children"].toArray()) visit(c.toInt(-1), world, m, depth);
    --depth;
  }

  // The bytes of buffer view `v`, and its stride.
  const std::string& buffer(int b) {
    const QJsonArray buffers = root_["buffers"].toArray();
    if (b < 0 || b >= buffers.size()) fail("buffers", "a buffer view names a buffer that does not exist");
    auto it = buffers_.find(b);
    if (it != buffers_.end()) return it->second;
    const QJsonObject o = buffers[b].toObject();
    std::string bytes;
    if (!o.contains("uri")) {
      bytes = glb_;
    } else {
      const QString uri = o["uri"].toString();
      if (uri.startsWith("data:")) {
        const int comma = uri.indexOf(',');
        if (comma < 0 || !uri.left(comma).endsWith(";base64")) fail("buffer " + std::to_string(b), "a data URI that is not base64");
        const QByteArray d = QByteArray::fromBase64(uri.mid(comma + 1).toLatin1());
        bytes.assign(d.constData(), size_t(d.size()));
      } else {
        if (!files_) fail("buffer " + std::to_string(b), "names a file, which cannot be read here");
        bytes = files_(QByteArray::fromPercentEncoding(uri.toUtf8()).toStdString());
      }
    }
    const double declared = o["byteLength"].toDouble(-1);
    if (!(declared >= 0) || declared > double(bytes.size()))
      fail("buffer " + std::to_string(b), "holds fewer bytes than its byteLength says (truncated)");
    return buffers_.emplace(b, std::move(bytes)).first->second;
  }

  // Accessor `a` read as `comps` doubles per element.
  std::vector<double> accessor(int a, int comps, const std::string& what) {
    const QJsonArray accessors = root_["accessors"].toArray();
    if (a < 0 || a >= accessors.size()) fail(what, "names an accessor that does not exist");
    const QJsonObject o = accessors[a].toObject();
    const QString type = o["type"].toString();
    const int n = type == "SCALAR" ? 1 : type == "VEC2" ? 2 : type == "VEC3" ? 3 : type == "VEC4" ? 4 : 0;
    if (n == 0 || n < comps) fail(what, "an accessor of type '" + type.toStdString() + "'");
    const int ct = o["componentType"].toInt();
    const size_t csize = ct == 5120 || ct == 5121 ? 1 : ct == 5122 || ct == 5123 ? 2 : ct == 5125 || ct == 5126 ? 4 : 0;
    if (!csize) fail(what, "an accessor of component type " + std::to_string(ct));
    const double countD = o["count"].toDouble(-1);
    if (!(countD >= 0) || countD > 1e9) fail(what, "an accessor's count is not a count");
    const size_t count = size_t(countD);
    if (!o.contains("bufferView")) fail(what, "an accessor without a buffer view (sparse accessors are not read)");
    const QJsonArray views = root_["bufferViews"].toArray();
    const int vi = o["bufferView"].toInt(-1);
    if (vi < 0 || vi >= views.size()) fail(what, "names a buffer view that does not exist");
    const QJsonObject v = views[vi].toObject();
    const std::string& b = buffer(v["buffer"].toInt(-1));
    const double viewOff = v["byteOffset"].toDouble(0), viewLen = v["byteLength"].toDouble(-1), off = o["byteOffset"].toDouble(0);
    const size_t stride = v["byteStride"].toInt(0) > 0 ? size_t(v["byteStride"].toInt()) : csize * size_t(n);
    if (!(viewOff >= 0 && viewLen >= 0 && off >= 0) || viewOff + viewLen > double(b.size()))
      fail(what, "a buffer view runs past its buffer's end");
    if (count > 0 && off + double(stride) * double(count - 1) + double(csize) * n > viewLen)
      fail(what, "an accessor runs past its buffer view's end");
    std::vector<double> out(count * size_t(comps), 0.0);  // its bytes are there (checked above)
    const bool normalized = o["normalized"].toBool(false);
    const char* base = b.data() + size_t(viewOff) + size_t(off);
    for (size_t i = 0; i < count; ++i)
      for (int c = 0; c < comps; ++c) {
        const char* p = base + i * stride + size_t(c) * csize;
        double x = 0;
        switch (ct) {
          case 5120: x = double(int8_t(*p)); if (normalized) x = std::max(x / 127.0, -1.0); break;
          case 5121: x = double(uint8_t(*p)); if (normalized) x /= 255.0; break;
          case 5122: { int16_t t; std::memcpy(&t, p, 2); x = t; if (normalized) x = std::max(x / 32767.0, -1.0); break; }
          case 5123: { uint16_t t; std::memcpy(&t, p, 2); x = t; if (normalized) x /= 65535.0; break; }
          case 5125: { uint32_t t; std::memcpy(&t, p, 4); x = t; break; }
          case 5126: { float t; std::memcpy(&t, p, 4); x = t; break; }
        }
        out[i * size_t(comps) + size_t(c)] = x;
      }
    return out;
  }

  void addMesh(int mi, const glm::dmat4& world, Mesh& m) {
    const QJsonArray meshes = root_["meshes"].toArray();
    if (mi < 0 || mi >= meshes.size()) fail("nodes", "a node names a mesh that does not exist");
    const glm::dmat3 normalMatrix = glm::transpose(glm::inverse(glm::dmat3(world)));
    const bool mirrored = glm::determinant(glm::dmat3(world)) < 0;  // glTF: the winding flips too
    const QJsonArray prims = meshes[mi].toObject()["primitives"].toArray();
    for (int pi = 0; pi < prims.size(); ++pi) {
      const QJsonObject prim = prims[pi].toObject();
      const std::string what = "mesh " + std::to_string(mi) + " primitive " + std::to_string(pi);
      if (prim["mode"].toInt(4) != 4) continue;  // points and lines have no surface
      const QJsonObject attr = prim["attributes"].toObject();
      if (!attr.contains("POSITION")) fail(what, "has no POSITION");
      const std::vector<double> pos = accessor(attr["POSITION"].toInt(-1), 3, what + " POSITION");
      const size_t nv = pos.size() / 3;
      std::vector<double> nrm, col;
      if (attr.contains("NORMAL")) nrm = accessor(attr["NORMAL"].toInt(-1), 3, what + " NORMAL");
      if (attr.contains("COLOR_0")) col = accessor(attr["COLOR_0"].toInt(-1), 3, what + " COLOR_0");
      if ((!nrm.empty() && nrm.size() != pos.size()) || (!col.empty() && col.size() != pos.size()))
        fail(what, "its NORMAL or COLOR_0 has not one value per vertex");
      std::vector<double> idx;
      if (prim.contains("indices")) idx = accessor(prim["indices"].toInt(-1), 1, what + " indices");
      else for (size_t i = 0; i < nv; ++i) idx.push_back(double(i));
      glm::vec3 albedo(kDefaultAlbedo);
      if (prim.contains("material")) {
        const QJsonArray mats = root_["materials"].toArray();
        const int mat = prim["material"].toInt(-1);
        if (mat < 0 || mat >= mats.size()) fail(what, "names a material that does not exist");
        const QJsonArray f = mats[mat].toObject()["pbrMetallicRoughness"].toObject()["baseColorFactor"].toArray();
        if (f.size() >= 3)
          albedo = glm::clamp(glm::vec3(float(f[0].toDouble()), float(f[1].toDouble()), float(f[2].toDouble())), glm::vec3(0.f), glm::vec3(1.f));
      }
      const size_t base = m.positions.size();
      for (size_t i = 0; i < nv; ++i)
        m.positions.push_back(glm::vec3(world * glm::dvec4(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2], 1.0)));
      // Normals and colours go per corner; a mesh mixing primitives with and without them gets
      // face normals and material colours where missing.
      for (size_t t = 0; t + 2 < idx.size(); t += 3) {
        glm::uvec3 tri;
        for (int k = 0; k < 3; ++k) {
          const double v = idx[t + size_t(k)];
          if (!(v >= 0) || v >= double(nv)) fail(what + " indices", "an index names a vertex that does not exist");
          tri[k] = unsigned(base + size_t(v));
        }
        if (mirrored) std::swap(tri[1], tri[2]);
        if (m.triangles.size() >= kMaxTriangles)
          fail("meshes", "more than " + std::to_string(kMaxTriangles / 1000000) + " million triangles");
        m.triangles.push_back(tri);
        m.triangleAlbedo.push_back(albedo);
        for (int kk = 0; kk < 3; ++kk) {
          const int k = mirrored && kk > 0 ? 3 - kk : kk;  // the corners in the triangle's order
          const size_t v = size_t(idx[t + size_t(k)]);
          cornerN_.push_back(nrm.empty() ? glm::vec3(0.f) : glm::vec3(normalMatrix * glm::dvec3(nrm[3 * v], nrm[3 * v + 1], nrm[3 * v + 2])));
          cornerC_.push_back(col.empty() ? albedo * 1.f : glm::clamp(glm::vec3(col[3 * v], col[3 * v + 1], col[3 * v + 2]) * albedo, glm::vec3(0.f), glm::vec3(1.f)));
        }
        anyNormal_ = anyNormal_ || !nrm.empty();
        anyColour_ = anyColour_ || !col.empty();
      }
    }
    if (anyNormal_) {
      m.cornerNormals = cornerN_;
      for (size_t i = 0; i < m.triangles.size(); ++i) {
        const auto& tr = m.triangles[i];
        const glm::vec3 f = glm::cross(m.positions[tr[1]] - m.positions[tr[0]], m.positions[tr[2]] - m.positions[tr[0]]);
        for (int k = 0; k < 3; ++k) {
          glm::vec3& c = m.cornerNormals[3 * i + size_t(k)];
          const float l = glm::length(c);
          c = l > 0 && std::isfinite(l) ? c / l : (glm::length(f) > 0 ? glm::normalize(f) : glm::vec3(0, 0, 1));
        }
      }
    }
    if (anyColour_) m.cornerColours = cornerC_;
  }

  std::string name_;
  std::function<std::string(const std::string&)> files_;
  QJsonObject root_;
  std::string glb_;
  std::map<int, std::string> buffers_;
  std::vector<glm::vec3> cornerN_, cornerC_;
  std::vector<char> visited_;
  bool anyNormal_ = false, anyColour_ = false;
};

}  // namespace

Mesh parseGltfMesh(const std::string& bytes, const std::string& name, const std::function<std::string(const std::string&)>& files) {
  Gltf g(name, files);
  g.load(bytes);
  return g.mesh();
}

}  // namespace relume::ibr
