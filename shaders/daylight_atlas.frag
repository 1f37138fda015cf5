// (The renderer prepends "#version 330 core", MAX_MAPS and IMAGE.) Per texel of a shadow map the
// distance of the nearest room surface (red), of the nearest box or mesh face (green) and of the
// nearest image-based object's silhouette (blue) along the map's line: the renderer draws the
// room with channel 0, the boxes and meshes with channel 1, the image-based objects with channel
// 2, keeping the minimum of each (GL_MIN blending; the atlas is cleared to a far distance).
// Distance from the sample point (perspective) or along the sun's direction from the map's plane
// (orthographic).
in vec3 vWorld;
flat in int vMap;
layout(std140) uniform MapBlock {
  vec4 mapData[MAX_MAPS * 7];
};
uniform int ortho;
uniform int channel;
#if IMAGE
// The fan view's texels (code, depth 0..65534 = 0..2 R, coverage), its layer; the view's direction
// towards its camera (world) and the square's half side: a covered texel stands at the surface
// point the view saw (ibr::ObjectShadows takes the silhouette's point between room and lamp so).
in vec2 vSquare;
uniform usampler2DArray fanData;
uniform int fanLayer;
uniform int fanSize;
uniform vec3 fanToCamera;
uniform float fanHalf;
#endif
out vec4 colour;
const float FAR = 1e30;
void main() {
  vec3 p = vWorld;
#if IMAGE
  int S = fanSize;
  ivec2 t = clamp(ivec2(floor(vec2(0.5 * vSquare.x + 0.5, 0.5 - 0.5 * vSquare.y) * float(S))), ivec2(0), ivec2(S - 1));
  uvec4 v = texelFetch(fanData, ivec3(t, fanLayer), 0);
  if (v.b < 128u) discard;  // (half covered or less: no silhouette)
  p += fanHalf * (1.0 - 2.0 * float(v.g) / 65534.0) * fanToCamera;
#endif
  vec3 origin = mapData[vMap * 7 + 4].xyz;
  float d = ortho == 1 ? dot(p - origin, mapData[vMap * 7 + 5].xyz) : length(p - origin);
  colour = vec4(FAR);
  colour[channel] = d;
}
