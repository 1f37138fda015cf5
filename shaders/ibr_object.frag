// (The renderer prepends "#version 330 core", OUTPUT, MAX_LAMPS, DAYLIGHT and display.glsl; with
// DAYLIGHT also MAX_MAPS and daylight_maps.glsl.)
// An image-based object (Dinh, Metoyer, Turk §3), drawn as the CPU renderer draws it
// (ibr::drawObject): the fragment's ray from the eye, in the fan's object frame, is marched
// through the depth of the fan image nearest the viewer (then the next nearest, and the nearest on
// another ring, where the one before did not see the surface), so the fan's pixels stand where
// the object's surface is; the pixel met is shaded by the tables of the 225 normal codes (computed by the library from the lights:
// first the indirect light, one row or one per cell, then per lamp 4 x 4 cells, bilinear), each lamp's entry divided by
// the squared distance from this point to the lamp and weighted by the object's own shadow (the
// fan image nearest the lamp's direction as a shadow map, 3 x 3 percentage-closer), averaged over
// the pixel's footprint in the fan; its depth written for the room's depth test.
in vec3 vWorld;
uniform mat4 worldToClip;
uniform vec3 eye;                  // world
uniform vec3 eyeObject;            // the eye in the fan's object frame
uniform mat3 worldToObject;        // a world direction into the object frame (turned, / scale)
uniform vec3 fanCentre;            // object frame
uniform float fanRadius;
uniform int fanSize;
uniform usampler2DArray fanData;   // per layer (one fan view): code, depth (0..65534 = 0..2 R), coverage
uniform sampler2DArray fanAlbedo;  // its albedo (sRGB texels, decoded by the sampler)
uniform sampler2D tables;          // kNormalCodes x rows, RGB; the drawn views' rows one after the other
uniform int rowsPerView;
uniform int indirectRows;          // 1, or one per cell (the light taken at each cell's point)
uniform int viewCount;             // 1 to 3: the nearest, the next, the nearest on another ring
uniform int viewLayer[3];
uniform vec3 viewAxes[9];          // right, up, towards the camera of each drawn view (object frame)
uniform int lampCount;             // at most MAX_LAMPS, those sharing an own-shadow view one after the other
uniform vec3 lampPosition[MAX_LAMPS];  // world
uniform int lampLayer[MAX_LAMPS];      // the lamp's own-shadow view
uniform vec3 lampAxes[3 * MAX_LAMPS];
#if DAYLIGHT
// The lamp seen past the room per point (the sun): through the sun's shadow maps, the room and the
// boxes and meshes in them (as the CPU path asks the room's rays per point).
uniform int lampPerPoint[MAX_LAMPS];
float sunThrough(vec3 p, vec3 n) {
  if (sunMaps == 0) return 1.0;
  float lit = 0.0;
  for (int j = 0; j < sunMaps; ++j) {
    int m = windowSamples + j;
    vec3 o = mapData[m * 7 + 4].xyz, w = mapData[m * 7 + 5].xyz;
    if (sampleState(m, p, max(-dot(n, w), 0.0), dot(p - o, w), false) == 1) lit += 1.0;
  }
  return lit / float(sunMaps);
}
#endif
uniform int footprint;             // fan pixels across a screen pixel (1..4)
out vec4 colour;

const float INV_PI = 0.31830988618379067;
const int CELLS = 4;

float surfaceAt(int layer, vec3 p0, vec3 dv, float t, float px, out ivec2 texel) {
  int S = fanSize;
  float R = fanRadius;
  texel = ivec2(clamp(int(floor((p0.x + t * dv.x + R) * px)), 0, S - 1), clamp(int(floor((R - (p0.y + t * dv.y)) * px)), 0, S - 1));
  uvec4 v = texelFetch(fanData, ivec3(texel, layer), 0);
  return v.b > 0u ? float(v.g) / 65534.0 * 2.0 * R : 1e30;
}

