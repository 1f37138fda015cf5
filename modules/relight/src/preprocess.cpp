// Preprocessing for virtual interactive relighting (Loscos, Drettakis, Robert 2000 §4).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <optional>
#include <glm/geometric.hpp>
#include <numbers>

#include "inverse_gi.h"
#include "relight_common.h"
#include "view_cast.h"
#include "relume/geometry/error.h"
#include "relume/image/image.h"
#include "relume/radiosity/form_factor.h"
#include "relume/raytrace/ray_scene.h"
#include "relume/relight/relighter.h"
#include "relume/relight/solution_render.h"

namespace relume {

using radiosity::HierarchicalRadiosity;
using namespace detail;

namespace {

constexpr double kPi = std::numbers::pi;

glm::dvec3 clampRho(const glm::dvec3& r) { return glm::clamp(r, glm::dvec3(0.005), glm::dvec3(0.95)); }

double grey(const glm::dvec3& c) { return (c.x + c.y + c.z) / 3; }

// Area-weighted means of reflectances, over everything added and per material: what a polygon no
// photo shows takes (polygons that share a material share its reflectance).
struct MaterialMeans {
  std::map<std::string, std::pair<glm::dvec3, double>> byMaterial;
  glm::dvec3 sum{0.0};
  double weight = 0;
  void add(const std::string& material, const glm::dvec3& rho, double w) {
    sum += w * rho;
    weight += w;
    if (!material.empty()) {
      byMaterial[material].first += w * rho;
      byMaterial[material].second += w;
    }
  }
  glm::dvec3 overall(const glm::dvec3& fallback) const { return weight > 0 ? sum / weight : fallback; }
  std::optional<glm::dvec3> of(const std::string& material) const {
    const auto it = byMaterial.find(material);
    if (it == byMaterial.end() || it->second.second <= 0) return std::nullopt;
    return it->second.first / it->second.second;
  }
};

struct Leaf {
  int node;
  int surface;
  double area;
  glm::dvec3 tex;  // mean original texture radiance
  double seen;     // fraction of its texels the main photo shows
};

void checkReferenceChoices(const Scene& scene, const std::map<std::string, glm::dvec2>& overrides,
                           const std::vector<ReferenceRegion>& regions) {
  auto uvPolygon = [&](int s) {
    const PlaneFrame f = PlaneFrame::of(scene.polygons[s].vertices);
    std::vector<glm::dvec2> uv;
    for (const auto& v : scene.polygons[s].vertices) uv.push_back(f.toUV(v));
    return uv;
  };
  for (const auto& [name, uv] : overrides) {
    const int s = scene.findPolygon(name);
    if (s < 0) throw Error(scene.sourceFile, "reference patch '" + name + "'", "the room has no polygon of that name");
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y) || !insideConvex2D(uvPolygon(s), uv, 1e-9))
      throw Error(scene.sourceFile, "reference patch '" + name + "'", "the point lies outside the polygon");
  }
  for (const auto& r : regions) {
    const std::string what = "reference region on '" + r.polygon + "'";
    const int s = scene.findPolygon(r.polygon);
    if (s < 0) throw Error(scene.sourceFile, what, "the room has no polygon of that name");
    if (scene.polygons[size_t(s)].kind != PolygonKind::Real)
      throw Error(scene.sourceFile, what, "only photographed surfaces (not lamps or windows) have real shadows to correct");
    if (r.discs.empty()) throw Error(scene.sourceFile, what, "has no painted area");
    for (const auto& d : r.discs)
      if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z) || d.z <= 0)
        throw Error(scene.sourceFile, what, "a disc needs a finite centre and a positive radius");
    if (!std::isfinite(r.reference.x) || !std::isfinite(r.reference.y) || !insideConvex2D(uvPolygon(s), r.reference, 1e-9))
      throw Error(scene.sourceFile, what, "the reference lies outside the polygon");
  }
}

}  // namespace

double photoExposure(const Scene& scene, const Photo& ph) {
  if (ph.hdr.empty()) return 1.0;
  auto path = [&](const std::string& rel) { return rel.front() == '/' ? rel : scene.baseDir + "/" + rel; };
  const ImageRGB ldr = readImageLinear(path(ph.file)), hdr = readImageLinear(path(ph.hdr));
  if (ldr.width != hdr.width || ldr.height != hdr.height) return 1.0;
  double num = 0, den = 0;
  for (size_t i = 0; i < ldr.pixels.size(); ++i) {
    const double a = ldr.pixels[i], b = hdr.pixels[i];
    if (a < 0.02 || a > 0.9 || b <= 0) continue;
    num += a * b;
    den += b * b;
  }
  return den > 0 ? num / den : 1.0;
}


// The preprocess's state after §4.2's step 1, kept for redoing step 2.
struct Preprocessor::Impl {
  Impl(const Scene& sc, const RelightOptions& opt) : scene(sc), o(opt) {}
  const Scene scene;
  const RelightOptions o;
  RelightData out;
  std::unique_ptr<HierarchicalRadiosity> hr;
  std::vector<Leaf> leaves;
  std::vector<int> leafIndex;                     // per node: its index in `leaves` (-1 none)
  LinkSums sums;                                  // after step 1
  std::vector<float> wSeen;                       // per node: corner values lean on what the photo shows
  std::vector<std::vector<glm::vec3>> inter;      // T_inter per polygon
  std::vector<glm::dvec3> rhoInter, lab;          // per leaf
  std::vector<uint8_t> real, observed, occluded, unoccluded;
  std::vector<std::vector<int>> frontier;         // per polygon: its frontier leaves
  std::vector<int> autoRef;                       // per polygon: its automatic default reference leaf
  static constexpr uint8_t kByRegion = 1, kByFrontier = 2, kByDefault = 3;
  std::vector<uint8_t> how;                       // per leaf: where its reference came from
  std::vector<glm::vec3> factor;                  // per node: Eq. 9's modulation
  glm::dvec3 meanRho{0.0};
  std::vector<glm::dvec3> unseenRho;              // per polygon no photo shows: its material's, else meanRho
  bool stale = false;                             // a redo did not finish: redo every polygon next

  struct Choices {
    std::vector<std::pair<int, int>> defaultRef, regionRef;  // (polygon, leaf)
  };
  glm::dvec3 rhoAt(int surface, const glm::dvec3& radiance, const glm::dvec3& irradiance) const {
    if (o.oracleAlbedos) return clampRho(scene.polygons[size_t(surface)].albedo);
    return observed[surface] ? clampRho(kPi * radiance / glm::max(irradiance, glm::dvec3(1e-12))) : unseenRho[surface];
  }
  void run(Progress& progress);
  Choices resolve(const std::map<std::string, glm::dvec2>& overrides, const std::vector<ReferenceRegion>& regions) const;
  void step2(const std::vector<uint8_t>& redo, const std::map<std::string, glm::dvec2>& overrides,
             const std::vector<ReferenceRegion>& regions);
  void finalPass(Progress& progress);
  std::vector<glm::dvec3> unoccludedReflectances() const;
  void forEachTexel(const std::vector<uint8_t>& polygons, const std::function<void(PolygonTexture&, size_t, int, glm::dvec2)>& fn);
};

bool ReferenceRegion::contains(glm::dvec2 uv) const {
  for (const auto& d : discs)
    if (glm::length(uv - glm::dvec2(d)) <= d.z) return true;
  return false;
}

