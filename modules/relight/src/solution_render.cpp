#include "relume/relight/solution_render.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>

#include "relume/raytrace/ray_scene.h"
#include "view_cast.h"

namespace relume {

using radiosity::HierarchicalRadiosity;
using radiosity::VisibilityType;

CornerStencil::CornerStencil(const HierarchicalRadiosity& h, const std::vector<float>* weights)
    : nodes_(h.nodes().size()) {
  const auto& nodes = h.nodes();
  for (size_t n = 0; n < nodes.size(); ++n)
    if (!nodes[n].isCluster() && nodes[n].isLeaf()) leaves_.push_back(int32_t(n));
  // Up to 4 contributions per corner, found in parallel, then packed.
  const size_t nc = leaves_.size() * 4;
  std::vector<std::array<int32_t, 4>> who(nc);
  std::vector<std::array<float, 4>> wts(nc);
  std::vector<uint8_t> count(nc, 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, leaves_.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i < r.end(); ++i) {
      const int n = leaves_[i];
      const auto& N = nodes[n];
      const double eps = 1e-5 * std::max(1e-3, double(N.u1 - N.u0) + double(N.v1 - N.v0));
      const glm::dvec2 corners[4] = {{N.u0, N.v0}, {N.u1, N.v0}, {N.u1, N.v1}, {N.u0, N.v1}};
      const auto& root = nodes[h.surfaceRoot(N.surface)];
      for (int c = 0; c < 4; ++c) {
        const size_t k = 4 * i + size_t(c);
        float sum = 0;
        for (int q = 0; q < 4; ++q) {
          const glm::dvec2 p = corners[c] + glm::dvec2((q & 1) ? eps : -eps, (q & 2) ? eps : -eps);
          if (p.x < root.u0 || p.x > root.u1 || p.y < root.v0 || p.y > root.v1) continue;
          const int leaf = h.findLeaf(N.surface, p);
          const auto& L = nodes[leaf];
          if (p.x < L.u0 || p.x > L.u1 || p.y < L.v0 || p.y > L.v1) continue;
          const float w = weights ? (*weights)[leaf] : 1.f;
          who[k][count[k]] = leaf;
          wts[k][count[k]] = w;
          ++count[k];
          sum += w;
        }
        if (count[k] == 0 || !(sum > 0)) {
          who[k][0] = n;
          wts[k][0] = 1.f;
          count[k] = 1;
          sum = 1.f;
        }
        for (int q = 0; q < count[k]; ++q) wts[k][q] /= sum;
      }
    }
  });
  begin_.resize(nc + 1);
  begin_[0] = 0;
  for (size_t k = 0; k < nc; ++k) begin_[k + 1] = begin_[k] + count[k];
  node_.resize(begin_[nc]);
  weight_.resize(begin_[nc]);
  for (size_t k = 0; k < nc; ++k)
    for (int q = 0; q < count[k]; ++q) {
      node_[begin_[k] + q] = who[k][q];
      weight_[begin_[k] + q] = wts[k][q];
    }
}

void CornerStencil::applyCompact(const std::vector<glm::vec3>& perNode, std::vector<std::array<glm::vec3, 4>>& out) const {
  out.resize(leaves_.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, leaves_.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i < r.end(); ++i)
      for (int c = 0; c < 4; ++c) {
        const size_t k = 4 * i + size_t(c);
        glm::vec3 v(0.f);
        for (uint32_t j = begin_[k]; j < begin_[k + 1]; ++j) v += weight_[j] * perNode[node_[j]];
        out[i][c] = v;
      }
  });
}

void CornerStencil::apply(const std::vector<glm::vec3>& perNode, std::vector<std::array<glm::vec3, 4>>& out) const {
  std::vector<std::array<glm::vec3, 4>> compact;
  applyCompact(perNode, compact);
  out.resize(std::max(out.size(), nodes_));
  for (size_t i = 0; i < leaves_.size(); ++i) out[leaves_[i]] = compact[i];
}

std::vector<std::array<glm::vec3, 4>> leafCornerValues(const HierarchicalRadiosity& h,
                                                       const std::vector<glm::vec3>& perNode,
                                                       const std::vector<float>* weights) {
  std::vector<std::array<glm::vec3, 4>> out(h.nodes().size());
  CornerStencil(h, weights).apply(perNode, out);
  return out;
}

glm::vec3 interpolateCorners(const HierarchicalRadiosity::Node& L, const std::array<glm::vec3, 4>& k, glm::dvec2 uv) {
  const float s = std::clamp(float((uv.x - L.u0) / std::max(1e-12f, L.u1 - L.u0)), 0.f, 1.f);
  const float t = std::clamp(float((uv.y - L.v0) / std::max(1e-12f, L.v1 - L.v0)), 0.f, 1.f);
  return (1 - s) * (1 - t) * k[0] + s * (1 - t) * k[1] + s * t * k[2] + (1 - s) * t * k[3];
}

