#include "relume/reconstruct/colmap_model.h"

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "relume/geometry/error.h"

namespace fs = std::filesystem;

namespace relume::recon {

namespace {

struct ModelSpec {
  const char* name;
  int id;      // COLMAP's model id in the binary format
  int params;  // parameter count
};
constexpr ModelSpec kModels[] = {
    {"SIMPLE_PINHOLE", 0, 3}, {"PINHOLE", 1, 4}, {"SIMPLE_RADIAL", 2, 4}, {"RADIAL", 3, 5}, {"OPENCV", 4, 8},
};

const ModelSpec* specByName(const std::string& n) {
  for (const auto& m : kModels)
    if (n == m.name) return &m;
  return nullptr;
}
const ModelSpec* specById(int id) {
  for (const auto& m : kModels)
    if (id == m.id) return &m;
  return nullptr;
}
std::string supportedModels() {
  std::string s;
  for (const auto& m : kModels) s += (s.empty() ? "" : ", ") + std::string(m.name);
  return s;
}

// Radial and tangential displacement of a normalised point (COLMAP's convention).
glm::dvec2 distortNormalised(const ColmapCamera& c, glm::dvec2 u) {
  const auto& p = c.params;
  const double r2 = u.x * u.x + u.y * u.y;
  if (c.model == "SIMPLE_RADIAL") return u * (1 + p[3] * r2);
  if (c.model == "RADIAL") return u * (1 + p[3] * r2 + p[4] * r2 * r2);
  if (c.model == "OPENCV") {
    const double k1 = p[4], k2 = p[5], p1 = p[6], p2 = p[7];
    const double radial = 1 + k1 * r2 + k2 * r2 * r2;
    return {u.x * radial + 2 * p1 * u.x * u.y + p2 * (r2 + 2 * u.x * u.x),
            u.y * radial + 2 * p2 * u.x * u.y + p1 * (r2 + 2 * u.y * u.y)};
  }
  return u;
}

std::string lineRef(const std::string& file, int line) { return file + ":" + std::to_string(line); }

// Lines of a COLMAP text file without comments; each with its 1-based line number.
std::vector<std::pair<int, std::string>> dataLines(std::istream& in, bool keepEmpty) {
  std::vector<std::pair<int, std::string>> out;
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (!line.empty() && line[0] == '#') continue;
    if (line.find_first_not_of(" \t") == std::string::npos && !keepEmpty) continue;
    out.emplace_back(n, line);
  }
  return out;
}

template <class T>
T readBin(std::istream& in, const std::string& path, const std::string& what) {
  T v{};
  in.read(reinterpret_cast<char*>(&v), sizeof(T));
  if (!in) throw Error(path, what, "the file ends early (truncated?)");
  return v;
}

// Bytes left in a stream (so that a count in a corrupt header cannot ask for more records than
// the file could hold).
uint64_t bytesLeft(std::istream& in) {
  const auto here = in.tellg();
  if (here < 0) return std::numeric_limits<uint64_t>::max();
  in.seekg(0, std::ios::end);
  const auto end = in.tellg();
  in.seekg(here);
  return end > here ? uint64_t(end - here) : 0;
}

std::ifstream openFile(const std::string& path, bool binary) {
  std::ifstream in(path, binary ? std::ios::binary : std::ios::in);
  if (!in) throw Error(path, "", "cannot open the file");
  return in;
}

}  // namespace

int ColmapCamera::parameterCount(const std::string& model) {
  const ModelSpec* s = specByName(model);
  return s ? s->params : -1;
}
std::string ColmapCamera::supportedModels() { return relume::recon::supportedModels(); }

