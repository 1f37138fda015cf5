// A Relume project.json: any bytes give a validated scene or a relume::Error, never a crash, a
// leak or a hang.
#include <string>

#include "relume/geometry/error.h"
#include "relume/project/room_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    (void)relume::parseProject(std::string(reinterpret_cast<const char*>(data), size), "project.json");
  } catch (const relume::Error&) {
  }
  return 0;
}
