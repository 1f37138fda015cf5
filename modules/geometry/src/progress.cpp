#include "relume/geometry/progress.h"

#include "relume/geometry/error.h"

namespace relume {

void Progress::report(double fraction, const std::string& text) {
  poll();
  if (callback_) callback_(fraction, text);
}

void Progress::poll() const {
  if (cancelled_.load()) throw Cancelled();
}

Progress& silentProgress() {
  thread_local Progress p;
  return p;
}

}  // namespace relume
