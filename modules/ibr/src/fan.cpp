#include "relume/ibr/fan.h"

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/geometric.hpp>
#include <limits>
#include <numbers>

#include "fan_pack.h"
#include "relume/geometry/binary.h"
#include "relume/geometry/error.h"
#include "relume/ibr/normal_code.h"

namespace relume::ibr {

using detail::kMaxRings;
using detail::kMaxSize;
using detail::kMaxViewsPerRing;

namespace {

constexpr char kMagic[8] = {'R', 'E', 'L', 'U', 'M', 'E', 'F', 'N'};

size_t pixelBytes(int size) { return size_t(size) * size_t(size) * 7; }  // alpha, code, depth x 2, RGB

}  // namespace

std::vector<uint8_t> detail::packView(const FanView& v) {
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

std::vector<int> ImageFan::viewsAround(const glm::dvec3& d) const {
  std::vector<int> out;
  const int n = viewsPerRing;
  // Every view when a ring's views cannot be told apart by azimuth alone: few of them, a ring
  // beyond the poles, or a direction (nearly) along the axis or not a direction at all, where
  // views tie and the exhaustive search's first one must be kept.
  const double across = std::hypot(d.x, d.y);
  bool all = n <= 4 || !(across > 1e-9 * std::abs(d.z)) || !std::isfinite(across + d.z);
  for (double e : ringElevations) all = all || !(std::abs(e) <= 90.0);
  if (all) {
    for (int k = 0; k < viewCount(); ++k) out.push_back(k);
    return out;
  }
  // On one ring, d . toCamera = cos(e) |d_xy| cos(phi_j - phi) + sin(e) d_z: largest for the
  // azimuths nearest phi, then the next nearest (the two on either side of phi and one beyond).
  const double phi = std::atan2(d.y, d.x);
  const double step = 2.0 * std::numbers::pi / n;
  const int j0 = int(std::floor(phi / step));
  out.reserve(4 * ringElevations.size());
  for (size_t r = 0; r < ringElevations.size(); ++r) {
    int js[4];
    for (int i = 0; i < 4; ++i) js[i] = ((j0 - 1 + i) % n + n) % n;
    std::sort(js, js + 4);
    for (int i = 0; i < 4; ++i) out.push_back(int(r) * n + js[i]);
  }
  return out;  // ascending: rings in order, each ring's four sorted (n > 4: all distinct)
}

int ImageFan::nearestView(const glm::dvec3& d) const {
  int best = 0;
  double bestDot = -2;
  for (int k : viewsAround(d)) {
    const double c = glm::dot(toCamera(k), d);
    if (c > bestDot) {
      bestDot = c;
      best = k;
    }
  }
  return best;
}

ImageFan::Axes ImageFan::axes(int k) const {
  const glm::dvec3 r = right(k), t = toCamera(k);
  return {r, glm::cross(t, r), t};
}

glm::dvec3 ImageFan::pointAt(int k, double x, double y, double depth) const { return pointAt(axes(k), x, y, depth); }

glm::dvec3 ImageFan::pointAt(const Axes& ax, double x, double y, double depth) const {
  const double a = (x / size * 2.0 - 1.0) * radius, b = (1.0 - y / size * 2.0) * radius;
  return centre + a * ax.right + b * ax.up + (radius - depth) * ax.toCamera;
}

const FanView& ImageFan::view(int k) const {
  if (k < 0 || size_t(k) >= compressed.size())
    throw Error(source, "image fan view " + std::to_string(k), "the fan has no such view (it has " +
                                                                  std::to_string(compressed.size()) + ")");
  std::lock_guard<std::mutex> lock(mutex_);
  if (decoded_.size() != compressed.size()) decoded_.resize(compressed.size());
  if (!decoded_[size_t(k)]) {
    const std::string where = "image fan view " + std::to_string(k);
    const size_t n = size_t(size) * size_t(size);
    const auto& c = compressed[size_t(k)];
    // Deflate packs at most about 1032 bytes into one: a short view claiming a big image is damaged
    // (checked before the image's memory is taken).
    if (pixelBytes(size) > 1100 * c.size() + 64) throw Error(source, where, "the view's pixels are damaged (too few bytes)");
    std::vector<uint8_t> raw(pixelBytes(size));
    uLongf len = uLongf(raw.size());
    if (uncompress(raw.data(), &len, c.data(), uLong(c.size())) != Z_OK || len != raw.size())
      throw Error(source, where, "the view's pixels are damaged");
    auto v = std::make_unique<FanView>();
    v->alpha.assign(raw.begin(), raw.begin() + long(n));
    v->code.assign(raw.begin() + long(n), raw.begin() + 2 * long(n));
    for (size_t i = 0; i < n; ++i)
      if ((v->code[i] >= kNormalCodes && v->code[i] != kNoNormal) || ((v->code[i] == kNoNormal) != (v->alpha[i] == 0)))
        throw Error(source, where, "the view's pixels are damaged (a normal code out of range)");
    v->depth.resize(n);
    for (size_t i = 0; i < n; ++i) {
      const uint16_t d = uint16_t((raw[2 * n + i] << 8) | raw[3 * n + i]);
      v->depth[i] = uint16_t(d + (i % size_t(size) ? v->depth[i - 1] : 0));
    }
    v->colour.assign(raw.begin() + 4 * long(n), raw.end());
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
    const int blocks = (size + kNearBlock - 1) / kNearBlock;
    v->nearBlock.assign(size_t(blocks) * size_t(blocks), std::numeric_limits<float>::infinity());
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        const size_t i = size_t(y) * size + x;
        if (!v->alpha[i]) continue;
        float& b = v->nearBlock[size_t(y / kNearBlock) * size_t(blocks) + size_t(x / kNearBlock)];
        b = std::min(b, float(depthMetres(v->depth[i])));
      }
    decoded_[size_t(k)] = std::move(v);
  }
  return *decoded_[size_t(k)];
}

std::vector<uint8_t> fanBytes(const ImageFan& fan) {
  ByteWriter w;
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
  w.seal();
  return std::move(w.bytes);
}

void writeFan(const ImageFan& fan, const std::string& path) { writeFileAtomically(path, fanBytes(fan)); }

std::unique_ptr<ImageFan> parseFan(const std::vector<uint8_t>& b, const std::string& name) {
  if (b.size() < 8 || std::memcmp(b.data(), kMagic, 8) != 0) throw Error(name, "", "not an image fan file (relume ibr-fan writes them)");
  ByteReader r(b, name, 8);
  const uint32_t version = r.u32("header");
  if (b.size() < 12 + 4) throw Error(name, "header", "the file is truncated");
  const bool intact = r.sealed();
  if (version != kFanVersion) {
    if (!intact) throw Error(name, "", "the file is damaged (its checksum does not match)");
    throw Error(name, "header", "an image fan of version " + std::to_string(version) + "; this Relume reads version " +
                                    std::to_string(kFanVersion) + " (build the fan again with relume ibr-fan)");
  }
  auto fan = std::make_unique<ImageFan>();
  fan->source = name;
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
  // A sphere from a micrometre to a kilometre across, holding the box.
  if (!(fan->radius >= 1e-6 && fan->radius <= 1e3)) throw Error(name, "header", "the object's radius is out of range (damaged)");
  for (int k = 0; k < 3; ++k)
    if (!(fan->boundsMin[k] <= fan->boundsMax[k]) || std::abs(fan->boundsMin[k] - fan->centre[k]) > 1.01 * fan->radius + 1e-9 ||
        std::abs(fan->boundsMax[k] - fan->centre[k]) > 1.01 * fan->radius + 1e-9)
      throw Error(name, "header", "the object's bounding box does not fit its sphere (damaged)");
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
  r.expectEnd();
  if (!intact) throw Error(name, "", "the file is damaged (its checksum does not match)");
  return fan;
}

std::unique_ptr<ImageFan> readFan(const std::string& path) { return parseFan(readFileBytes(path), path); }

}  // namespace relume::ibr
