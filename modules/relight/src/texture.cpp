#include "relume/relight/texture.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

#include "relume/geometry/error.h"
#include "relume/geometry/scene.h"
#include "relume/image/image.h"
#include "relume/raytrace/ray_scene.h"

namespace relume {

namespace {

// Which polygon each pixel centre of `cam` sees (-1: none).
std::vector<int> polygonIds(const Camera& cam, const RayScene& rays) {
  std::vector<int> ids(size_t(cam.width) * cam.height, -1);
  const glm::vec3 eye(cam.center());
  tbb::parallel_for(tbb::blocked_range<int>(0, cam.height, 8), [&](const tbb::blocked_range<int>& r) {
    std::vector<Ray> rs(cam.width);
    std::vector<RayHit> hits(cam.width);
    for (int y = r.begin(); y < r.end(); ++y) {
      for (int x = 0; x < cam.width; ++x) rs[x] = Ray{eye, glm::vec3(cam.rayDirection(x + 0.5, y + 0.5)), 0.f, 1e30f};
      rays.intersect(rs, hits);
      for (int x = 0; x < cam.width; ++x) ids[size_t(y) * cam.width + x] = hits[x].polygon;
    }
  });
  return ids;
}

// How far (pixels) a lamp's glow reaches into what surrounds its image: a fraction of the frame.
int glowRadius(int width) { return std::max(2, int(std::lround(0.025 * width))); }

// Which pixels have a marked pixel within the square of `radius` around them (the square clipped
// to the image), `marked` included: a row pass and a column pass of running counts, so that the
// cost does not grow with the radius (a per-pixel search of the square was a third of a
// preprocess at 640 x 480).
std::vector<uint8_t> nearMarked(const std::vector<uint8_t>& marked, int width, int height, int radius) {
  radius = std::max(radius, 0);
  std::vector<uint8_t> rows(marked.size(), 0), out(marked.size(), 0);
  std::vector<int> prefix(size_t(std::max(width, height)) + 1);
  for (int y = 0; y < height; ++y) {
    const uint8_t* m = &marked[size_t(y) * width];
    for (int x = 0; x < width; ++x) prefix[size_t(x) + 1] = prefix[size_t(x)] + (m[x] ? 1 : 0);
    for (int x = 0; x < width; ++x)
      rows[size_t(y) * width + x] = prefix[size_t(std::min(x + radius, width - 1)) + 1] > prefix[size_t(std::max(x - radius, 0))];
  }
  for (int x = 0; x < width; ++x) {
    for (int y = 0; y < height; ++y) prefix[size_t(y) + 1] = prefix[size_t(y)] + rows[size_t(y) * width + x];
    for (int y = 0; y < height; ++y)
      out[size_t(y) * width + x] = prefix[size_t(std::min(y + radius, height - 1)) + 1] > prefix[size_t(std::max(y - radius, 0))];
  }
  return out;
}

// Pixels next to a lamp's image mix its glow into whatever else they show (antialiasing, lens
// bloom): they are given to nobody but the lamp.
void isolateLamps(std::vector<int>& ids, int width, int height, const std::vector<uint8_t>& isLamp, int radius) {
  std::vector<uint8_t> lamp(ids.size(), 0);
  for (size_t i = 0; i < ids.size(); ++i) lamp[i] = ids[i] >= 0 && isLamp[size_t(ids[i])];
  const std::vector<uint8_t> near = nearMarked(lamp, width, height, radius);
  for (size_t i = 0; i < ids.size(); ++i)
    if (near[i] && !lamp[i]) ids[i] = -2;
}

// Do the pixel and its eight neighbours all see `polygon`?
bool awayFromOutline(const std::vector<int>& ids, int width, int height, int polygon, int x, int y) {
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int xx = std::clamp(x + dx, 0, width - 1), yy = std::clamp(y + dy, 0, height - 1);
      if (ids[size_t(yy) * width + xx] != polygon) return false;
    }
  return true;
}

// Bilinear sample using only the pixels that see `polygon`, so that no colour bleeds in from a
// neighbouring polygon (a lamp's glow onto the ceiling around it, a wall into the floor's edge).
// `inside`: every pixel used lies away from the polygon's outline (awayFromOutline), so that the
// camera's pixel filter mixed nothing else into it.
bool sampleOwnPixels(const ImageRGB& img, const std::vector<int>& ids, int polygon, double x, double y, glm::vec3& out,
                     bool& inside) {
  x -= 0.5;
  y -= 0.5;
  const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
  const float fx = float(x - x0), fy = float(y - y0);
  glm::vec3 sum(0.f);
  float wsum = 0.f;
  inside = true;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const int xx = std::clamp(x0 + i, 0, img.width - 1), yy = std::clamp(y0 + j, 0, img.height - 1);
      if (ids[size_t(yy) * img.width + xx] != polygon) continue;
      const float w = (i ? fx : 1 - fx) * (j ? fy : 1 - fy) + 1e-4f;
      sum += w * img.at(xx, yy);
      wsum += w;
      inside = inside && awayFromOutline(ids, img.width, img.height, polygon, xx, yy);
    }
  if (wsum <= 0.f) return false;
  out = sum / wsum;
  return true;
}

