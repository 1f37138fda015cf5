#include "relume/ibr/fan.h"

#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <numbers>

#include "relume/geometry/error.h"
#include "relume/ibr/normal_code.h"
#include "relume/raytrace/ray_scene.h"

namespace relume::ibr {

namespace {

constexpr char kMagic[8] = {'R', 'E', 'L', 'U', 'M', 'E', 'F', 'N'};
// Header limits: a fan file that claims more is damaged, not a bigger fan.
constexpr uint32_t kMaxSize = 4096, kMaxViewsPerRing = 4096, kMaxRings = 64;

size_t pixelBytes(int size) { return size_t(size) * size_t(size) * 7; }  // alpha, code, depth x 2, RGB

float srgbEncode(float c) {
  c = std::clamp(c, 0.f, 1.f);
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.f / 2.4f) - 0.055f;
}

std::vector<uint8_t> packView(const FanView& v) {
  std::vector<uint8_t> raw;
  raw.reserve(v.alpha.size() * 7);
  raw.insert(raw.end(), v.alpha.begin(), v.alpha.end());
  raw.insert(raw.end(), v.code.begin(), v.code.end());
  // Depth as differences along each row, high bytes then low bytes: smooth surfaces give small
  // differences, which deflate well.
  const size_t n = v.depth.size(), S = size_t(std::lround(std::sqrt(double(n))));
  std::vector<uint16_t> delta(n);
  for (size_t i = 0; i < n; ++i) delta[i] = uint16_t(v.depth[i] - (i % S ? v.depth[i - 1] : 0));
  for (uint16_t d : delta) raw.push_back(uint8_t(d >> 8));
  for (uint16_t d : delta) raw.push_back(uint8_t(d & 0xFF));
  raw.insert(raw.end(), v.colour.begin(), v.colour.end());
  uLongf len = compressBound(uLong(raw.size()));
  std::vector<uint8_t> out(len);
  if (compress2(out.data(), &len, raw.data(), uLong(raw.size()), 6) != Z_OK)
    throw Error("", "image fan", "cannot compress a view");
  out.resize(len);
  return out;
}

// Little-endian writing and bounds-checked reading.
struct Writer {
  std::vector<uint8_t> b;
  void raw(const void* p, size_t n) { b.insert(b.end(), static_cast<const uint8_t*>(p), static_cast<const uint8_t*>(p) + n); }
  void u32(uint32_t v) {
    for (int k = 0; k < 4; ++k) b.push_back(uint8_t(v >> (8 * k)));
  }
  void u64(uint64_t v) {
    for (int k = 0; k < 8; ++k) b.push_back(uint8_t(v >> (8 * k)));
  }
  void f64(double v) {
    uint64_t u;
    std::memcpy(&u, &v, 8);
    u64(u);
  }
};

struct Reader {
  const std::vector<uint8_t>& b;
  size_t pos = 0;
  const std::string& name;
  void need(size_t n, const char* what) const {
    if (n > b.size() - pos) throw Error(name, what, "the file is truncated (it ends inside its " + std::string(what) + ")");
  }
  uint32_t u32(const char* what) {
    need(4, what);
    uint32_t v = 0;
    for (int k = 0; k < 4; ++k) v |= uint32_t(b[pos + k]) << (8 * k);
    pos += 4;
    return v;
  }
  uint64_t u64(const char* what) {
    need(8, what);
    uint64_t v = 0;
    for (int k = 0; k < 8; ++k) v |= uint64_t(b[pos + k]) << (8 * k);
    pos += 8;
    return v;
  }
  double f64(const char* what) {
    const uint64_t u = u64(what);
    double v;
    std::memcpy(&v, &u, 8);
    if (!std::isfinite(v)) throw Error(name, what, "holds a value that is not a finite number");
    return v;
  }
};

}  // namespace

glm::dvec3 ImageFan::toCamera(int k) const {
  const int ring = k / viewsPerRing, j = k % viewsPerRing;
  const double phi = 2.0 * std::numbers::pi * j / viewsPerRing;
  const double theta = ringElevations[ring] * std::numbers::pi / 180.0;
  return glm::dvec3(std::cos(theta) * std::cos(phi), std::cos(theta) * std::sin(phi), std::sin(theta));
}

glm::dvec3 ImageFan::right(int k) const {
  const double phi = 2.0 * std::numbers::pi * (k % viewsPerRing) / viewsPerRing;
  return glm::dvec3(-std::sin(phi), std::cos(phi), 0.0);
}

glm::dvec3 ImageFan::up(int k) const { return glm::cross(toCamera(k), right(k)); }

int ImageFan::nearestView(const glm::dvec3& d) const {
  int best = 0;
  double bestDot = -2;
  for (int k = 0; k < viewCount(); ++k) {
    const double c = glm::dot(toCamera(k), d);
    if (c > bestDot) {
      bestDot = c;
      best = k;
    }
  }
  return best;
}