// 0: missed, 1: met the surface, 2: ended up more than CURTAIN pixels behind it (the "curtain" a
// height field hangs behind a depth edge: this view cannot tell what the ray meets).
const float CURTAIN = 1.5;
int marchView(int j, vec3 o, vec3 d, out float tHit, out ivec2 texel) {
  float R = fanRadius;
  vec3 r = viewAxes[3 * j], u = viewAxes[3 * j + 1], c = viewAxes[3 * j + 2];
  vec3 q = o - fanCentre;
  vec3 p0 = vec3(dot(q, r), dot(q, u), R - dot(q, c));
  vec3 dv = vec3(dot(d, r), dot(d, u), -dot(d, c));
  vec3 lo = vec3(-R, -R, 0.0), hi = vec3(R, R, 2.0 * R);
  float t0 = 0.0, t1 = 1e30;
  for (int a = 0; a < 3; ++a) {
    if (abs(dv[a]) < 1e-12) {
      if (p0[a] < lo[a] || p0[a] > hi[a]) return 0;
      continue;
    }
    float ta = (lo[a] - p0[a]) / dv[a], tb = (hi[a] - p0[a]) / dv[a];
    t0 = max(t0, min(ta, tb));
    t1 = min(t1, max(ta, tb));
  }
  if (!(t0 < t1)) return 0;
  int layer = viewLayer[j];
  float px = float(fanSize) / (2.0 * R);
  float across = length(dv.xy) * (t1 - t0) * px;
  int steps = max(1, int(ceil(2.0 * across)));
  float prev = t0;
  for (int i = 0; i <= steps; ++i) {
    float t = t0 + (t1 - t0) * float(i) / float(steps);
    ivec2 ti;
    if (p0.z + t * dv.z < surfaceAt(layer, p0, dv, t, px, ti)) {
      prev = t;
      continue;
    }
    float a = prev, b = t;
    for (int it = 0; i > 0 && it < 10; ++it) {
      float m = 0.5 * (a + b);
      ivec2 tm;
      if (p0.z + m * dv.z < surfaceAt(layer, p0, dv, m, px, tm)) a = m;
      else b = m;
    }
    float behind = p0.z + b * dv.z - surfaceAt(layer, p0, dv, b, px, texel);
    tHit = b;
    return behind > CURTAIN / px ? 2 : 1;
  }
  return 0;
}

// cosToView: the surface's normal against the shadow view's direction (a slope-scaled bias, as
// ibr::drawObject's: a face the lamp grazes does not shadow itself).
float selfShadow(int l, vec3 p, float cosToView) {
  float R = fanRadius;
  int S = fanSize;
  vec3 q = p - fanCentre;
  float px = float(S) / (2.0 * R);
  vec3 r = lampAxes[3 * l], u = lampAxes[3 * l + 1], c = lampAxes[3 * l + 2];
  float x = (dot(q, r) + R) * px, y = (R - dot(q, u)) * px;
  float depth = R - dot(q, c);
  float cv = clamp(cosToView, 0.12, 1.0);
  float bias = (2.0 + 2.2 * sqrt(1.0 - cv * cv) / cv) / px;
  int ix = int(floor(x)), iy = int(floor(y));
  float lit = 0.0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      int xx = ix + dx, yy = iy + dy;
      if (xx < 0 || yy < 0 || xx >= S || yy >= S) {
        lit += 1.0;
        continue;
      }
      uvec4 v = texelFetch(fanData, ivec3(xx, yy, lampLayer[l]), 0);
      lit += (v.b == 0u || depth <= float(v.g) / 65534.0 * 2.0 * R + bias) ? 1.0 : 0.0;
    }
  return lit / 9.0;
}

// Normal code k's normal in its view's frame (ibr::byteToNormal): the cells of the 17 x 17 grid
// inside the circle, row by row; row b (-8..8) holds 2 W + 1 of them, W the largest with
// W^2 + b^2 <= 72.
const int ROW_HALF[17] = int[17](2, 4, 6, 6, 7, 7, 8, 8, 8, 8, 8, 7, 7, 6, 6, 4, 2);
vec3 codeNormal(uint code) {
  int k = int(code);
  for (int j = 0; j < 17; ++j) {
    int w = ROW_HALF[j], n = 2 * w + 1;
    if (k < n) {
      float x = 2.0 * float(k - w) / 17.0, y = 2.0 * float(j - 8) / 17.0;
      return vec3(x, y, sqrt(max(0.0, 1.0 - x * x - y * y)));
    }
    k -= n;
  }
  return vec3(0.0, 0.0, 1.0);
}

vec3 entry(int j, int row, uint code) { return texelFetch(tables, ivec2(int(code), j * rowsPerView + row), 0).rgb; }