// Area in pixels of the polygon's image in `cam` (clipped to the near plane and the frame).
double projectedArea(const Camera& cam, const std::vector<glm::dvec3>& poly) {
  const glm::dvec3 c = cam.center();
  const glm::dvec3 forward = glm::transpose(cam.R) * glm::dvec3(0, 0, 1);
  const auto front = clipToHalfSpace(poly, c + 1e-3 * forward, forward);
  if (front.size() < 3) return 0;
  std::vector<glm::dvec2> px;
  for (const auto& p : front) {
    glm::dvec2 q;
    cam.project(p, q);
    px.push_back(q);
  }
  if (polygonArea2D(px) < 0) std::reverse(px.begin(), px.end());
  const auto inFrame = clipToRect(px, {0, 0}, {double(cam.width), double(cam.height)});
  return inFrame.size() < 3 ? 0 : std::abs(polygonArea2D(inFrame));
}

ImageRGB readPhoto(const Scene& scene, const Photo& ph) {
  const std::string rel = ph.hdr.empty() ? ph.file : ph.hdr;
  return readImageLinear(rel.front() == '/' ? rel : scene.baseDir + "/" + rel);
}

// Samples `img` (taken by `cam`) at the texels of `t` still lacking a value and marks them.
size_t sampleFromPhoto(PolygonTexture& t, const Camera& cam, const ImageRGB& img, const std::vector<int>& ids,
                       const RayScene& rays, TexelSource mark, const std::vector<uint8_t>& need) {
  const glm::dvec3 eye = cam.center();
  std::vector<Segment> segs;
  std::vector<size_t> idx;
  std::vector<glm::dvec2> px;
  for (int y = 0; y < t.height; ++y)
    for (int x = 0; x < t.width; ++x) {
      const size_t i = t.index(x, y);
      if (!need[i]) continue;
      const glm::dvec3 p = t.frame.toWorld(t.uvOf(x + 0.5, y + 0.5));
      if (glm::dot(t.frame.normal, eye - p) <= 0) continue;  // the camera sees the back
      glm::dvec2 q;
      if (!cam.project(p, q) || q.x < 0 || q.y < 0 || q.x >= cam.width || q.y >= cam.height) continue;
      segs.push_back({glm::vec3(eye), glm::vec3(p)});
      idx.push_back(i);
      px.push_back(q);
    }
  std::vector<uint8_t> blocked(segs.size(), 0);
  rays.occluded(segs, blocked, 2e-4f);
  size_t n = 0;
  const TexelSource outline = mark == TexelSource::MainPhoto ? TexelSource::MainPhotoOutline : TexelSource::OtherPhotoOutline;
  for (size_t k = 0; k < segs.size(); ++k) {
    bool inside = true;
    if (blocked[k] || !sampleOwnPixels(img, ids, t.polygon, px[k].x, px[k].y, t.original[idx[k]], inside)) continue;
    t.source[idx[k]] = inside ? mark : outline;
    ++n;
  }
  return n;
}

}  // namespace