double ColmapCamera::fx() const { return params.at(0); }
double ColmapCamera::fy() const {
  return (model == "PINHOLE" || model == "OPENCV") ? params.at(1) : params.at(0);
}
double ColmapCamera::cx() const {
  return (model == "PINHOLE" || model == "OPENCV") ? params.at(2) : params.at(1);
}
double ColmapCamera::cy() const {
  return (model == "PINHOLE" || model == "OPENCV") ? params.at(3) : params.at(2);
}
bool ColmapCamera::hasDistortion() const {
  if (model == "SIMPLE_RADIAL") return params[3] != 0;
  if (model == "RADIAL") return params[3] != 0 || params[4] != 0;
  if (model == "OPENCV") return params[4] != 0 || params[5] != 0 || params[6] != 0 || params[7] != 0;
  return false;
}
glm::dvec2 ColmapCamera::distort(glm::dvec2 n) const {
  const glm::dvec2 d = distortNormalised(*this, n);
  return {fx() * d.x + cx(), fy() * d.y + cy()};
}
glm::dvec2 ColmapCamera::undistort(glm::dvec2 pixel) const {
  const glm::dvec2 d((pixel.x - cx()) / fx(), (pixel.y - cy()) / fy());
  if (!hasDistortion()) return d;
  // Newton's method on distort(u) = d with a numerical 2x2 Jacobian.
  glm::dvec2 u = d;
  for (int it = 0; it < 50; ++it) {
    const glm::dvec2 r = distortNormalised(*this, u) - d;
    if (glm::length(r) < 1e-12) break;
    const double h = 1e-7;
    const glm::dvec2 jx = (distortNormalised(*this, u + glm::dvec2(h, 0)) - distortNormalised(*this, u)) / h;
    const glm::dvec2 jy = (distortNormalised(*this, u + glm::dvec2(0, h)) - distortNormalised(*this, u)) / h;
    const double det = jx.x * jy.y - jy.x * jx.y;
    if (std::abs(det) < 1e-15) break;
    u -= glm::dvec2((jy.y * r.x - jy.x * r.y) / det, (-jx.y * r.x + jx.x * r.y) / det);
  }
  return u;
}
glm::dmat3 ColmapCamera::K() const {
  glm::dmat3 K(1.0);
  K[0][0] = fx();
  K[1][1] = fy();
  K[2][0] = cx();
  K[2][1] = cy();
  return K;
}

glm::dmat3 ColmapImage::R() const {
  const glm::dvec4 n = q / glm::length(q);
  const double w = n.x, x = n.y, y = n.z, z = n.w;
  glm::dmat3 R;  // R[col][row]
  R[0][0] = 1 - 2 * (y * y + z * z);
  R[1][0] = 2 * (x * y - w * z);
  R[2][0] = 2 * (x * z + w * y);
  R[0][1] = 2 * (x * y + w * z);
  R[1][1] = 1 - 2 * (x * x + z * z);
  R[2][1] = 2 * (y * z - w * x);
  R[0][2] = 2 * (x * z - w * y);
  R[1][2] = 2 * (y * z + w * x);
  R[2][2] = 1 - 2 * (x * x + y * y);
  return R;
}
glm::dvec3 ColmapImage::center() const { return -(glm::transpose(R()) * t); }
void ColmapImage::setRotation(const glm::dmat3& R) {
  auto m = [&](int r, int c) { return R[c][r]; };
  const double tr = m(0, 0) + m(1, 1) + m(2, 2);
  glm::dvec4 out;
  if (tr > 0) {
    const double s = std::sqrt(tr + 1.0) * 2;
    out = {0.25 * s, (m(2, 1) - m(1, 2)) / s, (m(0, 2) - m(2, 0)) / s, (m(1, 0) - m(0, 1)) / s};
  } else if (m(0, 0) > m(1, 1) && m(0, 0) > m(2, 2)) {
    const double s = std::sqrt(1.0 + m(0, 0) - m(1, 1) - m(2, 2)) * 2;
    out = {(m(2, 1) - m(1, 2)) / s, 0.25 * s, (m(0, 1) + m(1, 0)) / s, (m(0, 2) + m(2, 0)) / s};
  } else if (m(1, 1) > m(2, 2)) {
    const double s = std::sqrt(1.0 + m(1, 1) - m(0, 0) - m(2, 2)) * 2;
    out = {(m(0, 2) - m(2, 0)) / s, (m(0, 1) + m(1, 0)) / s, 0.25 * s, (m(1, 2) + m(2, 1)) / s};
  } else {
    const double s = std::sqrt(1.0 + m(2, 2) - m(0, 0) - m(1, 1)) * 2;
    out = {(m(1, 0) - m(0, 1)) / s, (m(0, 2) + m(2, 0)) / s, (m(1, 2) + m(2, 1)) / s, 0.25 * s};
  }
  if (out.x < 0) out = -out;
  q = out / glm::length(out);
}