void main() {
  vec3 r = normalize(vWorld - eye);
  vec3 dObj = worldToObject * r;  // t stays the world distance
  // The first view that sees what the ray meets: a ray in front of a view's depth all the way
  // misses the object; one passing behind a surface there is asked of the next view; one that
  // every view sees passing behind a surface went behind a silhouette's edge: no object either.
  float tHit = 0.0;
  ivec2 texel = ivec2(0);
  int j = 0, m = 0;
  for (; j < viewCount; ++j) {
    m = marchView(j, eyeObject, dObj, tHit, texel);
    if (m != 2) break;
  }
  if (m != 1) discard;
  int layer = viewLayer[j];
  uvec4 hit = texelFetch(fanData, ivec3(texel, layer), 0);
  if (hit.b == 0u || hit.r == 255u) discard;
  vec3 pWorld = eye + tHit * r;
  vec3 pObj = eyeObject + tHit * dObj;
  float falloff[MAX_LAMPS];
  vec3 nc = codeNormal(hit.r);
  vec3 nObj = nc.x * viewAxes[3 * j] + nc.y * viewAxes[3 * j + 1] + nc.z * viewAxes[3 * j + 2];
  vec3 nWorld = normalize(transpose(worldToObject) * nObj);  // (the object frame's normal, turned back)
  float shadow = 1.0;
  for (int l = 0; l < lampCount; ++l) {
    vec3 dl = lampPosition[l] - pWorld;
    // (Lamps sharing a view share its shadow: one look-up for the lot.)
    if (l == 0 || lampLayer[l] != lampLayer[l - 1]) shadow = selfShadow(l, pObj, dot(nObj, lampAxes[3 * l + 2]));
    falloff[l] = shadow / max(dot(dl, dl), 1e-8);
#if DAYLIGHT
    if (lampPerPoint[l] != 0 && falloff[l] > 0.0) falloff[l] *= sunThrough(pWorld, nWorld);
#endif
  }
  int S = fanSize;
  float gx = clamp((float(texel.x) + 0.5) * float(CELLS) / float(S) - 0.5, 0.0, float(CELLS - 1));
  float gy = clamp((float(texel.y) + 0.5) * float(CELLS) / float(S) - 0.5, 0.0, float(CELLS - 1));
  int cx = min(int(gx), CELLS - 2), cy = min(int(gy), CELLS - 2);
  float fx = gx - float(cx), fy = gy - float(cy);
  int c00 = cy * CELLS + cx;
  vec4 w = vec4((1.0 - fx) * (1.0 - fy), fx * (1.0 - fy), (1.0 - fx) * fy, fx * fy);
  ivec4 cell = ivec4(c00, c00 + 1, c00 + CELLS, c00 + CELLS + 1);
  vec3 sum = vec3(0.0);
  float alphaSum = 0.0;
  int lo = -footprint / 2, hi = footprint - footprint / 2;
  for (int oy = lo; oy < hi; ++oy)
    for (int ox = lo; ox < hi; ++ox) {
      ivec2 t = texel + ivec2(ox, oy);
      if (t.x < 0 || t.y < 0 || t.x >= S || t.y >= S) continue;
      uvec4 v = texelFetch(fanData, ivec3(t, layer), 0);
      if (v.b == 0u || v.r == 255u) continue;
      vec3 e = indirectRows == 1 ? entry(j, 0, v.r)
                                 : w.x * entry(j, cell.x, v.r) + w.y * entry(j, cell.y, v.r) +
                                       w.z * entry(j, cell.z, v.r) + w.w * entry(j, cell.w, v.r);
      for (int l = 0; l < lampCount; ++l) {
        int base = indirectRows + l * CELLS * CELLS;
        vec3 lampEntry = w.x * entry(j, base + cell.x, v.r) + w.y * entry(j, base + cell.y, v.r) +
                         w.z * entry(j, base + cell.z, v.r) + w.w * entry(j, base + cell.w, v.r);
        e += lampEntry * falloff[l];
      }
      float a = float(v.b) / 255.0;
      sum += a * texelFetch(fanAlbedo, ivec3(t, layer), 0).rgb * INV_PI * e;
      alphaSum += a;
    }
  if (!(alphaSum > 0.0)) discard;
  vec4 clip = worldToClip * vec4(pWorld, 1.0);
  gl_FragDepth = 0.5 * clip.z / clip.w + 0.5;
  colour = displayColour(sum / alphaSum);
  colour.a = alphaSum / float(footprint * footprint);
}
