// The display transform every fragment shader of the viewport ends with (the renderer puts this
// file after the variant's defines): linear out (read back as radiance), or exposed and
// sRGB-encoded as the photo was (8-bit = sRGB(exposure x radiance)), or false-colour luminance.
// OUTPUT: 0 linear, 1 exposed sRGB, 2 false colour
uniform float exposure;
uniform float falseMin;         // log10 luminance at the bottom and top of the colour scale
uniform float falseMax;

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

vec4 displayColour(vec3 L) {
#if OUTPUT == 0
  return vec4(L, 1.0);
#elif OUTPUT == 1
  return vec4(srgb(L * exposure), 1.0);
#else
  float Y = dot(L, vec3(0.2126, 0.7152, 0.0722));
  float t = (log(max(Y, 1e-8)) / log(10.0) - falseMin) / max(falseMax - falseMin, 1e-6);
  return vec4(heat(t), 1.0);
#endif
}
