// (The renderer prepends "#version 330 core".) Positions through one camera, for depth and stencil
// only (daylight_map.frag): the view's depth pre-passes and the photo tiles an object's shadow may
// reach. (The shadow maps themselves: daylight_atlas.vert.)
layout(location = 0) in vec3 position;
uniform mat4 worldToClip;
invariant gl_Position;  // the depth pre-pass and the shading pass (daylight.vert) give the same depth
void main() {
  gl_Position = worldToClip * vec4(position, 1.0);
}
