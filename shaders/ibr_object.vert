// (The renderer prepends "#version 330 core" and OUTPUT, see ibr_object.frag.)
// An image-based object's bounding sphere as the octagon that covers its outline, seen from the
// eye: drawn in the plane that touches the sphere's far side, facing the eye, so that every ray
// from the eye through the sphere crosses it (the eye is outside the sphere: drawObjects skips the
// object otherwise). Each fragment marches its own ray from the eye through the fan's depth and
// writes the depth of what it meets. A third fewer fragments than the sphere's cube, whose back
// faces it replaces: on llvmpipe the march is most of an object's cost.
uniform mat4 worldToClip;
uniform vec4 sphere;                  // centre (world), radius
uniform vec3 eye;
out vec3 vWorld;

void main() {
  vec3 toEye = eye - sphere.xyz;
  float d = max(length(toEye), 1.0001 * sphere.w);
  vec3 w = toEye / max(length(toEye), 1e-12);
  float r = sphere.w;
  // The cone of rays from the eye that touch the sphere, cut by the far tangent plane (at d + r
  // from the eye): a circle of radius (d + r) tan(theta), sin(theta) = r / d; the octagon around it.
  float R = (d + r) * r / sqrt(d * d - r * r) / cos(3.14159265 / 8.0) * 1.01;
  vec3 u = normalize(cross(abs(w.z) < 0.9 ? vec3(0.0, 0.0, 1.0) : vec3(1.0, 0.0, 0.0), w));
  vec3 v = cross(w, u);
  float a = (float(gl_VertexID) + 0.5) * (2.0 * 3.14159265 / 8.0);
  vWorld = sphere.xyz - r * w + R * (cos(a) * u + sin(a) * v);
  gl_Position = worldToClip * vec4(vWorld, 1.0);
}
