// The daylight view's room, drawn at the photo's own pixels (gl_daylight.cpp), spread over the
// view with the display transform. (The renderer prepends "#version 330 core", OUTPUT and
// display.glsl.)
uniform sampler2D image;   // linear radiance, rows going up
uniform vec2 viewOrigin;
uniform vec2 viewSize;
out vec4 colour;
void main() {
  colour = displayColour(texture(image, (gl_FragCoord.xy - viewOrigin) / viewSize).rgb);
}
