// A preprocessed project's relight/relight.json, read for the project.json beside it (split.h's
// layout: project.json, relight.json). Any bytes give relighting data or a relume::Error, never a
// crash, a leak or a hang.
#include <string>

#include "relume/geometry/error.h"
#include "relume/project/relight_store.h"
#include "relume/project/room_io.h"
#include "split.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const relume::fuzz::Parts p = relume::fuzz::split3(data, size);
  try {
    const relume::Scene scene = relume::parseProject(p.a, "project.json");
    (void)relume::parseRelightJson(p.b, scene, "relight/relight.json");
  } catch (const relume::Error&) {
  }
  return 0;
}