bool PolygonTexture::photographed() const {
  return std::any_of(source.begin(), source.end(),
                     [](TexelSource s) { return fromPhoto(s); });
}

TexelSource PolygonTexture::sourceAt(glm::dvec2 uv) const {
  if (source.empty()) return TexelSource::Outside;
  const int x = std::clamp(int(std::floor((uv.x - origin.x) / texel)), 0, width - 1);
  const int y = std::clamp(int(std::floor((uv.y - origin.y) / texel)), 0, height - 1);
  return source[index(x, y)];
}

glm::vec3 PolygonTexture::sample(const std::vector<glm::vec3>& layer, glm::dvec2 uv) const {
  const double x = (uv.x - origin.x) / texel - 0.5, y = (uv.y - origin.y) / texel - 0.5;
  const int x0 = std::clamp(int(std::floor(x)), 0, width - 1), y0 = std::clamp(int(std::floor(y)), 0, height - 1);
  const int x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
  const float fx = float(std::clamp(x - x0, 0.0, 1.0)), fy = float(std::clamp(y - y0, 0.0, 1.0));
  return (1 - fx) * (1 - fy) * layer[index(x0, y0)] + fx * (1 - fy) * layer[index(x1, y0)] +
         (1 - fx) * fy * layer[index(x0, y1)] + fx * fy * layer[index(x1, y1)];
}

glm::dvec3 PolygonTexture::photographedMean(const std::vector<glm::vec3>& layer, size_t* count) const {
  glm::dvec3 sum(0.0), sumInside(0.0);
  size_t n = 0, nInside = 0;
  for (size_t k = 0; k < source.size() && k < layer.size(); ++k)
    if (fromPhoto(source[k])) {
      sum += glm::dvec3(layer[k]);
      ++n;
      if (photographedInside(source[k])) {
        sumInside += glm::dvec3(layer[k]);
        ++nInside;
      }
    }
  if (nInside > 0) sum = sumInside, n = nInside;
  if (count) *count = n;
  return n > 0 ? sum / double(n) : glm::dvec3(0.0);
}

glm::vec3 PolygonTexture::mean(const std::vector<glm::vec3>& layer, glm::dvec2 lo, glm::dvec2 hi, double* seen) const {
  const int x0 = std::max(0, int(std::ceil((lo.x - origin.x) / texel - 0.5)));
  const int x1 = std::min(width - 1, int(std::floor((hi.x - origin.x) / texel - 0.5)));
  const int y0 = std::max(0, int(std::ceil((lo.y - origin.y) / texel - 0.5)));
  const int y1 = std::min(height - 1, int(std::floor((hi.y - origin.y) / texel - 0.5)));
  glm::dvec3 sum(0.0);
  size_t n = 0, fromMain = 0;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const size_t i = index(x, y);
      if (source[i] == TexelSource::Outside) continue;
      sum += glm::dvec3(layer[i]);
      ++n;
      fromMain += fromMainPhoto(source[i]);
    }
  if (n == 0) {
    const glm::dvec2 c = 0.5 * (lo + hi);
    if (seen) *seen = fromMainPhoto(sourceAt(c)) ? 1.0 : 0.0;
    return sample(layer, c);
  }
  if (seen) *seen = double(fromMain) / double(n);
  return glm::vec3(sum / double(n));
}