glm::dvec3 ImageFan::pointAt(int k, double x, double y, double depth) const {
  const double a = (x / size * 2.0 - 1.0) * radius, b = (1.0 - y / size * 2.0) * radius;
  return centre + a * right(k) + b * up(k) + (radius - depth) * toCamera(k);
}

const FanView& ImageFan::view(int k) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (decoded_.size() != compressed.size()) decoded_.resize(compressed.size());
  if (!decoded_[size_t(k)]) {
    const size_t n = size_t(size) * size_t(size);
    std::vector<uint8_t> raw(pixelBytes(size));
    uLongf len = uLongf(raw.size());
    const auto& c = compressed[size_t(k)];
    if (uncompress(raw.data(), &len, c.data(), uLong(c.size())) != Z_OK || len != raw.size())
      throw Error(meshName, "image fan view " + std::to_string(k), "the view's pixels are damaged");
    auto v = std::make_unique<FanView>();
    v->alpha.assign(raw.begin(), raw.begin() + n);
    v->code.assign(raw.begin() + n, raw.begin() + 2 * n);
    v->depth.resize(n);
    for (size_t i = 0; i < n; ++i) {
      const uint16_t d = uint16_t((raw[2 * n + i] << 8) | raw[3 * n + i]);
      v->depth[i] = uint16_t(d + (i % size_t(size) ? v->depth[i - 1] : 0));
    }
    v->colour.assign(raw.begin() + 4 * n, raw.end());
    std::vector<double> sum(kTableCells * kTableCells, 0.0), count(sum.size(), 0.0);
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        const size_t i = size_t(y) * size + x;
        if (!v->alpha[i]) continue;
        const size_t c = size_t(y * kTableCells / size) * kTableCells + size_t(x * kTableCells / size);
        sum[c] += depthMetres(v->depth[i]);
        count[c] += 1;
      }
    v->cellDepth.resize(sum.size());
    for (size_t c = 0; c < sum.size(); ++c) v->cellDepth[c] = float(count[c] > 0 ? sum[c] / count[c] : radius);
    decoded_[size_t(k)] = std::move(v);
  }
  return *decoded_[size_t(k)];
}

