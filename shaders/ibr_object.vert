// (The renderer prepends "#version 330 core" and OUTPUT, see ibr_object.frag.)
// An image-based object's bounding sphere as a cube of the world: its back faces are drawn, and
// each fragment marches its own ray from the eye through the fan's depth.
layout(location = 0) in vec3 corner;  // the unit cube, [-1, 1]^3
uniform mat4 worldToClip;
uniform vec4 sphere;                  // centre (world), radius
out vec3 vWorld;

void main() {
  vWorld = sphere.xyz + sphere.w * corner;
  gl_Position = worldToClip * vec4(vWorld, 1.0);
}
