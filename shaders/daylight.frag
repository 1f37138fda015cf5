// The daylight view (gl_daylight.cpp; Grosch, Eble, Mueller 2007 §7): a room pixel is the room
// as the library relit it under the sky, minus its radiance per unit irradiance (the library's
// gain: photo / the photo's irradiance) times the light the objects newly block; an object pixel
// is albedo / pi x (its indirect light, per vertex from the library's irradiance volume, plus its
// direct light). Direct light and blocking both come from the same samples: the window samples
// (each radiance x cos x cos x area / r^2, the radiance of the sky region its direction looks
// into) and the sun's four directions (each a quarter of the sun's irradiance x cos), each with
// its shadow map: red the nearest room surface, green the nearest box or mesh face, blue the
// nearest image-based object's silhouette along the line. A sample lights a point when the room
// lets it through (the point is the nearest room surface, within a bias) and no object lies
// before it; a box's face takes no shadow of an image-based object (as on the CPU path), the
// room does. (The renderer prepends "#version 330 core",
// OBJECT, OUTPUT, display.glsl and daylight_maps.glsl.)
in vec3 vWorld;
flat in vec3 vNormal;
in vec3 vFrontE;
in vec3 vBackE;
flat in vec3 vAlbedo;
uniform sampler2D skyRadiance; // equirectangular, +Z up (the library's InteractiveSky::radiance)
uniform vec3 sunQuarter;       // a quarter of the sun's irradiance
uniform vec3 eye;
#if OBJECT == 0
uniform sampler2D room;        // the photo's pixels relit under the sky (top row first)
uniform sampler2D gain;        // photo / the photo's irradiance
uniform sampler2D sunLight;    // the sun's direct irradiance in `room`: the most a shadow takes of it
uniform usampler2D reach;      // per 8 x 8 tile of the photo: the samples whose shadow may fall there
uniform int reachWords;
uniform vec2 viewOrigin;       // the drawn rectangle in framebuffer pixels
uniform vec2 viewSize;
uniform vec2 photoSize;
#endif
out vec4 colour;

const float PI = 3.14159265358979;

vec3 skyAlong(vec3 d) {
  float u = atan(d.y, d.x) / (2.0 * PI) + 0.5;
  float v = acos(clamp(d.z, -1.0, 1.0)) / PI;
  return texture(skyRadiance, vec2(u, v)).rgb;
}

// Could map m's object channel hold anything at p: is p inside the map's cone (perspective: from
// the sample around the objects' sphere) or cylinder (orthographic: the sphere along the sun)?
// (One texel fetch, before the four of the map's matrix.)
bool inMap(int m, vec3 p, vec3 origin) {
  vec4 k = mapData[m * 7 + 6];
  if (m < windowSamples) {
    vec3 d = p - origin;
    return dot(d, k.xyz) >= k.w * length(d);
  }
  vec3 d = p - origin, along = mapData[m * 7 + 5].xyz;
  vec3 across = d - dot(d, along) * along;
  return dot(across, across) <= k.w * k.w;
}

