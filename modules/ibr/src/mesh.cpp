#include "relume/ibr/mesh.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <map>
#include <sstream>
#include <string_view>

#include "relume/geometry/error.h"

namespace relume::ibr {

namespace {

std::string readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path, "", "cannot be read");
  std::ostringstream s;
  s << in.rdbuf();
  if (in.bad()) throw Error(path, "", "cannot be read");
  return s.str();
}

// Whitespace-separated tokens of one line.
struct Tokens {
  std::string_view rest;
  std::string_view next() {
    size_t a = rest.find_first_not_of(" \t\r");
    if (a == std::string_view::npos) {
      rest = {};
      return {};
    }
    size_t b = rest.find_first_of(" \t\r", a);
    if (b == std::string_view::npos) b = rest.size();
    std::string_view t = rest.substr(a, b - a);
    rest = rest.substr(b);
    return t;
  }
};

bool toFloat(std::string_view t, float& v) {
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  return ec == std::errc() && p == t.data() + t.size();
}

bool toLong(std::string_view t, long& v) {
  auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  return ec == std::errc() && p == t.data() + t.size();
}

std::string lineText(size_t line) { return "line " + std::to_string(line); }

// A 1-based (or negative, relative) OBJ index into n items; -1 when out of range.
long objIndex(long i, size_t n) {
  if (i > 0 && size_t(i) <= n) return i - 1;
  if (i < 0 && i >= -long(n)) return long(n) + i;
  return -1;
}

std::map<std::string, glm::vec3> parseMtl(const std::string& bytes) {
  std::map<std::string, glm::vec3> kd;
  std::string current;
  std::string_view all(bytes);
  while (!all.empty()) {
    size_t e = all.find('\n');
    Tokens t{all.substr(0, e)};
    all = e == std::string_view::npos ? std::string_view() : all.substr(e + 1);
    const std::string_view key = t.next();
    if (key == "newmtl") {
      current = std::string(t.next());
      kd[current] = glm::vec3(kDefaultAlbedo);
    } else if (key == "Kd" && !current.empty()) {
      glm::vec3 c;
      bool ok = true;
      for (int k = 0; k < 3 && ok; ++k) ok = toFloat(t.next(), c[k]) && std::isfinite(c[k]);
      if (ok) kd[current] = glm::clamp(c, glm::vec3(0.f), glm::vec3(1.f));
    }
  }
  return kd;
}

// A file a mesh names (an MTL, a glTF buffer): a plain file in the mesh's folder or below it,
// named by a relative path without "..".
std::string besideFile(const std::string& mesh, const std::filesystem::path& dir, const std::string& rel,
                       const std::string& element) {
  const std::filesystem::path p(rel);
  if (rel.empty() || p.is_absolute() || std::any_of(p.begin(), p.end(), [](const auto& part) { return part == ".."; }))
    throw Error(mesh, element, "names a file outside the mesh's folder");
  std::error_code ec;
  if (!std::filesystem::is_regular_file(dir / p, ec)) throw Error(mesh, element, "names a file that is not there");
  try {
    return readAll((dir / p).string());
  } catch (const Error&) {
    throw Error(mesh, element, "the file it names cannot be read");
  }
}

}  // namespace

void validateMesh(const Mesh& m) {
  for (const auto& p : m.positions)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw Error(m.name, "vertices", "a coordinate is not a finite number");
  bool area = false;
  for (const auto& t : m.triangles) {
    for (int k = 0; k < 3; ++k)
      if (t[k] >= m.positions.size()) throw Error(m.name, "faces", "a face names a vertex that does not exist");
    area = area || glm::length(glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]])) > 0.f;
  }
  if (m.triangles.empty()) throw Error(m.name, "faces", "the mesh has no faces");
  if (!area) throw Error(m.name, "faces", "every face has zero area");
  if (!m.cornerNormals.empty() && m.cornerNormals.size() != 3 * m.triangles.size())
    throw Error(m.name, "normals", "not one normal per face corner");
  if (!m.cornerColours.empty() && m.cornerColours.size() != 3 * m.triangles.size())
    throw Error(m.name, "colours", "not one colour per face corner");
  if (m.cornerColours.empty() && m.triangleAlbedo.size() != m.triangles.size())
    throw Error(m.name, "colours", "not one colour per face");
}