void fillSmoothly(PolygonTexture& t, std::vector<glm::vec3>& layer, bool outsideOnly) {
  // Pull: a pyramid of weighted means of the known texels; push: unknown texels take the
  // (bilinearly upsampled) value of the coarser level.
  struct Level {
    int w, h;
    std::vector<glm::vec3> c;
    std::vector<float> wt;
  };
  std::vector<Level> lv;
  Level base{t.width, t.height, layer, std::vector<float>(layer.size(), 0.f)};
  for (size_t i = 0; i < layer.size(); ++i)
    if (outsideOnly ? t.source[i] != TexelSource::Outside
                    : fromPhoto(t.source[i]))
      base.wt[i] = 1.f;
  lv.push_back(std::move(base));
  while (lv.back().w > 1 || lv.back().h > 1) {
    const Level& f = lv.back();
    Level c{(f.w + 1) / 2, (f.h + 1) / 2, {}, {}};
    c.c.assign(size_t(c.w) * c.h, glm::vec3(0.f));
    c.wt.assign(size_t(c.w) * c.h, 0.f);
    for (int y = 0; y < f.h; ++y)
      for (int x = 0; x < f.w; ++x) {
        const size_t i = size_t(y) * f.w + x, j = size_t(y / 2) * c.w + x / 2;
        c.c[j] += f.wt[i] * f.c[i];
        c.wt[j] += f.wt[i];
      }
    for (size_t j = 0; j < c.c.size(); ++j)
      if (c.wt[j] > 0) {
        c.c[j] /= c.wt[j];
        c.wt[j] = std::min(1.f, c.wt[j]);
      }
    lv.push_back(std::move(c));
  }
  for (size_t k = lv.size() - 1; k-- > 0;) {
    Level& f = lv[k];
    const Level& c = lv[k + 1];
    for (int y = 0; y < f.h; ++y)
      for (int x = 0; x < f.w; ++x) {
        const size_t i = size_t(y) * f.w + x;
        if (f.wt[i] >= 1.f) continue;
        // Bilinear in the coarse level (texel centres at (X + 0.5) * 2 in fine units).
        const double cx = std::clamp((x + 0.5) / 2 - 0.5, 0.0, double(c.w - 1));
        const double cy = std::clamp((y + 0.5) / 2 - 0.5, 0.0, double(c.h - 1));
        const int x0 = int(cx), y0 = int(cy), x1 = std::min(x0 + 1, c.w - 1), y1 = std::min(y0 + 1, c.h - 1);
        const float fx = float(cx - x0), fy = float(cy - y0);
        const glm::vec3 up = (1 - fx) * (1 - fy) * c.c[size_t(y0) * c.w + x0] + fx * (1 - fy) * c.c[size_t(y0) * c.w + x1] +
                             (1 - fx) * fy * c.c[size_t(y1) * c.w + x0] + fx * fy * c.c[size_t(y1) * c.w + x1];
        f.c[i] = f.wt[i] * f.c[i] + (1 - f.wt[i]) * up;
        f.wt[i] = 1.f;
      }
  }
  layer = std::move(lv[0].c);
}

