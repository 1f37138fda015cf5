// (The renderer prepends "#version 330 core" and MAX_MAPS.) Per texel of a shadow map the distance
// of the nearest room surface (red) and of the nearest object surface (green) along the map's
// line: the renderer draws the room with channel 0, then the objects with channel 1, keeping the
// minimum of each (GL_MIN blending; the atlas is cleared to a far distance). Distance from the
// sample point (perspective) or along the sun's direction from the map's plane (orthographic).
in vec3 vWorld;
flat in int vMap;
layout(std140) uniform MapBlock {
  vec4 mapData[MAX_MAPS * 7];
};
uniform int ortho;
uniform int channel;
out vec4 colour;
const float FAR = 1e30;
void main() {
  vec3 origin = mapData[vMap * 7 + 4].xyz;
  float d = ortho == 1 ? dot(vWorld - origin, mapData[vMap * 7 + 5].xyz) : length(vWorld - origin);
  colour = channel == 0 ? vec4(d, FAR, 0.0, 1.0) : vec4(FAR, d, 0.0, 1.0);
}