Mesh parseObjMesh(const std::string& bytes, const std::string& name,
                  const std::function<std::string(const std::string&)>& mtl) {
  Mesh m;
  m.name = name;
  std::vector<glm::vec3> vn;
  std::map<std::string, glm::vec3> materials;
  glm::vec3 albedo(kDefaultAlbedo);
  bool anyNormal = false, allNormals = true;
  std::vector<glm::vec3> cornerN;  // filled as faces come; zero where a corner has none
  std::vector<long> fv, fn;
  std::string_view all(bytes);
  size_t line = 0;
  while (!all.empty()) {
    ++line;
    size_t e = all.find('\n');
    Tokens t{all.substr(0, e)};
    all = e == std::string_view::npos ? std::string_view() : all.substr(e + 1);
    const std::string_view key = t.next();
    if (key == "v" || key == "vn") {
      glm::vec3 p;
      for (int k = 0; k < 3; ++k)
        if (!toFloat(t.next(), p[k]))
          throw Error(name, lineText(line), std::string(key == "v" ? "a vertex" : "a normal") + " needs three numbers");
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        throw Error(name, lineText(line), "a coordinate is not a finite number");
      (key == "v" ? m.positions : vn).push_back(p);
    } else if (key == "f") {
      fv.clear();
      fn.clear();
      for (std::string_view c = t.next(); !c.empty(); c = t.next()) {
        const size_t s1 = c.find('/');
        long vi, ni = 0;
        if (!toLong(c.substr(0, s1), vi)) throw Error(name, lineText(line), "a face corner is not a vertex index");
        vi = objIndex(vi, m.positions.size());
        if (vi < 0) throw Error(name, lineText(line), "a face names a vertex that does not exist");
        if (s1 != std::string_view::npos) {
          const size_t s2 = c.find('/', s1 + 1);
          if (s2 != std::string_view::npos && s2 + 1 < c.size()) {
            if (!toLong(c.substr(s2 + 1), ni)) throw Error(name, lineText(line), "a face corner's normal index is not a number");
            ni = objIndex(ni, vn.size());
            if (ni < 0) throw Error(name, lineText(line), "a face names a normal that does not exist");
            ++ni;  // 0: none
          }
        }
        fv.push_back(vi);
        fn.push_back(ni);
      }
      if (fv.size() < 3) throw Error(name, lineText(line), "a face needs at least three corners");
      for (size_t k = 1; k + 1 < fv.size(); ++k) {
        m.triangles.push_back(glm::uvec3(unsigned(fv[0]), unsigned(fv[k]), unsigned(fv[k + 1])));
        m.triangleAlbedo.push_back(albedo);
        for (size_t c : {size_t(0), k, k + 1}) {
          if (fn[c] > 0) {
            anyNormal = true;
            cornerN.push_back(vn[size_t(fn[c] - 1)]);
          } else {
            allNormals = false;
            cornerN.push_back(glm::vec3(0.f));
          }
        }
      }
    } else if (key == "usemtl") {
      const std::string mat(t.next());
      auto it = materials.find(mat);
      albedo = it == materials.end() ? glm::vec3(kDefaultAlbedo) : it->second;
    } else if (key == "mtllib" && mtl) {
      for (std::string_view f = t.next(); !f.empty(); f = t.next()) {
        const auto more = parseMtl(mtl(std::string(f)));
        for (const auto& [k, v] : more) materials[k] = v;
      }
    }
  }
  if (anyNormal) {
    // Corners without a normal take their face's.
    for (size_t i = 0; i < m.triangles.size(); ++i) {
      const auto& tr = m.triangles[i];
      const glm::vec3 fnrm = glm::cross(m.positions[tr[1]] - m.positions[tr[0]], m.positions[tr[2]] - m.positions[tr[0]]);
      for (int k = 0; k < 3; ++k) {
        glm::vec3& c = cornerN[3 * i + k];
        const float l = glm::length(c);
        c = l > 0 ? c / l : (glm::length(fnrm) > 0 ? glm::normalize(fnrm) : glm::vec3(0, 0, 1));
      }
    }
    m.cornerNormals = std::move(cornerN);
  }
  (void)allNormals;
  validateMesh(m);
  return m;
}

