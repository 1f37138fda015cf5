// An image fan file: any bytes give a fan whose every view decodes (or a relume::Error), never a
// crash, a leak or a hang; decoded views have their sizes and codes in range.
#include <zlib.h>

#include <cstdlib>
#include <vector>

#include "relume/geometry/error.h"
#include "relume/ibr/fan.h"
#include "relume/ibr/normal_code.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // The checksum made right for the mutated bytes, so that the fuzzer reaches the header and the
  // views behind it (a wrong checksum is refused before anything else is trusted).
  std::vector<uint8_t> bytes(data, data + size);
  if (bytes.size() >= 16) {
    const uint32_t crc = uint32_t(crc32_z(0L, bytes.data(), bytes.size() - 4));
    for (int k = 0; k < 4; ++k) bytes[bytes.size() - 4 + size_t(k)] = uint8_t(crc >> (8 * k));
  }
  try {
    const auto fan = relume::ibr::parseFan(bytes, "object.fan");
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
