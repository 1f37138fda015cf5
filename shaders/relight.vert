// (The renderer prepends "#version 330 core" and the variant's defines, see relight.frag.)
// The session's display mesh: leaf elements clipped to their polygons (world position, the
// polygon's plane coordinates, and the leaf whose corner values shade it). Loscos 2000 §2.4
// shades the textures by B / D per vertex (Gouraud); here each vertex carries its leaf's bilinear
// B, D and B_orig at its place (RelightSession::displayVertexLight; the mesh is a watertight fan
// per leaf, so along leaf edges and at leaf centres these are exactly the CPU renderer's values).
layout(location = 0) in vec3 position;
layout(location = 1) in vec2 uv;
layout(location = 2) in int leaf;
layout(location = 3) in vec3 B;      // the leaf's bilinear B, D and B_orig at this vertex
layout(location = 4) in vec3 D;
layout(location = 5) in vec3 Borig;
uniform mat4 worldToClip;
uniform samplerBuffer corners;  // per leaf 12 texels: B, D, B_orig at its corners; texel 4's alpha its §4.3 category
uniform samplerBuffer rects;    // per leaf u0, v0, u1, v1
out vec2 vTC;
uniform vec2 texOrigin;         // uv of the surface texture's texel (0, 0) corner
uniform vec2 texExtent;         // its width and height in metres (texOrigin 0 and texExtent 1 on a surface with no texture)
out vec3 vB;
out vec3 vDen;                  // D (relit), B_orig (ratio-only)
#if MODE == 6
flat out vec4 vRect;
#endif
#if MODE == 7
flat out float vCategory;
#endif

void main() {
  vTC = (uv - texOrigin) / texExtent;  // (per vertex: it is affine in uv)
  vB = B;
#if MODE == 1
  vDen = Borig;  // ratio-only: B / B_orig
#else
  vDen = D;
#endif
#if MODE == 6
  vRect = texelFetch(rects, leaf);
#endif
#if MODE == 7
  vCategory = texelFetch(corners, leaf * 12 + 4).a;
#endif
  gl_Position = worldToClip * vec4(position, 1.0);
}