const ColmapImage* ColmapModel::findImage(const std::string& name) const {
  for (const auto& [id, im] : images)
    if (im.name == name) return &im;
  for (const auto& [id, im] : images)
    if (fs::path(im.name).stem().string() == name || fs::path(im.name).filename().string() == name) return &im;
  return nullptr;
}

Camera ColmapModel::camera(const ColmapImage& image) const {
  const auto it = cameras.find(image.camera);
  if (it == cameras.end())
    throw Error("", "image " + image.name, "refers to camera " + std::to_string(image.camera) + ", which the model lacks");
  Camera c;
  c.K = it->second.K();
  c.R = image.R();
  c.t = image.t;
  c.width = it->second.width;
  c.height = it->second.height;
  return c;
}

ColmapModel parseColmapText(std::istream& cameras, std::istream& images, std::istream* points, const std::string& camPath,
                            const std::string& imPath, const std::string& ptPath) {
  ColmapModel m;
  for (const auto& [ln, line] : dataLines(cameras, false)) {
    std::istringstream ss(line);
    ColmapCamera c;
    if (!(ss >> c.id >> c.model >> c.width >> c.height))
      throw Error(lineRef(camPath, ln), "camera", "expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS...");
    const ModelSpec* spec = specByName(c.model);
    if (!spec)
      throw Error(lineRef(camPath, ln), "camera " + std::to_string(c.id),
                  "camera model " + c.model + " is not supported (supported: " + supportedModels() + ")");
    double v;
    while (ss >> v) c.params.push_back(v);
    if (int(c.params.size()) != spec->params || c.width <= 0 || c.height <= 0)
      throw Error(lineRef(camPath, ln), "camera " + std::to_string(c.id),
                  c.model + " needs " + std::to_string(spec->params) + " parameters and a positive size");
    m.cameras[c.id] = c;
  }
  const auto lines = dataLines(images, true);
  for (size_t i = 0; i < lines.size(); ++i) {
    const auto& [ln, line] = lines[i];
    if (line.find_first_not_of(" \t") == std::string::npos) continue;  // a stray empty points line
    std::istringstream ss(line);
    ColmapImage im;
    if (!(ss >> im.id >> im.q.x >> im.q.y >> im.q.z >> im.q.w >> im.t.x >> im.t.y >> im.t.z >> im.camera))
      throw Error(lineRef(imPath, ln), "image", "expected IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME");
    std::getline(ss >> std::ws, im.name);
    if (im.name.empty()) throw Error(lineRef(imPath, ln), "image " + std::to_string(im.id), "has no file name");
    if (glm::length(im.q) < 1e-9) throw Error(lineRef(imPath, ln), "image " + im.name, "has a zero quaternion");
    if (!m.cameras.count(im.camera))
      throw Error(lineRef(imPath, ln), "image " + im.name, "refers to camera " + std::to_string(im.camera) + ", which cameras.txt lacks");
    if (i + 1 < lines.size()) {
      std::istringstream ps(lines[i + 1].second);
      // X Y as numbers, POINT3D_ID as an integer (-1: none).
      double x, y;
      long long id;
      while (ps >> x) {
        if (!(ps >> y >> id))
          throw Error(lineRef(imPath, lines[i + 1].first), "image " + im.name, "expected X Y POINT3D_ID triples");
        im.points.push_back({{x, y}, int64_t(id)});
      }
      if (!ps.eof()) throw Error(lineRef(imPath, lines[i + 1].first), "image " + im.name, "expected X Y POINT3D_ID triples");
      ++i;
    }
    m.images[im.id] = std::move(im);
  }
  if (points) {
    for (const auto& [ln, line] : dataLines(*points, false)) {
      std::istringstream ss(line);
      ColmapPoint p;
      int r, g, b;
      if (!(ss >> p.id >> p.xyz.x >> p.xyz.y >> p.xyz.z >> r >> g >> b >> p.error))
        throw Error(lineRef(ptPath, ln), "point", "expected POINT3D_ID X Y Z R G B ERROR TRACK...");
      if (r < 0 || r > 255 || g < 0 || g > 255 || b < 0 || b > 255)
        throw Error(lineRef(ptPath, ln), "point " + std::to_string(p.id), "colour components must lie in 0..255");
      p.rgb = {uint8_t(r), uint8_t(g), uint8_t(b)};
      std::vector<long long> v;
      long long x;
      while (ss >> x) v.push_back(x);
      if (!ss.eof() || v.size() % 2 != 0)
        throw Error(lineRef(ptPath, ln), "point " + std::to_string(p.id), "expected IMAGE_ID POINT2D_IDX pairs");
      for (size_t k = 0; k < v.size(); k += 2) p.track.push_back({int(v[k]), int(v[k + 1])});
      m.points[p.id] = std::move(p);
    }
  }
  return m;
}

