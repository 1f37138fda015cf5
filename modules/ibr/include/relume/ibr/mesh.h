#pragma once
// The meshes image-based objects are made from: triangles with per-corner normals and colours
// where the file has them. Read from Wavefront OBJ (with its MTL's diffuse colours) and PLY
// (ASCII and binary, vertex normals and colours) and glTF 2.0 (.gltf with its buffers, .glb);
// no limit on their size but memory.
#include <cstdint>
#include <functional>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

namespace relume::ibr {

struct Mesh {
  std::vector<glm::vec3> positions;
  std::vector<glm::uvec3> triangles;
  // Per triangle corner (3 x triangles, or empty: flat shading from the face's normal).
  std::vector<glm::vec3> cornerNormals;
  // Per triangle corner linear albedo (3 x triangles), or empty: triangleAlbedo.
  std::vector<glm::vec3> cornerColours;
  std::vector<glm::vec3> triangleAlbedo;  // per triangle (from its material; 0.8 grey without one)
  std::string name;                       // the file it came from
};

inline constexpr float kDefaultAlbedo = 0.8f;

// By extension (.obj, .ply, .gltf, .glb). Throws relume::Error naming the file: unreadable, an unknown format,
// a bad line or header, an index out of range, a coordinate that is not a finite number, no faces.
Mesh readMesh(const std::string& path);
// The same from bytes: `name` for the messages; an OBJ's MTL files are read through `mtl`
// (given the name a `mtllib` line gives; returns the bytes, or throws), none when it is empty.
Mesh parseObjMesh(const std::string& bytes, const std::string& name,
                  const std::function<std::string(const std::string&)>& mtl = {});
Mesh parsePlyMesh(const std::string& bytes, const std::string& name);
// glTF 2.0, JSON or binary (.glb): the default scene's nodes with their transforms, triangle
// primitives' POSITION, NORMAL, COLOR_0 and indices, each material's base colour factor (linear)
// as the albedo (textures are not read); turned from glTF's +Y up to +Z up. Buffers given as
// files are read through `files` (relative to the .gltf), data URIs and the .glb's own chunk
// directly.
Mesh parseGltfMesh(const std::string& bytes, const std::string& name,
                   const std::function<std::string(const std::string&)>& files = {});

// A smooth bumpy ball standing on z = 0 (radius r (1 + bump sin 3 theta cos 4 phi)), 2 nu (nv - 1)
// triangles, its normals averaged from its faces, albedo 0.8 grey: a mesh of any size for
// benchmarks and tests.
Mesh bumpyBall(int nu, int nv, double radius, double bump);

// Checks what every mesh must be (triangles indexing existing vertices, finite coordinates, at
// least one face of non-zero area); throws relume::Error naming `mesh.name`.
void validateMesh(const Mesh& mesh);

}  // namespace relume::ibr