void Preprocessor::Impl::run(Progress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  out.options = o;
  checkReferenceChoices(scene, o.referenceOverride, o.referenceRegions);
  if (!(o.meanReflectance > 0 && o.meanReflectance < 1))
    throw Error(scene.sourceFile, "mean reflectance", "must lie in (0, 1)");
  if (scene.lamps.empty())
    throw Error(scene.sourceFile, "lamps", "the room has no lamp: relighting needs at least one real lamp polygon");
  int photoIndex = -1;
  for (size_t i = 0; i < scene.photos.size(); ++i)
    if (scene.photos[i].name == scene.mainPhoto) photoIndex = int(i);
  if (photoIndex < 0 && !scene.photos.empty()) photoIndex = 0;
  if (photoIndex < 0) throw Error(scene.sourceFile, "photos", "the room has no photo to take textures from");
  const Photo& photo = scene.photos[photoIndex];
  out.photo = photo.name;
  out.photoExposure = photoExposure(scene, photo);

  const size_t np = scene.polygons.size(), nlamps = scene.lamps.size();
  std::vector<int> lampSurfaces;
  for (const auto& l : scene.lamps) lampSurfaces.push_back(l.polygon);
  real.assign(np, 0);
  for (size_t i = 0; i < np; ++i) real[i] = scene.polygons[i].kind == PolygonKind::Real;

  // Textures (the ray scene of the room itself tells what the camera sees).
  {
    std::vector<std::vector<glm::dvec3>> polys;
    for (const auto& p : scene.polygons) polys.push_back(p.vertices);
    RayScene rays(polys);
    ProgressScope scope(progress, 0.0, 0.15);
    DewarpStats ds;
    out.textures = dewarpPhotos(scene, rays, photoIndex, &ds, scope);
    if (ds.fromMain == 0)
      throw Error(scene.sourceFile, "photo " + photo.name, "its camera sees none of the polygons (check R and t)");
  }
  auto& tex = out.textures;

  // Polygon means and the image average (Eq. 1's B_A), in radiosity units (pi x radiance).
  std::vector<glm::dvec3> polyMean(np, glm::dvec3(0.0));
  glm::dvec3 imageMean(0.0);
  double seenArea = 0, realArea = 0, lampArea = 0;
  for (size_t i = 0; i < np; ++i) {
    const auto& t = tex[i];
    double seen = 0;
    polyMean[i] = kPi * glm::dvec3(t.mean(t.original, t.origin, t.uvOf(t.width, t.height), &seen));
    const double a = polygonArea(scene.polygons[i].vertices);
    if (real[i]) {
      realArea += a;
      imageMean += seen * a * polyMean[i];
      seenArea += seen * a;
    }
  }
  // How each lamp emits (faces, photometric distribution), set up once.
  std::vector<radiosity::EmitterShape> lampShapes;
  for (const auto& l : scene.lamps) {
    lampShapes.emplace_back(scene.polygons[l.polygon].vertices, l.twoSided, l.photometry);
    lampArea += lampShapes.back().faces() * polygonArea(scene.polygons[l.polygon].vertices);
  }
  if (seenArea <= 0 || grey(imageMean) <= 0)
    throw Error(scene.sourceFile, "photo " + photo.name, "shows no lit real surface to estimate reflectances from");
  imageMean /= seenArea;

  // A lamp the (HDR) photos show is measured directly: pi x the median radiance of its texels.
  std::vector<glm::dvec3> measured(nlamps, glm::dvec3(0.0));
  for (size_t l = 0; l < nlamps; ++l) {
    const auto& t = tex[lampSurfaces[l]];
    std::array<std::vector<float>, 3> ch;
    size_t inside = 0;
    for (size_t k = 0; k < t.source.size(); ++k) {
      inside += t.source[k] != TexelSource::Outside;
      if (fromPhoto(t.source[k]))
        for (int c = 0; c < 3; ++c) ch[c].push_back(t.original[k][c]);
    }
    if (photo.hdr.empty() || ch[0].size() < 4 || ch[0].size() < inside / 4) continue;
    for (int c = 0; c < 3; ++c) {
      std::nth_element(ch[c].begin(), ch[c].begin() + ch[c].size() / 2, ch[c].end());
      measured[l][c] = kPi * ch[c][ch[c].size() / 2];
    }
    // A photometric lamp's radiance towards the camera is its exitance / pi times its weight
    // there; seen where it sends (nearly) nothing, it tells nothing.
    if (lampShapes[l].photometry) {
      const double w = lampShapes[l].weight(photo.camera.center());
      measured[l] = w > 0.05 ? measured[l] / w : glm::dvec3(0.0);
    }
  }
  // A lamp the photo shows no brighter than the room's surfaces is off: there is no light of it
  // to estimate or take away (a room lit by daylight is another method's).
  for (size_t l = 0; l < nlamps; ++l)
    if (grey(measured[l]) > 0 && grey(measured[l]) <= 2.0 * grey(imageMean) / (o.meanReflectance))
      throw Error(scene.sourceFile, "lamp " + scene.lamps[l].name,
                  "is off in the photo (its pixels are no brighter than the room's surfaces); relighting starts from "
                  "the lamps that lit the photo");
  // Calibrated photos: a lamp with a photometric file is known from the file (its flux over its
  // area), unless the photo shows it.
  if (o.calibratedPhotos)
    for (size_t l = 0; l < nlamps; ++l)
      if (grey(measured[l]) <= 0 && scene.lamps[l].photometry)
        measured[l] = glm::dvec3(scene.lamps[l].photometry->flux() / polygonArea(scene.polygons[lampSurfaces[l]].vertices));
  double rhoHat = o.meanReflectance;
  // Polygons no photo shows (a wall behind the camera) still reflect light: they get the mean
  // reflectance of the room (its colour from the photo), refined with the computed ones below.
  observed.assign(np, 0);
  for (size_t i = 0; i < np; ++i)
    observed[i] = tex[i].photographed();
  meanRho = clampRho(rhoHat * imageMean / grey(imageMean));
  unseenRho.assign(np, meanRho);
  auto eq1 = [&](double rh) {
    std::vector<glm::dvec3> r(np, glm::dvec3(0.0));
    for (size_t i = 0; i < np; ++i)
      if (real[i]) r[i] = observed[i] ? clampRho(polyMean[i] / glm::max(imageMean, glm::dvec3(1e-12)) * rh) : clampRho(rh * imageMean / grey(imageMean));
    return r;
  };
  auto rhoOf = [this](int surface, const glm::dvec3& radiance, const glm::dvec3& irradiance) {
    return rhoAt(surface, radiance, irradiance);
  };
  // The room's mean reflectance over the elements the photo shows, and per polygon no photo shows
  // the mean over the photographed polygons of its material (polygons that share a material
  // share its reflectance), else the room's.
  auto updateMeanRho = [&](const HierarchicalRadiosity& hr, const std::vector<Leaf>& ls) {
    MaterialMeans means;
    for (const auto& L : ls)
      if (observed[L.surface] && L.seen >= 0.5)
        means.add(scene.polygons[L.surface].material, rhoOf(L.surface, L.tex, glm::dvec3(hr.irradiance(L.node))), L.area);
    meanRho = means.overall(meanRho);
    out.estimates.unseenByMaterial.clear();
    out.estimates.unseenWithoutMaterial.clear();
    for (size_t i = 0; i < np; ++i) {
      if (!real[i] || observed[i]) continue;
      const auto shared = o.sharedMaterials ? means.of(scene.polygons[i].material) : std::nullopt;
      unseenRho[i] = shared.value_or(meanRho);
      (shared ? out.estimates.unseenByMaterial : out.estimates.unseenWithoutMaterial).push_back(scene.polygons[i].name);
    }
  };
  // Eq. 2's lamps light the photographed surfaces more or less than the photo says (the room's
  // brightness where no photo looks, a lamp just below the ceiling that gets much of its upper
  // face's light back): scaled by the solution itself, so that the computed reflectances of the
  // photographed surfaces average the mean reflectance.
  double eq2Scale = 1.0;
  auto eq2 = [&](double rh) {  // energy balance with uniform reflectance, every lamp the same (per face)
    return (1 - rh) / rh * imageMean * realArea / lampArea * eq2Scale;
  };

  std::vector<glm::dvec3> lampScale(nlamps, glm::dvec3(1.0));
  auto exitances = [&](double rh) {
    std::vector<glm::dvec3> e(nlamps);
    for (size_t l = 0; l < nlamps; ++l) e[l] = eq2(rh) * lampScale[l];
    return e;
  };
  out.estimates.meanReflectanceGiven = rhoHat;

  radiosity::Options eo = o.engine;
  hr = std::make_unique<HierarchicalRadiosity>(engineSurfaces(scene, eq1(rhoHat), exitances(rhoHat)), eo);
  auto& h = *hr;
  {
    ProgressScope scope(progress, 0.15, 0.4);
    h.solve(scope);
    h.pushLampLinksToLeaves(scope);
  }
  auto leafData = [&]() {
    const auto ids = leavesOf(h, real);
    std::vector<Leaf> ls(ids.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, ids.size(), 64), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t k = r.begin(); k < r.end(); ++k) {
        const auto& N = h.nodes()[ids[k]];
        const auto& t = tex[N.surface];
        double seen = 0;
        const glm::vec3 m = t.mean(t.original, {N.u0, N.v0}, {N.u1, N.v1}, &seen);
        ls[k] = Leaf{ids[k], N.surface, double(N.area), glm::dvec3(m), seen};
      }
    });
    return ls;
  };
  leaves = leafData();
  // The glow around lamps: the photo minus its reprojected textures, in the rings the textures
  // left out.
  {
    const std::string rel = photo.hdr.empty() ? photo.file : photo.hdr;
    const ImageRGB img = readImageLinear(rel.front() == '/' ? rel : scene.baseDir + "/" + rel);
    const ImageRGB clean = castView(h, photo.camera, progress, [&](int s, int, glm::dvec2 uv) {
      return tex[s].sample(tex[s].original, uv);
    });
    out.glowLamp = lampGlowRing(scene, h.rayScene(), photo.camera);
    out.glow = ImageRGB(img.width, img.height);
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x)
        if (out.glowLamp[size_t(y) * img.width + x] >= 0)
          out.glow.set(x, y, glm::max(img.at(x, y) - clean.at(x, y), glm::vec3(0.f)));
  }

  // §4: the user's mean reflectance, then the mean of the computed reflectances (rho = B / E over
  // unshadowed elements the photo shows) until it settles; per-lamp emittances by least squares.
  auto unshadowedSeen = [&](const LinkSums& sums, const Leaf& L) {
    return L.seen >= 0.8 && grey(glm::dvec3(sums.directBlocked[L.node])) <= 1e-3 * grey(glm::dvec3(sums.direct[L.node]));
  };
  std::string lsReason = o.lampLeastSquares ? "" : "switched off";
  bool lsUsed = false;
  // Direct form factor (unoccluded, unit exitance) from each lamp averaged over each leaf, and its
  // spread over the leaf (max - min): adaptive, so that the ceiling patch above a lamp hanging just
  // below it is integrated, not missed.
  std::vector<std::vector<double>> F(leaves.size(), std::vector<double>(nlamps, 0.0)), Fspread = F;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, leaves.size(), 32), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t k = r.begin(); k < r.end(); ++k) {
      const auto& N = h.nodes()[leaves[k].node];
      const auto& verts = scene.polygons[N.surface].vertices;
      const glm::dvec3 n = glm::normalize(polygonNormal(verts));
      std::vector<glm::dvec2> uvPoly;
      for (const auto& v : verts) uvPoly.push_back(h.toUV(N.surface, v));
      const glm::dvec3 o = h.toWorld(N.surface, {0, 0});
      const glm::dvec3 du = h.toWorld(N.surface, {1, 0}) - o, dv = h.toWorld(N.surface, {0, 1}) - o;
      for (size_t l = 0; l < nlamps; ++l) {
        const auto f = radiosity::emitterFormFactorOverElement(o, du, dv, n, uvPoly, {N.u0, N.v0}, {N.u1, N.v1},
                                                               scene.polygons[lampSurfaces[l]].vertices, lampShapes[l]);
        F[k][l] = f.mean;
        Fspread[k][l] = f.maximum - f.minimum;
      }
    }
  });
  // Per-lamp least squares over unshadowed elements the photo shows: observed B = rho_surface x
  // (sum_l m_l D_l + I), alternating between the surfaces' reflectances and the multipliers m of
  // the lamps not `fixed` (their exitance e is known). With no lamp fixed the total power is kept
  // (the scale of rho against m is otherwise free). False (with the reason) when ill-posed.
  auto fitLamps = [&](const std::vector<glm::dvec3>& e, const std::vector<uint8_t>& fixed, std::vector<glm::dvec3>& mult,
                      std::string& reason) {
    const LinkSums sums = linkSums(h, true);
    mult.assign(nlamps, glm::dvec3(1.0));
    std::vector<size_t> rows;
    for (size_t k = 0; k < leaves.size(); ++k)
      if (unshadowedSeen(sums, leaves[k])) rows.push_back(k);
    std::vector<size_t> freeL;
    for (size_t l = 0; l < nlamps; ++l)
      if (!fixed[l]) freeL.push_back(l);
    const bool anyFixed = freeL.size() < nlamps;
    if (freeL.empty()) return true;
    // One multiplier per lamp on the luminance (mean of R, G, B): a lamp's colour cannot be told
    // apart from the colours of what it lights, so it keeps the colour it was given.
    {
      std::vector<double> m(nlamps, 1.0), y(rows.size()), I(rows.size());
      std::vector<std::vector<double>> D(rows.size(), std::vector<double>(nlamps));
      for (size_t r = 0; r < rows.size(); ++r) {
        const Leaf& L = leaves[rows[r]];
        y[r] = kPi * grey(L.tex);
        double dsum = 0;
        for (size_t l = 0; l < nlamps; ++l) dsum += D[r][l] = F[rows[r]][l] * grey(e[l]);
        I[r] = std::max(0.0, grey(glm::dvec3(h.irradiance(L.node))) - dsum);
      }
      double power0 = 0;
      for (size_t l : freeL) power0 += grey(e[l]) * polygonArea(scene.polygons[lampSurfaces[l]].vertices);
      for (int it = 0; it < 30; ++it) {
        std::vector<double> sNum(np, 0), sDen(np, 0), rs(np, 0);
        for (size_t r = 0; r < rows.size(); ++r) {
          double H = I[r];
          for (size_t l = 0; l < nlamps; ++l) H += m[l] * D[r][l];
          const Leaf& L = leaves[rows[r]];
          sNum[L.surface] += L.area * y[r] * H;
          sDen[L.surface] += L.area * H * H;
        }
        for (size_t s = 0; s < np; ++s) rs[s] = sDen[s] > 0 ? sNum[s] / sDen[s] : 0;
        // Robust weights: a polygon whose texture the constant-reflectance model fits badly (a
        // checkerboard, a pattern) counts less, by its relative residual variance.
        std::vector<double> res(np, 0), yy(np, 0), aa(np, 0), ws(np, 1.0);
        for (size_t r = 0; r < rows.size(); ++r) {
          const Leaf& L = leaves[rows[r]];
          double H = I[r];
          for (size_t l = 0; l < nlamps; ++l) H += m[l] * D[r][l];
          const double d = y[r] - rs[L.surface] * H;
          res[L.surface] += L.area * d * d;
          yy[L.surface] += L.area * y[r];
          aa[L.surface] += L.area;
        }
        for (size_t s = 0; s < np; ++s)
          if (aa[s] > 0 && yy[s] > 0) {
            const double meanY = yy[s] / aa[s];
            ws[s] = 1.0 / (res[s] / aa[s] / (meanY * meanY) + 1e-4);
          }
        const size_t nf = freeL.size();
        std::vector<std::vector<double>> A(nf, std::vector<double>(nf, 0));
        std::vector<double> b(nf, 0);
        for (size_t r = 0; r < rows.size(); ++r) {
          const Leaf& L = leaves[rows[r]];
          const double p = rs[L.surface], w = L.area * ws[L.surface];
          if (p <= 0) continue;
          double known = I[r];
          for (size_t l = 0; l < nlamps; ++l)
            if (fixed[l]) known += D[r][l];
          for (size_t i = 0; i < nf; ++i) {
            b[i] += w * p * D[r][freeL[i]] * (y[r] - p * known);
            for (size_t k = 0; k < nf; ++k) A[i][k] += w * p * p * D[r][freeL[i]] * D[r][freeL[k]];
          }
        }
        std::vector<double> x;
        if (!solveDense(A, b, x)) {
          reason = "singular: some lamp lights too few unshadowed elements the photo shows";
          return false;
        }
        double power = 0;
        for (size_t i = 0; i < nf; ++i) power += x[i] * grey(e[freeL[i]]) * polygonArea(scene.polygons[lampSurfaces[freeL[i]]].vertices);
        for (size_t i = 0; i < nf; ++i) {
          if (!(x[i] > 0) || power <= 0) {
            reason = "lamp " + scene.lamps[freeL[i]].name + " came out non-positive";
            return false;
          }
          m[freeL[i]] = anyFixed ? x[i] : x[i] * power0 / power;
        }
      }
      for (size_t l = 0; l < nlamps; ++l) mult[l] = glm::dvec3(m[l]);
    }
    return true;
  };
  int round = 0;
  for (; round < 2; ++round) {
    progress.report(0.4 + 0.02 * round, "estimating reflectances and lamps, round " + std::to_string(round + 1));
    const auto rho = eq1(rhoHat);
    auto e = exitances(rhoHat);
    for (size_t i = 0; i < np; ++i)
      if (real[i]) h.setReflectance(int(i), rho[i]);
    for (size_t l = 0; l < nlamps; ++l) h.setExitance(lampSurfaces[l], e[l]);
    h.iterate(progress);
    // The mean of the computed reflectances (rho = B / E over unshadowed elements the photo shows).
    auto computedMean = [&]() {
      const LinkSums sums = linkSums(h, true);
      double num = 0, den = 0;
      for (const auto& L : leaves) {
        if (!unshadowedSeen(sums, L)) continue;
        const glm::dvec3 E(h.irradiance(L.node));
        if (grey(E) <= 0) continue;
        num += L.area * grey(clampRho(kPi * L.tex / glm::max(E, glm::dvec3(1e-12))));
        den += L.area;
      }
      return den > 0 ? std::clamp(num / den, 0.02, 0.95) : rhoHat;
    };
    const double computed = computedMean();
    if (round == 0) out.estimates.meanReflectanceRefined = computed;
    // With the reflectances held, the irradiance is linear in the lamps: one scale makes the
    // computed reflectances average rho-hat.
    if (std::abs(computed - rhoHat) > 1e-3 * rhoHat) {
      eq2Scale *= computed / rhoHat;
      e = exitances(rhoHat);
      for (size_t l = 0; l < nlamps; ++l) h.setExitance(lampSurfaces[l], e[l]);
      h.iterate(progress);
    }
    if (o.lampLeastSquares && nlamps > 1) {
      std::vector<glm::dvec3> m;
      lsUsed = fitLamps(e, std::vector<uint8_t>(nlamps, 0), m, lsReason);
      for (size_t l = 0; l < nlamps; ++l) lampScale[l] = lsUsed ? lampScale[l] * m[l] : glm::dvec3(1.0);
    }
    out.estimates.eq2Scale = eq2Scale;
  }
  out.estimates.reflectanceRounds = round;
  out.estimates.lampModel = lsUsed ? "least-squares" : "equal";
  out.estimates.lampModelReason = lsUsed ? "" : (nlamps < 2 ? "one lamp" : lsReason);
  out.lampExitance = exitances(rhoHat);
  // Per-element reflectance: the texture over the computed irradiance, a few rounds (the
  // interreflections depend on the reflectances). An element lit mostly by other elements has E
  // nearly proportional to their reflectances, and the plain update pi L / E swings about the
  // answer from round to round; so a step (in log space) that reverses the element's previous
  // step goes only half way (to the geometric mean), while an element lit directly still gets its
  // answer in one step. On the synthetic room of inverse_gi_test every photographed polygon came
  // out 6-9 % high after four plain rounds, within 3.3 % with the swings halved. (The benchmark's
  // room1 as re-rendered on 2026-12-07: its ceiling 0.794 against the truth's 0.793.)
  auto radiometricReflectances = [&](const std::vector<glm::dvec3>& exitance, int rounds) {
    for (size_t l = 0; l < nlamps; ++l) h.setExitance(lampSurfaces[l], exitance[l]);
    std::vector<glm::dvec3> lastStep(leaves.size(), glm::dvec3(0.0));
    for (int r = 0; r < rounds; ++r) {
      h.iterate(progress);
      for (size_t k = 0; k < leaves.size(); ++k) {
        const Leaf& L = leaves[k];
        const glm::dvec3 est = rhoOf(L.surface, L.tex, glm::dvec3(h.irradiance(L.node)));
        const glm::dvec3 cur = glm::max(glm::dvec3(h.reflectanceOf(L.node)), glm::dvec3(1e-4));
        glm::dvec3 step = glm::log(glm::max(est, glm::dvec3(1e-6)) / cur);
        for (int c = 0; c < 3; ++c)
          if (step[c] * lastStep[k][c] < 0) step[c] *= 0.5;  // it swung back: half way
        lastStep[k] = step;
        h.setElementReflectance(L.node, cur * glm::exp(step));
      }
      updateMeanRho(h, leaves);
    }
    h.iterate(progress);
  };
  // Photographed lamps are known; the others are scaled like them (least squares, or Eq. 2 when
  // that is ill-posed), then fitted against them with the photographed ones held fixed.
  std::vector<uint8_t> isMeasured(nlamps, 0);
  size_t nMeasured = 0;
  for (size_t l = 0; l < nlamps; ++l) nMeasured += isMeasured[l] = grey(measured[l]) > 0;
  if (nMeasured > 0 && o.lampsFromPhoto) {
    glm::dvec3 num(0.0), den(0.0);
    for (size_t l = 0; l < nlamps; ++l)
      if (isMeasured[l]) {
        num += measured[l];
        den += out.lampExitance[l];
      }
    const glm::dvec3 k = num / glm::max(den, glm::dvec3(1e-30));
    for (size_t l = 0; l < nlamps; ++l) out.lampExitance[l] = isMeasured[l] ? measured[l] : out.lampExitance[l] * k;
    out.estimates.lampModel = "photographed";
    out.estimates.lampModelReason = "lamps seen in the HDR photo are measured";
    if (nMeasured < nlamps) {
      radiometricReflectances(out.lampExitance, 3);
      std::vector<glm::dvec3> m;
      std::string why;
      if (o.lampLeastSquares && fitLamps(out.lampExitance, isMeasured, m, why)) {
        for (size_t l = 0; l < nlamps; ++l) out.lampExitance[l] *= m[l];
        out.estimates.lampModel = "photographed+least-squares";
        out.estimates.lampModelReason = "lamps the photo does not show fitted against those it shows";
      } else {
        out.estimates.lampModel = "photographed+scaled";
        out.estimates.lampModelReason = "lamps the photo does not show scaled like those it shows" + (why.empty() ? "" : " (" + why + ")");
      }
    }
  }
  // Inverse global illumination (Yu et al. 1999): the lamps and reflectances again, jointly, from
  // every element the photo shows, its indirect light gathered from what the photos show.
  std::vector<glm::dvec3> jointExitance(nlamps, glm::dvec3(0.0));
  std::vector<double> jointError(nlamps, 0.0);
  if (o.inverseGlobalIllumination) {
    progress.report(0.5, "inverse global illumination: reflectances and lamps");
    const auto& nodes = h.nodes();
    const size_t nn = nodes.size();
    // Per leaf and lamp the visible direct form factor (unit exitance): the averaged factor times
    // the lamp's visibility; and its spread.
    const LampVisibility vis(h, lampSurfaces);
    std::vector<std::vector<double>> G(leaves.size(), std::vector<double>(nlamps, 0.0)), spread = G;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, leaves.size(), 32), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t k = r.begin(); k < r.end(); ++k) {
        const auto& N = nodes[leaves[k].node];
        const auto v = vis.at(N.surface, rectOf(N));
        for (size_t l = 0; l < nlamps; ++l) {
          G[k][l] = F[k][l] * v[l];
          spread[k][l] = Fspread[k][l] * v[l];
        }
      }
    });
    std::vector<std::optional<glm::dvec3>> fixed(nlamps);
    if (o.lampsFromPhoto)
      for (size_t l = 0; l < nlamps; ++l)
        if (isMeasured[l]) fixed[l] = measured[l];
    std::vector<glm::dvec3> e = out.lampExitance;
    JointFitResult fit;
    std::vector<JointFitRow> rows;
    double measuredShare = 0;
    // The light arriving at each candidate element from the room's surfaces, gathered as Yu et
    // al. do: rays from stratified points of the element, cosine-distributed about its normal; a
    // ray ending on a photographed texel brings its photographed radiosity (measured, fixed), one
    // ending where no photo looked brings the simulation's, per lamp (linear in the lamps), and one
    // ending on a lamp nothing (its light is G's).
    constexpr int kGatherRays = 128;
    std::vector<size_t> cand;
    for (size_t k = 0; k < leaves.size(); ++k)
      if (observed[leaves[k].surface] && leaves[k].seen >= 0.8) cand.push_back(k);
    std::vector<glm::dvec3> Iph(cand.size(), glm::dvec3(0.0));
    std::vector<std::vector<std::pair<int, int>>> simHits(cand.size());  // (leaf node, rays)
    {
      std::vector<Ray> rays(cand.size() * kGatherRays);
      tbb::parallel_for(tbb::blocked_range<size_t>(0, cand.size(), 16), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t c = r.begin(); c < r.end(); ++c) {
          const auto& N = nodes[leaves[cand[c]].node];
          const auto& verts = scene.polygons[N.surface].vertices;
          const glm::dvec3 n = glm::normalize(polygonNormal(verts));
          const glm::dvec3 t = glm::normalize(std::abs(n.x) < 0.9 ? glm::cross(n, glm::dvec3(1, 0, 0)) : glm::cross(n, glm::dvec3(0, 1, 0)));
          const glm::dvec3 b = glm::cross(n, t);
          std::vector<glm::dvec2> uvPoly;
          for (const auto& v : verts) uvPoly.push_back(h.toUV(N.surface, v));
          uint64_t state = 0x9E3779B97F4A7C15ull * (cand[c] + 1);
          auto uniform = [&state] {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            return double(state >> 11) * (1.0 / 9007199254740992.0);
          };
          constexpr int g = 11;  // 11 x 11 = 121 strata for the directions, points jittered
          for (int k = 0; k < kGatherRays; ++k) {
            glm::dvec2 uv(N.u0 + uniform() * (N.u1 - N.u0), N.v0 + uniform() * (N.v1 - N.v0));
            for (int tries = 0; tries < 8 && !insideConvex2D(uvPoly, uv, 1e-9); ++tries)
              uv = {N.u0 + uniform() * (N.u1 - N.u0), N.v0 + uniform() * (N.v1 - N.v0)};
            if (!insideConvex2D(uvPoly, uv, 1e-9)) uv = h.toUV(N.surface, glm::dvec3(N.center));
            const int st = k % (g * g);
            const double u1 = (st % g + uniform()) / g, u2 = (st / g + uniform()) / g;
            const double rr = std::sqrt(u1), phi = 2 * kPi * u2;
            const glm::dvec3 d = rr * std::cos(phi) * t + rr * std::sin(phi) * b + std::sqrt(std::max(0.0, 1 - u1)) * n;
            Ray& ray = rays[c * kGatherRays + size_t(k)];
            ray.origin = glm::vec3(h.toWorld(N.surface, uv) + 1e-4 * n);
            ray.direction = glm::vec3(d);
            ray.tnear = 0.f;
          }
        }
      });
      std::vector<RayHit> hits(rays.size());
      h.rayScene().intersect(rays, hits);
      tbb::parallel_for(tbb::blocked_range<size_t>(0, cand.size(), 16), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t c = r.begin(); c < r.end(); ++c) {
          std::map<int, int> sim;
          for (int k = 0; k < kGatherRays; ++k) {
            const RayHit& hit = hits[c * kGatherRays + size_t(k)];
            const int p = hit.polygon;
            if (p < 0 || size_t(p) >= np || h.isEmitter(p) || !real[size_t(p)]) continue;  // out of the model, or a lamp
            const glm::dvec2 uv = h.toUV(p, glm::dvec3(hit.point));
            const auto& tp = tex[size_t(p)];
            if (fromPhoto(tp.sourceAt(uv)))
              Iph[c] += kPi * glm::dvec3(tp.sample(tp.original, uv)) / double(kGatherRays);
            else if (const int leaf = h.findLeaf(p, uv); leaf >= 0)
              ++sim[leaf];
          }
          simHits[c].assign(sim.begin(), sim.end());
        }
      });
    }
    for (int round = 0; round < 3; ++round) {
      progress.report(0.5 + 0.01 * round, "inverse global illumination, round " + std::to_string(round + 1));
      // The simulation (the light where no photo measured it) needs reflectances that belong to
      // the lamps it is run with: the last fit's (polygons no photo shows take their material's,
      // else the fitted mean), or in the first round those computed with the lamps estimated so far.
      if (!fit.ok) {
        radiometricReflectances(e, 2);
      } else {
        MaterialMeans means;
        for (size_t i = 0; i < np; ++i)
          if (real[i] && grey(fit.reflectance[i]) > 0)
            means.add(scene.polygons[i].material, clampRho(fit.reflectance[i]), polygonArea(scene.polygons[i].vertices));
        for (size_t i = 0; i < np; ++i) {
          if (!real[i]) continue;
          glm::dvec3 r = clampRho(fit.reflectance[i]);
          if (grey(fit.reflectance[i]) <= 0) {
            const auto shared = o.sharedMaterials ? means.of(scene.polygons[i].material) : std::nullopt;
            r = shared.value_or(means.overall(meanRho));
          }
          h.setElementReflectance(h.surfaceRoot(int(i)), r);
        }
      }
      // The simulation's radiosity per lamp at unit exitance, with the reflectances as they are.
      std::vector<std::vector<glm::dvec3>> unitB(nlamps);
      for (size_t l = 0; l < nlamps; ++l) {
        for (size_t k = 0; k < nlamps; ++k) h.setExitance(lampSurfaces[k], glm::dvec3(k == l ? 1.0 : 0.0));
        h.iterate(progress);
        unitB[l].resize(nn);
        for (size_t i = 0; i < nn; ++i) unitB[l][i] = glm::dvec3(h.radiosity(int(i)));
      }
      for (size_t l = 0; l < nlamps; ++l) h.setExitance(lampSurfaces[l], e[l]);
      rows.clear();
      double shareSum = 0, shareArea = 0;
      for (size_t c = 0; c < cand.size(); ++c) {
        const size_t k = cand[c];
        const Leaf& L = leaves[k];
        std::vector<glm::dvec3> S(nlamps, glm::dvec3(0.0));
        for (const auto& [leaf, count] : simHits[c])
          for (size_t l = 0; l < nlamps; ++l) S[l] += double(count) / kGatherRays * unitB[l][size_t(leaf)];
        double direct = 0, var = 0, simulated = 0;
        for (size_t l = 0; l < nlamps; ++l) {
          direct += G[k][l] * grey(e[l]);
          var += spread[k][l] * grey(e[l]);
          simulated += grey(S[l] * e[l]);
        }
        const double indirect = grey(Iph[c]) + simulated;
        // An element whose direct light varies strongly across it (beside a lamp) is no sample
        // of one irradiance: left out.
        if (var > 0.5 * (direct + indirect)) continue;
        JointFitRow row{L.surface, L.area, kPi * L.tex, G[k], Iph[c], std::move(S)};
        rows.push_back(std::move(row));
        if (indirect > 0) {
          shareSum += L.area * grey(Iph[c]) / indirect;
          shareArea += L.area;
        }
      }
      measuredShare = shareArea > 0 ? shareSum / shareArea : 0;
      fit = jointFit(rows, np, e, fixed);
      if (!fit.ok) break;
      e = fit.exitance;
    }
    if (fit.ok) {
      out.lampExitance = e;
      jointExitance = e;
      jointError = fit.uncertainty;
      rhoHat = std::clamp(fit.meanReflectance, 0.02, 0.95);
      out.estimates.meanReflectanceRecovered = fit.meanReflectance;
      out.estimates.jointFitElements = rows.size();
      out.estimates.indirectMeasuredShare = measuredShare;
      out.estimates.lampModel = nMeasured > 0 && o.lampsFromPhoto ? "photographed+inverse-global-illumination" : "inverse-global-illumination";
      out.estimates.lampModelReason = nMeasured > 0 && o.lampsFromPhoto
                                          ? "lamps the HDR photo shows measured, the others fitted with the room's reflectances"
                                          : "lamps and reflectances fitted jointly; measured indirect light sets the scale";
    } else {
      out.estimates.lampModelReason += " (inverse global illumination not used: " + fit.reason + ")";
    }
  }
  if (o.oracleLamps) {
    for (size_t l = 0; l < nlamps; ++l) out.lampExitance[l] = kPi * scene.lamps[l].radiance;
    out.estimates.lampModel = "oracle";
    out.estimates.lampModelReason = "the scene's true lamps (evaluation only)";
  }
  for (size_t l = 0; l < nlamps; ++l) {
    LampEstimate le;
    le.name = scene.lamps[l].name;
    le.jointFit = jointExitance[l];
    le.uncertainty = jointError[l];
    le.twoSided = scene.lamps[l].twoSided && !scene.lamps[l].photometry;  // a distribution's exitance is all its flux
    le.equal = eq2(rhoHat);
    le.leastSquares = lsUsed ? eq2(rhoHat) * lampScale[l] : glm::dvec3(0.0);
    le.photographed = measured[l];
    le.used = out.lampExitance[l];
    out.estimates.lamps.push_back(le);
  }
  radiometricReflectances(out.lampExitance, 4);

  // §4.1: texture-based refinement along real shadows; lamp links at the leaves.
  {
    ProgressScope scope(progress, 0.55, 0.7);
    out.colourScale = rhoHat / (grey(imageMean) / kPi);
    textureRefine(h, tex, lampSurfaces, real, out.colourScale, o, &out.estimates, scope);
  }
  leaves = leafData();
  // Reflectance per element from its texture and its computed irradiance; B_orig = D_orig.
  auto setLeafReflectance = [&](const std::vector<glm::dvec3>& rho) {
    for (size_t k = 0; k < leaves.size(); ++k) h.setElementReflectance(leaves[k].node, rho[k]);
  };
  {
    h.iterate(progress);
    std::vector<glm::dvec3> rho(leaves.size());
    for (size_t k = 0; k < leaves.size(); ++k)
      rho[k] = rhoOf(leaves[k].surface, leaves[k].tex, glm::dvec3(h.irradiance(leaves[k].node)));
    setLeafReflectance(rho);
    h.iterate(progress);
  }

  // §4.2, step 1: add the blocked light back (Eq. 5-6), modulating at leaf vertices.
  progress.report(0.75, "adding blocked light back (Eq. 5-6)");
  sums = linkSums(h, o.blockedIndirect);
  std::vector<glm::vec3> Enode(h.nodes().size());
  for (size_t i = 0; i < Enode.size(); ++i) Enode[i] = h.irradiance(int(i));
  // Corner values lean on the elements the photo shows: hidden ones (behind a poster, under a
  // box) have no light to speak of and would spread their extreme ratios to visible neighbours.
  wSeen.assign(h.nodes().size(), 1.f);
  for (const auto& L : leaves) wSeen[L.node] = float(L.seen) + 1e-3f;
  const std::vector<uint8_t> all(np, 1);
  {
    const auto cU = leafCornerValues(h, sums.unoccluded, &wSeen), cE = leafCornerValues(h, Enode, &wSeen);
    for (size_t s = 0; s < np; ++s) tex[s].unoccluded = tex[s].original;
    forEachTexel(all, [&](PolygonTexture& t, size_t i, int leaf, glm::dvec2 uv) {
      const auto& L = h.nodes()[leaf];
      const glm::vec3 u = interpolateCorners(L, cU[leaf], uv), e = interpolateCorners(L, cE[leaf], uv);
      const glm::vec3 f = glm::clamp(u / glm::max(e, glm::vec3(1e-20f)), glm::vec3(1.f), glm::vec3(50.f));
      t.unoccluded[i] = t.original[i] * f;
    });
    for (size_t s = 0; s < np; ++s) fillSmoothly(tex[s], tex[s].unoccluded, true);
  }
  // T_inter: what step 2 starts from (kept, so that step 2 can be redone per polygon).
  rhoInter = unoccludedReflectances();
  inter.resize(np);
  for (size_t s = 0; s < np; ++s) inter[s] = tex[s].unoccluded;

  // §4.3, step 2: the element sets and automatic references do not depend on the user's choices.
  progress.report(0.82, "reference-patch correction (Eq. 7-9)");
  leafIndex.assign(h.nodes().size(), -1);
  for (size_t k = 0; k < leaves.size(); ++k) leafIndex[leaves[k].node] = int(k);
  occluded.assign(leaves.size(), 0);
  unoccluded.assign(leaves.size(), 0);
  for (size_t k = 0; k < leaves.size(); ++k) {
    const double d = grey(glm::dvec3(sums.direct[leaves[k].node]));
    const double b = grey(glm::dvec3(sums.directBlocked[leaves[k].node]));
    occluded[k] = d > 0 && b > o.occludedFraction * d;
    unoccluded[k] = b <= 1e-3 * d;
  }
  lab.resize(leaves.size());
  for (size_t k = 0; k < leaves.size(); ++k) lab[k] = linearRgbToLab(rhoInter[k]);
  frontier.assign(np, {});
  for (size_t k = 0; k < leaves.size(); ++k) {
    if (!unoccluded[k] || leaves[k].seen < 0.5) continue;
    for (int n : neighbours(h, leaves[k].node))
      if (leafIndex[n] >= 0 && occluded[leafIndex[n]]) {
        frontier[leaves[k].surface].push_back(int(k));
        break;
      }
  }
  // Automatic default reference per polygon: the unoccluded element the photo shows whose colour
  // is nearest the polygon's mean unoccluded colour.
  autoRef.assign(np, -1);
  {
    std::vector<glm::dvec3> meanRhoInter(np, glm::dvec3(0.0));
    std::vector<double> wsum(np, 0);
    for (size_t k = 0; k < leaves.size(); ++k)
      if (unoccluded[k] && leaves[k].seen >= 0.5) {
        meanRhoInter[leaves[k].surface] += leaves[k].area * rhoInter[k];
        wsum[leaves[k].surface] += leaves[k].area;
      }
    std::vector<double> best(np, 1e300);
    for (size_t k = 0; k < leaves.size(); ++k) {
      const int s = leaves[k].surface;
      if (!unoccluded[k] || leaves[k].seen < 0.5 || wsum[s] <= 0) continue;
      const double d = glm::length(lab[k] - linearRgbToLab(meanRhoInter[s] / wsum[s]));
      if (d < best[s]) {
        best[s] = d;
        autoRef[s] = int(k);
      }
    }
    for (size_t s = 0; s < np; ++s)
      if (autoRef[s] >= 0) {
        const auto& N = h.nodes()[leaves[autoRef[s]].node];
        out.referencePatch[scene.polygons[s].name] = {0.5 * (N.u0 + N.u1), 0.5 * (N.v0 + N.v1)};
      }
  }
  factor.assign(h.nodes().size(), glm::vec3(1.f));
  how.assign(leaves.size(), 0);
  step2(all, o.referenceOverride, o.referenceRegions);
  finalPass(progress);
  out.estimates.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  progress.report(1.0, "preprocessed");
}

