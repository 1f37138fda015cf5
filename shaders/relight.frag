// (The renderer prepends "#version 330 core" and the variant's MODE, OUTPUT, GLOW and CHECKER:
// each program does only its own work, as branches on uniforms cost every fragment on llvmpipe.)
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
// OUTPUT: 0 linear, 1 exposed sRGB, 2 false colour
uniform float exposure;
uniform float falseMin;         // log10 luminance at the bottom and top of the colour scale
uniform float falseMax;
out vec4 colour;

const float INV_PI = 0.31830988618379067;

vec3 ratio(vec3 b, vec3 d) {
  return vec3(d.r > 1e-12 ? b.r / d.r : 1.0, d.g > 1e-12 ? b.g / d.g : 1.0, d.b > 1e-12 ? b.b / d.b : 1.0);
}

// The sRGB encoding: a fit of 1.055 v^(1/2.4) - 0.055 by v^(1/2), v^(1/4) and v^(1/8) (within
// 0.25 / 255 of it on [0.0031308, 1]): three square roots cost llvmpipe far less than pow.
vec3 srgb(vec3 v) {
  v = clamp(v, 0.0, 1.0);
  vec3 s1 = sqrt(v), s2 = sqrt(s1), s3 = sqrt(s2);
  vec3 curve = 0.662002687 * s1 + 0.684122060 * s2 - 0.323583601 * s3 - 0.0225411470 * v;
  return mix(curve, 12.92 * v, lessThanEqual(v, vec3(0.0031308)));
}

vec3 heat(float t) {  // blue -> cyan -> green -> yellow -> red
  t = clamp(t, 0.0, 1.0);
  vec3 a = vec3(0.05, 0.1, 0.6), b = vec3(0.1, 0.7, 0.9), c = vec3(0.15, 0.8, 0.2), d = vec3(0.95, 0.9, 0.1),
       e = vec3(0.9, 0.1, 0.1);
  if (t < 0.25) return mix(a, b, t * 4.0);
  if (t < 0.5) return mix(b, c, t * 4.0 - 1.0);
  if (t < 0.75) return mix(c, d, t * 4.0 - 2.0);
  return mix(d, e, t * 4.0 - 3.0);
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
  vec3 L = radiance();
#if OUTPUT == 0
  colour = vec4(L, 1.0);
#elif OUTPUT == 1
  vec3 e = L * exposure;
  colour = vec4(srgb(e), 1.0);
#else
  float Y = dot(L, vec3(0.2126, 0.7152, 0.0722));
  float t = (log(max(Y, 1e-8)) / log(10.0) - falseMin) / max(falseMax - falseMin, 1e-6);
  colour = vec4(heat(t), 1.0);
#endif
}
