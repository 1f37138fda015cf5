// (The renderer prepends "#version 330 core".) A daylight shadow map (gl_daylight.cpp): the room's
// or the objects' polygons seen from a window sample (perspective) or from the sun (orthographic).
layout(location = 0) in vec3 position;
uniform mat4 worldToClip;
invariant gl_Position;  // the view's depth pre-pass (daylight_map.vert) and its shading pass give the same depth
out vec3 vWorld;
void main() {
  vWorld = position;
  gl_Position = worldToClip * vec4(position, 1.0);
}
