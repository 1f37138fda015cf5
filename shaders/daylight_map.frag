// (The renderer prepends "#version 330 core".) Per texel the distance of the nearest room surface
// (red) and of the nearest object surface (green) along the map's line: the renderer draws the
// room with channel 0, then the objects with channel 1, keeping the minimum of each (GL_MIN
// blending; the map is cleared to a far distance). Distance from the sample point (perspective) or
// along the sun's direction from the map's plane (orthographic).
in vec3 vWorld;
uniform vec3 origin;
uniform vec3 along;   // orthographic: the direction of the light's travel
uniform int ortho;
uniform int channel;
out vec4 colour;
const float FAR = 1e30;
void main() {
  float d = ortho == 1 ? dot(vWorld - origin, along) : length(vWorld - origin);
  colour = channel == 0 ? vec4(d, FAR, 0.0, 1.0) : vec4(FAR, d, 0.0, 1.0);
}
