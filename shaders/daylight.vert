// (The renderer prepends "#version 330 core", OBJECT and OUTPUT.) The daylight view: the room's
// polygons (OBJECT 0) or the virtual objects' faces (OBJECT 1) seen through the photo's camera.
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;      // the face's
layout(location = 2) in vec3 frontE;      // objects: indirect irradiance on the front, per vertex
layout(location = 3) in vec3 backE;       // and on the back
layout(location = 4) in vec3 albedo;      // objects: the face's
uniform mat4 worldToClip;
invariant gl_Position;  // the view's depth pre-pass (daylight_map.vert) and its shading pass give the same depth
out vec3 vWorld;
flat out vec3 vNormal;
out vec3 vFrontE;
out vec3 vBackE;
flat out vec3 vAlbedo;
void main() {
  vWorld = position;
  vNormal = normal;
  vFrontE = frontE;
  vBackE = backE;
  vAlbedo = albedo;
  gl_Position = worldToClip * vec4(position, 1.0);
}