std::vector<PolygonTexture> dewarpPhotos(const Scene& scene, const RayScene& rays, int photoIndex, DewarpStats* stats,
                                         Progress& progress) {
  const Photo& main = scene.photos.at(photoIndex);
  std::vector<ImageRGB> images(scene.photos.size());
  std::vector<std::vector<int>> ids(scene.photos.size());
  images[photoIndex] = readPhoto(scene, main);
  std::vector<uint8_t> isLamp(scene.polygons.size(), 0);
  for (size_t i = 0; i < scene.polygons.size(); ++i) isLamp[i] = scene.polygons[i].kind == PolygonKind::Light;
  auto idsOf = [&](const Camera& c) {
    auto v = polygonIds(c, rays);
    isolateLamps(v, c.width, c.height, isLamp, glowRadius(c.width));
    return v;
  };
  ids[photoIndex] = idsOf(main.camera);
  const auto& cam = main.camera;
  std::vector<PolygonTexture> out(scene.polygons.size());
  DewarpStats st;
  for (size_t p = 0; p < scene.polygons.size(); ++p) {
    progress.report(0.9 * double(p) / scene.polygons.size(), "de-warping " + scene.polygons[p].name);
    const auto& poly = scene.polygons[p].vertices;
    PolygonTexture& t = out[p];
    t.polygon = int(p);
    t.frame = PlaneFrame::of(poly);
    std::vector<glm::dvec2> uvPoly;
    glm::dvec2 lo(1e300), hi(-1e300);
    for (const auto& v : poly) {
      uvPoly.push_back(t.frame.toUV(v));
      lo = glm::min(lo, uvPoly.back());
      hi = glm::max(hi, uvPoly.back());
    }
    // Resolution: one texel per photo pixel on average over the polygon's image (the best view
    // when the chosen photo does not see it), bounded to 4..1024 texels a side.
    const double area = polygonArea(poly);
    double pixels = projectedArea(cam, poly);
    if (pixels < 16)
      for (const auto& ph : scene.photos) pixels = std::max(pixels, projectedArea(ph.camera, poly));
    const glm::dvec2 ext = hi - lo;
    double texel = pixels >= 16 ? std::sqrt(area / pixels) : std::sqrt(area) / 32;
    const double finest = std::max(ext.x, ext.y) / 1024;
    texel = std::clamp(texel, finest, std::max(finest, std::max(1e-4, std::min(ext.x, ext.y) / 4)));
    t.texel = texel;
    t.width = std::max(1, int(std::ceil(ext.x / texel)) + 2);
    t.height = std::max(1, int(std::ceil(ext.y / texel)) + 2);
    t.origin = lo - glm::dvec2(texel);
    const size_t n = size_t(t.width) * t.height;
    t.source.assign(n, TexelSource::Outside);
    t.original.assign(n, glm::vec3(0.f));
    std::vector<uint8_t> need(n, 0);
    for (int y = 0; y < t.height; ++y)
      for (int x = 0; x < t.width; ++x)
        if (insideConvex2D(uvPoly, t.uvOf(x + 0.5, y + 0.5), 1e-9)) {
          need[t.index(x, y)] = 1;
          t.source[t.index(x, y)] = TexelSource::Smooth;
        }
    const size_t inside = size_t(std::count(need.begin(), need.end(), 1));
    st.texels += inside;
    st.fromMain += sampleFromPhoto(t, cam, images[photoIndex], ids[photoIndex], rays, TexelSource::MainPhoto, need);
  }
  // Texels the main photo lacks, from the other photos in turn, each brought to the main photo's
  // exposure first: its radiance scale relative to the main photo is the median ratio over the
  // texels both photos show (all polygons together).
  std::vector<uint8_t> need;
  for (size_t q = 0; q < scene.photos.size(); ++q) {
    if (int(q) == photoIndex) continue;
    std::vector<size_t> wanting;  // polygons with texels still missing that photo q sees
    for (size_t p = 0; p < out.size(); ++p)
      if (std::count(out[p].source.begin(), out[p].source.end(), TexelSource::Smooth) > 0 &&
          projectedArea(scene.photos[q].camera, scene.polygons[p].vertices) >= 1)
        wanting.push_back(p);
    if (wanting.empty()) continue;
    progress.report(0.9, "filling what " + main.name + " does not show from " + scene.photos[q].name);
    progress.poll();  // reading and ray-casting a photo takes a while: answer Cancel first
    images[q] = readPhoto(scene, scene.photos[q]);
    progress.poll();
    ids[q] = idsOf(scene.photos[q].camera);
    progress.poll();
    // Real surfaces only (a lamp's or a window's radiance depends on the direction), seen by photo
    // q, and no texel at the clipping level of an LDR photo in either photo.
    const bool ldr = main.hdr.empty() || scene.photos[q].hdr.empty();
    auto clipped = [&](const glm::vec3& v) { return ldr && std::max({v.x, v.y, v.z}) >= 0.98f; };
    std::vector<double> ratios;
    for (size_t p = 0; p < out.size(); ++p) {
      if (scene.polygons[p].kind != PolygonKind::Real || projectedArea(scene.photos[q].camera, scene.polygons[p].vertices) < 1)
        continue;
      PolygonTexture probe = out[p];
      need.assign(probe.source.size(), 0);
      // A fifth of the texels (plenty), away from the outline in both photos (photographedInside):
      // an outline pixel's value mixes in a neighbour, differently in each view.
      for (size_t i = 0; i < need.size(); i += 5) need[i] = probe.source[i] == TexelSource::MainPhoto;
      if (std::find(need.begin(), need.end(), 1) == need.end()) continue;
      sampleFromPhoto(probe, scene.photos[q].camera, images[q], ids[q], rays, TexelSource::OtherPhoto, need);
      for (size_t i = 0; i < need.size(); ++i) {
        if (!need[i] || probe.source[i] != TexelSource::OtherPhoto) continue;  // not sampled from photo q now
        const glm::vec3 m = out[p].original[i], o = probe.original[i];
        if (clipped(m) || clipped(o)) continue;
        const double a = double(m.x) + m.y + m.z, b = double(o.x) + o.y + o.z;
        if (a > 1e-6 && b > 1e-6) ratios.push_back(a / b);
      }
    }
    float scale = 1.f;
    if (ratios.size() >= 64) {
      std::nth_element(ratios.begin(), ratios.begin() + long(ratios.size() / 2), ratios.end());
      scale = float(ratios[ratios.size() / 2]);
    }
    st.exposureScale.push_back(scale);
    st.exposureOverlap.push_back(ratios.size());
    for (size_t p : wanting) {
      PolygonTexture& t = out[p];
      need.assign(t.source.size(), 0);
      for (size_t i = 0; i < need.size(); ++i) need[i] = t.source[i] == TexelSource::Smooth;
      st.fromOther += sampleFromPhoto(t, scene.photos[q].camera, images[q], ids[q], rays, TexelSource::OtherPhoto, need);
      for (size_t i = 0; i < need.size(); ++i)  // needed texels now from a photo came from this one
        if (need[i] && fromOtherPhoto(t.source[i])) t.original[i] *= scale;
    }
    images[q] = ImageRGB();  // each photo fills once: its pixels are not needed again
    ids[q].clear();
  }
  for (auto& t : out) {
    st.smooth += size_t(std::count(t.source.begin(), t.source.end(), TexelSource::Smooth));
    fillSmoothly(t, t.original, false);
  }
  progress.report(1.0, "textures de-warped");
  if (stats) *stats = st;
  return out;
}