std::unique_ptr<ImageFan> buildFan(const Mesh& meshIn, const FanOptions& o, Progress& progress) {
  validateMesh(meshIn);
  if (o.viewsPerRing < 1 || o.viewsPerRing > int(kMaxViewsPerRing))
    throw Error(meshIn.name, "--views", "views per ring must be 1 to " + std::to_string(kMaxViewsPerRing));
  if (o.size < 8 || o.size > int(kMaxSize)) throw Error(meshIn.name, "--size", "the size must be 8 to 4096 pixels");
  if (o.ringElevations.empty() || o.ringElevations.size() > kMaxRings)
    throw Error(meshIn.name, "--rings", "give 1 to 64 ring elevations");
  for (double e : o.ringElevations)
    if (!(e > -90.0 && e < 90.0)) throw Error(meshIn.name, "--rings", "a ring's elevation must lie strictly between -90 and 90 degrees");
  if (o.samplesPerAxis < 1 || o.samplesPerAxis > 8) throw Error(meshIn.name, "samples", "1 to 8 rays per pixel side");
  const Mesh* mesh = &meshIn;
  Mesh turned;
  if (o.yUp) {  // (x, y, z) -> (x, -z, y): +Y becomes +Z, a proper rotation
    turned = meshIn;
    for (auto& p : turned.positions) p = glm::vec3(p.x, -p.z, p.y);
    for (auto& n : turned.cornerNormals) n = glm::vec3(n.x, -n.z, n.y);
    mesh = &turned;
  }
  auto fan = std::make_unique<ImageFan>();
  fan->size = o.size;
  fan->viewsPerRing = o.viewsPerRing;
  fan->ringElevations = o.ringElevations;
  fan->dithered = o.dither;
  fan->meshTriangles = mesh->triangles.size();
  fan->meshName = std::filesystem::path(mesh->name).filename().string();
  glm::dvec3 lo(1e300), hi(-1e300);
  std::vector<char> used(mesh->positions.size(), 0);
  for (const auto& t : mesh->triangles)
    for (int k = 0; k < 3; ++k) used[t[k]] = 1;
  for (size_t i = 0; i < mesh->positions.size(); ++i)
    if (used[i]) {
      lo = glm::min(lo, glm::dvec3(mesh->positions[i]));
      hi = glm::max(hi, glm::dvec3(mesh->positions[i]));
    }
  fan->boundsMin = lo;
  fan->boundsMax = hi;
  fan->centre = 0.5 * (lo + hi);
  double r2 = 0;
  for (size_t i = 0; i < mesh->positions.size(); ++i)
    if (used[i]) r2 = std::max(r2, glm::dot(glm::dvec3(mesh->positions[i]) - fan->centre, glm::dvec3(mesh->positions[i]) - fan->centre));
  fan->radius = std::sqrt(r2) * 1.001 + 1e-6;
  progress.report(0.0, "image fan: building the ray-casting scene of " + std::to_string(mesh->triangles.size()) + " triangles");
  const RayScene scene(std::span<const glm::vec3>(mesh->positions), std::span<const glm::uvec3>(mesh->triangles));
  const int S = o.size, ss = o.samplesPerAxis;
  const size_t n = size_t(S) * S;
  const double R = fan->radius;
  std::vector<Ray> rays(n * ss * ss);
  std::vector<RayHit> hits(rays.size());
  std::vector<glm::vec2> nxy(n);
  std::vector<uint8_t> mask(n);
  fan->compressed.resize(size_t(fan->viewCount()));
  for (int k = 0; k < fan->viewCount(); ++k) {
    if (k % std::max(1, fan->viewCount() / 50) == 0)
      progress.report(double(k) / fan->viewCount(), "image fan: view " + std::to_string(k + 1) + " of " + std::to_string(fan->viewCount()));
    else
      progress.poll();
    const glm::dvec3 d = fan->toCamera(k), rt = fan->right(k), upv = fan->up(k);
    for (int y = 0; y < S; ++y)
      for (int x = 0; x < S; ++x)
        for (int sy = 0; sy < ss; ++sy)
          for (int sx = 0; sx < ss; ++sx) {
            const double px = x + (sx + 0.5) / ss, py = y + (sy + 0.5) / ss;
            const glm::dvec3 from = fan->pointAt(k, px, py, 0.0);
            rays[((size_t(y) * S + x) * ss + sy) * ss + sx] = Ray{glm::vec3(from), glm::vec3(-d), 0.f, float(2.0 * R)};
          }
    scene.intersect(rays, hits);
    FanView v;
    v.alpha.assign(n, 0);
    v.code.assign(n, kNoNormal);
    v.depth.assign(n, kNoDepth);
    v.colour.assign(3 * n, 0);
    for (size_t i = 0; i < n; ++i) {
      int count = 0;
      glm::dvec3 nsum(0.0), csum(0.0);
      double tsum = 0;
      for (int s = 0; s < ss * ss; ++s) {
        const RayHit& h = hits[i * ss * ss + s];
        if (h.polygon < 0) continue;
        ++count;
        const size_t tri = size_t(h.polygon);
        const float u = h.barycentric.x, w = h.barycentric.y, a = 1.f - u - w;
        glm::vec3 ng = h.geometricNormal;
        const bool back = glm::dot(glm::dvec3(ng), d) < 0;
        glm::vec3 nrm = mesh->cornerNormals.empty()
                            ? ng
                            : a * mesh->cornerNormals[3 * tri] + u * mesh->cornerNormals[3 * tri + 1] + w * mesh->cornerNormals[3 * tri + 2];
        if (back) nrm = -nrm;  // a face seen from behind: its other side faces the viewer
        const float l = glm::length(nrm);
        nsum += l > 0 ? glm::dvec3(nrm / l) : d;
        csum += mesh->cornerColours.empty()
                    ? glm::dvec3(mesh->triangleAlbedo[tri])
                    : glm::dvec3(a * mesh->cornerColours[3 * tri] + u * mesh->cornerColours[3 * tri + 1] + w * mesh->cornerColours[3 * tri + 2]);
        tsum += h.t;
      }
      mask[i] = count > 0;
      if (!count) {
        nxy[i] = glm::vec2(0.f);
        continue;
      }
      v.alpha[i] = uint8_t(std::lround(255.0 * count / (ss * ss)));
      const double nl = glm::length(nsum);
      const glm::dvec3 nv = nl > 0 ? nsum / nl : d;
      nxy[i] = glm::vec2(float(glm::dot(nv, rt)), float(glm::dot(nv, upv)));
      const double t = tsum / count;
      v.depth[i] = uint16_t(std::clamp(std::lround(t / (2.0 * R) * 65534.0), 0L, 65534L));
      for (int c = 0; c < 3; ++c) v.colour[3 * i + c] = uint8_t(std::lround(255.f * srgbEncode(float(csum[c] / count))));
    }
    encodeNormalImage(nxy, mask, S, S, o.dither, v.code);
    fan->compressed[size_t(k)] = packView(v);
  }
  progress.report(1.0, "image fan: done");
  return fan;
}

