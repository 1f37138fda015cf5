// (The renderer prepends "#version 330 core", the variant's MODE, OUTPUT, GLOW, CHECKER and
// SHADOWS, and display.glsl: each program does only its own work, as branches on uniforms cost
// every fragment on llvmpipe.)
// Loscos 2000 §2.4: displayed radiance = texture x B / D (B and D from the vertices, see
// relight.vert), plus, in the photo's own view, each lamp's glow layer scaled with its lamp
// (the CPU renderer does the same). Then the display transform in the same pass: linear out
// (read back as radiance), or exposed and sRGB-encoded as the photo was (8-bit =
// sRGB(exposure x radiance)), or false-colour luminance.
in vec2 vUV;
in vec3 vWorld;
in vec3 vB;
in vec3 vDen;
#if MODE == 6
flat in vec4 vRect;
#endif
#if MODE == 7
flat in float vCategory;
#endif
uniform sampler2D original;     // the photo texture (linear radiance; alpha 0 where no photo saw it)
uniform sampler2D unoccluded;   // T_final: real shadows removed
uniform vec2 texOrigin;         // uv of texel (0, 0)'s corner
uniform float texelSize;        // metres per texel
uniform vec2 texSize;           // texels
uniform int kind;               // 0 textured, 1 window, 2 virtual (radiance B / pi)
// MODE: 0 relit, 1 ratio-only, 2 photo, 3 unoccluded, 4 B, 5 D, 6 leaves, 7 references
uniform vec3 normal;
uniform vec3 eye;
// CHECKER 1: texels no photo saw drawn as a checker (away from the photo's own view)
uniform sampler2D glow;         // GLOW 1: photo-sized linear glow, alpha = its lamp's index (-1 none)
uniform vec4 glowBox;           // the glow's pixels lie in [x0, x1) x [y0, y1), texture coordinates
uniform vec3 lampScale[32];
uniform vec2 viewOrigin;        // bottom-left of the drawn rectangle in framebuffer pixels
uniform vec2 viewSize;
out vec4 colour;

const float INV_PI = 0.31830988618379067;

#if SHADOWS
// Shadows of image-based objects (Dinh, Metoyer, Turk §4, onto any real surface; as the CPU
// renderer's ibr::drawShadows): per caster (one object seen from one lamp's direction, its fan
// image nearest that direction as a silhouette) the lines from this point to points spread over
// the lamp meet the plane of that image through the object's centre; where the silhouette covers
// the crossing, and its surface lies between the point and the lamp, that share of the lamp is
// blocked. The lamp's direct irradiance here (its points as small patches) times the blocked
// share, over the irradiance shown (B), is taken off: a dimmed lamp's shadow is lighter, a lamp
// switched off casts none. Only where the room itself lets the lamp through (vVis, per vertex).
in vec4 vVis0;
in vec4 vVis1;
uniform usampler2DArray silhouettes;  // per caster layer: code, depth (0..65534 = 0..2 R), coverage
uniform int casterCount;
uniform vec4 casterSphere[16];   // the object's centre (world), radius x scale
uniform vec4 casterRight[16];    // its image's x axis (world), the fan's radius
uniform vec4 casterUp[16];       // its image's y axis, the object's scale
uniform vec4 casterAxis[16];     // its image's direction towards the lamp, pixels across
uniform vec4 casterLight[16];    // the lamp's exitance (W/m^2, RGB), its area
uniform vec4 casterLamp[16];     // the lamp's normal, weight (0 one face; < 0 both faces, |w| the photometric weight)
uniform vec4 casterCone[16];     // cone: axis, cos^2 of its half angle (0: no cone test)
uniform vec4 casterApex[16];     // cone: apex, near side
uniform ivec4 casterIndex[16];   // layer, lamp (in the visibility list), the lamp's surface, first sample
uniform int casterSamples[16];   // samples on the lamp
uniform vec4 lampSamples[256];   // point, weight (summing to 1 per caster)
uniform int surfaceId;           // this range's engine surface
uniform int receives;            // 1: a real surface that is no lamp

float lampVisible(int l) {
  if (l < 4) return vVis0[l];
  return l < 8 ? vVis1[l - 4] : 1.0;
}