namespace {

enum class PlyType { I8, U8, I16, U16, I32, U32, F32, F64 };

bool plyType(std::string_view s, PlyType& t) {
  static const std::pair<const char*, PlyType> names[] = {
      {"char", PlyType::I8},    {"int8", PlyType::I8},     {"uchar", PlyType::U8},   {"uint8", PlyType::U8},
      {"short", PlyType::I16},  {"int16", PlyType::I16},   {"ushort", PlyType::U16}, {"uint16", PlyType::U16},
      {"int", PlyType::I32},    {"int32", PlyType::I32},   {"uint", PlyType::U32},   {"uint32", PlyType::U32},
      {"float", PlyType::F32},  {"float32", PlyType::F32}, {"double", PlyType::F64}, {"float64", PlyType::F64}};
  for (const auto& [n, v] : names)
    if (s == n) {
      t = v;
      return true;
    }
  return false;
}

size_t plySize(PlyType t) {
  switch (t) {
    case PlyType::I8: case PlyType::U8: return 1;
    case PlyType::I16: case PlyType::U16: return 2;
    case PlyType::I32: case PlyType::U32: case PlyType::F32: return 4;
    case PlyType::F64: return 8;
  }
  return 1;
}

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::F32;
  bool list = false;
  PlyType countType = PlyType::U8;
};

struct PlyElement {
  std::string name;
  size_t count = 0;
  std::vector<PlyProperty> props;
};

// Reads values from the body: ASCII tokens or binary of either byte order.
class PlyReader {
 public:
  PlyReader(std::string_view body, int format, const std::string& name) : body_(body), format_(format), name_(name) {}
  double value(PlyType t) {
    if (format_ == 0) {
      const size_t a = body_.find_first_not_of(" \t\r\n", pos_);
      if (a == std::string_view::npos) throw Error(name_, "body", "the file ends before its elements do");
      size_t b = body_.find_first_of(" \t\r\n", a);
      if (b == std::string_view::npos) b = body_.size();
      pos_ = b;
      std::string_view tok = body_.substr(a, b - a);
      double v;
      if (!tok.empty() && tok.front() == '+') tok.remove_prefix(1);
      auto [p, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
      if (ec != std::errc() || p != tok.data() + tok.size()) throw Error(name_, "body", "a value is not a number");
      return v;
    }
    const size_t n = plySize(t);
    if (pos_ + n > body_.size()) throw Error(name_, "body", "the file ends before its elements do");
    unsigned char b[8];
    std::memcpy(b, body_.data() + pos_, n);
    pos_ += n;
    const bool little = std::endian::native == std::endian::little;
    if ((format_ == 1) != little) std::reverse(b, b + n);
    switch (t) {
      case PlyType::I8: return double(int8_t(b[0]));
      case PlyType::U8: return double(b[0]);
      case PlyType::I16: { int16_t v; std::memcpy(&v, b, 2); return v; }
      case PlyType::U16: { uint16_t v; std::memcpy(&v, b, 2); return v; }
      case PlyType::I32: { int32_t v; std::memcpy(&v, b, 4); return v; }
      case PlyType::U32: { uint32_t v; std::memcpy(&v, b, 4); return v; }
      case PlyType::F32: { float v; std::memcpy(&v, b, 4); return v; }
      case PlyType::F64: { double v; std::memcpy(&v, b, 8); return v; }
    }
    return 0;
  }

 private:
  std::string_view body_;
  size_t pos_ = 0;
  int format_;  // 0 ASCII, 1 binary little endian, 2 big endian
  const std::string& name_;
};

}  // namespace