std::vector<uint8_t> fanBytes(const ImageFan& fan) {
  Writer w;
  w.raw(kMagic, 8);
  w.u32(kFanVersion);
  w.u32(uint32_t(fan.size));
  w.u32(uint32_t(fan.viewsPerRing));
  w.u32(uint32_t(fan.ringElevations.size()));
  w.u32(fan.dithered ? 1u : 0u);
  for (double e : fan.ringElevations) w.f64(e);
  for (int k = 0; k < 3; ++k) w.f64(fan.centre[k]);
  w.f64(fan.radius);
  for (int k = 0; k < 3; ++k) w.f64(fan.boundsMin[k]);
  for (int k = 0; k < 3; ++k) w.f64(fan.boundsMax[k]);
  w.u64(fan.meshTriangles);
  w.u32(uint32_t(fan.meshName.size()));
  w.raw(fan.meshName.data(), fan.meshName.size());
  for (const auto& c : fan.compressed) {
    w.u32(uint32_t(c.size()));
    w.raw(c.data(), c.size());
  }
  w.u32(uint32_t(crc32(0L, w.b.data(), uInt(w.b.size()))));
  return w.b;
}

void writeFan(const ImageFan& fan, const std::string& path) {
  const std::vector<uint8_t> bytes = fanBytes(fan);
  const std::string tmp = path + ".part";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw Error(path, "", std::string("cannot be written: ") + std::strerror(errno));
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t k = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (k < 0) {
      if (errno == EINTR) continue;
      const int e = errno;
      ::close(fd);
      std::remove(tmp.c_str());
      throw Error(path, "", std::string("cannot be written: ") + std::strerror(e));
    }
    done += size_t(k);
  }
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    std::remove(tmp.c_str());
    throw Error(path, "", "cannot be written (the disk refused to keep it)");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw Error(path, "", "cannot be written: " + ec.message());
  }
}

std::unique_ptr<ImageFan> parseFan(const std::vector<uint8_t>& b, const std::string& name) {
  if (b.size() < 8 || std::memcmp(b.data(), kMagic, 8) != 0) throw Error(name, "", "not an image fan file (relume ibr-fan writes them)");
  Reader r{b, 8, name};
  const uint32_t version = r.u32("header");
  if (version != kFanVersion)
    throw Error(name, "header", "an image fan of version " + std::to_string(version) + "; this Relume reads version " +
                                    std::to_string(kFanVersion) + " (build the fan again with relume ibr-fan)");
  if (b.size() < 12 + 4) throw Error(name, "header", "the file is truncated");
  const uint32_t crcStored = uint32_t(b[b.size() - 4]) | uint32_t(b[b.size() - 3]) << 8 | uint32_t(b[b.size() - 2]) << 16 |
                             uint32_t(b[b.size() - 1]) << 24;
  auto fan = std::make_unique<ImageFan>();
  const uint32_t size = r.u32("header"), perRing = r.u32("header"), rings = r.u32("header"), flags = r.u32("header");
  if (size < 8 || size > kMaxSize || perRing < 1 || perRing > kMaxViewsPerRing || rings < 1 || rings > kMaxRings || flags > 1)
    throw Error(name, "header", "the header is damaged (sizes out of range)");
  fan->size = int(size);
  fan->viewsPerRing = int(perRing);
  fan->dithered = flags & 1;
  for (uint32_t i = 0; i < rings; ++i) {
    const double e = r.f64("header");
    if (!(e > -90 && e < 90)) throw Error(name, "header", "a ring's elevation is out of range");
    fan->ringElevations.push_back(e);
  }
  for (int k = 0; k < 3; ++k) fan->centre[k] = r.f64("header");
  fan->radius = r.f64("header");
  for (int k = 0; k < 3; ++k) fan->boundsMin[k] = r.f64("header");
  for (int k = 0; k < 3; ++k) fan->boundsMax[k] = r.f64("header");
  if (!(fan->radius > 0)) throw Error(name, "header", "the object's radius is not positive");
  fan->meshTriangles = r.u64("header");
  const uint32_t nameLen = r.u32("header");
  r.need(nameLen, "header");
  fan->meshName.assign(reinterpret_cast<const char*>(b.data() + r.pos), nameLen);
  r.pos += nameLen;
  fan->compressed.resize(size_t(fan->viewCount()));
  for (auto& c : fan->compressed) {
    const uint32_t len = r.u32("views");
    r.need(len, "views");
    c.assign(b.begin() + long(r.pos), b.begin() + long(r.pos + len));
    r.pos += len;
  }
  r.need(4, "checksum");
  if (r.pos + 4 != b.size()) throw Error(name, "", "the file has bytes after its end (damaged)");
  if (uint32_t(crc32(0L, b.data(), uInt(r.pos))) != crcStored) throw Error(name, "", "the file is damaged (its checksum does not match)");
  return fan;
}

std::unique_ptr<ImageFan> readFan(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(path, "", "cannot be read");
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw Error(path, "", "cannot be read");
  return parseFan(bytes, path);
}

}  // namespace relume::ibr
