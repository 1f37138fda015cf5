// (The renderer prepends "#version 330 core", MAX_MAPS and IMAGE.) Every shadow map of one atlas
// in one instanced draw (gl_daylight.cpp): instance i is map firstMap + i, drawn into its tile of
// the atlas (columns x rows tiles). The map's own square is kept by four clip distances, so that a
// polygon crossing its edge does not spill into the next tile. (One draw for all maps: llvmpipe
// pays for every change of target, which cost more than drawing the maps' texels.)
// IMAGE 1: an image-based object's silhouette in one map (map firstMap, tile `tile`): the square
// of the fan view nearest the map's light, through the object's centre across that view's
// direction (what the library's shadows read, ibr::ObjectShadows), made from gl_VertexID.
layout(std140) uniform MapBlock {
  vec4 mapData[MAX_MAPS * 7];
};
uniform int firstMap;
uniform ivec2 grid;  // the atlas's columns and rows
out vec3 vWorld;
flat out int vMap;
out float gl_ClipDistance[4];
#if IMAGE
uniform int tile;
uniform vec3 fanCentre;       // world
uniform vec3 fanRight, fanUp; // the view's image axes, world
uniform float fanHalf;        // the square's half side, metres
out vec2 vSquare;             // -1..1 across the square, +y up
#else
layout(location = 0) in vec3 position;
#endif
void main() {
#if IMAGE
  int m = firstMap, t = tile;
  vSquare = vec2((gl_VertexID & 1) != 0 ? 1.0 : -1.0, (gl_VertexID & 2) != 0 ? 1.0 : -1.0);
  vec3 position = fanCentre + fanHalf * (vSquare.x * fanRight + vSquare.y * fanUp);
#else
  int m = firstMap + gl_InstanceID, t = gl_InstanceID;
#endif
  mat4 clip = mat4(mapData[m * 7 + 0], mapData[m * 7 + 1], mapData[m * 7 + 2], mapData[m * 7 + 3]);
  vec4 c = clip * vec4(position, 1.0);
  gl_ClipDistance[0] = c.w - c.x;
  gl_ClipDistance[1] = c.w + c.x;
  gl_ClipDistance[2] = c.w - c.y;
  gl_ClipDistance[3] = c.w + c.y;
  // The map's [-w, w] square onto its tile: linear in the clip coordinates, so perspective holds.
  vec2 tileAt = vec2(t % grid.x, t / grid.x);
  c.xy = ((c.xy + c.w) * 0.5 + tileAt * c.w) / vec2(grid) * 2.0 - c.w;
  gl_Position = c;
  vWorld = position;
  vMap = m;
}
