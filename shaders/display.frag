#version 330 core
// The display transform: the linear image plus, in the photo's own view, each lamp's glow
// layer scaled with its lamp; then either linear out (read back as radiance), or exposed and
// sRGB-encoded as the photo was (8-bit = sRGB(exposure x radiance)), or false-colour luminance.
uniform sampler2D linearImage;
uniform sampler2D glow;       // photo-sized linear glow
uniform sampler2D glowLamp;   // per pixel the lamp index, -1 for none
uniform int glowOn;
uniform vec3 lampScale[32];
uniform vec2 viewOrigin;      // bottom-left of the photo's rectangle in window pixels
uniform vec2 viewSize;
uniform int outputMode;          // 0 linear, 1 exposed sRGB, 2 false colour
uniform float exposure;
uniform float falseMin;       // log10 luminance at the bottom and top of the colour scale
uniform float falseMax;
out vec4 colour;

float srgb(float v) {
  v = clamp(v, 0.0, 1.0);
  return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
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

void main() {
  vec2 p = gl_FragCoord.xy - viewOrigin;
  if (p.x < 0.0 || p.y < 0.0 || p.x >= viewSize.x || p.y >= viewSize.y) {
    colour = outputMode == 0 ? vec4(0.0, 0.0, 0.0, 1.0) : vec4(0.16, 0.16, 0.17, 1.0);
    return;
  }
  ivec2 ip = ivec2(p);
  vec4 S = texelFetch(linearImage, ip, 0);
  vec3 L = S.rgb;
  if (S.a == 0.0) {
    // Nothing drawn here: a hairline crack where leaves of different sizes meet (a T-junction)
    // takes the mean of its drawn neighbours; open background keeps its colour.
    vec3 sum = vec3(0.0);
    float n = 0.0;
    ivec2 size = textureSize(linearImage, 0);
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        ivec2 q = ip + ivec2(dx, dy);
        if (q.x < 0 || q.y < 0 || q.x >= size.x || q.y >= size.y) continue;
        vec4 N = texelFetch(linearImage, q, 0);
        if (N.a > 0.0) {
          sum += N.rgb;
          n += 1.0;
        }
      }
    if (n >= 5.0) L = sum / n;
  }
  if (glowOn != 0) {
    vec2 q = vec2(p.x, viewSize.y - p.y) / viewSize;  // the glow images are stored top row first
    int lamp = int(round(texture(glowLamp, q).r));
    if (lamp >= 0) L += texture(glow, q).rgb * lampScale[lamp];
  }
  if (outputMode == 0) {
    colour = vec4(L, 1.0);
  } else if (outputMode == 1) {
    vec3 e = L * exposure;
    colour = vec4(srgb(e.r), srgb(e.g), srgb(e.b), 1.0);
  } else {
    float Y = dot(L, vec3(0.2126, 0.7152, 0.0722));
    float t = (log(max(Y, 1e-8)) / log(10.0) - falseMin) / max(falseMax - falseMin, 1e-6);
    colour = vec4(heat(t), 1.0);
  }
}