ColmapModel readColmapText(const std::string& folder) {
  const std::string cam = (fs::path(folder) / "cameras.txt").string(), im = (fs::path(folder) / "images.txt").string(),
                    pt = (fs::path(folder) / "points3D.txt").string();
  std::ifstream c = openFile(cam, false), i = openFile(im, false);
  if (!fs::exists(pt)) return parseColmapText(c, i, nullptr, cam, im, pt);
  std::ifstream p = openFile(pt, false);
  return parseColmapText(c, i, &p, cam, im, pt);
}

ColmapModel parseColmapBinary(std::istream& cameras, std::istream& images, std::istream* points, const std::string& camPath,
                              const std::string& imPath, const std::string& ptPath) {
  ColmapModel m;
  {
    std::istream& in = cameras;
    const uint64_t n = readBin<uint64_t>(in, camPath, "header");
    if (n > 100000) throw Error(camPath, "header", "is not a COLMAP cameras.bin (camera count " + std::to_string(n) + ")");
    for (uint64_t i = 0; i < n; ++i) {
      const std::string what = "camera record " + std::to_string(i);
      ColmapCamera c;
      c.id = int(readBin<uint32_t>(in, camPath, what));
      const int modelId = readBin<int32_t>(in, camPath, what);
      c.width = int(readBin<uint64_t>(in, camPath, what));
      c.height = int(readBin<uint64_t>(in, camPath, what));
      const ModelSpec* spec = specById(modelId);
      if (!spec)
        throw Error(camPath, "camera " + std::to_string(c.id),
                    "camera model id " + std::to_string(modelId) + " is not supported (supported: " + supportedModels() + ")");
      c.model = spec->name;
      if (c.width <= 0 || c.height <= 0) throw Error(camPath, "camera " + std::to_string(c.id), "has no positive image size");
      for (int k = 0; k < spec->params; ++k) c.params.push_back(readBin<double>(in, camPath, what));
      m.cameras[c.id] = c;
    }
  }
  {
    std::istream& in = images;
    const uint64_t n = readBin<uint64_t>(in, imPath, "header");
    if (n > 10000000) throw Error(imPath, "header", "is not a COLMAP images.bin");
    for (uint64_t i = 0; i < n; ++i) {
      const std::string what = "image record " + std::to_string(i);
      ColmapImage im;
      im.id = int(readBin<uint32_t>(in, imPath, what));
      im.q.x = readBin<double>(in, imPath, what);
      im.q.y = readBin<double>(in, imPath, what);
      im.q.z = readBin<double>(in, imPath, what);
      im.q.w = readBin<double>(in, imPath, what);
      for (int k = 0; k < 3; ++k) im.t[k] = readBin<double>(in, imPath, what);
      im.camera = int(readBin<uint32_t>(in, imPath, what));
      char ch;
      while ((ch = readBin<char>(in, imPath, what)) != '\0') im.name += ch;
      const uint64_t np = readBin<uint64_t>(in, imPath, what);
      if (np > bytesLeft(in) / 24) throw Error(imPath, what, "has more points than the file holds (corrupt file?)");
      im.points.resize(np);
      for (auto& o : im.points) {
        o.xy.x = readBin<double>(in, imPath, what);
        o.xy.y = readBin<double>(in, imPath, what);
        const uint64_t id = readBin<uint64_t>(in, imPath, what);
        o.point3D = id == std::numeric_limits<uint64_t>::max() ? -1 : int64_t(id);
      }
      if (!m.cameras.count(im.camera))
        throw Error(imPath, "image " + im.name, "refers to camera " + std::to_string(im.camera) + ", which cameras.bin lacks");
      m.images[im.id] = std::move(im);
    }
  }
  if (points) {
    std::istream& in = *points;
    const uint64_t n = readBin<uint64_t>(in, ptPath, "header");
    for (uint64_t i = 0; i < n; ++i) {
      const std::string what = "point record " + std::to_string(i);
      ColmapPoint p;
      p.id = int64_t(readBin<uint64_t>(in, ptPath, what));
      for (int k = 0; k < 3; ++k) p.xyz[k] = readBin<double>(in, ptPath, what);
      for (int k = 0; k < 3; ++k) p.rgb[k] = readBin<uint8_t>(in, ptPath, what);
      p.error = readBin<double>(in, ptPath, what);
      const uint64_t tl = readBin<uint64_t>(in, ptPath, what);
      if (tl > bytesLeft(in) / 8) throw Error(ptPath, what, "has a longer track than the file holds (corrupt file?)");
      p.track.resize(tl);
      for (auto& e : p.track) {
        e.image = int(readBin<uint32_t>(in, ptPath, what));
        e.point2D = int(readBin<uint32_t>(in, ptPath, what));
      }
      m.points[p.id] = std::move(p);
    }
  }
  return m;
}

