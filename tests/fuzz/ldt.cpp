// A EULUMDAT (.ldt) photometric file: any bytes give a distribution or a relume::Error,
// never a crash, a leak or a hang; its intensities are finite.
#include <cmath>
#include <cstdlib>
#include <string>

#include "relume/geometry/error.h"
#include "relume/geometry/photometry.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const relume::PhotometricDistribution d =
        relume::parseEulumdat(std::string(reinterpret_cast<const char*>(data), size), "luminaire.ldt");
    if (!std::isfinite(d.intensity(33.0, 47.0))) std::abort();
  } catch (const relume::Error&) {
  }
  return 0;
}
