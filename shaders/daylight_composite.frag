// The daylight view's room, drawn at the photo's own pixels (gl_daylight.cpp), spread over the
// view with the display transform. (The renderer prepends "#version 330 core", OUTPUT and
// display.glsl.)
uniform sampler2D image;   // linear radiance, rows going up (topFirst 0) or top row first (1)
uniform int topFirst;
uniform vec2 viewOrigin;
uniform vec2 viewSize;
out vec4 colour;
void main() {
  vec2 f = (gl_FragCoord.xy - viewOrigin) / viewSize;
  colour = displayColour(texture(image, topFirst == 1 ? vec2(f.x, 1.0 - f.y) : f).rgb);
}