vec3 objectShadowKeep(vec3 X, vec3 n, vec3 E) {
  vec3 taken = vec3(0.0);
  for (int c = 0; c < casterCount; ++c) {
    ivec4 I = casterIndex[c];
    if (I.z == surfaceId) continue;
    float vis = lampVisible(I.y);
    if (vis <= 0.0) continue;
    vec4 cone = casterCone[c];
    if (cone.w > 0.0) {
      vec3 v = X - casterApex[c].xyz;
      float d = dot(v, cone.xyz);
      if (d < casterApex[c].w || d * d < cone.w * dot(v, v)) continue;
    }
    vec3 cw = casterSphere[c].xyz;
    float rs = casterSphere[c].w;
    vec3 Rw = casterRight[c].xyz, Uw = casterUp[c].xyz, Nw = casterAxis[c].xyz;
    float fanR = casterRight[c].w, scale = casterUp[c].w;
    int S = int(casterAxis[c].w);
    vec3 lampN = casterLamp[c].xyz;
    float wgt = casterLamp[c].w;
    float blocked = 0.0, f = 0.0;
    for (int i = 0; i < casterSamples[c]; ++i) {
      vec4 smp = lampSamples[I.w + i];
      vec3 seg = smp.xyz - X;
      float len2 = dot(seg, seg);
      vec3 dir = seg * inversesqrt(len2);
      float cosL = -dot(lampN, dir);
      cosL = wgt < 0.0 ? abs(cosL) * -wgt : max(cosL, 0.0);
      f += smp.w * max(dot(n, dir), 0.0) * cosL / len2;
      float s = clamp(dot(cw - X, seg) / len2, 0.0, 1.0);
      vec3 closest = X + s * seg - cw;
      if (dot(closest, closest) > rs * rs) continue;
      float den = dot(seg, Nw);
      if (abs(den) < 1e-12) continue;
      float u = dot(cw - X, Nw) / den;
      if (u <= 0.0 || u >= 1.0) continue;
      vec3 q = X + u * seg - cw;
      int tx = int(floor((dot(q, Rw) / rs + 1.0) * 0.5 * float(S)));
      int ty = int(floor((1.0 - dot(q, Uw) / rs) * 0.5 * float(S)));
      if (tx < 0 || ty < 0 || tx >= S || ty >= S) continue;
      uvec4 t = texelFetch(silhouettes, ivec3(tx, ty, I.x), 0);
      if (t.b == 0u) continue;
      float a = ((float(tx) + 0.5) / float(S) * 2.0 - 1.0) * fanR, b = (1.0 - (float(ty) + 0.5) / float(S) * 2.0) * fanR;
      vec3 p = cw + scale * (a * Rw + b * Uw + (fanR - float(t.g) / 65534.0 * 2.0 * fanR) * Nw);
      if (dot(p - X, seg) <= 1e-3 * sqrt(len2)) continue;
      blocked += smp.w * float(t.b) / 255.0;
    }
    if (blocked <= 0.0) continue;
    taken += blocked * vis * f * casterLight[c].w * INV_PI * casterLight[c].xyz;
  }
  return vec3(E.r > 0.0 ? clamp(1.0 - taken.r / E.r, 0.0, 1.0) : 1.0, E.g > 0.0 ? clamp(1.0 - taken.g / E.g, 0.0, 1.0) : 1.0,
              E.b > 0.0 ? clamp(1.0 - taken.b / E.b, 0.0, 1.0) : 1.0);
}
#endif

vec3 ratio(vec3 b, vec3 d) {
  return vec3(d.r > 1e-12 ? b.r / d.r : 1.0, d.g > 1e-12 ? b.g / d.g : 1.0, d.b > 1e-12 ? b.b / d.b : 1.0);
}

vec3 radiance() {
  if (dot(vWorld - eye, normal) > 0.0) return vec3(0.0);  // back faces are black
  vec3 result;
#if MODE == 4
  result = vB * INV_PI;
#elif MODE == 5
  result = (kind == 2 ? vB : vDen) * INV_PI;
#else
  // One texture fetch: the photo's for photo and ratio-only, T_final otherwise.
  vec2 tc = (vUV - texOrigin) / texelSize / texSize;
#if MODE == 1 || MODE == 2
  vec4 t = texture(original, tc);
#else
  vec4 t = texture(unoccluded, tc);
#endif
#if MODE == 2 || MODE == 3
  result = kind == 2 ? vec3(0.0) : t.rgb;
#else
  result = kind == 2 ? vB * INV_PI : (kind == 1 ? t.rgb : t.rgb * ratio(vB, vDen));
#endif
#if SHADOWS && (MODE == 0 || MODE == 1)
  if (receives == 1) result *= objectShadowKeep(vWorld, normal, vB);
#endif
#if CHECKER
  if (kind != 2 && t.a < 1.0) {
    // Seen by no photo (filled smoothly by the preprocess): a 10 cm checker says so.
    float cell = mod(floor(vUV.x / 0.1) + floor(vUV.y / 0.1), 2.0);
    vec3 mark = cell > 0.5 ? result * 0.35 + vec3(0.004, 0.004, 0.012) : result;
    result = mix(result, mark, 1.0 - t.a);
  }
#endif
#endif
#if MODE == 6
  {  // leaf outlines, about a pixel wide, over the relit image
    vec2 w = fwidth(vUV) * 1.5;
    vec4 r = vRect;
    bool border = vUV.x - r.x < w.x || r.z - vUV.x < w.x || vUV.y - r.y < w.y || r.w - vUV.y < w.y;
    if (border) result = mix(result, vec3(0.9, 0.15, 0.1) * max(1.0, dot(result, vec3(0.333))), 0.8);
  }
#endif
#if MODE == 7
  if (vCategory > 1.5) {  // §4.3: occluded elements blue, their frontier yellow
    vec3 tint = vCategory > 2.5 ? vec3(1.0, 0.85, 0.1) : vec3(0.15, 0.35, 1.0);
    result = mix(result, tint * max(0.25, dot(result, vec3(0.333))), 0.6);
  }
#endif
#if GLOW
  vec2 p = gl_FragCoord.xy - viewOrigin;
  vec2 q = vec2(p.x, viewSize.y - p.y) / viewSize;  // the glow image is stored top row first
  if (q.x >= glowBox.x && q.y >= glowBox.y && q.x < glowBox.z && q.y < glowBox.w) {
    vec4 g = texture(glow, q);
    int lamp = int(round(g.a));
    if (lamp >= 0) result += g.rgb * lampScale[lamp];
  }
#endif
  return result;
}

void main() {
  colour = displayColour(radiance());
}