ColmapModel readColmapBinary(const std::string& folder) {
  const std::string cam = (fs::path(folder) / "cameras.bin").string(), im = (fs::path(folder) / "images.bin").string(),
                    pt = (fs::path(folder) / "points3D.bin").string();
  std::ifstream c = openFile(cam, true), i = openFile(im, true);
  if (!fs::exists(pt)) return parseColmapBinary(c, i, nullptr, cam, im, pt);
  std::ifstream p = openFile(pt, true);
  return parseColmapBinary(c, i, &p, cam, im, pt);
}

ColmapModel readColmapModel(const std::string& folder) {
  if (!fs::is_directory(folder)) throw Error(folder, "", "is not a folder holding a COLMAP model");
  if (fs::exists(fs::path(folder) / "cameras.txt")) return readColmapText(folder);
  if (fs::exists(fs::path(folder) / "cameras.bin")) return readColmapBinary(folder);
  throw Error(folder, "", "holds no COLMAP model (neither cameras.txt nor cameras.bin)");
}

namespace {
void writeAtomically(const fs::path& path, const std::string& text) {
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    out.flush();
    if (!out) throw Error(path.string(), "", "cannot write the file");
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) throw Error(path.string(), "", "cannot replace the file: " + ec.message());
}
}  // namespace

void writeColmapText(const ColmapModel& m, const std::string& folder) {
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) throw Error(folder, "", "cannot create the folder: " + ec.message());
  std::ostringstream cs;
  cs.precision(17);
  cs << "# Camera list with one line of data per camera:\n#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
     << "# Number of cameras: " << m.cameras.size() << "\n";
  for (const auto& [id, c] : m.cameras) {
    cs << id << ' ' << c.model << ' ' << c.width << ' ' << c.height;
    for (double p : c.params) cs << ' ' << p;
    cs << '\n';
  }
  std::ostringstream is;
  is.precision(17);
  is << "# Image list with two lines of data per image:\n"
     << "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
     << "# Number of images: " << m.images.size() << "\n";
  for (const auto& [id, im] : m.images) {
    is << id << ' ' << im.q.x << ' ' << im.q.y << ' ' << im.q.z << ' ' << im.q.w << ' ' << im.t.x << ' ' << im.t.y
       << ' ' << im.t.z << ' ' << im.camera << ' ' << im.name << '\n';
    for (size_t k = 0; k < im.points.size(); ++k)
      is << (k ? " " : "") << im.points[k].xy.x << ' ' << im.points[k].xy.y << ' ' << im.points[k].point3D;
    is << '\n';
  }
  std::ostringstream ps;
  ps.precision(17);
  ps << "# 3D point list with one line of data per point:\n"
     << "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n"
     << "# Number of points: " << m.points.size() << "\n";
  for (const auto& [id, p] : m.points) {
    ps << id << ' ' << p.xyz.x << ' ' << p.xyz.y << ' ' << p.xyz.z << ' ' << int(p.rgb[0]) << ' ' << int(p.rgb[1])
       << ' ' << int(p.rgb[2]) << ' ' << p.error;
    for (const auto& e : p.track) ps << ' ' << e.image << ' ' << e.point2D;
    ps << '\n';
  }
  writeAtomically(fs::path(folder) / "cameras.txt", cs.str());
  writeAtomically(fs::path(folder) / "images.txt", is.str());
  writeAtomically(fs::path(folder) / "points3D.txt", ps.str());
}

