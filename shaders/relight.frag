#version 330 core
// Loscos 2000 Sec. 2.4: displayed radiance = texture x B / D, with B and D interpolated bilinearly
// from the leaf's corner values (as RelightSession::render does on the CPU). Output: linear
// radiance, no exposure (the display pass applies it).
in vec2 vUV;
in vec3 vWorld;
flat in int vLeaf;
uniform samplerBuffer corners;  // per leaf 12 texels: B, D, B_orig at u0v0, u1v0, u1v1, u0v1
uniform samplerBuffer rects;    // per leaf u0, v0, u1, v1
uniform sampler2D original;     // the photo texture (linear radiance)
uniform sampler2D unoccluded;   // T_final: real shadows removed
uniform vec2 texOrigin;         // uv of texel (0, 0)'s corner
uniform float texelSize;        // metres per texel
uniform vec2 texSize;           // texels
uniform int kind;               // 0 textured, 1 window, 2 virtual (radiance B / pi)
uniform int mode;               // 0 relit, 1 ratio-only, 2 photo, 3 unoccluded, 4 B, 5 D, 6 leaves, 7 references
uniform vec3 normal;
uniform vec3 eye;
uniform int checkerUnseen;
out vec4 colour;

const float INV_PI = 0.31830988618379067;

vec3 interpolate(int block, vec2 st) {
  int base = vLeaf * 12 + block * 4;
  vec3 c0 = texelFetch(corners, base).rgb;
  vec3 c1 = texelFetch(corners, base + 1).rgb;
  vec3 c2 = texelFetch(corners, base + 2).rgb;
  vec3 c3 = texelFetch(corners, base + 3).rgb;
  return (1.0 - st.x) * (1.0 - st.y) * c0 + st.x * (1.0 - st.y) * c1 + st.x * st.y * c2 + (1.0 - st.x) * st.y * c3;
}

vec3 ratio(vec3 b, vec3 d) {
  return vec3(d.r > 1e-12 ? b.r / d.r : 1.0, d.g > 1e-12 ? b.g / d.g : 1.0, d.b > 1e-12 ? b.b / d.b : 1.0);
}

void main() {
  if (dot(vWorld - eye, normal) > 0.0) {  // back faces are black
    colour = vec4(0.0, 0.0, 0.0, 1.0);
    return;
  }
  vec4 r = texelFetch(rects, vLeaf);
  vec2 st = clamp((vUV - r.xy) / max(r.zw - r.xy, vec2(1e-12)), 0.0, 1.0);
  vec3 B = interpolate(0, st);
  vec2 tc = (vUV - texOrigin) / texelSize / texSize;
  vec3 result;
  float seen = 1.0;  // the textures' alpha: 0 where no photo saw the texel
  if (mode == 4) {
    result = B * INV_PI;
  } else if (mode == 5) {
    result = (kind == 2 ? B : interpolate(1, st)) * INV_PI;
  } else if (kind == 2) {
    result = (mode == 2 || mode == 3) ? vec3(0.0) : B * INV_PI;
  } else {
    // One texture fetch: the photo's for photo and ratio-only, T_final otherwise.
    vec4 t = (mode == 1 || mode == 2) ? texture(original, tc) : texture(unoccluded, tc);
    seen = t.a;
    if (mode == 2 || mode == 3 || kind == 1) result = t.rgb;
    else if (mode == 1) result = t.rgb * ratio(B, interpolate(2, st));
    else result = t.rgb * ratio(B, interpolate(1, st));
  }
  if (checkerUnseen != 0 && seen < 1.0) {
    // Seen by no photo (filled smoothly by the preprocess): a 10 cm checker says so.
    float cell = mod(floor(vUV.x / 0.1) + floor(vUV.y / 0.1), 2.0);
    vec3 mark = cell > 0.5 ? result * 0.35 + vec3(0.004, 0.004, 0.012) : result;
    result = mix(result, mark, 1.0 - seen);
  }
  if (mode == 6) {  // leaf outlines, about a pixel wide, over the relit image
    vec2 w = fwidth(vUV) * 1.5;
    bool border = vUV.x - r.x < w.x || r.z - vUV.x < w.x || vUV.y - r.y < w.y || r.w - vUV.y < w.y;
    if (border) result = mix(result, vec3(0.9, 0.15, 0.1) * max(1.0, dot(result, vec3(0.333))), 0.8);
  }
  if (mode == 7) {  // §4.3: occluded elements blue, the frontier they take references from yellow
    float category = texelFetch(corners, vLeaf * 12 + 4).a;
    vec3 tint = category > 2.5 ? vec3(1.0, 0.85, 0.1) : (category > 1.5 ? vec3(0.15, 0.35, 1.0) : vec3(0.0));
    if (category > 1.5) result = mix(result, tint * max(0.25, dot(result, vec3(0.333))), 0.6);
  }
  colour = vec4(result, 1.0);
}