Mesh parsePlyMesh(const std::string& bytes, const std::string& name) {
  std::string_view all(bytes);
  if (all.substr(0, 3) != "ply") throw Error(name, "header", "not a PLY file (no 'ply' on its first line)");
  const size_t endHeader = all.find("end_header");
  if (endHeader == std::string_view::npos) throw Error(name, "header", "no end_header");
  size_t bodyStart = all.find('\n', endHeader);
  if (bodyStart == std::string_view::npos) bodyStart = all.size();
  else ++bodyStart;
  int format = -1;
  std::vector<PlyElement> elements;
  std::string_view header = all.substr(0, endHeader);
  size_t line = 0;
  while (!header.empty()) {
    ++line;
    const size_t e = header.find('\n');
    Tokens t{header.substr(0, e)};
    header = e == std::string_view::npos ? std::string_view() : header.substr(e + 1);
    const std::string_view key = t.next();
    if (key == "format") {
      const std::string_view f = t.next();
      format = f == "ascii" ? 0 : f == "binary_little_endian" ? 1 : f == "binary_big_endian" ? 2 : -2;
      if (format == -2) throw Error(name, "header", "unknown format '" + std::string(f) + "'");
    } else if (key == "element") {
      PlyElement el;
      el.name = std::string(t.next());
      long n;
      if (!toLong(t.next(), n) || n < 0) throw Error(name, "header " + lineText(line), "an element needs a count");
      el.count = size_t(n);
      elements.push_back(el);
    } else if (key == "property") {
      if (elements.empty()) throw Error(name, "header " + lineText(line), "a property before any element");
      PlyProperty p;
      std::string_view ty = t.next();
      if (ty == "list") {
        p.list = true;
        if (!plyType(t.next(), p.countType) || !plyType(t.next(), p.type))
          throw Error(name, "header " + lineText(line), "a list property of unknown types");
      } else if (!plyType(ty, p.type)) {
        throw Error(name, "header " + lineText(line), "a property of unknown type '" + std::string(ty) + "'");
      }
      p.name = std::string(t.next());
      elements.back().props.push_back(p);
    }
  }
  if (format < 0) throw Error(name, "header", "no format line");
  Mesh m;
  m.name = name;
  // Bound the counts by what the body can hold (a value is at least one byte, or two characters).
  const size_t bodyBytes = all.size() - bodyStart;
  int vertexElements = 0, faceElements = 0;
  for (const auto& el : elements) {
    if (el.count > bodyBytes) throw Error(name, "element " + el.name, "more elements than the file has bytes for");
    vertexElements += el.name == "vertex";
    faceElements += el.name == "face";
  }
  if (vertexElements != 1) throw Error(name, "header", "needs exactly one vertex element");
  if (faceElements > 1) throw Error(name, "header", "more than one face element");
  PlyReader r(all.substr(bodyStart), format, name);
  std::vector<glm::vec3> vertexNormal, vertexColour;
  bool hasNormal = false, hasColour = false;
  for (const auto& el : elements) {
    if (el.name == "vertex") {
      int ix[9];
      std::fill(ix, ix + 9, -1);
      const char* names[9] = {"x", "y", "z", "nx", "ny", "nz", "red", "green", "blue"};
      for (size_t k = 0; k < el.props.size(); ++k)
        for (int j = 0; j < 9; ++j)
          if (el.props[k].name == names[j] && !el.props[k].list) ix[j] = int(k);
      if (ix[0] < 0 || ix[1] < 0 || ix[2] < 0) throw Error(name, "element vertex", "needs x, y and z");
      hasNormal = ix[3] >= 0 && ix[4] >= 0 && ix[5] >= 0;
      hasColour = ix[6] >= 0 && ix[7] >= 0 && ix[8] >= 0;
      m.positions.resize(el.count);
      if (hasNormal) vertexNormal.resize(el.count);
      if (hasColour) vertexColour.resize(el.count);
      std::vector<double> vals(el.props.size());
      for (size_t v = 0; v < el.count; ++v) {
        for (size_t k = 0; k < el.props.size(); ++k) {
          const auto& p = el.props[k];
          if (p.list) {
            const double n = r.value(p.countType);
            if (!(n >= 0) || n > double(bodyBytes)) throw Error(name, "element vertex", "a list length is not a count");
            for (size_t i = 0; i < size_t(n); ++i) r.value(p.type);
            vals[k] = 0;
          } else {
            vals[k] = r.value(p.type);
          }
        }
        m.positions[v] = glm::vec3(vals[ix[0]], vals[ix[1]], vals[ix[2]]);
        if (hasNormal) vertexNormal[v] = glm::vec3(vals[ix[3]], vals[ix[4]], vals[ix[5]]);
        if (hasColour) {
          const bool bytes8 = el.props[ix[6]].type == PlyType::U8;
          glm::vec3 c(vals[ix[6]], vals[ix[7]], vals[ix[8]]);
          if (bytes8) {  // 8-bit colours are sRGB-encoded
            for (int k = 0; k < 3; ++k) {
              const float s = c[k] / 255.f;
              c[k] = s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f);
            }
          }
          vertexColour[v] = glm::clamp(c, glm::vec3(0.f), glm::vec3(1.f));
        }
      }
    } else if (el.name == "face") {
      if (m.positions.empty() && el.count > 0) throw Error(name, "element face", "faces come before the vertices they name");
      int ix = -1;
      for (size_t k = 0; k < el.props.size(); ++k)
        if (el.props[k].list && (el.props[k].name == "vertex_indices" || el.props[k].name == "vertex_index")) ix = int(k);
      if (ix < 0) throw Error(name, "element face", "needs a vertex_indices list");
      std::vector<long> idx;
      for (size_t f = 0; f < el.count; ++f) {
        for (size_t k = 0; k < el.props.size(); ++k) {
          const auto& p = el.props[k];
          if (!p.list) {
            r.value(p.type);
            continue;
          }
          const double n = r.value(p.countType);
          if (!(n >= 0) || n > double(bodyBytes)) throw Error(name, "element face", "a list length is not a count");
          idx.clear();
          for (size_t i = 0; i < size_t(n); ++i) {
            const double v = r.value(p.type);
            if (int(k) == ix) {
              if (!(v >= 0) || v >= double(m.positions.size()))
                throw Error(name, "element face", "a face names a vertex that does not exist");
              idx.push_back(long(v));
            }
          }
          if (int(k) != ix) continue;
          if (idx.size() < 3) throw Error(name, "element face", "a face needs at least three corners");
          for (size_t i = 1; i + 1 < idx.size(); ++i)
            m.triangles.push_back(glm::uvec3(unsigned(idx[0]), unsigned(idx[i]), unsigned(idx[i + 1])));
        }
      }
    } else if (el.name != "face" && !el.props.empty()) {  // other elements: read past
      for (size_t i = 0; i < el.count; ++i)
        for (const auto& p : el.props) {
          if (!p.list) {
            r.value(p.type);
            continue;
          }
          const double n = r.value(p.countType);
          if (!(n >= 0) || n > double(bodyBytes)) throw Error(name, "element " + el.name, "a list length is not a count");
          for (size_t j = 0; j < size_t(n); ++j) r.value(p.type);
        }
    }
  }
  if (hasNormal) {
    m.cornerNormals.reserve(3 * m.triangles.size());
    for (const auto& t : m.triangles)
      for (int k = 0; k < 3; ++k) {
        const glm::vec3 n = vertexNormal[t[k]];
        const float l = glm::length(n);
        m.cornerNormals.push_back(l > 0 && std::isfinite(l) ? n / l : glm::vec3(0, 0, 1));
      }
  }
  if (hasColour) {
    m.cornerColours.reserve(3 * m.triangles.size());
    for (const auto& t : m.triangles)
      for (int k = 0; k < 3; ++k) m.cornerColours.push_back(vertexColour[t[k]]);
  } else {
    m.triangleAlbedo.assign(m.triangles.size(), glm::vec3(kDefaultAlbedo));
  }
  validateMesh(m);
  return m;
}

Mesh readMesh(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext != ".obj" && ext != ".ply" && ext != ".gltf" && ext != ".glb")
    throw Error(path, "", "not a mesh Relume reads (.obj, .ply, .gltf or .glb)");
  const std::string bytes = readAll(path);
  if (ext == ".ply") return parsePlyMesh(bytes, path);
  const auto dir = std::filesystem::path(path).parent_path();
  if (ext == ".gltf" || ext == ".glb")
    return parseGltfMesh(bytes, path, [&](const std::string& rel) { return besideFile(path, dir, rel, "buffer " + rel); });
  return parseObjMesh(bytes, path, [&](const std::string& lib) { return besideFile(path, dir, lib, "mtllib " + lib); });
}

}  // namespace relume::ibr