#if OBJECT == 1
// The direct light on an object's point: every sample the room lets through and no object blocks.
// (Outside its map, a sample is taken as let through: the maps cover the objects' sphere.)
vec3 direct(vec3 p, vec3 n) {
  vec3 e = vec3(0.0);
  for (int m = 0; m < windowSamples; ++m) {
    vec4 o = mapData[m * 7 + 4], w = mapData[m * 7 + 5];
    vec3 d = o.xyz - p;
    float r2 = dot(d, d), r = sqrt(r2);
    vec3 dir = d / r;
    float cx = dot(n, dir), cw = -dot(w.xyz, dir);
    if (cx <= 0.0 || cw <= 0.0) continue;
    if (sampleState(m, p, cx, r, false) != 1) continue;
    e += skyAlong(dir) * (cx * cw * w.w / r2);
  }
  for (int j = 0; j < sunMaps; ++j) {
    int m = windowSamples + j;
    vec4 o = mapData[m * 7 + 4], w = mapData[m * 7 + 5];
    float c = -dot(n, w.xyz);
    if (c <= 0.0) continue;
    if (sampleState(m, p, c, dot(p - o.xyz, w.xyz), false) != 1) continue;
    e += sunQuarter * c;
  }
  return e;
}
#else
// The light the objects take away from a room point: the samples whose shadow may reach its tile.
// ex, ey: a photo pixel's step across the surface at p.
vec3 blocked(vec3 p, vec3 n, ivec2 tile, vec3 ex, vec3 ey, vec3 sunHere) {
  vec3 e = vec3(0.0), es = vec3(0.0);
  for (int k = 0; k < reachWords; ++k) {
    uint bits = texelFetch(reach, ivec2(tile.x * reachWords + k, tile.y), 0).r;
    while (bits != 0u) {
      uint low = bits & (~bits + 1u);
      bits ^= low;
      int m = k * 32 + int(round(log2(float(low))));
      if (m < windowSamples) {
        vec4 o = mapData[m * 7 + 4];
        if (!inMap(m, p, o.xyz)) continue;
        vec4 w = mapData[m * 7 + 5];
        vec3 d = o.xyz - p;
        float r2 = dot(d, d), r = sqrt(r2);
        vec3 dir = d / r;
        float cx = dot(n, dir), cw = -dot(w.xyz, dir);
        if (cx <= 0.0 || cw <= 0.0) continue;
        if (sampleState(m, p, cx, r, true) == 2) e += skyAlong(dir) * (cx * cw * w.w / r2);
      } else if (sunMaps > 0) {
        // The sun over the pixel's footprint, as the library's room light takes it (4 x 4 points
        // over 1.5 photo pixels, each towards one of the disc's directions): where the room's
        // own shadow edge crosses the pixel, only the share the room lets through is taken away.
        for (int j = 0; j < sunMaps; ++j) {
          int s = windowSamples + j;
          vec4 o = mapData[s * 7 + 4], w = mapData[s * 7 + 5];
          float c = -dot(n, w.xyz);
          if (c <= 0.0) continue;
          // (The cylinder test widened by the footprint's reach.)
          float radius = mapData[s * 7 + 6].w;
          vec3 d = p - o.xyz, across = d - dot(d, w.xyz) * w.xyz;
          float reach = radius + 1.1 * (length(ex) + length(ey));
          if (dot(across, across) > reach * reach) continue;
          for (int f = 0; f < 16 / sunMaps; ++f) {
            int k16 = f * sunMaps + j;
            vec2 at = ((vec2(k16 % 4, k16 / 4) + 0.5) / 4.0 - 0.5) * 1.5;
            vec3 q = p + at.x * ex + at.y * ey;
            if (sampleState(s, q, c, dot(q - o.xyz, w.xyz), true) == 2) es += sunQuarter * (c * float(sunMaps) / 16.0);
          }
        }
      }
    }
  }
  return e + min(es, sunHere);
}
#endif

void main() {
#if OBJECT == 1
  vec3 n = vNormal;
  bool back = dot(n, vWorld - eye) > 0.0;
  if (back) n = -n;
  vec3 e = (back ? vBackE : vFrontE) + direct(vWorld + 1e-4 * n, n);
  colour = displayColour(vAlbedo / PI * e);
#else
  vec2 f = (gl_FragCoord.xy - viewOrigin) / viewSize;
  vec2 uv = vec2(f.x, 1.0 - f.y);  // the photo's rows are top first
  vec3 base = texture(room, uv).rgb;
  ivec2 px = ivec2(min(uv * photoSize, photoSize - 1.0));
  vec3 n = vNormal;
  if (dot(n, vWorld - eye) > 0.0) n = -n;
  // (Derivatives here, in uniform control flow: a photo pixel spans viewSize / photoSize of the view's.)
  vec3 ex = dFdx(vWorld) * (viewSize.x / photoSize.x), ey = dFdy(vWorld) * (viewSize.y / photoSize.y);
  vec3 b = blocked(vWorld + 1e-4 * n, n, px / 8, ex, ey, texture(sunLight, uv).rgb);
  colour = displayColour(max(base - texture(gain, uv).rgb * b, vec3(0.0)));
#endif
}