// Each element's leaf index on the user's chosen points, checked before anything changes.
Preprocessor::Impl::Choices Preprocessor::Impl::resolve(const std::map<std::string, glm::dvec2>& overrides,
                                                       const std::vector<ReferenceRegion>& regions) const {
  checkReferenceChoices(scene, overrides, regions);
  Choices c;
  for (const auto& [name, uv] : overrides) {
    const int s = scene.findPolygon(name);
    const int leaf = hr->findLeaf(s, uv);
    if (leaf < 0 || leafIndex[leaf] < 0) throw Error(scene.sourceFile, "reference patch '" + name + "'", "no element there");
    c.defaultRef.emplace_back(s, leafIndex[leaf]);
  }
  for (const auto& r : regions) {
    const int s = scene.findPolygon(r.polygon);
    const int leaf = hr->findLeaf(s, r.reference);
    if (leaf < 0 || leafIndex[leaf] < 0)
      throw Error(scene.sourceFile, "reference region on '" + r.polygon + "'", "no element at the reference");
    c.regionRef.emplace_back(s, leafIndex[leaf]);
  }
  return c;
}

// §4.3, step 2 on the polygons in `redo`: each occluded element takes its reflectance from a
// reference — the latest painted region holding it, else the nearest frontier element of similar
// colour, else the polygon's default (the user's, else the automatic one) — Eq. 7-9, and T_final
// = T_inter modulated by the ratio. Other polygons keep what they had.
void Preprocessor::Impl::step2(const std::vector<uint8_t>& redo, const std::map<std::string, glm::dvec2>& overrides,
                               const std::vector<ReferenceRegion>& regions) {
  const Choices c = resolve(overrides, regions);
  auto& h = *hr;
  auto& tex = out.textures;
  const size_t np = scene.polygons.size();
  std::vector<int> defaultRef = autoRef;
  for (const auto& [s, k] : c.defaultRef) defaultRef[s] = k;
  out.referenceOverride = overrides;
  out.referenceRegions = regions;
  out.options.referenceOverride = overrides;
  out.options.referenceRegions = regions;
  for (size_t k = 0; k < leaves.size(); ++k) {
    const int s = leaves[k].surface;
    if (!occluded[k] || !redo[s]) continue;
    const auto& N = h.nodes()[leaves[k].node];
    factor[leaves[k].node] = glm::vec3(1.f);
    how[k] = 0;
    if (o.reference == RelightOptions::Reference::Off) continue;
    int ref = -1;
    for (size_t r = 0; r < c.regionRef.size(); ++r)
      if (c.regionRef[r].first == s && regions[r].contains({0.5 * (N.u0 + N.u1), 0.5 * (N.v0 + N.v1)}))
        ref = c.regionRef[r].second;
    if (ref >= 0) {
      how[k] = kByRegion;
    } else if (o.reference == RelightOptions::Reference::Chosen) {
      // Only the user's choice: the polygon's reference patch as it is; else step 1 stands.
      if (!overrides.count(scene.polygons[size_t(s)].name) || defaultRef[s] < 0) continue;
      ref = defaultRef[s];
      how[k] = kByDefault;
    } else {
      const glm::dvec3 ci = glm::dvec3(N.center);
      double bestDist = 1e300;
      for (int n : frontier[s]) {
        if (glm::length(lab[n] - lab[k]) >= o.colourThreshold) continue;
        const double d = glm::length(glm::dvec3(h.nodes()[leaves[n].node].center) - ci);
        if (d < bestDist) {
          bestDist = d;
          ref = n;
        }
      }
      if (ref >= 0) how[k] = kByFrontier;
      else {
        ref = defaultRef[s];
        if (ref < 0) continue;
        how[k] = kByDefault;
      }
    }
    // Eq. 8 with the reflectance of step 1 (already divided by the unoccluded irradiance, so the
    // form-factor ratio of Eq. 7 is inside it), then Eq. 9's modulation of T_inter.
    glm::dvec3 f = rhoInter[ref] / rhoInter[k];
    if (o.reference == RelightOptions::Reference::Weighted || o.reference == RelightOptions::Reference::Chosen) {
      const double d = grey(glm::dvec3(sums.direct[leaves[k].node]));
      const double b = std::clamp(grey(glm::dvec3(sums.directBlocked[leaves[k].node])) / std::max(d, 1e-30), 0.0, 0.999);
      const double r = b / (1 - b), w = r * r / (1 + r * r);
      f = glm::pow(f, glm::dvec3(w));
    }
    factor[leaves[k].node] = glm::vec3(f);
  }
  auto& est = out.estimates;
  est.occludedLeaves = est.frontierLeaves = est.referencedByFrontier = est.referencedByDefault = est.referencedByRegion = 0;
  for (const auto& f : frontier) est.frontierLeaves += f.size();
  for (size_t k = 0; k < leaves.size(); ++k) {
    est.occludedLeaves += occluded[k] && o.reference != RelightOptions::Reference::Off;
    est.referencedByRegion += how[k] == kByRegion;
    est.referencedByFrontier += how[k] == kByFrontier;
    est.referencedByDefault += how[k] == kByDefault;
  }
  const auto cF = leafCornerValues(h, factor, &wSeen);
  for (size_t s = 0; s < np; ++s)
    if (redo[s]) tex[s].unoccluded = inter[s];
  forEachTexel(redo, [&](PolygonTexture& t, size_t i, int leaf, glm::dvec2 uv) {
    t.unoccluded[i] *= interpolateCorners(h.nodes()[leaf], cF[leaf], uv);
  });
  for (size_t s = 0; s < np; ++s)
    if (redo[s]) fillSmoothly(tex[s], tex[s].unoccluded, true);
}

