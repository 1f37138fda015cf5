// Rendering a mesh's image fan with Embree (kept apart from the fan files, which need no ray tracer).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <glm/geometric.hpp>

#include "fan_pack.h"
#include "relume/geometry/error.h"
#include "relume/ibr/fan.h"
#include "relume/ibr/normal_code.h"
#include "relume/raytrace/ray_scene.h"

namespace relume::ibr {

using detail::kMaxRings;
using detail::kMaxSize;
using detail::kMaxViewsPerRing;
using detail::packView;
using detail::srgbEncode;

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
  fan->source = mesh->name;
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
  // Rays in bands of rows (at most about a million at a time, whatever the size).
  const int bandRows = std::max(1, std::min(S, int(1'000'000 / (size_t(S) * ss * ss))));
  std::vector<Ray> rays(size_t(bandRows) * S * ss * ss);
  std::vector<RayHit> hits(rays.size());
  std::vector<glm::vec2> nxy(n);
  std::vector<uint8_t> mask(n);
  fan->compressed.resize(size_t(fan->viewCount()));
  for (int k = 0; k < fan->viewCount(); ++k) {
    if (k % std::max(1, fan->viewCount() / 50) == 0)
      progress.report(double(k) / fan->viewCount(), "image fan: view " + std::to_string(k + 1) + " of " + std::to_string(fan->viewCount()));
    else
      progress.poll();
    const ImageFan::Axes ax = fan->axes(k);
    const glm::dvec3 d = ax.toCamera, rt = ax.right, upv = ax.up;
    FanView v;
    v.alpha.assign(n, 0);
    v.code.assign(n, kNoNormal);
    v.depth.assign(n, kNoDepth);
    v.colour.assign(3 * n, 0);
    for (int y0 = 0; y0 < S; y0 += bandRows) {
      const int rowsHere = std::min(bandRows, S - y0);
      const size_t count0 = size_t(rowsHere) * S * ss * ss;
      for (int y = y0; y < y0 + rowsHere; ++y)
        for (int x = 0; x < S; ++x)
          for (int sy = 0; sy < ss; ++sy)
            for (int sx = 0; sx < ss; ++sx) {
              const double px = x + (sx + 0.5) / ss, py = y + (sy + 0.5) / ss;
              const glm::dvec3 from = fan->pointAt(ax, px, py, 0.0);
              rays[((size_t(y - y0) * S + x) * ss + sy) * ss + sx] = Ray{glm::vec3(from), glm::vec3(-d), 0.f, float(2.0 * R)};
            }
      scene.intersect(std::span<const Ray>(rays.data(), count0), std::span<RayHit>(hits.data(), count0));
      for (size_t i = size_t(y0) * S; i < size_t(y0 + rowsHere) * S; ++i) {
        int count = 0;
        glm::dvec3 nsum(0.0), csum(0.0);
        double tsum = 0;
        for (int s = 0; s < ss * ss; ++s) {
          const RayHit& h = hits[(i - size_t(y0) * S) * ss * ss + s];
          if (h.polygon < 0) continue;
          ++count;
          const size_t tri = size_t(h.polygon);
          const float u = h.barycentric.x, w = h.barycentric.y, a = 1.f - u - w;
          glm::vec3 ng = h.geometricNormal;
          glm::vec3 nrm = ng;
          if (!mesh->cornerNormals.empty()) {
            nrm = a * mesh->cornerNormals[3 * tri] + u * mesh->cornerNormals[3 * tri + 1] + w * mesh->cornerNormals[3 * tri + 2];
            // The face's side is its normals' (whatever its winding, which a file may get wrong).
            if (glm::dot(ng, nrm) < 0) ng = -ng;
          }
          if (glm::dot(glm::dvec3(ng), d) < 0) nrm = -nrm;  // seen from behind: its other side faces the viewer
          const float l = glm::length(nrm);
          nsum += l > 0 ? glm::dvec3(nrm / l) : d;
          csum += mesh->cornerColours.empty()
                      ? glm::dvec3(mesh->triangleAlbedo[tri])
                      : glm::dvec3(a * mesh->cornerColours[3 * tri] + u * mesh->cornerColours[3 * tri + 1] +
                                   w * mesh->cornerColours[3 * tri + 2]);
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
    }
    encodeNormalImage(nxy, mask, S, S, o.dither, v.code);
    fan->compressed[size_t(k)] = packView(v);
  }
  progress.report(1.0, "image fan: done");
  return fan;
}

}  // namespace relume::ibr
