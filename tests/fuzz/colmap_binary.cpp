// COLMAP binary model (cameras.bin, images.bin, points3D.bin): any bytes give a model or a
// relume::Error, never a crash, a leak, a hang or an allocation the input cannot back.
#include <sstream>

#include "relume/geometry/error.h"
#include "relume/reconstruct/colmap_model.h"
#include "split.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto parts = relume::fuzz::split3(data, size);
  std::istringstream cameras(parts.a, std::ios::binary), images(parts.b, std::ios::binary), points(parts.c, std::ios::binary);
  try {
    const auto m = relume::recon::parseColmapBinary(cameras, images, parts.hasC ? &points : nullptr, "cameras.bin", "images.bin",
                                                    "points3D.bin");
    for (const auto& [id, im] : m.images) (void)m.camera(im);
  } catch (const relume::Error&) {
  }
  return 0;
}
