// COLMAP text model (cameras.txt, images.txt, points3D.txt): any bytes give a model or a
// relume::Error, never a crash, a leak or a hang.
#include <sstream>

#include "relume/geometry/error.h"
#include "relume/reconstruct/colmap_model.h"
#include "split.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto parts = relume::fuzz::split3(data, size);
  std::istringstream cameras(parts.a), images(parts.b), points(parts.c);
  try {
    const auto m = relume::recon::parseColmapText(cameras, images, parts.hasC ? &points : nullptr, "cameras.txt", "images.txt",
                                                  "points3D.txt");
    for (const auto& [id, im] : m.images) (void)m.camera(im);
  } catch (const relume::Error&) {
  }
  return 0;
}
