// (The renderer prepends "#version 330 core", the variant's MODE, OUTPUT, GLOW, CHECKER and
// SHADOWS, and display.glsl: each program does only its own work, as branches on uniforms cost
// every fragment on llvmpipe.)
// Loscos 2000 §2.4: displayed radiance = texture x B / D (B and D from the vertices, see
// relight.vert), plus, in the photo's own view, each lamp's glow layer scaled with its lamp
// (the CPU renderer does the same). Then the display transform in the same pass: linear out
// (read back as radiance), or exposed and sRGB-encoded as the photo was (8-bit =
// sRGB(exposure x radiance)), or false-colour luminance.
in vec2 vTC;                    // the surface texture's coordinates of this point (relight.vert; plane coordinates on a surface with no texture)
uniform vec2 texOrigin;         // uv of the texture's texel (0, 0) corner
uniform vec2 texExtent;         // the texture's width and height in metres
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
uniform int kind;               // 0 textured, 1 window, 2 virtual (radiance B / pi)
// MODE: 0 relit, 1 ratio-only, 2 photo, 3 unoccluded, 4 B, 5 D, 6 leaves, 7 references
uniform float front;            // 1, or 0 where the camera sees this surface's back (drawn black)
// CHECKER 1: texels no photo saw drawn as a checker (away from the photo's own view)
uniform sampler2D glow;         // GLOW 1: photo-sized linear glow, alpha = its lamp's index (-1 none)
uniform vec4 glowBox;           // the glow's pixels lie in [x0, x1) x [y0, y1), texture coordinates
uniform vec3 lampScale[32];
uniform vec2 viewOrigin;        // bottom-left of the drawn rectangle in framebuffer pixels
uniform vec2 viewSize;
out vec4 colour;

const float INV_PI = 0.31830988618379067;

#if SHADOWS
// Shadows of image-based objects (Dinh, Metoyer, Turk §4, onto any real surface): the share of
// the light kept, mapped over this surface's plane by the library (ibr::shadowMaps, the light
// each silhouette takes off over the irradiance shown), 1 where no shadow reaches. Only the
// surfaces that have a map are drawn with this variant.
uniform sampler2D shadowMap;
uniform vec4 shadowFrame;       // its origin (plane coordinates), 1 / its width and height in metres
#endif

vec3 ratio(vec3 b, vec3 d) {  // B / D, and 1 where D is 0 (at most 1e-12)
  return mix(vec3(1.0), b / max(d, vec3(1e-12)), greaterThan(d, vec3(1e-12)));
}

vec3 radiance() {
  // The point's plane coordinates (metres), from the texture coordinates (one varying fewer per
  // triangle and pixel: the display mesh's triangles are small).
  vec2 vUV = texOrigin + vTC * texExtent;
  vec3 result;
#if MODE == 4
  result = vB * INV_PI;
#elif MODE == 5
  result = (kind == 2 ? vB : vDen) * INV_PI;
#else
  // One texture fetch: the photo's for photo and ratio-only, T_final otherwise.
  vec2 tc = vTC;
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
  result *= texture(shadowMap, (vUV - shadowFrame.xy) * shadowFrame.zw).rgb;
#endif
#if CHECKER
  if (kind != 2 && t.a < 1.0) {
    // Seen by no photo (filled smoothly by the preprocess): a 10 cm checker says so.
    float cell = mod(floor(vUV.x * 10.0) + floor(vUV.y * 10.0), 2.0);
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
  return mix(vec3(0.0), result, bvec3(front > 0.5));  // back faces are black (a select: exact 0)
}

void main() {
  colour = displayColour(radiance());
}