// rho_final, B_final, and the reflectance map (T_final over the unoccluded irradiance): global,
// since a polygon's reflectance lights every other.
void Preprocessor::Impl::finalPass(Progress& progress) {
  progress.report(0.9, "final reflectances");
  auto& h = *hr;
  auto& tex = out.textures;
  const size_t np = scene.polygons.size();
  const auto rho = unoccludedReflectances();
  for (size_t k = 0; k < leaves.size(); ++k) h.setElementReflectance(leaves[k].node, rho[k]);
  h.iterate(progress);
  const LinkSums finalSums = linkSums(h, o.blockedIndirect);
  const auto cU = leafCornerValues(h, finalSums.unoccluded, &wSeen);
  for (size_t s = 0; s < np; ++s) tex[s].albedo.assign(tex[s].original.size(), glm::vec3(0.f));
  const std::vector<uint8_t> all(np, 1);
  forEachTexel(all, [&](PolygonTexture& t, size_t i, int leaf, glm::dvec2 uv) {
    const glm::vec3 u = interpolateCorners(h.nodes()[leaf], cU[leaf], uv);
    t.albedo[i] = glm::clamp(float(kPi) * t.unoccluded[i] / glm::max(u, glm::vec3(1e-20f)), glm::vec3(0.f), glm::vec3(1.f));
  });
  for (size_t s = 0; s < np; ++s) {
    if (real[s] && !observed[s]) {  // nothing seen: the mean reflectance, lit by the solution
      std::fill(tex[s].albedo.begin(), tex[s].albedo.end(), glm::vec3(unseenRho[s]));
      const auto& t = tex[s];
      for (int y = 0; y < t.height; ++y)
        for (int x = 0; x < t.width; ++x) {
          if (t.source[t.index(x, y)] == TexelSource::Outside) continue;
          const glm::dvec2 uv = t.uvOf(x + 0.5, y + 0.5);
          const int leaf = h.findLeaf(int(s), uv);
          const glm::vec3 u = interpolateCorners(h.nodes()[leaf], cU[leaf], uv);
          tex[s].original[t.index(x, y)] = tex[s].unoccluded[t.index(x, y)] = glm::vec3(unseenRho[s]) * u / float(kPi);
        }
      fillSmoothly(tex[s], tex[s].original, true);
      fillSmoothly(tex[s], tex[s].unoccluded, true);
    }
    if (real[s]) fillSmoothly(tex[s], tex[s].albedo, true);
    // The oracle's reflectances are the scene's, wherever the session takes them from.
    if (real[s] && o.oracleAlbedos)
      std::fill(tex[s].albedo.begin(), tex[s].albedo.end(), glm::vec3(rhoAt(int(s), glm::dvec3(0.0), glm::dvec3(1.0))));
  }
  for (size_t s = 0; s < np; ++s)
    if (!real[s]) {
      tex[s].unoccluded = tex[s].original;
      tex[s].albedo.assign(tex[s].original.size(), glm::vec3(0.f));
    }
}

