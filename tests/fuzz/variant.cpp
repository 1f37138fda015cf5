// A lighting change (`relume relight --virtual-lamp/--virtual-object F.json`): the JSON and the OBJ
// of a virtual object it names, in split.h's layout. Any bytes give a variant or a relume::Error,
// never a crash, a leak or a hang.
#include <string>

#include "relume/geometry/error.h"
#include "relume/project/room_io.h"
#include "split.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const relume::fuzz::Parts p = relume::fuzz::split3(data, size);
  const relume::FileBytes files = [&](const std::string&) { return p.b; };
  try {
    (void)relume::parseVariantFile(p.a, "change.json", files);
  } catch (const relume::Error&) {
  }
  return 0;
}
