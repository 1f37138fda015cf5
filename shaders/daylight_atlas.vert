// (The renderer prepends "#version 330 core" and MAX_MAPS.) Every shadow map of one atlas in one
// instanced draw (gl_daylight.cpp): instance i is map firstMap + i, drawn into its tile of the
// atlas (columns x rows tiles). The map's own square is kept by four clip distances, so that a
// polygon crossing its edge does not spill into the next tile. (One draw for all maps: llvmpipe
// pays for every change of target, which cost more than drawing the maps' texels.)
layout(location = 0) in vec3 position;
layout(std140) uniform MapBlock {
  vec4 mapData[MAX_MAPS * 7];
};
uniform int firstMap;
uniform ivec2 grid;  // the atlas's columns and rows
out vec3 vWorld;
flat out int vMap;
out float gl_ClipDistance[4];
void main() {
  int m = firstMap + gl_InstanceID;
  mat4 clip = mat4(mapData[m * 7 + 0], mapData[m * 7 + 1], mapData[m * 7 + 2], mapData[m * 7 + 3]);
  vec4 c = clip * vec4(position, 1.0);
  gl_ClipDistance[0] = c.w - c.x;
  gl_ClipDistance[1] = c.w + c.x;
  gl_ClipDistance[2] = c.w - c.y;
  gl_ClipDistance[3] = c.w + c.y;
  // The map's [-w, w] square onto its tile: linear in the clip coordinates, so perspective holds.
  vec2 tile = vec2(gl_InstanceID % grid.x, gl_InstanceID / grid.x);
  c.xy = ((c.xy + c.w) * 0.5 + tile * c.w) / vec2(grid) * 2.0 - c.w;
  gl_Position = c;
  vWorld = position;
  vMap = m;
}
