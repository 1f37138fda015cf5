// An OBJ mesh (a virtual object's, a room's geometry.obj): any bytes give faces or a
// relume::Error, never a crash, a leak or a hang.
#include <string>

#include "relume/geometry/error.h"
#include "relume/project/room_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    (void)relume::parseObjFaces(std::string(reinterpret_cast<const char*>(data), size), "mesh.obj");
  } catch (const relume::Error&) {
  }
  return 0;
}