std::vector<int> lampGlowRing(const Scene& scene, const RayScene& rays, const Camera& cam) {
  const std::vector<int> ids = polygonIds(cam, rays);
  std::vector<int> lampOf(scene.polygons.size(), -1);
  for (size_t p = 0; p < lampOf.size(); ++p) lampOf[p] = scene.lampOfPolygon(int(p));
  auto lampAt = [&](size_t i) { return ids[i] >= 0 ? lampOf[size_t(ids[i])] : -1; };
  std::vector<uint8_t> lamp(ids.size(), 0);
  for (size_t i = 0; i < ids.size(); ++i) lamp[i] = lampAt(i) >= 0;
  const int radius = glowRadius(cam.width);
  // Only pixels with a lamp's pixel in their square search it for the nearest.
  const std::vector<uint8_t> near = nearMarked(lamp, cam.width, cam.height, radius);
  std::vector<int> ring(ids.size(), -1);
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) {
      const size_t i = size_t(y) * cam.width + x;
      if (lamp[i] || !near[i]) continue;
      int best = -1, bestD = 1 << 30;
      for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx) {
          const int xx = x + dx, yy = y + dy;
          if (xx < 0 || yy < 0 || xx >= cam.width || yy >= cam.height) continue;
          const int l = lampAt(size_t(yy) * cam.width + xx);
          if (l >= 0 && dx * dx + dy * dy < bestD) {
            bestD = dx * dx + dy * dy;
            best = l;
          }
        }
      ring[i] = best;
    }
  return ring;
}

glm::dvec3 linearRgbToLab(const glm::dvec3& rgb) {
  const double X = 0.4124 * rgb.r + 0.3576 * rgb.g + 0.1805 * rgb.b;
  const double Y = 0.2126 * rgb.r + 0.7152 * rgb.g + 0.0722 * rgb.b;
  const double Z = 0.0193 * rgb.r + 0.1192 * rgb.g + 0.9505 * rgb.b;
  auto f = [](double t) { return t > 216.0 / 24389.0 ? std::cbrt(t) : (24389.0 / 27.0 * t + 16) / 116; };
  const double fx = f(X / 0.95047), fy = f(Y), fz = f(Z / 1.08883);
  return {116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)};
}

}  // namespace relume
