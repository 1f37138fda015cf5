// A mesh for an image-based object, OBJ (with an MTL), PLY or glTF: any bytes give a valid mesh
// (every triangle indexes a vertex, coordinates finite) or a relume::Error, never a crash, leak or
// hang. The first byte picks the format ('0' OBJ, '1' PLY, '2' glTF or GLB).
#include <cmath>
#include <cstdlib>
#include <string>

#include "relume/geometry/error.h"
#include "relume/ibr/mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const std::string bytes(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    const int format = data[0] % 3;
    const relume::ibr::Mesh m =
        format == 1   ? relume::ibr::parsePlyMesh(bytes, "object.ply")
        : format == 2 ? relume::ibr::parseGltfMesh(bytes, "object.gltf",
                                                   [](const std::string&) { return std::string(64, '\0'); })
                      : relume::ibr::parseObjMesh(bytes, "object.obj", [](const std::string&) {
                          return std::string("newmtl red\nKd 0.8 0.1 0.1\n");
                        });
    for (const auto& t : m.triangles)
      for (int k = 0; k < 3; ++k)
        if (t[k] >= m.positions.size()) std::abort();
    for (const auto& p : m.positions)
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) std::abort();
  } catch (const relume::Error&) {
  }
  return 0;
}
