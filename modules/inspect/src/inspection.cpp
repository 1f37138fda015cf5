// The inspector's data, gathered from the engine and the session (see inspection.h).
#include "relume/inspect/inspection.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "relume/geometry/polygon.h"
#include "relume/radiosity/hierarchy.h"
#include "relume/relight/relighter.h"

namespace relume::inspect {

using radiosity::HierarchicalRadiosity;
using radiosity::VisibilityType;

ElementMesh elementMesh(const HierarchicalRadiosity& h) {
  ElementMesh mesh;
  const auto& nodes = h.nodes();
  const size_t ns = h.surfaces().size();
  std::vector<std::vector<glm::dvec2>> outlines(ns);
  for (size_t s = 0; s < ns; ++s) {
    if (h.isRemoved(int(s))) continue;
    for (const auto& v : h.surfaces()[s].vertices) outlines[s].push_back(h.toUV(int(s), v));
    if (polygonArea2D(outlines[s]) < 0) std::reverse(outlines[s].begin(), outlines[s].end());
  }
  for (size_t n = 0; n < nodes.size(); ++n) {
    const auto& N = nodes[n];
    if (N.isCluster() || !N.isLeaf() || outlines[size_t(N.surface)].empty()) continue;
    const auto piece = clipToRect(outlines[size_t(N.surface)], {N.u0, N.v0}, {N.u1, N.v1});
    if (piece.size() < 3 || polygonArea2D(piece) <= 0) continue;
    std::vector<glm::dvec3> world;
    for (const auto& p : piece) world.push_back(h.toWorld(N.surface, p));
    mesh.node.push_back(int(n));
    mesh.surface.push_back(N.surface);
    mesh.outline.push_back(std::move(world));
  }
  return mesh;
}

namespace {

double grey(const glm::vec3& c) { return (double(c.x) + c.y + c.z) / 3.0; }

// Per node, the types of the links a lamp's elements send it (bit 1 << type).
std::vector<uint8_t> lampLinkTypes(const HierarchicalRadiosity& h, int lampSurface) {
  std::vector<uint8_t> types(h.nodes().size(), 0);
  for (const auto& l : h.links()) {
    if (l.source < 0 || l.receiver < 0) continue;
    const auto& S = h.nodes()[size_t(l.source)];
    if (S.isCluster() || S.surface != lampSurface) continue;
    types[size_t(l.receiver)] |= uint8_t(1u << unsigned(l.type));
  }
  return types;
}

LampVisibilityClass classOf(const HierarchicalRadiosity& h, const std::vector<uint8_t>& types, int node) {
  uint8_t t = 0;
  for (int n = node; n >= 0; n = h.nodes()[size_t(n)].parent) t |= types[size_t(n)];
  if (t == 0) return LampVisibilityClass::None;
  if (t == (1u << unsigned(VisibilityType::Visible))) return LampVisibilityClass::Visible;
  if (t == (1u << unsigned(VisibilityType::Invisible))) return LampVisibilityClass::Invisible;
  return LampVisibilityClass::Partial;
}

}  // namespace

LampVisibilityClass lampVisibility(const HierarchicalRadiosity& h, int node, int lampSurface) {
  return classOf(h, lampLinkTypes(h, lampSurface), node);
}

std::vector<LampVisibilityClass> lampVisibility(const HierarchicalRadiosity& h, const std::vector<int>& nodes, int lampSurface) {
  const auto types = lampLinkTypes(h, lampSurface);
  std::vector<LampVisibilityClass> out(nodes.size());
  for (size_t i = 0; i < nodes.size(); ++i) out[i] = classOf(h, types, nodes[i]);
  return out;
}

std::vector<double> elementValues(const RelightSession& session, const ElementMesh& mesh, Quantity q, int lampSurface) {
  const auto& h = session.engine();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> v(mesh.node.size(), nan);
  if (q == Quantity::LampVisibility) {
    const auto cls = lampVisibility(h, mesh.node, lampSurface);
    for (size_t i = 0; i < v.size(); ++i)
      if (cls[i] != LampVisibilityClass::None) v[i] = double(int(cls[i]));
    return v;
  }
  const size_t real = session.realPolygonCount();
  for (size_t i = 0; i < v.size(); ++i) {
    const int n = mesh.node[i], s = mesh.surface[i];
    const auto& N = h.nodes()[size_t(n)];
    switch (q) {
      case Quantity::Radiosity: v[i] = grey(h.radiosity(n)); break;
      case Quantity::Irradiance: v[i] = grey(h.irradiance(n)); break;
      case Quantity::DisplayFactor: v[i] = grey(session.displayFactor(n)); break;
      case Quantity::Ratio: {
        const double d = grey(session.displayFactor(n));
        const double b = grey(session.shading(n));
        if (d > 0) v[i] = b / d;
        break;
      }
      case Quantity::Reflectance: v[i] = grey(h.reflectanceOf(n)); break;
      case Quantity::FinalTexture:
        if (size_t(s) < real) {
          const auto& t = session.texture(s);
          const auto& layer = t.unoccluded.empty() ? t.original : t.unoccluded;
          if (!layer.empty()) v[i] = grey(t.mean(layer, {N.u0, N.v0}, {N.u1, N.v1}));
        }
        break;
      case Quantity::Level: v[i] = N.level; break;
      case Quantity::LampVisibility: break;
    }
  }
  return v;
}

std::vector<LinkRow> linksOf(const HierarchicalRadiosity& h, int node) {
  std::vector<LinkRow> rows;
  const auto& links = h.links();
  for (size_t k = 0; k < links.size(); ++k) {
    const auto& l = links[k];
    if (l.receiver != node && l.source != node) continue;
    LinkRow r;
    r.link = int(k);
    r.source = l.source;
    r.receiver = l.receiver;
    r.receives = l.receiver == node;
    r.formFactor = l.formFactor;
    r.visibility = l.visibility;
    r.error = l.variation;
    r.type = int(l.type);
    rows.push_back(r);
  }
  return rows;
}

std::vector<PolygonCounts> countsPerPolygon(const HierarchicalRadiosity& h) {
  std::vector<PolygonCounts> c(h.surfaces().size());
  for (size_t s = 0; s < c.size(); ++s) {
    c[s].surface = int(s);
    c[s].name = h.surfaces()[s].name;
  }
  for (const auto& N : h.nodes()) {
    if (N.isCluster()) continue;
    ++c[size_t(N.surface)].elements;
    if (N.isLeaf()) ++c[size_t(N.surface)].leaves;
  }
  for (const auto& l : h.links()) {
    if (l.receiver < 0) continue;
    const auto& R = h.nodes()[size_t(l.receiver)];
    if (!R.isCluster()) ++c[size_t(R.surface)].links;
  }
  std::erase_if(c, [&](const PolygonCounts& p) { return h.isRemoved(p.surface); });
  return c;
}

glm::dvec3 nodeCentre(const HierarchicalRadiosity& h, int node) {
  const auto& N = h.nodes()[size_t(node)];
  if (N.isCluster()) return 0.5 * (glm::dvec3(N.bmin) + glm::dvec3(N.bmax));
  return h.toWorld(N.surface, {0.5 * (double(N.u0) + N.u1), 0.5 * (double(N.v0) + N.v1)});
}

}  // namespace relume::inspect