namespace {

glm::vec3 hashColour(uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return glm::vec3(0.35f + 0.65f * float(x & 255) / 255.f, 0.35f + 0.65f * float((x >> 8) & 255) / 255.f,
                   0.35f + 0.65f * float((x >> 16) & 255) / 255.f);
}

glm::vec3 heat(float t) {  // blue -> green -> yellow -> red
  t = std::clamp(t, 0.f, 1.f);
  if (t < 1.f / 3) return glm::mix(glm::vec3(0.1f, 0.1f, 0.8f), glm::vec3(0.1f, 0.8f, 0.2f), 3 * t);
  if (t < 2.f / 3) return glm::mix(glm::vec3(0.1f, 0.8f, 0.2f), glm::vec3(0.95f, 0.9f, 0.1f), 3 * t - 1);
  return glm::mix(glm::vec3(0.95f, 0.9f, 0.1f), glm::vec3(0.9f, 0.1f, 0.1f), 3 * t - 2);
}

}  // namespace

ImageRGB renderRadiosity(const HierarchicalRadiosity& h, const std::vector<glm::vec3>& perNode, const Camera& cam,
                         Progress& progress) {
  const auto corners = leafCornerValues(h, perNode);
  const float invPi = float(1.0 / std::numbers::pi);
  return detail::castView(h, cam, progress, [&](int, int leaf, glm::dvec2 uv) {
    return interpolateCorners(h.nodes()[leaf], corners[leaf], uv) * invPi;
  });
}

ImageRGB renderSolution(const HierarchicalRadiosity& h, const Camera& cam, RenderShow show, Progress& progress) {
  const auto& nodes = h.nodes();
  if (show == RenderShow::Radiance) {
    std::vector<glm::vec3> b(nodes.size());
    for (size_t n = 0; n < nodes.size(); ++n) b[n] = h.radiosity(int(n));
    return renderRadiosity(h, b, cam, progress);
  }
  std::vector<float> linkCount;
  std::vector<glm::vec3> visColour;
  if (show == RenderShow::Links || show == RenderShow::Visibility) {
    // Per node: links arriving there; per leaf: summed over its ancestors too.
    std::vector<float> own(nodes.size(), 0.f);
    std::vector<float> visF(nodes.size(), 0.f), allF(nodes.size(), 0.f);
    std::vector<uint8_t> partial(nodes.size(), 0);
    for (const auto& l : h.links()) {
      own[l.receiver] += 1.f;
      if (h.sourceIsEmitter(l.source)) {
        visF[l.receiver] += l.formFactor * l.visibility;
        allF[l.receiver] += l.formFactor;
        if (l.type == VisibilityType::Partial) partial[l.receiver] = 1;
      }
    }
    for (size_t n = 1; n < nodes.size(); ++n) {  // parents come before children
      const int p = nodes[n].parent;
      own[n] += own[p];
      visF[n] += visF[p];
      allF[n] += allF[p];
      partial[n] |= partial[p];
    }
    linkCount = own;
    visColour.resize(nodes.size());
    for (size_t n = 0; n < nodes.size(); ++n) {
      if (allF[n] <= 0) visColour[n] = glm::vec3(0.3f);
      else if (partial[n]) visColour[n] = glm::vec3(0.95f, 0.85f, 0.1f) * (0.4f + 0.6f * visF[n] / allF[n]);
      else if (visF[n] <= 1e-6f * allF[n]) visColour[n] = glm::vec3(0.85f, 0.1f, 0.1f);
      else visColour[n] = glm::vec3(0.1f, 0.8f, 0.2f);
    }
  }
  float maxLinks = 1.f;
  for (float c : linkCount) maxLinks = std::max(maxLinks, c);
  const glm::dvec3 eye = cam.center();
  return detail::castView(h, cam, progress, [&](int, int leaf, glm::dvec2 uv) {
    const auto& L = nodes[leaf];
    // Leaf borders drawn dark, about one pixel wide (the hit point from uv, its distance from the eye).
    const double px = 1.5 * glm::length(h.toWorld(L.surface, uv) - eye) / cam.fx();
    const bool border = uv.x - L.u0 < px || L.u1 - uv.x < px || uv.y - L.v0 < px || L.v1 - uv.y < px;
    glm::vec3 c;
    if (show == RenderShow::Leaves) c = hashColour(uint32_t(leaf));
    else if (show == RenderShow::Links) c = heat(std::log1p(linkCount[leaf]) / std::log1p(maxLinks));
    else c = visColour[leaf];
    return border ? c * 0.25f : c;
  });
}

}  // namespace relume