std::vector<glm::dvec3> Preprocessor::Impl::unoccludedReflectances() const {
  std::vector<glm::dvec3> rho(leaves.size());
  for (size_t k = 0; k < leaves.size(); ++k) {
    const auto& N = hr->nodes()[leaves[k].node];
    const auto& t = out.textures[N.surface];
    const glm::dvec3 m(t.mean(t.unoccluded, {N.u0, N.v0}, {N.u1, N.v1}));
    rho[k] = rhoAt(leaves[k].surface, m, glm::dvec3(sums.unoccluded[leaves[k].node]));
  }
  return rho;
}

void Preprocessor::Impl::forEachTexel(const std::vector<uint8_t>& polygons,
                                      const std::function<void(PolygonTexture&, size_t, int, glm::dvec2)>& fn) {
  tbb::parallel_for(size_t(0), scene.polygons.size(), [&](size_t s) {
    if (!real[s] || !polygons[s]) return;
    auto& t = out.textures[s];
    for (int y = 0; y < t.height; ++y)
      for (int x = 0; x < t.width; ++x) {
        if (t.source[t.index(x, y)] == TexelSource::Outside) continue;
        const glm::dvec2 uv = t.uvOf(x + 0.5, y + 0.5);
        fn(t, t.index(x, y), hr->findLeaf(int(s), uv), uv);
      }
  });
}