void replaceColmapText(const ColmapModel& model, const std::string& folder) {
  const fs::path dir = fs::path(folder).lexically_normal();
  const fs::path target = dir.has_filename() ? dir : dir.parent_path();
  const fs::path fresh = target.string() + ".new", old = target.string() + ".old";
  std::error_code ec;
  // An earlier replacement that stopped between its two renames left the model only in .old.
  if (!fs::exists(target) && fs::exists(old)) fs::rename(old, target, ec);
  fs::remove_all(fresh, ec);
  fs::remove_all(old, ec);
  writeColmapText(model, fresh.string());
  if (fs::exists(target)) {
    fs::rename(target, old, ec);
    if (ec) {
      fs::remove_all(fresh, ec);
      throw Error(target.string(), "", "cannot replace the model: " + ec.message());
    }
  }
  fs::rename(fresh, target, ec);
  if (ec) {
    const std::string why = ec.message();
    std::error_code back;
    if (fs::exists(old)) fs::rename(old, target, back);
    fs::remove_all(fresh, back);
    throw Error(target.string(), "", "cannot replace the model: " + why);
  }
  fs::remove_all(old, ec);
}

void transformModel(ColmapModel& m, const Similarity& S) {
  for (auto& [id, p] : m.points) p.xyz = S.apply(p.xyz);
  const glm::dmat3 Rt = glm::transpose(S.R);
  for (auto& [id, im] : m.images) {
    // x = Ri X + ti with X = R^T (X' - t) / s; scale the camera frame by s: x' = Ri R^T X' + (s ti - Ri R^T t).
    const glm::dmat3 Ri = im.R() * Rt;
    im.t = S.s * im.t - Ri * S.t;
    im.setRotation(Ri);
  }
}

glm::dvec3 meanCameraCentre(const ColmapModel& model) {
  glm::dvec3 c(0.0);
  for (const auto& [id, im] : model.images) c += im.center() / double(model.images.size());
  return c;
}

glm::dvec3 estimateUp(const ColmapModel& model) {
  glm::dmat3 M(0.0);
  glm::dvec3 meanUp(0.0), firstX(0.0);
  double spread = 0;  // the widest angle (as 1 - |cos|) between a camera's x axis and the first's
  for (const auto& [id, im] : model.images) {
    const glm::dmat3 Rt = glm::transpose(im.R());
    const glm::dvec3 x = Rt * glm::dvec3(1, 0, 0);
    meanUp -= Rt * glm::dvec3(0, 1, 0);
    M += glm::outerProduct(x, x);
    if (glm::length(firstX) == 0) firstX = x;
    spread = std::max(spread, 1 - std::abs(glm::dot(x, firstX)));
  }
  if (glm::length(meanUp) < 1e-12) return glm::dvec3(0.0);
  meanUp = glm::normalize(meanUp);
  if (spread < 1 - std::cos(10.0 * 3.14159265358979323846 / 180)) return meanUp;
  // The eigenvector of M's smallest eigenvalue: power iteration on trace(M) I - M.
  const double tr = M[0][0] + M[1][1] + M[2][2];
  const glm::dmat3 A = glm::dmat3(tr) - M;
  glm::dvec3 v = meanUp;
  for (int k = 0; k < 200; ++k) v = glm::normalize(A * v);
  return glm::dot(v, meanUp) < 0 ? -v : v;
}

double meanReprojectionError(const ColmapModel& model) {
  double sum = 0, n = 0;
  for (const auto& [id, p] : model.points) {
    if (p.error < 0) continue;
    sum += p.error * double(p.track.size());
    n += double(p.track.size());
  }
  return n > 0 ? sum / n : 0.0;
}

}  // namespace relume::recon
