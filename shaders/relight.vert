#version 330 core
// The session's display mesh: leaf elements clipped to their polygons (world position, the
// polygon's plane coordinates, and the leaf whose corner values shade it).
layout(location = 0) in vec3 position;
layout(location = 1) in vec2 uv;
layout(location = 2) in int leaf;
uniform mat4 worldToClip;
out vec2 vUV;
out vec3 vWorld;
flat out int vLeaf;
void main() {
  vUV = uv;
  vWorld = position;
  vLeaf = leaf;
  gl_Position = worldToClip * vec4(position, 1.0);
}