Preprocessor::Preprocessor(const Scene& scene, const RelightOptions& options, Progress& progress)
    : impl_(std::make_unique<Impl>(scene, options)) {
  impl_->run(progress);
}

Preprocessor::~Preprocessor() = default;

const RelightData& Preprocessor::data() const { return impl_->out; }

std::vector<int> Preprocessor::redoReferences(const std::map<std::string, glm::dvec2>& overrides,
                                              const std::vector<ReferenceRegion>& regions, Progress& progress) {
  auto& im = *impl_;
  const size_t np = im.scene.polygons.size();
  im.resolve(overrides, regions);  // refused before anything changes
  // The polygons whose choices differ from those applied (all after a failed or cancelled redo).
  std::vector<uint8_t> redo(np, im.stale ? 1 : 0);
  auto choicesOf = [&](int s, const std::map<std::string, glm::dvec2>& ov, const std::vector<ReferenceRegion>& rs) {
    const std::string& name = im.scene.polygons[size_t(s)].name;
    std::pair<std::optional<glm::dvec2>, std::vector<ReferenceRegion>> c;
    if (auto it = ov.find(name); it != ov.end()) c.first = it->second;
    for (const auto& r : rs)
      if (r.polygon == name) c.second.push_back(r);
    return c;
  };
  for (size_t s = 0; s < np; ++s)
    if (choicesOf(int(s), overrides, regions) != choicesOf(int(s), im.out.referenceOverride, im.out.referenceRegions))
      redo[s] = 1;
  std::vector<int> changed;
  for (size_t s = 0; s < np; ++s)
    if (redo[s] && im.real[s]) changed.push_back(int(s));
  if (changed.empty()) {  // the same choices per polygon (maybe listed in another order)
    im.out.referenceOverride = im.out.options.referenceOverride = overrides;
    im.out.referenceRegions = im.out.options.referenceRegions = regions;
    return changed;
  }
  const auto t0 = std::chrono::steady_clock::now();
  im.stale = true;
  im.step2(redo, overrides, regions);
  im.finalPass(progress);
  im.stale = false;
  im.out.estimates.stepTwoSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  progress.report(1.0, "reference patches recomputed");
  return changed;
}

RelightData preprocessRoom(const Scene& scene, const RelightOptions& options, Progress& progress) {
  Preprocessor p(scene, options, progress);
  return p.data();
}

}  // namespace relume
