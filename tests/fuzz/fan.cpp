// An image fan file: any bytes give a fan whose every view decodes (or a relume::Error), never a
// crash, a leak or a hang; decoded views have their sizes and codes in range.
#include <cstdlib>
#include <vector>

#include "relume/geometry/error.h"
#include "relume/ibr/fan.h"
#include "relume/ibr/normal_code.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const auto fan = relume::ibr::parseFan(std::vector<uint8_t>(data, data + size), "object.fan");
    for (int k = 0; k < fan->viewCount(); ++k) {
      const relume::ibr::FanView& v = fan->view(k);
      const size_t n = size_t(fan->size) * size_t(fan->size);
      if (v.alpha.size() != n || v.code.size() != n || v.depth.size() != n || v.colour.size() != 3 * n) std::abort();
      for (uint8_t c : v.code)  // a code out of range would index past the tables
        if (c >= relume::ibr::kNormalCodes && c != relume::ibr::kNoNormal) std::abort();
    }
  } catch (const relume::Error&) {
  }
  return 0;
}
