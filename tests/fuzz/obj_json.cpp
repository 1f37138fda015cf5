// An OBJ room with its JSON (materials, lamps, photos, variants) and one further file the JSON
// names, in split.h's layout. Any bytes give a validated scene or a relume::Error, never a crash,
// a leak or a hang.
#include <string>

#include "relume/geometry/error.h"
#include "relume/project/room_io.h"
#include "split.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const relume::fuzz::Parts p = relume::fuzz::split3(data, size);
  const relume::FileBytes files = [&](const std::string& name) -> std::string {
    if (p.hasC) return p.c;
    throw relume::Error(name, "", "the file does not exist");
  };
  try {
    (void)relume::parseObjWithJson(p.a, "room.obj", p.b, "room.json", files);
  } catch (const relume::Error&) {
  }
  return 0;
}
